"""Tracking a performance: joint tracking and KD control through the arbiter, exact
through checkpoints, lost when the stream stops, preempted per joint by keys."""

from __future__ import annotations

import math

import pytest
from helpers import play_events, tap

from puppet.data.catalog import find, load_setup, setup_from_text
from puppet.data.errors import DataError
from puppet.interface import events as ev
from puppet.interface.controllers.tracking import TRACK
from puppet.mocap.bvh import read_bvh
from puppet.mocap.clip_source import ClipSource
from puppet.mocap.retarget import load_mapping, retarget_clip
from puppet.session import Session

MOCAP = find("interface", "biped-mocap")


@pytest.fixture(scope="module")
def walk():
    return retarget_clip(read_bvh("assets/mocap/cmu-131_01-walk.bvh"),
                         load_mapping("assets/mappings/cmu-131.yaml"))


def _interface(**changes) -> str:
    text = MOCAP.read_text(encoding="utf-8")
    for old, new in changes.items():
        assert old in text, old
        text = text.replace(old, new)
    return text


def _with_knee_key() -> Session:
    """biped-mocap with a key `k` that sets the near knee (a key that takes a joint)."""
    text = _interface(**{"  - {key: o,": "  - {key: k, set: {knee_near: -90}}\n  - {key: o,"})
    return Session(setup_from_text(text, MOCAP))




def test_kd_control_follows_the_clip_and_a_rewind_replays_it_to_the_bit(walk):
    s = Session(load_setup("biped-mocap"))
    events = ClipSource(walk).events(s.sim.dt, 3.0)
    play_events(s, events, 960)  # 2 s
    s.checkpoint()
    play_events(s, [e for e in events if e[0] >= 960], 1440)
    first = s.sim.state_hash()
    s.restore_checkpoint()
    play_events(s, [e for e in events if e[0] >= 960], 1440)
    assert s.sim.state_hash() == first
    c = s.character
    assert c.upright() and c.com()[1] > 0.8
    assert s.runtime.tracker.status == "tracking kd with pulls"


def _letting_go():
    """biped-mocap without tracking.stand: a lost stream lets go of the joints."""
    import dataclasses

    setup = load_setup("biped-mocap")
    tracking = setup.interface.tracking.model_copy(update={"stand": None})
    return Session(dataclasses.replace(setup, interface=setup.interface.model_copy(
        update={"tracking": tracking})))


def test_the_stream_lost_lets_go_and_a_new_sample_takes_the_joints_back(walk):
    s = _letting_go()
    dt = s.sim.dt
    events = ClipSource(walk).events(dt, 0.5)
    play_events(s, events, round(0.5 / dt))
    owners = s.runtime.owners.table
    assert set(owners.values()) == {TRACK}
    play_events(s, [], round(0.7 / dt))  # 0.2 s without a sample: still tracking
    assert not s.runtime.tracker.lost
    play_events(s, [], round(0.8 / dt))  # past 0.25 s: lost, the joints are nobody's
    assert s.runtime.tracker.lost and "LOST" in s.runtime.tracker.status
    assert TRACK not in s.runtime.owners.table.values()
    # the interface's gains are back on the joints (KD had scaled them)
    assert s.character.servos["knee_near"].stiffness == pytest.approx(1000.0)
    s.handle(ev.channels(walk.at(0.8)))
    assert not s.runtime.tracker.lost
    assert TRACK in s.runtime.owners.table.values()


def test_a_key_takes_its_joints_from_the_performer_and_the_rest_follow_on(walk):
    s = _with_knee_key()
    dt = s.sim.dt
    events = ClipSource(walk).events(dt, 1.5)
    play_events(s, [e for e in events if e[0] < 480], 480)
    s.handle(ev.key("k", True))
    play_events(s, [e for e in events if e[0] >= 480], round(1.5 / dt))
    servos = s.character.servos
    assert servos["knee_near"].target == pytest.approx(math.radians(-90))
    assert s.runtime.owners.table.get("knee_far") == TRACK
    assert servos["knee_far"].target == pytest.approx(
        math.radians(s.runtime.channels["knee_far"]))


