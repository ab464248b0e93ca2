"""Behaviours the seeded mutation runs of issue 17 found no test looking at (the second
round; the first is tests/test_gaps.py), each tested as the feature reads: grid maps
driven by channels, by a channel and the mouse, and through roles; ..."""

from __future__ import annotations

import math
import textwrap
from pathlib import Path

import pytest

from puppet.data.catalog import load_setup
from puppet.interface import events as ev
from puppet.session import Session


def make(tmp_path, text: str) -> Session:
    path = tmp_path / "iface.yaml"
    path.write_text(textwrap.dedent(text))
    return Session(load_setup(str(path)))


def deg(s) -> dict[str, float]:
    return {n: round(math.degrees(sv.target), 6) for n, sv in s.character.servos.items()}


# -- grid maps over channels ---------------------------------------------------------------
CAT_GRID = """
name: t
description: grid maps on channels
character: cat
poses:
  low: {joints: {hip_near: 0, knee_near: -40}}
  high: {joints: {hip_near: 40, knee_near: -80}}
  back: {joints: {shoulder_near: -40}}
  front: {joints: {shoulder_near: 20}}
maps:
  - {grid: [[high], [low]], x: channel.gx, y: channel.gy}
  - {grid: [[back, front], [back, front]], x: mouse.x, y: channel.gy}
"""


def test_a_grid_map_on_two_channels_blends_its_poses_as_the_channels_say(tmp_path):
    s = make(tmp_path, CAT_GRID)
    for gy, hip, knee in ((0.25, 10, -50), (1.0, 40, -80), (0.5, 20, -60)):
        s.handle(ev.channels({"gx": 0.3, "gy": gy}))
        s.advance(1)
        assert (deg(s)["hip_near"], deg(s)["knee_near"]) == pytest.approx((hip, knee)), gy


def test_a_grid_map_on_the_mouse_and_a_channel_reads_both(tmp_path):
    s = make(tmp_path, CAT_GRID)
    s.handle(ev.channels({"gx": 0.0, "gy": 0.5}))
    for x, shoulder in ((0.75, 5), (0.0, -40), (0.5, -10)):
        s.handle(ev.mouse(x, 0.9))
        s.advance(1)
        assert deg(s)["shoulder_near"] == pytest.approx(shoulder), x


def test_a_grid_map_of_roles_drives_the_joints_of_the_binding_in_force(tmp_path):
    s = make(tmp_path, """
    name: t
    description: a grid map through roles
    character: cat
    roles:
      leg_hip: {a: hip_near, b: hip_far}
    poses:
      low: {joints: {leg_hip: 0}}
      high: {joints: {leg_hip: 40}}
    maps:
      - {grid: [[high], [low]], x: channel.gx, y: channel.gy, joints: [leg_hip]}
    binding: b
    """)
    near = deg(s)["hip_near"]
    s.handle(ev.channels({"gx": 0.5, "gy": 0.75}))
    s.advance(1)
    assert deg(s)["hip_far"] == pytest.approx(30)
    assert deg(s)["hip_near"] == near  # not the other binding's joint


# -- channels after a restore --------------------------------------------------------------
LUXO_CHANNEL = """
name: t
description: a channel on the knee
character: luxo
maps:
  - {input: channel.k, joint: knee, from: [0, 1], to: [0, 60]}
"""


def test_a_channel_moves_its_joint_after_a_restore_and_after_a_rewind(tmp_path):
    s = make(tmp_path, LUXO_CHANNEL)
    s.handle(ev.channels({"k": 0.5}))
    s.advance(100)
    s.handle(ev.action("checkpoint"))
    s.handle(ev.channels({"k": 0.25}))
    s.advance(100)
    assert deg(s)["knee"] == pytest.approx(15)
    s.handle(ev.action("restore"))
    assert s.steps == 100 and deg(s)["knee"] == pytest.approx(30)
    s.handle(ev.channels({"k": 1.0}))
    s.advance(1)
    assert deg(s)["knee"] == pytest.approx(60)
    s.handle(ev.action("rewind") | {"to_step": 50})
    s.handle(ev.channels({"k": 0.1}))
    s.advance(1)
    assert deg(s)["knee"] == pytest.approx(6)


