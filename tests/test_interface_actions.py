"""The interface vocabulary acts through Session.handle/advance, as the window uses it:
poses, sequences and their preemption, maps (curves, couplings, grids, gamepad,
channels), state machines, meta actions, IK reach and grasp."""

import math
import pickle
import textwrap

import pymunk
import pytest

from puppet.data.catalog import load_setup
from puppet.interface import events as ev
from puppet.interface.app_keys import SetSlowdown
from puppet.session import Session

HEADER = "name: t\ndescription: test interface\ncharacter: luxo\n"
POSES = """
poses:
  crouch: {joints: {ankle: -70, knee: 130}, stiffness: {knee: 30}}
  tall: {joints: {ankle: 0, knee: 0}}
  lean: {joints: {ankle: -40}}
sequences:
  hop: [{pose: crouch, hold: 0.1}, {pose: tall, hold: 0.05}, {pose: lean, hold: 0.1}]
  sit: [{pose: crouch, hold: 0.2}]
"""


def make(tmp_path, *parts: str) -> Session:
    path = tmp_path / "iface.yaml"
    path.write_text(HEADER + "".join(textwrap.dedent(p) for p in parts))
    return Session(load_setup(str(path)))


def targets(session) -> dict[str, float]:
    return {n: round(math.degrees(s.target), 6) for n, s in session.character.servos.items()}


def press(session, key):
    out = session.handle(ev.key(key, True))
    session.handle(ev.key(key, False))
    return out


# -- poses ------------------------------------------------------------------------
def test_pose_key_sets_targets_and_gains_and_adjust_is_relative(tmp_path):
    s = make(tmp_path, POSES, """
    keys:
      - {key: a, pose: crouch}
      - {key: s, adjust: {knee: -10}}
      - {key: d, set: {ankle: 5}}
    """)
    press(s, "a")
    assert targets(s) == {"ankle": -70, "knee": 130}
    assert s.character.servos["knee"].stiffness == 30
    press(s, "s")
    press(s, "s")
    assert targets(s)["knee"] == pytest.approx(110)
    press(s, "d")
    assert targets(s) == {"ankle": 5, "knee": pytest.approx(110)}


# -- sequences ----------------------------------------------------------------------
def test_sequence_plays_its_poses_for_their_durations_then_goes_idle(tmp_path):
    s = make(tmp_path, POSES, "keys:\n  - {key: h, sequence: hop}\n")
    assert s.runtime.next_wakeup is None
    press(s, "h")
    assert targets(s) == {"ankle": -70, "knee": 130}
    # 0.1 s = 48 steps; the next pose is written by the tick at step 48, which runs
    # before stepping from 48 (after any events at that step).
    s.advance(48)
    assert targets(s)["knee"] == 130
    s.advance(1)
    assert targets(s) == {"ankle": 0, "knee": 0}
    s.advance(24)
    assert targets(s) == {"ankle": -40, "knee": 0}
    s.advance(48)
    assert s.runtime.sequence is None and s.runtime.next_wakeup is None
    assert targets(s) == {"ankle": -40, "knee": 0}  # the last pose holds


def test_new_sequence_replaces_the_running_one(tmp_path):
    s = make(tmp_path, POSES, "keys:\n  - {key: h, sequence: hop}\n  - {key: j, sequence: sit}\n")
    press(s, "h")
    s.advance(10)
    press(s, "j")
    s.advance(200)  # hop's later poses never come
    assert targets(s) == {"ankle": -70, "knee": 130}


def test_set_key_cancels_the_sequence_only_on_the_joints_it_touches(tmp_path):
    s = make(tmp_path, POSES, "keys:\n  - {key: h, sequence: hop}\n  - {key: k, set: {knee: 20}}\n")
    press(s, "h")
    s.advance(10)
    press(s, "k")
    s.advance(39)
    assert targets(s) == {"ankle": 0, "knee": 20}  # ankle still follows the sequence
    s.advance(24)
    assert targets(s) == {"ankle": -40, "knee": 20}


