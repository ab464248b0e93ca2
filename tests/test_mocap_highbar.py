"""Mocap and grasp (issue 30): Ishigaki's intentional contacts (tracking.contacts). With
both hands held to the high bar, the performer's hands moving about their centre of
mass swing the figure's about the bar. The log (assets/logs/biped-mocap-highbar) swings
and fails without the contacts; the swing turns with the performer's hands; a hand let
go is no contact; a checkpoint in mid-swing replays to the bit."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from puppet.data.catalog import find, load_setup
from puppet.interface import events as ev
from puppet.mocap.clip_source import ClipSource
from puppet.mocap.clips import open_clip
from puppet.mocap.retarget import load_mapping
from puppet.session import Session
from puppet.session.playback import play
from puppet.testing import replay_log

LOG = "assets/logs/biped-mocap-highbar.jsonl"
BAR = (0.0, 2.8)


def _without_contacts(setup):
    tracking = setup.interface.tracking.model_copy(update={"contacts": None})
    return dataclasses.replace(setup, interface=setup.interface.model_copy(
        update={"tracking": tracking}))


def test_the_log_swings_on_the_bar_and_hangs_still_without_the_contacts():
    result = replay_log(LOG)
    assert not result.failed, [str(f) for f in result.failed]
    old = replay_log(LOG, adjust=_without_contacts)
    kinds = [f.kind for f in old.failed if f.kind != "same_end"]
    assert kinds == ["swung", "swung"], [str(f) for f in old.failed]


@pytest.fixture(scope="module")
def walk():
    return open_clip("cmu-131_01-walk", load_mapping(find("mapping", "cmu-131")))


def _com(character):
    m = x = y = 0.0
    for body in character.bodies.values():
        p = body.local_to_world(body.center_of_gravity)
        m += body.mass
        x += body.mass * p[0]
        y += body.mass * p[1]
    return x / m, y / m


def _swing(walk, until: float, session=None):
    """(the figure's bar-less-centre-of-mass angle, the performer's hands' mean angle
    about their centre of mass), every 24 steps to ``until``; and the session."""
    s = session or Session(load_setup("biped-mocap-highbar"))
    events = ClipSource(walk).events(s.sim.dt, 8.3)
    mine, theirs = [], []
    while s.steps < round(until / s.sim.dt):
        nxt = s.steps + 24
        play(s, [e for e in events if s.steps <= e[0] < nxt], nxt)
        x, y = _com(s.character)
        mine.append(math.atan2(BAR[1] - y, BAR[0] - x))
        ch = s.runtime.channels
        theirs.append([math.atan2(ch[f"{h}.y"], ch[f"{h}.x"]) for h in ("hand_near", "hand_far")])
    return np.unwrap(mine), np.unwrap(np.array(theirs), axis=0).mean(axis=1), s


def test_the_swing_turns_with_the_performers_hands(walk):
    mine, theirs, s = _swing(walk, 8.3)
    start = 10  # from 1 s
    assert np.corrcoef(mine[start:], theirs[start:])[0, 1] > 0.4
    assert set(s.runtime.tracker.contact) == {"hand_near", "hand_far"}


def test_a_hand_let_go_is_no_contact_and_the_other_still_swings(walk):
    s = Session(load_setup("biped-mocap-highbar"))
    _swing(walk, 2.0, s)
    s.handle(ev.key("q", True))
    s.handle(ev.key("q", False))
    _swing(walk, 2.5, s)
    tracker = s.runtime.tracker
    assert set(tracker.contact) == {"hand_far"}
    assert "hand_near" not in s.runtime.grasping.held


def test_a_checkpoint_in_mid_swing_replays_to_the_bit(walk):
    s = Session(load_setup("biped-mocap-highbar"))
    events = ClipSource(walk).events(s.sim.dt, 8.3)
    dt = s.sim.dt
    play(s, [e for e in events if e[0] < round(3.0 / dt)], round(3.0 / dt))
    s.checkpoint()
    play(s, [e for e in events if s.steps <= e[0] < round(4.5 / dt)], round(4.5 / dt))
    first = s.sim.state_hash()
    s.restore_checkpoint()
    assert s.runtime.tracker.contact
    play(s, [e for e in events if s.steps <= e[0] < round(4.5 / dt)], round(4.5 / dt))
    assert s.sim.state_hash() == first


def test_a_contact_on_no_chain_is_one_line_at_its_place(tmp_path):
    from puppet.data.errors import DataError

    text = find("interface", "biped-mocap-highbar").read_text(encoding="utf-8")
    path = tmp_path / "x.yaml"
    path.write_text(text.replace("{hand_near: hand_near,", "{hand_nar: hand_near,"),
                    encoding="utf-8")
    with pytest.raises(DataError) as err:
        load_setup(str(path))
    assert "unknown chain 'hand_nar'; did you mean 'hand_near'?" in str(err.value)
    assert err.value.line is not None
