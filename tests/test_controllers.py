"""Each controller of the interface runtime on its own, against the protocol every one
follows (``puppet.interface.controllers.base``): it starts, ``tick`` does what is due
and ``next_wakeup`` says when that is (None: idle); ``get_state`` gives plain values
that ``set_state`` takes back so that a fresh controller behaves exactly as the old
one would have; ``adopt`` (a hot reload) keeps what the new interface defines the same
way and ends the rest; ``stop`` ends everything.

The controllers are built here by hand from a parsed interface, a character and (for
reaches and grasps) a Simulation, without a runtime or a session around them."""

from __future__ import annotations

import json
import math
import textwrap

import pytest

from puppet.data.catalog import load_character_named, load_scene_named
from puppet.data.interfaces import parse_interface
from puppet.data.yamlfile import load_text
from puppet.interface import maps as mapping
from puppet.interface.controllers.gesture import GestureController
from puppet.interface.controllers.grasp import GraspController
from puppet.interface.controllers.perturbation import Perturber
from puppet.interface.controllers.reach import ReachController
from puppet.interface.controllers.sequence import SequenceController
from puppet.interface.controllers.state_machine import StateMachine
from puppet.interface.ik import Chain
from puppet.interface.ownership import GESTURE, SEQUENCE, JointOwners, reach_owner
from puppet.interface.poses import compile_poses
from puppet.physics.character import Character
from puppet.physics.simulation import Simulation

DT = 1.0 / 480.0
HEADER = "name: t\ndescription: controller test\ncharacter: luxo\n"
BODY = """
poses:
  crouch: {joints: {ankle: -70, knee: 130}}
  tall: {joints: {ankle: 0, knee: 0}}
  lean: {joints: {ankle: -40}}
sequences:
  hop: [{pose: crouch, hold: 0.1}, {pose: tall, hold: 0.05}, {pose: lean, hold: 0.1}]
  sit: [{pose: crouch, hold: 0.2}]
chains:
  shade: {joints: [ankle, knee], end: [0.0, 0.43]}
maps:
  - {input: mouse.x, joint: ankle, to: [-60, 60]}
  - {input: mouse.y, joint: knee, to: [0, 120]}
gestures:
  - {key: h, path: [[0, 0.5, 0.5], [0.05, 0.2, 0.8], [0.1, 0.9, 0.1]]}
keys:
  - {key: e, reach: {chain: shade, target: [0.05, 0.33], duration: 0.1, hold: 0.05}}
  - key: s
    reach: {chain: shade, steer: {x: channel.hx, y: channel.hy, x_from: [-1, 1],
            y_from: [-1, 1], x_to: [-0.05, 0.1], y_to: [0.28, 0.4]}, duration: 0.1}
  - {key: g, grasp: {chain: shade, points: [[5.0, 5.0]], tolerance: 0.03, within: 0.1}}
perturbation: {impulse: 0.001, every: 0.01, seed: 3}
"""

LUXO, _ = load_character_named("luxo")


def spec_of(text: str = BODY):
    return parse_interface(load_text(HEADER + textwrap.dedent(text), "t.yaml"))


def targets(servos) -> dict[str, float]:
    return {n: s.target for n, s in servos.items()}


def plain(state):
    """The state through JSON: the protocol's "plain values"."""
    return json.loads(json.dumps(state))


def run_out(controller, servos, step: int, limit: int = 10_000) -> list:
    """Tick ``controller`` at each of its wake-ups until it is idle (or ``limit``):
    [(step, joint targets)] after each tick."""
    seen = []
    while True:
        wake = controller.next_wakeup(step)
        if wake is None or wake > limit:
            return seen
        controller.tick(wake)
        seen.append((wake, targets(servos)))
        step = wake + 1


# -- sequences ------------------------------------------------------------------------
def sequence_controller(spec=None):
    spec = spec or spec_of()
    character = Character(LUXO)
    owners = JointOwners()
    return SequenceController(spec.sequences, compile_poses(spec.poses), character.servos,
                              owners, DT), character.servos, owners