# -- balance --------------------------------------------------------------------------------
def _standing(name="luxo-mouse"):
    s = Session(load_setup(name))
    s.advance(480)  # settled on its base
    return s


def test_standing_the_support_is_the_base_on_the_floor():
    from puppet.physics.balance import balance

    s = _standing()
    scene = s.setup.scene
    b = balance(s.character, scene.gravity, scene.ground_height)
    bottom = [sh.bb for sh in s.character.shapes["base"]]
    left, right = min(bb.left for bb in bottom), max(bb.right for bb in bottom)
    assert b.support[0] == pytest.approx(left, abs=0.01)  # from one end of the base
    assert b.support[1] == pytest.approx(right, abs=0.01)  # to the other
    assert b.ground_y == 0.0


def test_over_a_gap_the_lowest_contact_is_the_ground_and_in_the_air_the_lowest_point():
    from puppet.physics.balance import balance, ground_contacts

    s = _standing()
    lowest = min(p[1] for p in ground_contacts(s.character))
    b = balance(s.character, (0.0, -9.81), lambda x: None)  # no ground known under it
    assert b.ground_y == lowest and abs(lowest) < 0.01
    s.character.bodies["base"].velocity = (0.0, 3.0)  # thrown up: off the floor
    s.advance(60)
    assert not ground_contacts(s.character)
    b = balance(s.character, (0.0, -9.81), lambda x: None)
    lowest = min(shape.bb.bottom for shapes in s.character.shapes.values() for shape in shapes)
    assert b.ground_y == lowest and b.ground_y > 0.05


def test_weightless_the_extrapolated_com_still_leads_by_the_speed():
    from puppet.physics.balance import balance

    s = _standing()
    for body in s.character.bodies.values():
        body.velocity = (0.5, 0.0)
    b = balance(s.character, (0.0, 0.0), lambda x: 0.0)  # no gravity: earth's is taken
    height = b.com[1]
    assert b.xcom == pytest.approx(b.com[0] + 0.5 * math.sqrt(height / 9.81), rel=1e-9)


# -- props, the start, snapshots ----------------------------------------------------------
PENDULUM = """
name: t
description: the pendulum scene, mouse on the knee
character: luxo
scene: pendulum
maps:
  - {input: mouse.y, joint: knee, from: [0, 1], to: [0, 90]}
"""


def test_a_hanging_bar_still_hangs_from_its_pivot_after_two_restores(tmp_path):
    straight = make(tmp_path, PENDULUM)  # the same checkpoints, no detours
    for at in (300, 700):
        straight.advance(at - straight.steps)
        straight.handle(ev.action("checkpoint"))
    straight.advance(1400 - straight.steps)
    want = straight.sim.state_hash()
    s = make(tmp_path, PENDULUM)
    for back_at in (300, 700):  # a checkpoint, a detour, back; twice
        s.advance(back_at - s.steps)
        s.handle(ev.action("checkpoint"))
        s.advance(150)
        s.handle(ev.action("restore"))
        assert s.steps == back_at
        assert s.sim.props["swing"].pin is not None
    s.advance(1400 - s.steps)
    assert s.sim.state_hash() == want
    bar = s.sim.props["swing"].body
    top = bar.local_to_world((0.0, 0.0))
    assert math.dist(top, (0.06, 0.88)) < 1e-3  # hanging where the scene pins it


def test_a_character_that_starts_over_a_gap_starts_at_the_scenes_start_height(tmp_path):
    scene = tmp_path / "gap.yaml"
    scene.write_text(textwrap.dedent("""\
        name: gap
        description: Luxo starts over a gap, 0.5 m up
        ground:
          - points: [[-10.0, 0.0], [-1.0, 0.0]]
          - points: [[1.0, 0.0], [10.0, 0.0]]
        start: {x: 0.0, y: 0.5}
        """))
    s = Session(load_setup("luxo-mouse", str(scene)))
    assert s.setup.scene.ground_height(0.0) is None
    assert s.character.lowest_point() == pytest.approx(0.502, abs=1e-6)


