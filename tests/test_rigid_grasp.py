"""Rigid grasps: a grasp that also holds the held link's angle to the prop (or the
world) as it was at the catch - a gear joint of ratio 1 next to the grasp's pivot, let
go with it - through the data, the controllers, checkpoints, rewinds and replays.

A plain grasp is a pivot: the held link turns freely about the point, so a figure
standing on pinned feet is an inverted pendulum. A rigid one does not turn."""

from __future__ import annotations

import math
import pickle

import pymunk
import pytest

from puppet.data.errors import DataError
from puppet.interface import events as ev
from puppet.session.playback import play
from puppet.timeline.log import read_log, record_events
from puppet.timeline.replay import replay
from tests.test_checkpoint_format import _drive, _sim
from tests.test_reach_grasp import LUXO, play_on, press, session

# the swinging-bar grasp of test_reach_grasp.py, rigid; and a weak rigid one
RIGID = LUXO.replace("grasp: true, tolerance: 0.03}}",
                     "grasp: true, tolerance: 0.03, rigid: true}}\n"
                     "  - {key: h, reach: {chain: shade, point: {prop: swing}, duration: 0.3,"
                     " hold: 2.0, grasp: true, tolerance: 0.03, rigid: true, max_torque: 0.05}}")
EVENTS = [(240, ev.key("g", True)), (241, ev.key("g", False)),
          (520, ev.key("c", True)), (521, ev.key("c", False)),  # a manual checkpoint
          (1300, ev.key("u", True)), (1301, ev.key("u", False))]
END = 1500


def relative_angle(s) -> float:
    """The held link's (the upper arm's: the shade's) angle to the swinging bar (rad)."""
    return s.character.bodies["upper_arm"].angle - s.sim.props["swing"].body.angle


def held_angles(tmp_path, text, key) -> list[float]:
    """The shade's angle to the bar while it holds the bar, every 20 steps."""
    s = session(tmp_path, text)
    s.advance(240)
    press(s, key)
    out = []
    for _ in range(60):
        s.advance(20)
        if "shade" in s.sim.grasps:
            out.append(relative_angle(s))
    assert len(out) > 40, "the shade should catch the swinging bar"
    return out


def spread(values) -> float:
    return max(values) - min(values)


def test_a_rigid_grasp_holds_the_angle_a_pivot_lets_turn(tmp_path):
    pivot = held_angles(tmp_path, LUXO, "g")
    rigid = held_angles(tmp_path, RIGID, "g")
    weak = held_angles(tmp_path, RIGID, "h")  # 0.05 N*m: the angle hold gives way
    assert spread(pivot) > 0.1  # the shade turns about the bar's tip (0.18 rad)
    assert spread(rigid) < 0.002  # 0.001 rad: the gear joint's own give
    assert spread(weak) > 0.1


def test_the_angle_hold_goes_with_the_grasp(tmp_path):
    s = session(tmp_path, RIGID)
    s.advance(240)
    press(s, "g")
    s.advance(300)
    assert "shade" in s.sim.rigid and "shade" in s.sim.grasps
    gears = [c for c in s.sim.space.constraints if isinstance(c, pymunk.GearJoint)]
    assert gears == [s.sim.rigid["shade"]] and gears[0].max_force == math.inf
    press(s, "u")
    s.advance(1)
    assert not s.sim.rigid and not s.sim.grasps
    assert not [c for c in s.sim.space.constraints if isinstance(c, pymunk.GearJoint)]
    press(s, "h")  # a weak one has its torque
    s.advance(300)
    assert s.sim.rigid["shade"].max_force == 0.05


def test_a_rigid_grasp_survives_checkpoint_rewind_and_replay(tmp_path):
    straight = session(tmp_path, RIGID)
    held = {}
    play(straight, EVENTS, END, 100, lambda s: held.setdefault(s.steps, sorted(s.sim.rigid)))
    assert held[500] == held[1200] == ["shade"] and held[1500] == []
    want = straight.sim.state_hash()
    pivot = session(tmp_path)
    play(pivot, EVENTS, END)
    assert pivot.sim.state_hash() != want  # the angle hold made a difference

    # back to the manual checkpoint (taken while holding) and on again
    s = session(tmp_path, RIGID)
    play(s, EVENTS, 900)
    s.handle(ev.action("restore"))
    assert s.steps == 520 and "shade" in s.sim.rigid
    assert s.sim.rigid["shade"] in s.sim.space.constraints  # the restored space's own
    play_on(s, EVENTS, END)
    assert s.sim.state_hash() == want

    # a rewind to a step between keyframes while holding, then on
    s = session(tmp_path, RIGID)
    play(s, EVENTS, 1100)
    s.rewind_to(700)
    assert s.steps == 700 and "shade" in s.sim.rigid
    play_on(s, EVENTS, END)
    assert s.sim.state_hash() == want

    # a recorded log replays to the same bits
    path = record_events(session(tmp_path, RIGID), EVENTS, END, tmp_path / "rigid.jsonl")
    assert read_log(path).end_hash == want
    assert replay(path, check=False).final_hash == want


@pytest.mark.parametrize("setup", ["luxo-mouse", "cat-bound"])
def test_a_rigid_grasp_restores_as_pymunks_pickle_does(setup):
    """The snapshot format carries the gear joint exactly: the restored space agrees
    bit for bit with unpickling the space, 2000 steps on."""
    sim = _sim(setup)
    _drive(sim, 480)
    c = sim.character
    first, last = c.link_order[0], c.link_order[-1]
    sim.attach("held", first, (0.0, 0.0), tuple(c.bodies[first].position), rigid=True)
    sim.attach("weak", last, (0.0, 0.0), tuple(c.bodies[last].position), rigid=True,
               max_torque=0.5)
    _drive(sim, 240)
    legacy = pickle.dumps((sim.space, c.state_objects(), sim.steps), pickle.HIGHEST_PROTOCOL)
    new = _sim(setup)
    new.restore(sim.snapshot())
    assert sorted(new.rigid) == ["held", "weak"]
    assert new.rigid["weak"].max_force == 0.5
    space, character, steps = pickle.loads(legacy)
    old = _sim(setup)
    old.space, old.steps = space, steps
    old.character.bind(character)
    for run in (old, new):
        _drive(run, 2016)
    assert new.state_vector() == old.state_vector()
    new.detach("held")
    new.detach("weak")
    assert not [x for x in new.space.constraints if isinstance(x, pymunk.GearJoint)]


@pytest.mark.parametrize("bad, message", [
    ("grasp: {chain: shade, prop: any, max_torque: 3}", "'max_torque' limits a rigid grasp"),
    ("reach: {chain: shade, point: {prop: rail}, rigid: true}", "it needs a reach with "
                                                                "'grasp: true'"),
    ("grasp: {chain: shade, prop: any, rigid: true, max_torque: -1}", "max_torque"),
])
def test_rigid_mistakes_are_one_line_errors(tmp_path, bad, message):
    text = LUXO.replace("- {key: u, release: all}", "- {key: u, release: all}\n"
                        f"  - {{key: k, {bad}}}")
    with pytest.raises(DataError) as info:
        session(tmp_path, text)
    assert message in str(info.value) and "\n" not in str(info.value).strip()
    assert str(info.value).startswith(str(tmp_path / "t.yaml") + ":")