def test_sequence_starts_ticks_at_each_hold_and_goes_idle():
    seq, servos, owners = sequence_controller()
    assert seq.next_wakeup(0) is None and seq.owners() == set()
    seq.start("hop", 10)
    assert math.degrees(servos["knee"].target) == pytest.approx(130)  # first pose at once
    assert owners.owned(SEQUENCE) == {"ankle", "knee"} and seq.owners() == {SEQUENCE}
    seen = run_out(seq, servos, 11)
    assert [s for s, _ in seen] == [10 + 48, 10 + 48 + 24, 10 + 48 + 24 + 48]
    assert [round(math.degrees(t["ankle"])) for _, t in seen] == [0, -40, -40]
    assert seq.running is None and seq.next_wakeup(0) is None
    assert not owners and seq.owners() == set()


@pytest.mark.parametrize("repeat, plays", [(None, 1), (3, 3)])
def test_sequence_repeat_plays_it_that_many_times(repeat, plays):
    seq, servos, _ = sequence_controller()
    seq.start("hop", 0, repeat)
    seen = run_out(seq, servos, 1)
    # each play: 48 + 24 + 48 steps; a new pose at every step change but the last
    assert seen[-1][0] == 120 * plays
    ankles = [round(math.degrees(t["ankle"])) for _, t in seen]
    assert ankles == [0, -40, -70] * (plays - 1) + [0, -40, -40]


def test_sequence_forever_runs_until_its_joints_are_taken():
    seq, servos, owners = sequence_controller()
    seq.start("hop", 0, "forever")
    seen = run_out(seq, servos, 1, limit=120 * 50)
    assert len(seen) == 3 * 50 and seq.running is not None  # still going after 50 plays
    assert seq.running.plays_left is None
    owners.take({"ankle", "knee"})  # a pose took both joints: it ends at its next tick
    seq.tick(seq.next_wakeup(0))
    assert seq.running is None and seq.next_wakeup(0) is None


def test_sequence_writes_only_the_joints_it_still_owns():
    seq, servos, owners = sequence_controller()
    seq.start("hop", 0)
    owners.take({"knee"})
    servos["knee"].target = 1.0
    seen = run_out(seq, servos, 1)
    assert all(t["knee"] == 1.0 for _, t in seen)
    assert [round(math.degrees(t["ankle"])) for _, t in seen] == [0, -40, -40]


def test_sequence_state_round_trip_gives_the_same_future():
    seq, servos, owners = sequence_controller()
    seq.start("hop", 0, 2)
    seq.tick(seq.next_wakeup(1))  # into the second pose
    state, owned, now = plain(seq.get_state()), plain(owners.get_state()), targets(servos)
    future = run_out(seq, servos, 49)
    fresh, servos2, owners2 = sequence_controller()
    fresh.set_state(state)
    owners2.set_state(owned)
    for name, value in now.items():
        servos2[name].target = value
    assert run_out(fresh, servos2, 49) == future
    assert len(future) == 5  # two plays of three steps, one done


def test_sequence_adopt_keeps_a_sequence_defined_the_same_way_only():
    old, _, _ = sequence_controller()
    old.start("sit", 0)
    new, _, _ = sequence_controller()
    assert new.adopt(old, lambda kind, name: kind == "sequence", 5) == {SEQUENCE}
    assert new.running.to_state() == old.running.to_state()
    assert new.running is not old.running  # a copy: the old one may go on or be dropped
    other, _, _ = sequence_controller()
    assert other.adopt(old, lambda kind, name: False, 5) == set()
    assert other.running is None and other.next_wakeup(0) is None


def test_sequence_stop_ends_it():
    seq, _, _ = sequence_controller()
    seq.start("hop", 0, "forever")
    seq.stop()
    assert seq.running is None and seq.next_wakeup(0) is None and seq.get_state() is None


# -- gestures --------------------------------------------------------------------------
def gesture_controller():
    spec = spec_of()
    character = Character(LUXO)
    servos, owners = character.servos, JointOwners()
    g = GestureController(spec.gestures, servos, owners, DT)
    g.mouse_maps = [mapping.compile_map(m, servos, {}) for m in spec.maps]
    g.mouse_joints = {"ankle", "knee"}
    return g, servos, owners


def test_gesture_plays_its_mouse_path_through_the_maps_in_sim_time():
    g, servos, owners = gesture_controller()
    g.start("h", 100)  # the first point is due at once
    assert (math.degrees(servos["ankle"].target), math.degrees(servos["knee"].target)) == \
        (pytest.approx(0), pytest.approx(60))
    assert owners.owned(GESTURE) == {"ankle", "knee"} and g.owners() == {GESTURE}
    seen = run_out(g, servos, 101)
    assert [s for s, _ in seen] == [100 + 24, 100 + 48]
    last = seen[-1][1]
    assert (math.degrees(last["ankle"]), math.degrees(last["knee"])) == \
        (pytest.approx(48), pytest.approx(12))
    assert g.running is None and not owners