def test_moving_the_mouse_takes_the_mapped_joint_from_a_sequence(tmp_path):
    s = make(tmp_path, POSES, """
    keys:
      - {key: h, sequence: hop}
    maps:
      - {input: mouse.y, joint: knee, to: [0, 100]}
    """)
    press(s, "h")
    s.handle(ev.mouse(0.5, 0.5))
    s.advance(49)
    assert targets(s) == {"ankle": 0, "knee": 50}


# -- maps -----------------------------------------------------------------------------
def test_response_curves_and_couplings(tmp_path):
    s = make(tmp_path, """
    maps:
      - {input: mouse.x, joint: ankle, to: [0, 80], curve: {power: 2}}
      - {input: mouse.y, joints: {knee: -1.0}, to: [0, 40], curve: smoothstep}
    """)
    s.handle(ev.mouse(0.5, 0.25))
    t = targets(s)
    assert t["ankle"] == pytest.approx(20)  # 0.5^2 * 80
    assert t["knee"] == pytest.approx(-40 * (3 * 0.25 ** 2 - 2 * 0.25 ** 3))


def test_pose_grid_blends_the_four_nearest_poses(tmp_path):
    s = make(tmp_path, """
    poses:
      a: {joints: {ankle: 0, knee: 0}}
      b: {joints: {ankle: 40, knee: 0}}
      c: {joints: {ankle: 80, knee: 0}}
      d: {joints: {ankle: 0, knee: 100}}
      e: {joints: {ankle: 40, knee: 100}}
      f: {joints: {ankle: 80, knee: 100}}
    maps:
      - grid: [[a, b, c], [d, e, f]]
    """)
    s.handle(ev.mouse(0.0, 1.0))
    assert targets(s) == {"ankle": 0, "knee": 0}
    s.handle(ev.mouse(1.0, 0.0))
    assert targets(s) == {"ankle": 80, "knee": 100}
    s.handle(ev.mouse(0.75, 0.5))
    assert targets(s) == {"ankle": pytest.approx(60), "knee": pytest.approx(50)}


def test_gamepad_channels_and_buttons_drive_maps_and_keys(tmp_path):
    s = make(tmp_path, """
    maps:
      - {input: gamepad.axis1, joint: knee, from: [-1, 1], to: [0, 100]}
      - {input: channel.lean, joint: ankle, to: [0, 10]}
    keys:
      - {key: gamepad.button0, set: {ankle: -30}}
      - {key: mouse.right, set: {ankle: 33}}
    """)
    s.handle(ev.gamepad("axis1", 0.5))
    s.handle(ev.channel("lean", 0.5))
    assert targets(s) == {"ankle": 5, "knee": 75}
    s.handle(ev.gamepad("button0", 1.0))
    assert targets(s)["ankle"] == -30
    s.handle(ev.mouse_button("right", True))
    assert targets(s)["ankle"] == 33


def test_select_control_mode_switches_which_maps_the_mouse_drives(tmp_path):
    s = make(tmp_path, """
    modes:
      direct: [{input: mouse.x, joint: ankle, to: [0, 50]}]
      folded: [{input: mouse.x, joint: knee, to: [0, 100]}]
    keys:
      - {key: m, mode: folded}
    """)
    s.handle(ev.mouse(1.0, 0.5))
    assert targets(s) == {"ankle": 50, "knee": 55}
    press(s, "m")
    assert targets(s) == {"ankle": 50, "knee": 100}  # applied at once
    s.handle(ev.mouse(0.2, 0.5))
    assert targets(s) == {"ankle": 50, "knee": 20}


def test_entering_a_mode_or_state_runs_only_the_maps_that_became_active(tmp_path):
    """A sequence owns the ankle; the always-active mouse map on the ankle does not
    take it back when a mode or state whose own maps read the same input is entered."""
    s = make(tmp_path, POSES, """
    maps:
      - {input: mouse.y, joint: ankle, to: [0, 50]}
    modes:
      still: []
      folded: [{input: mouse.y, joint: knee, to: [0, 100]}]
    initial: idle
    states:
      idle: {}
      bent:
        maps: [{input: mouse.y, joint: knee, to: [0, 80]}]
    keys:
      - {key: a, sequence: sit}
      - {key: m, mode: folded}
      - {key: y, goto: bent}
    """)
    s.handle(ev.mouse(0.5, 1.0))
    press(s, "a")
    assert targets(s) == {"ankle": -70, "knee": 130}  # the sequence's crouch
    press(s, "m")
    assert targets(s) == {"ankle": -70, "knee": 100}  # the mode's map took the knee only
    press(s, "y")
    assert targets(s) == {"ankle": -70, "knee": 80}  # the state's map, the knee only
    s.handle(ev.mouse(0.5, 0.2))  # the mouse moves: every map reading it acts
    assert targets(s) == {"ankle": 10, "knee": 16}


