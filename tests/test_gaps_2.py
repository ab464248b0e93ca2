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


# -- what each expectation reports --------------------------------------------------------
class _Run:
    """A trajectory of two links (base, head) every 0.1 s, as evaluate() reads it."""

    links = ["base", "head"]

    def __init__(self, degrees, base_contact, head_contact, x=None, y=None):
        import numpy as np

        n = len(degrees)
        self.t = np.arange(n) * 0.1
        self.root_angle = np.radians(np.asarray(degrees, dtype=float))
        self.contact = np.array(list(zip(base_contact, head_contact)), dtype=bool)
        self.x = np.array(x if x is not None else [[0.1 * i, 0.1 * i] for i in range(n)],
                          dtype=float)
        self.y = np.array(y if y is not None else [[0.0, 0.3]] * n, dtype=float)
        self.com = np.stack([self.x[:, 0], self.y[:, 0]], axis=1)

    def index(self, link):
        return self.links.index(link)


def _outcome(item, traj):
    from puppet.timeline.expectations import evaluate, parse_expectations

    e, = parse_expectations([item]).items
    return evaluate(e, traj, "")


HEADSTAND = _Run([0, 90, 180, 180, 180, 90, 0], [1, 0, 0, 0, 0, 0, 1], [0, 0, 1, 1, 1, 0, 0])


def test_stood_on_reports_the_longest_stretch_upside_down_on_that_link_alone():
    got = _outcome({"stood_on": {"link": "head", "min_seconds": 0.3}}, HEADSTAND)
    assert got.passed and got.measured == ("longest stretch on head alone, upside down: "
                                           "0.300 s (t = 0.20 to 0.40 s)")
    never = _outcome({"stood_on": {"link": "base", "min_seconds": 0.1}}, HEADSTAND)
    assert not never.passed
    assert never.measured == "longest stretch on base alone, upside down: 0.000 s"


def test_landed_at_reports_where_the_longest_flight_touched_down():
    hop = _Run([0] * 7, [1, 0, 0, 1, 0, 0, 0], [0] * 7)  # the last flight is the longest
    got = _outcome({"landed_at": {"link": "head", "min": 0.5}}, hop)
    assert got.passed and got.measured == ("longest flight 0.30 s from t = 0.40 s, touched "
                                           "down at x = 0.600 m (t = 0.60 s)")
    ground = _Run([0] * 3, [1, 1, 1], [0, 0, 0])
    assert _outcome({"landed_at": {"link": "base", "min": 0.0}}, ground).measured == \
        "never in the air"


def test_x_and_height_at_end_report_what_they_measured():
    run = _Run([0] * 5, [1] * 5, [0] * 5, y=[[0.0, 0.3], [0.0, 0.5], [0.0, 0.4],
                                             [0.0, 0.35], [0.0, 0.31]])
    assert _outcome({"x_at_end": {"link": "head", "min": 0.3}}, run).measured == \
        "x = 0.400 m at t = 0.40 s"
    assert _outcome({"height_at_end": {"link": "head", "min": 0.3}}, run).measured == \
        "y = 0.310 m at t = 0.40 s"
    held = _outcome({"height_at_end": {"link": "head", "max": 0.45, "held": 0.2}}, run)
    assert held.passed and held.measured == "y = 0.310..0.400 m over the last 0.2 s"


def test_got_up_without_ever_lying_says_so():
    got = _outcome({"got_up": {"lay_seconds": 0.1, "within_seconds": 1.0}},
                   _Run([0, 10, 0], [1, 1, 1], [0, 0, 0]))
    assert not got.passed and got.measured == "never lay (root >= 80 deg on the ground)"


def test_an_expectation_given_in_code_names_its_unknown_link():
    from puppet.data.errors import DataError
    from puppet.timeline.expectations import parse_expectations

    with pytest.raises(DataError) as info:
        parse_expectations([{"x_at_end": {"link": "tail", "min": 0}}]).check_links(["base"])
    assert str(info.value) == "expect: unknown link 'tail'; the character has: base"


# -- any_state, buttons, props, blow-ups ------------------------------------------------
def test_an_any_state_transition_does_not_re_enter_the_state_it_leads_to(tmp_path):
    s = make(tmp_path, """
    name: t
    description: two machines with a state of the same name
    character: luxo
    keys:
      - {key: j, goto: watch.busy}
    initial: idle
    states:
      idle: {}
    machines:
      watch:
        initial: idle
        states:
          idle: {}
          busy: {}
        any_state:
          transitions:
            - {to: idle, after: 0.1}
    """)
    watch = s.runtime.machines["watch"]
    s.advance(480)
    assert (watch.current, watch.entered) == ("idle", 0)  # in idle: nothing to do
    s.handle(ev.key("j", True))
    assert watch.current == "busy"
    s.advance(60)  # 0.125 s: any_state takes it back to idle once
    assert watch.current == "idle" and 480 < watch.entered <= 540
    entered = watch.entered
    s.advance(240)
    assert watch.entered == entered