def test_a_snapshot_keeps_a_kinematic_body_and_a_one_argument_constraint():
    import pymunk

    from puppet.physics import snapshot

    def build():
        space = pymunk.Space()
        space.gravity = (0, -9.81)
        wheel = pymunk.Body(1.0, 0.5)
        belt = pymunk.Body(body_type=pymunk.Body.KINEMATIC)
        belt.angular_velocity = 2.0
        space.add(wheel, belt, pymunk.Circle(wheel, 0.1), pymunk.SimpleMotor(belt, wheel, 3.0))
        return space

    live = build()
    for _ in range(10):
        live.step(0.01)
    copy, _ = snapshot.rebuild(snapshot.capture(live, {}))
    kinds = sorted(b.body_type for b in copy.bodies)
    assert kinds == sorted(b.body_type for b in live.bodies) == [pymunk.Body.DYNAMIC,
                                                                 pymunk.Body.KINEMATIC]
    motor = next(c for c in copy.constraints if isinstance(c, pymunk.SimpleMotor))
    assert motor.rate == 3.0
    for _ in range(50):
        live.step(0.01)
        copy.step(0.01)
    assert [(b.angle, b.angular_velocity) for b in copy.bodies] == \
        [(b.angle, b.angular_velocity) for b in live.bodies]


# -- a scripted drag that glides -----------------------------------------------------------
def test_a_scripted_drag_glides_to_its_target_at_the_mouse_rate():
    from puppet.data.yamlfile import load_text
    from puppet.timeline.script import compile_script, parse_script

    spec = parse_script(load_text(textwrap.dedent("""\
        events:
          - {t: 0.5, drag: {link: base, start: [0.0, 0.2], to: [0.3, 0.5], over: 0.5, hold: 0.1}}
        """), "glide.yaml"))
    dt = 1 / 480
    events = compile_script(spec, dt)
    moves = [(step, e["target"]) for step, e in events if e.get("phase") == "move"]
    assert len(moves) == 120  # 0.5 s at 240 Hz
    assert moves[-1] == (480, pytest.approx([0.3, 0.5]))
    assert moves[59][1] == pytest.approx([0.15, 0.35])  # half way, half the way
    steps = [step for step, _ in moves]
    assert steps == sorted(steps) and steps[0] == 242
    assert events[0][0] == 240 and events[0][1]["phase"] == "start"
    assert events[-1] == (528, {"type": "drag", "phase": "end"})


# -- never_fell reports the largest tilt on the ground -----------------------------------
class _Flip:
    """A trajectory as evaluate() reads it: upright on the ground, upside down in the air."""

    def __init__(self):
        import numpy as np

        degrees = [0, 0, 0, 90, 180, 270, 360, 360, 360]
        self.contact = np.array([[c] for c in (1, 1, 1, 0, 0, 0, 0, 1, 1)], dtype=bool)
        self.t = np.arange(len(degrees)) * 0.1
        self.root_angle = np.radians(degrees)


def test_a_flip_is_no_fall_and_the_tilt_reported_is_the_one_on_the_ground():
    from puppet.timeline.expectations import evaluate, parse_expectations

    e, = parse_expectations([{"never_fell": True}]).items
    outcome = evaluate(e, _Flip(), "")
    assert outcome.passed, str(outcome)
    assert outcome.measured == "largest tilt on the ground 0 deg at t = 0.00 s"