# -- state machines ----------------------------------------------------------------------
STATES = POSES + """
initial: standing
states:
  standing:
    enter: {pose: tall}
    keys:
      - {key: space, goto: crouched}
  crouched:
    enter: {pose: crouch}
    keys:
      - {key: space, goto: standing}
    transitions:
      - {to: leaning, after: 0.5}
  leaning:
    enter: {pose: lean}
    maps:
      - {input: mouse.y, joint: knee, to: [0, 10]}
    transitions:
      - {to: standing, when: {sensor: joint.knee, below: 20}}
"""


def test_every_sensor_puppet_check_accepts_has_a_reader():
    from puppet.data import interface_refs as refs
    from puppet.interface import conditions

    assert set(conditions.FIXED) == set(refs.FIXED_SENSORS)
    assert set(conditions.NAMED) == set(refs.JOINT_SENSORS) | set(refs.LINK_SENSORS)


def test_same_key_does_different_things_in_different_states(tmp_path):
    s = make(tmp_path, STATES)
    assert s.runtime.state == "standing" and targets(s) == {"ankle": 0, "knee": 0}
    press(s, "space")
    assert s.runtime.state == "crouched" and targets(s)["knee"] == 130
    press(s, "space")
    assert s.runtime.state == "standing"


def test_timer_and_sensor_transitions(tmp_path):
    s = make(tmp_path, STATES)
    press(s, "space")
    s.advance(240)
    assert s.runtime.state == "crouched"
    s.advance(1)
    assert s.runtime.state == "leaning"
    s.handle(ev.mouse(0.5, 1.0))
    assert targets(s)["knee"] == 10  # the leaning state's own map
    for _ in range(200):
        s.advance(12)
        if s.runtime.state == "standing":
            break
    assert s.runtime.state == "standing"
    assert math.degrees(s.character.joint_angle("knee")) < 20


# -- meta actions ---------------------------------------------------------------------------
def test_meta_keys(tmp_path):
    s = make(tmp_path, """
    keys:
      - {key: g, gravity: [0, -3]}
      - {key: f, friction: 0.1}
      - {key: z, slowdown: 10}
      - {key: x, app: pause}
      - {key: k, app: checkpoint}
      - {key: h, stiffness: {knee: 99}, damping: {knee: 1.5}, while_held: true}
    """)
    press(s, "g")
    assert tuple(s.sim.space.gravity) == (0, -3)
    press(s, "f")
    assert all(seg.friction == 0.1 for seg in s.sim.ground)
    assert press(s, "z") == SetSlowdown(10)
    assert press(s, "x") == "pause"
    s.advance(10)
    assert press(s, "k") is None  # a sim action: the session took the checkpoint
    assert s.history.last_manual(s.steps).step == 10
    knee = s.character.servos["knee"]
    k0 = knee.stiffness
    s.handle(ev.key("h", True))
    assert (knee.stiffness, knee.damping) == (99, 1.5)
    s.handle(ev.key("h", False))
    assert knee.stiffness == k0


def test_random_perturbations_are_seeded_and_deterministic(tmp_path):
    body = ("perturbation: {impulse: 0.002, every: 0.05, seed: 3}\n"
            "keys:\n  - {key: t, perturb: toggle}\n")
    runs = []
    for perturb in (True, True, False):
        s = make(tmp_path, body)
        if perturb:
            press(s, "t")
        s.advance(480)
        runs.append(s.sim.state_hash())
    assert runs[0] == runs[1] != runs[2]