def test_a_gamepad_button_is_down_above_half_way(tmp_path):
    s = make(tmp_path, """
    name: t
    description: a gamepad button as a key
    character: luxo
    poses:
      fold: {joints: {knee: 100}}
      open: {joints: {knee: 10}}
    keys:
      - {key: gamepad.a, pose: fold}
      - {key: o, pose: open}
    """)
    start = deg(s)["knee"]
    steps = [("a", 0.5, start), ("a", 0.6, 100), ("o", None, 10), ("a", 0.55, 10),
             ("a", 0.5, 10), ("a", 0.51, 100)]  # a press each time it passes 0.5 upward
    for what, value, knee in steps:
        if value is None:
            s.handle(ev.key(what, True))
            s.handle(ev.key(what, False))
        else:
            s.handle(ev.gamepad(what, value))
        s.advance(1)
        assert deg(s)["knee"] == pytest.approx(knee), (what, value)


def test_a_dynamic_prop_of_several_shapes_weighs_its_mass(tmp_path):
    scene = tmp_path / "dumbbell.yaml"
    scene.write_text(textwrap.dedent("""\
        name: dumbbell
        description: a 0.4 kg dumbbell of two balls and a bar, ahead of Luxo
        ground:
          - points: [[-10.0, 0.0], [10.0, 0.0]]
        props:
          dumbbell:
            body: dynamic
            mass: 0.4
            position: [0.8, 0.3]
            shapes:
              - {circle: [-0.1, 0.0], radius: 0.04}
              - {circle: [0.1, 0.0], radius: 0.04}
              - {segment: [[-0.1, 0.0], [0.1, 0.0]], radius: 0.01}
        """))
    s = Session(load_setup("luxo-mouse", str(scene)))
    body = s.sim.props["dumbbell"].body
    assert body.mass == pytest.approx(0.4)
    assert body.center_of_gravity.x == pytest.approx(0.0, abs=1e-9)


@pytest.mark.parametrize("vy", [250.0, -250.0])
def test_a_runaway_vertical_speed_alone_is_a_blow_up(vy):
    s = Session(load_setup("luxo-mouse"))
    s.character.bodies["upper_arm"].velocity = (0.0, vy)
    assert s.sim.blown_up()


def test_two_add_maps_on_one_joint_add_up(tmp_path):
    s = make(tmp_path, """
    name: t
    description: two contributions to the knee
    character: luxo
    maps:
      - {input: channel.a, joint: knee, from: [0, 1], to: [0, 20], combine: add}
      - {input: channel.b, joint: knee, from: [0, 1], to: [0, 10], combine: add}
    """)
    base = deg(s)["knee"]
    s.handle(ev.channels({"a": 1.0, "b": 0.5}))
    s.advance(1)
    assert deg(s)["knee"] == pytest.approx(base + 25)


def test_an_any_state_key_works_in_every_state_and_gotos_that_loop_stop(tmp_path):
    s = make(tmp_path, """
    name: t
    description: an any_state key; two states that go to each other on entry
    character: luxo
    keys:
      - {key: l, goto: ping}
    initial: rest
    states:
      rest: {}
      ping: {enter: {goto: pong}}
      pong: {enter: {goto: ping}}
      other: {}
    any_state:
      keys:
        - {key: t, goto: rest}
        - {key: o, goto: other}
    """)
    main = s.runtime.machines["main"]
    for key, state in (("o", "other"), ("t", "rest"), ("o", "other"), ("o", "other")):
        s.handle(ev.key(key, True))
        s.handle(ev.key(key, False))
        assert main.current == state, key
    s.handle(ev.key("l", True))  # ping -> pong -> ping ...: stopped after a few, no hang
    s.handle(ev.key("l", False))
    assert main.current in ("ping", "pong")
    s.advance(10)


def test_a_links_position_is_its_centre_of_mass_in_the_world():
    s = _standing()
    body = s.character.bodies["upper_arm"]
    x, y = body.local_to_world(body.center_of_gravity)
    assert s.character.link_position("upper_arm") == (x, y) and abs(x - y) > 0.01