def test_the_pulls_off_is_free_fall():
    """A performer in the air (feet 0.3 m off the floor): the pulls lift the figure off
    the ground; with them off (the key) it drops back, its joints still tracking."""
    s = Session(load_setup("biped-mocap"))
    dt = s.sim.dt
    pose = {"root.x": 0.0, "root.y": 1.25, "root.angle": 0.0, "clearance": 0.3}
    pose.update({j: 0.0 for j in s.character.servos})
    for _ in range(0, round(0.6 / dt), 8):
        s.handle(ev.channels(pose))
        s.advance(8)
    lifted = min(min(sh.cache_bb().bottom for sh in s.character.shapes[f])
                 for f in ("foot_near", "foot_far"))
    assert lifted > 0.15
    s.handle(ev.key("f", True))
    assert "free fall" in s.runtime.tracker.status
    for _ in range(0, round(0.6 / dt), 8):
        s.handle(ev.channels(pose))
        s.advance(8)
    dropped = min(min(sh.cache_bb().bottom for sh in s.character.shapes[f])
                  for f in ("foot_near", "foot_far"))
    assert dropped < 0.02


@pytest.mark.parametrize("change, message", [
    ({"tracking:\n": "unused:\n"}, "tracking"),  # the section gone: track needs it
    ({"  root: {at: hip_near}\n": ""}, "tracking.root"),
    ({"root: {at: hip_near}": "root: {at: knee_near}"}, "root link"),
    ({"scale: {foot_near: 125": "scale: {toe: 125"}, "toe"),
])
def test_tracking_mistakes_are_one_line_errors(change, message):
    text = _interface(**change)
    if "unused:" in text:  # drop the whole section (up to the next top-level key)
        head, _, rest = text.partition("unused:\n")
        lines = rest.splitlines()
        while lines and lines[0].startswith(" "):
            lines.pop(0)
        text = head + "\n".join(lines) + "\n"
    with pytest.raises(DataError) as err:
        setup_from_text(text, MOCAP)
    assert message in str(err.value) and "\n" not in str(err.value)
    assert "biped-mocap.yaml:" in str(err.value)


@pytest.mark.parametrize("impulse, case", [(8.0, "small"), (30.0, "large"), (200.0, "fall")])
def test_a_push_is_judged_small_large_or_a_fall_and_the_pulls_give_way(walk, impulse, case):
    """Standing (the clip's first second), shoved at the chest: the extrapolated
    centre of mass against the feet decides the case, the pulls weaken at once and
    come back to full after the case's hold and recovery."""
    s = Session(load_setup("biped-mocap"))
    dt = s.sim.dt
    events = ClipSource(walk).events(dt, 6.0)
    play_events(s, events, round(0.5 / dt))
    tracker = s.runtime.tracker
    s.handle({"type": "push", "link": "chest", "impulse": [impulse, 0.0]})
    start = s.steps
    play_events(s, [e for e in events if e[0] >= start], start + 8)
    assert tracker.reaction is not None and tracker.reaction[0] == case
    spec = getattr(tracker.spec.reaction, case)
    assert tracker._weight(s.steps) == pytest.approx(spec.weight)
    assert f"reacting to a {case} push" in tracker.status
    end = start + round((spec.hold + spec.recover) / dt) + 16
    if case == "fall":  # a get-up after the hold, then the performer over the blend
        get_up = tracker.spec.reaction.get_up
        play_events(s, [e for e in events if e[0] >= s.steps], start + round(spec.hold / dt) + 16)
        assert tracker.getup is not None and "getting up (hands_knees)" in tracker.status
        end = start + round((spec.hold + sum(p.hold for p in get_up.steps)
                             + tracker.spec.blend) / dt) + 16
    play_events(s, [e for e in events if e[0] >= s.steps], end)
    assert tracker.reaction is None and tracker._weight(s.steps) == 1.0
    assert tracker.getup is None and tracker.back is None