# -- IK reach and grasp --------------------------------------------------------------------------
def test_two_link_ik_reaches_a_reachable_point():
    from puppet.interface.ik import solve_two_link

    a1, a2 = (0.0, 0.2), (0.05, 0.2)
    for d in ((0.1, 0.3), (-0.2, 0.1), (0.3, -0.05)):
        q1, q2 = solve_two_link(a1, a2, d)

        def rot(v, a):
            c, s = math.cos(a), math.sin(a)
            return (v[0] * c - v[1] * s, v[0] * s + v[1] * c)
        e1, e2 = rot(a1, q1), rot(a2, q1 + q2)
        assert (e1[0] + e2[0], e1[1] + e2[1]) == pytest.approx(d, abs=1e-9)


REACH = """
gains:
  ankle: {stiffness: 60, damping: 0.6, max_torque: 40}
  knee: {stiffness: 40, damping: 0.4, max_torque: 30}
chains:
  shade: {joints: [ankle, knee], end: [0.0, 0.43]}
keys:
  - key: e
    reach: {chain: shade, target: [0.06, 0.30], duration: 0.4, hold: 0.4}
  - key: q
    reach: {chain: shade, target: [0.06, 0.30], frame: root, duration: 0.4, grasp: true,
            tolerance: 0.03}
  - {key: w, release: shade}
"""


def test_luxo_reaches_a_point_with_its_shade(tmp_path):
    s = make(tmp_path, REACH)
    s.advance(240)  # settle on the ground
    root = s.character.bodies["base"]
    target = root.local_to_world((0.06, 0.30))
    chain = s.runtime.chains["shade"]
    start = chain.end_world(s.character)
    press(s, "e")
    s.advance(96)  # halfway: the Hermite path is at its middle
    mid = chain.end_world(s.character)
    assert math.dist(mid, target) < math.dist(start, target)
    s.advance(384)
    assert math.dist(chain.end_world(s.character), target) < 0.01
    assert s.runtime.reaches == {} and s.runtime.next_wakeup is None


def test_grasp_pins_the_end_to_the_point_and_release_lets_go(tmp_path):
    s = make(tmp_path, REACH)
    s.advance(240)
    press(s, "q")
    s.advance(300)
    assert "shade" in s.runtime.grasped
    pins = [c for c in s.sim.space.constraints if isinstance(c, pymunk.PivotJoint)
            and c.b is s.sim.space.static_body]
    assert len(pins) == 1
    press(s, "w")
    assert not s.runtime.grasped
    assert not [c for c in s.sim.space.constraints if isinstance(c, pymunk.PivotJoint)
                and c.b is s.sim.space.static_body]


# -- runtime state and the idle path -------------------------------------------------------
def test_runtime_state_is_plain_data_and_restores_mid_sequence(tmp_path):
    s = make(tmp_path, STATES, "keys:\n  - {key: h, sequence: hop}\n")
    press(s, "space")
    press(s, "h")
    s.advance(30)
    snap = s.sim.checkpoint()
    state = pickle.loads(pickle.dumps(s.runtime.get_state()))
    s.advance(500)
    straight = (s.sim.state_hash(), s.runtime.state, targets(s))
    s.sim.restore(snap)
    s.runtime.set_state(state)
    s.advance(500)
    assert (s.sim.state_hash(), s.runtime.state, targets(s)) == straight


def test_idle_interfaces_never_tick(tmp_path, monkeypatch):
    s = Session(load_setup("luxo-mouse"))
    calls = []
    monkeypatch.setattr(s.runtime, "tick", lambda *a: calls.append(a))
    s.handle(ev.mouse(0.3, 0.6))
    s.advance(1000)
    assert calls == [] and s.runtime.next_wakeup is None


def test_perturbations_restore_from_a_checkpoint(tmp_path):
    s = make(tmp_path, "perturbation: {every: 0.02, seed: 5, start_on: true}\n")
    s.advance(100)
    snap, state = s.sim.checkpoint(), pickle.loads(pickle.dumps(s.runtime.get_state()))
    s.advance(300)
    straight = s.sim.state_hash()
    s.sim.restore(snap)
    s.runtime.set_state(state)
    s.advance(300)
    assert s.sim.state_hash() == straight