def test_gesture_state_round_trip_and_adopt_and_stop():
    g, servos, owners = gesture_controller()
    g.start("h", 0)
    state, owned = plain(g.get_state()), plain(owners.get_state())
    future = run_out(g, servos, 1)
    fresh, servos2, owners2 = gesture_controller()
    fresh.set_state(state)
    owners2.set_state(owned)
    assert run_out(fresh, servos2, 1) == future

    old, _, _ = gesture_controller()
    old.start("h", 0)
    new, _, _ = gesture_controller()
    assert new.adopt(old, lambda *a: True, 3) == {GESTURE}  # the same path
    assert new.get_state() == old.get_state()
    changed, _, _ = gesture_controller()
    changed.paths["h"] = [(0, 0.1, 0.1)]  # the reloaded file recorded another path
    assert changed.adopt(old, lambda *a: True, 3) == set() and changed.running is None
    old.stop()
    assert old.running is None and old.next_wakeup(0) is None


def test_gesture_ends_when_its_joints_are_taken():
    g, servos, owners = gesture_controller()
    g.start("h", 0)
    owners.take({"ankle", "knee"})
    g.tick(g.next_wakeup(1))
    assert g.running is None and g.next_wakeup(0) is None


# -- reaches ---------------------------------------------------------------------------
def reach_setup(spec=None):
    spec = spec or spec_of()
    scene, _ = load_scene_named("flat")
    sim = Simulation(LUXO, scene)
    chains = {n: Chain.from_spec(n, c, LUXO) for n, c in spec.chains.items()}
    owners, inputs = JointOwners(), {}
    grasps = GraspController(chains, sim.character, sim, DT)
    reach = ReachController(chains, sim.character, sim, owners, sim.character.servos,
                            grasps, inputs.get, DT)  # reads inputs by name
    return reach, sim, owners, inputs, spec


def key_action(spec, key):
    return next(k for k in spec.keys if k.key == key)


def run_with_physics(controller, sim, steps: int) -> list:
    """Tick the controller when due and step the physics, for ``steps`` steps:
    [(step, joint targets)] at each tick."""
    seen = []
    for _ in range(steps):
        wake = controller.next_wakeup(sim.steps)
        if wake is not None and wake <= sim.steps:
            controller.tick(sim.steps)
            seen.append((sim.steps, targets(sim.character.servos)))
        sim.step()
    return seen


def test_reach_runs_for_duration_plus_hold_then_ends_and_frees_its_joints():
    reach, sim, owners, _, spec = reach_setup()
    reach.start(key_action(spec, "e").reach, 0)
    assert owners.owned(reach_owner("shade")) == {"ankle", "knee"}
    assert reach.owners() == {reach_owner("shade")}
    seen = run_with_physics(reach, sim, 200)
    assert [s for s, _ in seen] == list(range(0, 48 + 24 + 1))  # re-solved every step
    assert reach.reaches == {} and not owners and reach.next_wakeup(0) is None
    # the last solve put the end at the target (kinematically, in the base's frame then)
    chain = reach.chains["shade"]
    sim.character.place(*sim.character.bodies["base"].position,
                        sim.character.bodies["base"].angle,
                        {j: seen[-1][1][j] for j in chain.joints})
    base = sim.character.bodies["base"]
    assert math.dist(chain.end_world(sim.character), base.local_to_world((0.05, 0.33))) < 0.02


def test_reach_state_round_trip_gives_the_same_future():
    reach, sim, owners, _, spec = reach_setup()
    reach.start(key_action(spec, "e").reach, 0)
    run_with_physics(reach, sim, 30)
    # a checkpoint (not a plain snapshot): restoring it is bit-identical to not restoring
    snap, state, owned = sim.checkpoint(), plain(reach.get_state()), plain(owners.get_state())
    now = targets(sim.character.servos)
    future = run_with_physics(reach, sim, 100)
    again, sim2, owners2, _, _ = reach_setup()
    sim2.restore(snap)
    again.character = sim2.character
    again.set_state(state)
    owners2.set_state(owned)
    for name, value in now.items():
        sim2.character.servos[name].target = value
    assert run_with_physics(again, sim2, 100) == future
    assert len(future) == 72 - 30 + 1