def test_lost_then_off_then_on_tracks_again(walk):
    """A lost stream, then `o` (off) and `t` (KD): tracking starts afresh, not stuck
    lost holding the joints at KD's weak gains (blended in over tracking.blend)."""
    s = _letting_go()
    dt = s.sim.dt
    play_events(s, ClipSource(walk).events(dt, 0.3), round(0.3 / dt))
    play_events(s, [], round(0.7 / dt))
    tracker = s.runtime.tracker
    assert tracker.lost
    s.handle(ev.key("o", True))
    s.handle(ev.key("t", True))
    assert not tracker.lost and tracker.mode == "kd"
    events = [e for e in ClipSource(walk, start=0.7).events(dt, 1.3)]
    play_events(s, events, round(1.3 / dt))
    assert not tracker.lost and "LOST" not in tracker.status
    assert s.character.servos["knee_far"].target == pytest.approx(
        math.radians(s.runtime.channels["knee_far"]))


def test_a_joint_a_key_takes_gets_its_own_gains_and_no_pull(walk):
    s = _with_knee_key()
    dt = s.sim.dt
    events = ClipSource(walk).events(dt, 1.0)
    play_events(s, [e for e in events if e[0] < 240], 240)
    knee = s.character.servos["knee_near"]
    assert knee.stiffness < 500  # KD's inertia-scaled gain
    s.handle(ev.key("k", True))
    play_events(s, [e for e in events if e[0] >= 240], 480)
    assert knee.stiffness == pytest.approx(1000.0)  # the interface's (the character's)
    assert s.character.servos["knee_far"].stiffness < 500  # still the performer's


def test_a_checkpoint_in_mid_reaction_replays_to_the_bit(walk):
    s = Session(load_setup("biped-mocap"))
    dt = s.sim.dt
    events = ClipSource(walk).events(dt, 3.0)
    play_events(s, events, 480)
    s.handle({"type": "push", "link": "chest", "impulse": [30.0, 0.0]})
    play_events(s, [e for e in events if e[0] >= 480], 500)
    assert s.runtime.tracker.reaction is not None
    s.checkpoint()
    play_events(s, [e for e in events if e[0] >= 500], 1000)
    first = s.sim.state_hash()
    s.restore_checkpoint()
    assert s.runtime.tracker.reaction is not None
    play_events(s, [e for e in events if e[0] >= 500], 1000)
    assert s.sim.state_hash() == first


def test_a_looped_clip_walks_on_and_samples_on_its_grid(walk):
    loop = ClipSource(walk, loop=True)
    end = walk.channels["root.x"][-1] - walk.channels["root.x"][0]
    assert loop.values_at(walk.duration + 1.0)["root.x"] == pytest.approx(
        walk.at(1.0)["root.x"] + end)
    src = ClipSource(walk)
    assert len(src.drain(0.0)) == 1 and src.drain(0.01) == []  # one sample a period
    assert len(src.drain(1 / 60 + 0.001)) == 1
    (event,) = src.drain(0.5)  # the frame loop late: the newest grid sample
    assert event["values"] == ClipSource(walk).values_at(30 / 60)
    assert len(src.drain(0.2)) == 1  # a rewind: samples again from there


def test_a_mapping_that_cannot_feed_the_tracking_is_refused(tmp_path):
    from puppet.commands.check import check_file

    folder = tmp_path / "interfaces"
    folder.mkdir()
    text = _interface(**{"mapping: cmu-131": "mapping: thin"})  # a file beside it
    (folder / "m.yaml").write_text(text, encoding="utf-8")
    (folder / "thin.yaml").write_text(
        "name: thin\nroot: {point: Hips}\nplane: [0, 0, 1]\nsegments:\n"
        "  thigh: {from: Hips, to: Knee}\nchannels:\n  hip_near: {segment: thigh}\n",
        encoding="utf-8")
    with pytest.raises(DataError, match="root.angle") as err:
        check_file(folder / "m.yaml")
    assert "m.yaml:" in str(err.value) and "\n" not in str(err.value)


