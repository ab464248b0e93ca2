"""The figure keeps its feet (issue 30): lost tracking stands it (biped-mocap's
tracking.stand) within lost_after and hands it back to the performer blended; a shove
judged a fall is a fall and a get-up through the recovery poses, with no levitation.
The two logs (assets/logs/biped-mocap-lost, -fall) fail if the figure ends down: replayed
on the old behaviour (no stand, no get-up) they fail."""

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
from puppet.testing import replay_log

LOST = "assets/logs/biped-mocap-lost.jsonl"
FALL = "assets/logs/biped-mocap-fall.jsonl"


def _without(**fields):
    """An ``adjust`` for replay_log: biped-mocap's tracking with ``fields`` replaced."""
    def adjust(setup):
        tracking = setup.interface.tracking
        reaction = fields.pop("reaction", None)
        if reaction is not None:
            fields["reaction"] = tracking.reaction.model_copy(update=reaction)
        return dataclasses.replace(setup, interface=setup.interface.model_copy(
            update={"tracking": tracking.model_copy(update=fields)}))
    return adjust


def _levitation(result, after: float) -> float:
    """m the pelvis rose, after ``after`` s, between samples at which neither a foot
    nor a forearm (hand) touched the ground."""
    traj = result.trajectory
    pelvis = traj.y[:, traj.index("pelvis")]
    supports = [traj.index(n) for n in ("foot_near", "foot_far", "forearm_near",
                                        "forearm_far")]
    free = ~np.any(traj.contact[:, supports], axis=1)
    rose = 0.0
    for i in range(1, len(pelvis)):
        if traj.t[i] > after and free[i] and free[i - 1] and pelvis[i] > pelvis[i - 1]:
            rose += pelvis[i] - pelvis[i - 1]
    return rose


def test_the_lost_log_stands_and_walks_on_and_fails_without_standing():
    result = replay_log(LOST)
    assert not result.failed, [str(f) for f in result.failed]
    old = replay_log(LOST, adjust=_without(stand=None))  # let go, as before: it goes down
    kinds = {f.kind for f in old.failed}
    assert kinds & {"never_fell", "tilt_never_above", "upright_at_end"}, \
        [str(f) for f in old.failed]


def _rise(result, after: float) -> tuple[float, float]:
    """(s from the pelvis's lowest, after ``after``, to 90% of its standing height;
    s of that spent on all fours: the pelvis 0.4-0.9 m up, a hand and a knee or a foot
    on the ground)."""
    traj = result.trajectory
    pelvis = traj.y[:, traj.index("pelvis")]
    late = np.nonzero(traj.t > after)[0]
    low = late[np.argmin(pelvis[late])]
    up = low + int(np.argmax(pelvis[low:] > 0.9 * pelvis[0]))
    hands = np.any(traj.contact[:, [traj.index("forearm_near"), traj.index("forearm_far")]],
                   axis=1)
    legs = np.any(traj.contact[:, [traj.index(n) for n in ("shank_near", "shank_far",
                                                            "foot_near", "foot_far")]], axis=1)
    on_all_fours = hands & legs & (pelvis > 0.4) & (pelvis < 0.9)
    step = traj.t[1] - traj.t[0]
    return traj.t[up] - traj.t[low], float(np.sum(on_all_fours[low:up]) * step)


def test_the_fall_log_gets_up_through_the_poses_and_fails_without_the_get_up():
    result = replay_log(FALL)
    assert not result.failed, [str(f) for f in result.failed]
    assert _levitation(result, 5.3) < 0.02  # m: the pelvis rose only pushing on the ground
    took, fours = _rise(result, 5.3)
    assert took > 2.5 and fours > 0.25, (took, fours)  # through hands and knees
    old = replay_log(FALL, adjust=_without(reaction={"get_up": None}))
    # the pulls come back after the fall's hold and lift it like strings: no hands and
    # knees, up in no time
    took, fours = _rise(old, 5.3)
    assert took < 1.5 and fours < 0.2, (took, fours)


@pytest.fixture(scope="module")
def walk_source():
    clip = open_clip("cmu-131_01-walk", load_mapping(find("mapping", "cmu-131")))
    return clip


def _run(session, events, until):
    from puppet.session.playback import play

    play(session, [e for e in events if e[0] >= session.steps], until)


def test_lost_tracking_stands_the_figure_within_lost_after_and_blends_back(walk_source):
    s = Session(load_setup("biped-mocap"))
    dt = s.sim.dt
    drop = (4.9, 5.6)
    events = ClipSource(walk_source, drop=drop).events(dt, 6.5)
    tracker = s.runtime.tracker
    _run(s, events, round(drop[0] / dt))
    assert not tracker.lost
    _run(s, events, round((drop[0] + 0.25) / dt) + tracker.every + 1)
    assert tracker.lost and tracker.hold is not None  # standing within lost_after
    assert "LOST" in tracker.status and "standing" in tracker.status
    # back: the targets move on from where they were, no jump (a blend of 0.5 s)
    _run(s, events, round(drop[1] / dt) - 1)
    servos = s.character.servos
    before = {j: servos[j].target for j in tracker.joints}
    _run(s, events, round(drop[1] / dt) + 2 * tracker.every)
    assert not tracker.lost and tracker.back is not None
    jump = max(abs(servos[j].target - before[j]) for j in tracker.joints)
    assert math.degrees(jump) < 10.0
    _run(s, events, round(6.5 / dt))
    assert tracker.back is None and s.character.upright()


def test_lost_and_found_actions_run(tmp_path):
    """tracking.lost and .found: actions of the interface (a state for the keys)."""
    from puppet.mocap import puppet_osc  # noqa: F401 (the channels a stream sends)

    text = find("interface", "biped-mocap").read_text(encoding="utf-8")
    text = text.replace("  stand: stand_still\n", "  lost: {goto: waiting}\n"
                                                 "  found: {goto: following}\n")
    text += ("initial: following\nstates:\n  following: {description: the performer}\n"
             "  waiting: {description: the stream is lost}\n")
    path = tmp_path / "lost-found.yaml"
    path.write_text(text.replace("name: biped-mocap", "name: lost-found"), encoding="utf-8")
    s = Session(load_setup(str(path)))
    dt = s.sim.dt
    frame = {"hip_near": 5.0, "root.x": 0.0, "root.y": 0.93, "root.angle": 0.0}
    for _ in range(10):
        s.handle(ev.channels(frame))
        s.advance(8)
    assert s.runtime.state == "following"
    s.advance(round(0.4 / dt))
    assert s.runtime.state == "waiting" and s.runtime.tracker.lost
    assert s.runtime.tracker.hold is None  # no stand: it let go, the keys have it
    s.handle(ev.channels(frame))
    s.advance(8)
    assert s.runtime.state == "following" and not s.runtime.tracker.lost


def test_a_checkpoint_in_mid_get_up_replays_to_the_bit(walk_source):
    s = Session(load_setup("biped-mocap"))
    dt = s.sim.dt
    events = ClipSource(walk_source).events(dt, 9.0)
    _run(s, events, round(5.3 / dt))
    s.handle(ev.key("shift+]", True))
    _run(s, events, round(7.5 / dt))
    tracker = s.runtime.tracker
    assert tracker.getup is not None and "getting up" in tracker.status
    s.checkpoint()
    _run(s, events, round(8.5 / dt))
    first = s.sim.state_hash()
    s.restore_checkpoint()
    assert s.runtime.tracker.getup is not None
    _run(s, events, round(8.5 / dt))
    assert s.sim.state_hash() == first