def test_gamepad_channel_and_button_events_replay_from_a_log(tmp_path):
    from puppet.session.playback import play
    from puppet.timeline.log import read_log, record_events

    body = """
    maps:
      - {input: gamepad.axis0, joint: ankle, from: [-1, 1], to: [-60, 60]}
      - {input: channel.fold, joint: knee, to: [0, 120]}
    keys:
      - {key: mouse.left, adjust: {knee: 20}}
    """
    events = [(10, ev.gamepad("axis0", -0.5)), (50, ev.channel("fold", 0.8)),
              (90, ev.mouse_button("left", True)), (95, ev.mouse_button("left", False))]
    first = make(tmp_path, body)
    path = record_events(first, events, 400, tmp_path / "pad.jsonl")
    again = make(tmp_path, body)
    play(again, read_log(path).pairs(), 400)
    assert again.sim.state_hash() == first.sim.state_hash()
    assert targets(again) == {"ankle": -30, "knee": pytest.approx(116)}


def test_pointer_for_pose_finds_where_the_mouse_maps_hold_the_start_pose(tmp_path):
    s = Session(load_setup("luxo-mouse"))
    before = targets(s)
    x, y = s.runtime.pointer_for_pose()
    assert targets(s) == before  # the search leaves the targets alone
    assert (x, y) == (pytest.approx(0.656, abs=0.002), pytest.approx(0.583, abs=0.002))
    s.handle(ev.mouse(x, y))
    assert targets(s) == {j: pytest.approx(a, abs=0.5) for j, a in before.items()}
    # no mouse maps, or none that reach the pose: nowhere to put the pointer
    assert make(tmp_path, POSES).runtime.pointer_for_pose() is None
    assert make(tmp_path, "maps: [{input: mouse.x, joint: ankle, to: [10, 80]}]\n"
                ).runtime.pointer_for_pose() is None


# -- designer feedback: two maps on one joint --------------------------------------------------
def test_two_maps_writing_one_joint_in_one_mode_warn_at_load_naming_both(tmp_path, capsys):
    from puppet.commands import main
    from puppet.commands.check import check_file

    path = tmp_path / "interfaces" / "two.yaml"
    path.parent.mkdir()
    path.write_text("name: two\ndescription: two maps\ncharacter: luxo\n"
                    "maps:\n"
                    "  - {input: mouse.x, joint: knee, to: [-30, 30]}\n"
                    "modes:\n"
                    "  lean:\n"
                    "    - {input: mouse.y, joint: ankle, to: [-30, 30]}\n"
                    "    - {input: mouse.y, joints: {knee: 1, ankle: -1}, to: [0, 20]}\n"
                    "  calm:\n"
                    "    - {input: mouse.y, joint: ankle, to: [-10, 10]}\n")
    warnings: list[str] = []
    assert check_file(path, warnings) == "interface"
    assert len(warnings) == 2, warnings  # knee (top level and lean) and ankle (within lean)
    knee = next(w for w in warnings if "'knee'" in w)
    assert knee.startswith(f"{path}:9:") and "line 5" in knee and "mode 'lean'" in knee
    ankle = next(w for w in warnings if "'ankle'" in w)
    assert ankle.startswith(f"{path}:9:") and "line 8" in ankle
    assert main(["check", str(path)]) == 0  # a warning, not an error
    assert "warning: this map and the one at line 5" in capsys.readouterr().err


def test_a_pose_key_stops_a_running_sequence_for_good(tmp_path):
    s = make(tmp_path, """
    poses:
      crouch: {joints: {ankle: -70, knee: 130}}
      tall: {joints: {ankle: 0, knee: 0}}
      wide: {joints: {ankle: -15, knee: 35}}
    sequences:
      hop: [{pose: crouch, hold: 0.1}, {pose: tall, hold: 0.05}, {pose: crouch, hold: 0.1}]
    keys:
      - {key: h, sequence: hop}
      - {key: w, pose: wide}
    """)
    press(s, "h")
    s.advance(30)
    assert s.runtime.sequence is not None
    press(s, "w")
    assert targets(s) == {"ankle": -15, "knee": 35}
    for _ in range(6):  # past every later step of the sequence
        s.advance(25)
        assert targets(s) == {"ankle": -15, "knee": 35}
    assert s.runtime.sequence is None