def test_a_state_changes_on_a_channel_condition():
    """Conditions read channels like sensors: a performer's jump (clearance) switches
    the state; before any value the condition never holds."""
    text = _interface(**{"control_rate: 120\n": """control_rate: 120
states:
  grounded:
    transitions:
      - {to: airborne, when: {sensor: channel.clearance, above: 0.05}}
  airborne:
    transitions:
      - {to: grounded, when: {sensor: channel.clearance, below: 0.01}}
"""})
    s = Session(setup_from_text(text, MOCAP))
    s.advance(120)
    assert s.runtime.state == "grounded"  # no value yet
    s.handle(ev.channels({"clearance": 0.2}))
    s.advance(8)
    assert s.runtime.state == "airborne"
    s.handle(ev.channels({"clearance": 0.0}))
    s.advance(8)
    assert s.runtime.state == "grounded"


def test_a_large_push_makes_a_protective_step(walk):
    """Shoved forward while standing: judged large, one foot is lifted and put down
    ahead, past the extrapolated centre of mass, and the figure stays up."""
    s = Session(load_setup("biped-mocap"))
    dt = s.sim.dt
    events = ClipSource(walk).events(dt, 3.0)
    play_events(s, events, round(0.5 / dt))
    c, tracker = s.character, s.runtime.tracker
    s.handle({"type": "push", "link": "chest", "impulse": [30.0, 0.0]})
    start = s.steps
    play_events(s, [e for e in events if e[0] >= start], start + 8)
    assert tracker.reaction[0] == "large" and tracker.step is not None
    foot, _, x0, _, x1, _ = tracker.step
    assert x1 > x0 + 0.05  # ahead: the way the push went
    peak = 0.0
    for _ in range(round(tracker.spec.reaction.step_time / dt / 8)):
        play_events(s, [e for e in events if e[0] >= s.steps], s.steps + 8)
        peak = max(peak, min(sh.cache_bb().bottom for sh in c.shapes[foot]))
    assert peak > 0.05  # lifted
    assert c.link_position(foot)[0] > x0 + 0.05 and c.in_contact(foot)  # put down ahead
    play_events(s, [e for e in events if e[0] >= s.steps], s.steps + round(1.5 / dt))
    assert c.upright()


def test_kinematic_on_and_off_switch_the_pulls_and_toggle_flips_them(tmp_path):
    text = (load_setup("biped-mocap").interface_path).read_text()
    text = text.replace("keys:\n", "keys:\n  - {key: '7', kinematic: 'on'}\n"
                                   "  - {key: '8', kinematic: 'off'}\n", 1)
    path = tmp_path / "biped-mocap.yaml"
    path.write_text(text)
    s = Session(load_setup(str(path)))
    tracker = s.runtime.tracker
    for key, want in (("7", True), ("7", True), ("8", False), ("8", False), ("f", True),
                      ("f", False), ("7", True)):
        tap(s, key)
        s.advance(2)
        assert tracker.kinematic is want, key


def test_after_a_push_the_pulls_come_back_from_their_weight_to_full_over_recover():
    s = Session(load_setup("biped-mocap"))
    tracker = s.runtime.tracker
    small = tracker.spec.reaction.small
    dt = s.sim.dt
    tracker.reaction = ("small", 0)
    assert tracker._weight(0) == pytest.approx(small.weight)
    half = round((small.hold + small.recover / 2) / dt)
    assert tracker._weight(half) == pytest.approx(small.weight + (1 - small.weight) / 2,
                                                  abs=0.01)
    assert tracker._weight(round((small.hold + small.recover) / dt) + 1) == 1.0
    assert tracker.reaction is None