# -- a ghost, headless ----------------------------------------------------------------------
def test_a_ghost_plays_its_log_in_step_with_the_live_time_and_back():
    from pathlib import Path

    from puppet.timeline.ghost import Ghost
    from puppet.timeline.replay import replay

    hop = Path(__file__).resolve().parents[1] / "assets" / "logs" / "luxo-hop.jsonl"
    live = Session(load_setup("luxo-mouse"))  # standing still beside the ghost
    live.advance(600)
    ghost = Ghost(hop)
    ghost.sync(live)
    assert ghost.session.steps == 600
    assert ghost.session.sim.state_hash() == replay(hop, until_step=600).final_hash
    live.rewind_to(300)
    ghost.sync(live)
    assert ghost.session.steps == 300
    assert ghost.session.sim.state_hash() == replay(hop, until_step=300).final_hash


# -- expectations: a window's ends, a sidecar's other name -----------------------------
class _States:
    """A trajectory as _stayed reads it: a state per sample, every 0.1 s."""

    def __init__(self, states):
        import numpy as np

        self.t = np.arange(len(states)) * 0.1
        self.state = np.array(states, dtype=object)
        self.state_names = dict.fromkeys(states)


def test_stayed_in_state_counts_the_samples_at_both_ends_of_its_time_span():
    from puppet.timeline.expectations import evaluate, parse_expectations

    traj = _States(["sit", "sit", "up", "up", "up", "sit"])  # up from 0.2 s to 0.4 s
    for window, passed in (({"from": 0.2, "until": 0.4}, True),
                           ({"from": 0.2, "until": 0.5}, False),  # sits again at 0.5 s
                           ({"from": 0.1, "until": 0.4}, False)):  # still sat at 0.1 s
        e, = parse_expectations([{"stayed_in_state": {"state": "up", **window}}]).items
        outcome = evaluate(e, traj, "")
        assert outcome.passed is passed, (window, str(outcome))
    e, = parse_expectations([{"stayed_in_state": {"state": "up", "from": 0.2,
                                                  "until": 0.5}}]).items
    assert evaluate(e, traj, "").measured == "left 'up' for 'sit' at t = 0.50 s"


def test_a_sidecar_named_after_the_whole_log_file_name_is_read(tmp_path):
    import shutil
    from pathlib import Path

    from puppet.timeline.replay import replay

    hop = Path(__file__).resolve().parents[1] / "assets" / "logs" / "luxo-hop.jsonl"
    log = tmp_path / "hop.jsonl"
    shutil.copy(hop, log)
    (tmp_path / "hop.jsonl.expect.yaml").write_text(
        "expect:\n  - x_at_end: {link: base, min: 100.0}\n")
    result = replay(log, until_step=240)
    assert [o.expectation for o in result.failed] == ["x_at_end base min 100.0"], \
        [str(o) for o in result.outcomes]


# -- what a replay samples -----------------------------------------------------------------
HOP_LOG = Path(__file__).resolve().parents[1] / "assets" / "logs" / "luxo-hop.jsonl"


def _hop_at(step: int) -> Session:
    from puppet.timeline.log import read_log
    from puppet.timeline.replay import LogFeeder, new_session, setup_for_log

    log = read_log(HOP_LOG)
    s = new_session(log, setup_for_log(log, False)[0])
    feeder = LogFeeder(s, log)
    feeder.advance(step)
    return s


def test_a_replays_joint_angles_are_the_angles_reached_not_the_targets():
    from puppet.timeline.replay import replay

    traj = replay(HOP_LOG, until_step=600).trajectory
    s = _hop_at(600)
    knee = list(s.character.servos).index("knee")
    assert traj.joint_angle[-1, knee] == s.character.servos["knee"].angle
    assert abs(traj.joint_angle[:, knee] - traj.joint_target[:, knee]).max() > 0.01


def test_motion_sampled_at_less_than_one_frame_a_second():
    from puppet.timeline.motion import sample_motion

    motion = sample_motion(HOP_LOG, 0.5)  # a frame every 2 s of the 4.5 s hop
    assert motion.t.tolist() == [0.0, 2.0, 4.0]
    with pytest.raises(ValueError, match="fps must be positive"):
        sample_motion(HOP_LOG, 0.0)