def test_steered_reach_follows_its_inputs_until_preempted():
    reach, sim, owners, inputs, spec = reach_setup()
    reach.start(key_action(spec, "s").reach, 0)
    assert reach.reaches["shade"].end is None  # held until preempted
    run_with_physics(reach, sim, 100)
    middle = reach.target_now(reach.reaches["shade"].target)  # no input yet: the middle
    base = sim.character.bodies["base"]
    assert middle == pytest.approx(tuple(base.local_to_world((0.025, 0.34))))
    inputs["channel.hx"], inputs["channel.hy"] = 1.0, -3.0  # y clamps to its range
    assert reach.target_now(reach.reaches["shade"].target) == \
        pytest.approx(tuple(base.local_to_world((0.1, 0.28))))
    owners.take({"ankle", "knee"})  # a pose took the joints
    run_with_physics(reach, sim, 2)
    assert reach.reaches == {} and reach.next_wakeup(0) is None


def test_reach_adopt_keeps_reaches_of_chains_defined_the_same_way():
    old, _, _, _, spec = reach_setup()
    old.start(key_action(spec, "e").reach, 0)
    new, _, _, _, _ = reach_setup()
    assert new.adopt(old, lambda kind, name: kind == "chain" and name == "shade", 7) == \
        {reach_owner("shade")}
    assert new.get_state() == old.get_state()
    gone, _, _, _, _ = reach_setup()
    assert gone.adopt(old, lambda *a: False, 7) == set() and gone.reaches == {}
    old.stop()
    assert old.reaches == {} and old.next_wakeup(0) is None


# -- grasps ----------------------------------------------------------------------------
def test_grasp_armed_far_away_does_not_catch_and_disarms_after_within():
    reach, sim, _, _, spec = reach_setup()
    grasps = reach.grasps
    grasps.arm(key_action(spec, "g").grasp, 0)  # points [[5, 5]], tolerance 3 cm
    assert grasps.next_wakeup(0) == 0
    run_with_physics(grasps, sim, 100)
    assert grasps.held == {} and not sim.grasps
    assert grasps.armed == {} and grasps.next_wakeup(0) is None  # 0.1 s = 48 steps


def test_grasp_catches_a_point_within_tolerance_and_the_simulation_holds_it():
    reach, sim, _, _, _ = reach_setup()
    grasps = reach.grasps
    end = reach.chains["shade"].end_world(sim.character)
    assert not grasps.try_grasp("shade", [(end[0] + 0.05, end[1])], tolerance=0.03)
    assert grasps.try_grasp("shade", [(end[0] + 0.02, end[1])], tolerance=0.03)
    assert "shade" in sim.grasps and grasps.held["shade"] == pytest.approx(
        (end[0] + 0.02, end[1]))
    grasps.release("all")
    assert grasps.held == {} and not sim.grasps


def test_grasp_state_round_trip_adopt_and_stop():
    reach, sim, _, _, spec = reach_setup()
    grasps = reach.grasps
    grasps.arm(key_action(spec, "g").grasp, 10)
    state = plain(grasps.get_state())
    state_copy = plain(state)
    again = reach_setup()[0].grasps
    again.set_state(state)
    state["armed"]["shade"][0][0][0] = 0.0  # set_state copied: the caller's list is not shared
    assert again.get_state() == state_copy
    assert state_copy["released"] == {}  # where each chain let go: nothing yet
    assert [again.next_wakeup(s) for s in (10, 40)] == [10, 40]
    again.tick(57)  # until = 10 + 48
    assert again.armed
    again.tick(58)
    assert not again.armed

    end = reach.chains["shade"].end_world(sim.character)
    grasps.try_grasp("shade", [end])
    new = GraspController(reach.chains, sim.character, sim, DT)
    assert new.adopt(grasps, lambda kind, name: True, 0) == set()  # owns no joints
    assert new.armed == grasps.armed and "shade" in sim.grasps  # still held
    changed = GraspController(reach.chains, sim.character, sim, DT)
    changed.adopt(grasps, lambda kind, name: False, 0)  # the chain changed: let go
    assert changed.armed == {} and not sim.grasps
    grasps.arm(key_action(spec, "g").grasp, 0)
    grasps.stop()
    assert grasps.armed == {} and grasps.next_wakeup(0) is None