def test_more_of_what_expectations_report():
    still_lying = _Run([0, 90, 90, 90, 90], [1, 1, 1, 1, 1], [0, 0, 0, 0, 0])
    got = _outcome({"got_up": {"lay_seconds": 0.1, "within_seconds": 1.0}}, still_lying)
    assert not got.passed and got.measured == ("lay 0.40 s until t = 0.40 s, not standing "
                                               "at the end (90 deg)")
    assert got.expectation.startswith("got_up")  # the failing line names what was expected
    hop = _Run([0] * 7, [1, 0, 0, 1, 0, 0, 0], [0] * 7)  # flights of 0.2 s and 0.3 s
    for most, passed in ((0.3, True), (0.29, False)):
        got = _outcome({"airborne": {"link": "base", "max_seconds": most}}, hop)
        assert got.passed is passed, (most, str(got))
    assert got.measured == "longest time out of contact 0.300 s (from t = 0.40 s)"
    both = _Run([180] * 4, [1, 1, 0, 0], [1, 1, 1, 1])  # upside down; base down at first
    got = _outcome({"stood_on": {"link": "head", "min_seconds": 0.1}}, both)
    assert got.measured == ("longest stretch on head alone, upside down: 0.200 s "
                            "(t = 0.20 to 0.30 s)")


@pytest.mark.parametrize("interface", ["luxo-mouse", "cat-trot", "biped-walk"])
def test_a_limb_without_children_ends_at_its_farthest_point_in_the_hierarchy(interface):
    from puppet.timeline.motion import planar_hierarchy

    spec = load_setup(interface).character
    anchors = {j.child: tuple(j.anchor) for j in spec.joints}
    ends = {j.name: j.end for j in planar_hierarchy(spec) if j.end is not None}
    assert ends
    for name, end in ends.items():
        ax, ay = anchors.get(name, (0.0, 0.0))
        points = []
        for s in next(lk for lk in spec.links if lk.name == name).shapes:
            points += ([tuple(s.center)] if s.type == "circle" else
                       [tuple(s.a), tuple(s.b)] if s.type == "segment" else
                       [tuple(p) for p in s.points])
        reach = max(math.dist(p, (ax, ay)) for p in points)
        assert math.hypot(*end) == pytest.approx(reach), name
        assert any(math.dist(p, (ax + end[0], ay + end[1])) < 1e-9 for p in points), name


def test_tilt_never_above_reports_the_most_tilted_link_also_when_all_stand_upright():
    import numpy as np

    run = _Run([0, 0, 0], [1, 1, 1], [0, 0, 0])
    run.angle = np.zeros((3, 2))
    got = _outcome({"tilt_never_above": {"links": ["base", "head"], "max": 10}}, run)
    assert got.passed and got.measured == "base 0 deg from upright at t = 0.00 s (the most)"
    run.angle[1, 1] = math.radians(30)
    got = _outcome({"tilt_never_above": {"links": ["base", "head"], "max": 10}}, run)
    assert not got.passed and got.measured == "head 30 deg from upright at t = 0.10 s (the most)"


def test_the_nearest_place_on_a_grasp_segment_is_the_foot_of_the_perpendicular(tmp_path):
    s = make(tmp_path, PENDULUM)
    swing = s.sim.props["swing"]
    (a, b), = swing.segments
    pa, pb = swing.body.local_to_world(a), swing.body.local_to_world(b)  # the bar, slanted
    mid = ((pa[0] + pb[0]) / 2, (pa[1] + pb[1]) / 2)
    ux, uy = (pb[0] - pa[0]) / math.dist(pa, pb), (pb[1] - pa[1]) / math.dist(pa, pb)
    beside = (mid[0] - 0.02 * uy, mid[1] + 0.02 * ux)  # 2 cm off the bar's middle
    distance, point, name = swing.nearest(beside)
    assert distance == pytest.approx(0.02) and point == pytest.approx(mid) and name is None


def test_a_motion_export_cut_short_makes_no_claim_about_the_end(tmp_path, capsys):
    import argparse

    from puppet.timeline.motion import export_motion_command

    out = tmp_path / "hop.csv"
    common = dict(logs=[str(HOP_LOG)], export_motion=str(out), fps=30.0,
                  allow_truncated=False, as_recorded=False)
    assert export_motion_command(argparse.Namespace(until_step=480, **common)) == 0
    said = capsys.readouterr().out
    assert said.startswith(f"wrote {out}: 31 frames at 30 fps") and "recorded" not in said
    assert export_motion_command(argparse.Namespace(until_step=None, **common)) == 0
    assert "(same end as recorded)" in capsys.readouterr().out


def test_a_joint_with_no_start_angle_starts_straight(tmp_path):
    from puppet.data.catalog import ROOT

    text = (ROOT / "characters" / "luxo.yaml").read_text(encoding="utf-8")
    assert "joints: {ankle: -25, knee: 55}" in text
    character = tmp_path / "luxo.yaml"
    character.write_text(text.replace("joints: {ankle: -25, knee: 55}", "joints: {ankle: -25}"))
    s = make(tmp_path, f"""
    name: t
    description: luxo with no start angle for the knee
    character: {character}
    """)
    knee = s.character.servos["knee"]
    assert knee.target == 0.0 and knee.angle == pytest.approx(0.0, abs=1e-9)
    assert math.degrees(s.character.servos["ankle"].target) == pytest.approx(-25)
