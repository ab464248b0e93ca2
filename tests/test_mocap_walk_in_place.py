"""Oshita's walking in place (issue 30): stepping on the spot walks the figure forward at
the rhythm's speed (tracking.walk_in_place). The log (assets/logs/biped-mocap-in-place)
covers over 2 m in 10 s from a clip that stays in place, and fails without the walk;
a faster rhythm walks faster; when the steps stop the figure stops where it got to;
a checkpoint in mid-walk replays to the bit."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from puppet.data.catalog import find, load_setup
from puppet.interface import events as ev
from puppet.mocap.clip_source import ClipSource
from puppet.mocap.clips import open_clip
from puppet.mocap.retarget import load_mapping
from puppet.session import Session
from puppet.testing import replay_log

LOG = "assets/logs/biped-mocap-in-place.jsonl"


@pytest.fixture(scope="module")
def in_place():
    return open_clip("cmu-131_01-walk-in-place", load_mapping(find("mapping", "cmu-131")))


def _without_walk(setup):
    tracking = setup.interface.tracking.model_copy(update={"walk_in_place": None})
    return dataclasses.replace(setup, interface=setup.interface.model_copy(
        update={"tracking": tracking}))


def test_the_clip_stays_in_place(in_place):
    x = in_place.channels["root.x"]
    assert in_place.duration > 10.0 and np.max(np.abs(x)) < 0.02


def test_the_log_walks_on_and_fails_without_walking_in_place():
    result = replay_log(LOG)
    assert not result.failed, [str(f) for f in result.failed]
    old = replay_log(LOG, adjust=_without_walk)  # the performer's steps, on the spot
    kinds = {f.kind for f in old.failed}
    assert {"x_at_end", "mean_speed"} <= kinds, [str(f) for f in old.failed]
    traj = old.trajectory
    pelvis = traj.x[:, traj.index("pelvis")]
    assert abs(pelvis[-1] - pelvis[0]) < 0.2


def _run(session, events, until):
    from puppet.session.playback import play

    play(session, [e for e in events if session.steps <= e[0] < until], until)


def _walk(clip, speed: float, seconds: float):
    """(x of the pelvis at 3 s, at ``seconds``; the session) with the in-place clip
    played at ``speed``."""
    s = Session(load_setup("biped-mocap-in-place"))
    dt = s.sim.dt
    events = ClipSource(clip, speed=speed).events(dt, seconds)
    _run(s, events, round(3.0 / dt))
    x3 = s.character.link_position("pelvis")[0]
    _run(s, events, round(seconds / dt))
    return x3, s.character.link_position("pelvis")[0], s


def test_a_faster_rhythm_walks_faster(in_place):
    slow = _walk(in_place, 0.8, 7.0)
    fast = _walk(in_place, 1.2, 7.0)
    v_slow, v_fast = (slow[1] - slow[0]) / 4.0, (fast[1] - fast[0]) / 4.0
    assert slow[2].character.upright() and fast[2].character.upright()
    assert v_fast / v_slow == pytest.approx(1.2 / 0.8, rel=0.2), (v_slow, v_fast)
    tracker = fast[2].runtime.tracker
    assert tracker.walking and "walking in place" in tracker.status
    period = tracker.walk[2]  # a step: half the clip's 1.12 s cycle at 1.2x
    assert period == pytest.approx(1.1167 / 2 / 1.2, abs=0.05)


def test_when_the_steps_stop_the_figure_stops_where_it_got_to(in_place):
    s = Session(load_setup("biped-mocap-in-place"))
    dt = s.sim.dt
    events = ClipSource(in_place).events(dt, 4.0)
    _run(s, events, round(4.0 / dt))
    tracker = s.runtime.tracker
    assert tracker.walking
    gone = s.character.link_position("pelvis")[0]
    assert gone > 2.0
    # the performer stands still: the same frame, both feet down, from 4 s on
    still = next(in_place.at(t) for t in np.arange(0.0, 1.2, 0.01)
                 if abs(tracker._feet_gap(in_place.at(t))) < 0.01)
    for k in range(round(4.0 * 60), round(8.0 * 60)):
        step = round(k / 60 / dt)
        _run(s, [], step)
        s.handle(ev.channels(still))
    assert not tracker.walking and tracker.walk[7] == 0.0  # blended out
    x = s.character.link_position("pelvis")[0]
    assert s.character.upright() and x > gone - 0.3  # no pull back to the start


def test_a_checkpoint_in_mid_walk_replays_to_the_bit(in_place):
    s = Session(load_setup("biped-mocap-in-place"))
    dt = s.sim.dt
    events = ClipSource(in_place).events(dt, 6.0)
    _run(s, events, round(3.3 / dt))
    assert s.runtime.tracker.walking
    s.checkpoint()
    _run(s, events, round(5.0 / dt))
    first = s.sim.state_hash()
    s.restore_checkpoint()
    _run(s, events, round(5.0 / dt))
    assert s.sim.state_hash() == first


@pytest.mark.parametrize("old, new, says", [
    ("cycle: [4.52, 5.64]", "cycle: [4.52, 55.64]", "the clip's length"),
    ("clip: cmu-131_01-walk\n", "clip: cmu-131_01-wlk\n", "did you mean 'cmu-131_01-walk'"),
    ("library: cmu-library\n", "library: nothing\n", "no motion library named 'nothing'"),
    ("steps: [0.25, 1.2]", "steps: [1.2, 0.25]", "step periods"),
])
def test_a_bad_walk_is_one_line_at_its_place(tmp_path, old, new, says):
    from puppet.data.errors import DataError

    text = find("interface", "biped-mocap-in-place").read_text(encoding="utf-8")
    assert old in text
    path = tmp_path / "x.yaml"
    path.write_text(text.replace(old, new), encoding="utf-8")
    with pytest.raises(DataError) as err:
        load_setup(str(path))
    assert says in str(err.value) and "\n" not in str(err.value)
    assert err.value.line is not None