# -- random motion -----------------------------------------------------------------------
def perturber(spec=None):
    spec = spec or spec_of()
    sim = Simulation(LUXO, load_scene_named("flat")[0])
    p = Perturber(spec.perturbation, sim.character, DT)
    p.sim = sim  # keep the space alive: a body's moment is gone with its space
    return p, sim.character


def spins(character) -> list[float]:
    return [character.bodies[n].angular_velocity for n in character.link_order]


def kicks(p, character, step: int, n: int) -> list:
    """The next ``n`` kicks: [(step, each link's spin from that kick alone)]."""
    out = []
    for _ in range(n):
        wake = p.next_wakeup(step)
        for body in character.bodies.values():
            body.angular_velocity = 0.0
        p.tick(wake)
        out.append((wake, spins(character)))
        step = wake + 1
    return out


def test_perturber_kicks_every_period_once_switched_on():
    p, character = perturber()
    assert p.next_wakeup(0) is None
    p.switch("on", 100)
    seen = kicks(p, character, 100, 3)
    assert [s for s, _ in seen] == [100, 105, 110]  # every 0.01 s = 5 steps (rounded)
    assert all(v != 0.0 for v in seen[0][1])
    p.switch("toggle", 111)
    assert p.next_wakeup(111) is None and p.owners() == set()


def test_perturber_state_round_trip_through_json_gives_the_same_kicks():
    p, character = perturber()
    p.switch("on", 0)
    kicks(p, character, 0, 4)
    state = plain(p.get_state())
    future = kicks(p, character, 16, 5)
    again, character2 = perturber()
    again.set_state(state)
    assert kicks(again, character2, 16, 5) == future  # the same steps, the same impulses
    assert len({tuple(v) for _, v in future}) == 5


def test_perturber_adopt_and_stop():
    old, _ = perturber()
    old.switch("on", 0)
    old.tick(0)
    same, _ = perturber()
    same.adopt(old, lambda kind, name: True, 3)
    assert same.get_state() == old.get_state()  # the same generator, mid-stream
    changed, _ = perturber(spec_of(BODY.replace("seed: 3", "seed: 4")))
    changed.adopt(old, lambda kind, name: False, 3)
    assert changed.on and changed.next_wakeup(3) == 3  # on, with its own seed from now
    old.stop()
    assert not old.on and old.next_wakeup(0) is None and old.get_state()[2] is None


# -- state machines ---------------------------------------------------------------------
MACHINE = """
poses:
  stand: {joints: {ankle: -25, knee: 55}}
states:
  a:
    transitions:
      - {to: b, after: 0.5}
  b:
    transitions:
      - {to: a, after: 0.1, when: {sensor: joint.knee, above: 500}}
any_state:
  transitions:
    - {to: a, after: 1.0}
"""


def machine(spec=None):
    spec = spec or spec_of(MACHINE)
    m = spec.state_machines()["main"]
    return StateMachine("main", m, spec, Character(LUXO), DT)


def test_state_machine_timer_and_polled_sensor_and_any_state():
    m = machine()
    m.enter("a", 0)
    assert m.next_wakeup(0) == 240  # its own timer (0.5 s) before any_state's (1 s)
    assert m.due(239) is None and m.due(240) == ("main", "b")
    m.enter("b", 240)
    # b: the sensor test is polled from 0.1 s in, on multiples of 8 steps (60 Hz);
    # any_state's timer leads back to a after 1 s in b
    assert m.every == 8 and m.next_wakeup(241) == 288
    assert m.due(288) is None  # the knee is not above 500 deg
    assert m.due(240 + 480) == ("main", "a")
    m.enter("a", 720)
    assert all(to != ("main", "a") for to, *_ in m.transitions["a"])  # never to itself


def test_state_machine_state_round_trip_and_stop():
    m = machine()
    m.enter("b", 100)
    state = plain(m.get_state())
    again = machine()
    again.set_state(state)
    assert [again.next_wakeup(s) for s in (100, 200, 500)] == \
        [m.next_wakeup(s) for s in (100, 200, 500)]
    assert again.due(580) == m.due(580) == ("main", "a")
    m.stop()
    assert (m.current, m.entered) == ("a", 0)
