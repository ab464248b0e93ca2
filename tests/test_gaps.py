"""Behaviours that planted bugs slipped past (issue 17), each tested as the feature reads:
a rewind after a branch shows the branch, a grasp's tolerance, a clamped map's ends, the
servo torque's sign; and a second, independent test for behaviours one test guarded
(pose preemption of a sequence, the slowdown table's top, a negative mass, a drag across
a restore, which way the IK bends a two-joint limb)."""

from __future__ import annotations

import math
import random
import textwrap

import pytest

from puppet.app.clock import SLOWDOWNS, SimClock
from puppet.data.catalog import load_setup
from puppet.interface import events as ev
from puppet.interface.ik import forward, solve_two_link
from puppet.session import Session

HEADER = "name: t\ndescription: gaps\ncharacter: luxo\n"


def make(tmp_path, body: str) -> Session:
    path = tmp_path / "iface.yaml"
    path.write_text(HEADER + textwrap.dedent(body))
    return Session(load_setup(str(path)))


def press(s, key):
    s.handle(ev.key(key, True))
    s.handle(ev.key(key, False))


def deg(s) -> dict[str, float]:
    return {n: round(math.degrees(sv.target), 6) for n, sv in s.character.servos.items()}


# -- a rewind after a branch shows the branch ----------------------------------------------
def _wiggle(session, frames, seed, hashes):
    rng = random.Random(seed)
    for _ in range(frames):
        session.handle(ev.mouse(rng.random(), rng.random()))
        session.advance(8)
        hashes[session.steps] = session.sim.state_hash()


def test_a_rewind_after_a_branch_shows_the_branch_not_the_abandoned_input():
    s = Session(load_setup("luxo-mouse"))
    first: dict[int, str] = {}
    _wiggle(s, 250, 1, first)  # 2000 steps of the first take
    s.handle(ev.action("rewind") | {"to_step": 600})
    s.advance(4)  # new input lands between the abandoned events' steps
    live: dict[int, str] = {}
    _wiggle(s, 150, 2, live)  # the branch: steps 604..1804
    head = s.steps
    for step in (1404, 900, 1796):  # rewinds past the branch point, into the branch
        s.handle(ev.action("rewind") | {"to_step": step})
        assert s.steps == step
        assert s.sim.state_hash() == live[step]
    s.handle(ev.action("rewind") | {"to_step": 296})  # before the fork: the common past
    assert s.sim.state_hash() == first[296]
    s.handle(ev.action("rewind") | {"to_step": head})  # and forward again to the head
    assert s.sim.state_hash() == live[head]


# -- grasp tolerance ----------------------------------------------------------------------
GRASP = """
chains:
  shade: {{joints: [ankle, knee], end: [0.0, 0.43]}}
keys:
  - {{key: f, grasp: {{chain: shade, points: [[{fx}, {fy}]], tolerance: 0.03}}}}
  - {{key: n, grasp: {{chain: shade, points: [[{nx}, {ny}]], tolerance: 0.03}}}}
  - {{key: o, grasp: {{chain: shade, points: [[{ox}, {oy}]], tolerance: 0.03}}}}
  - {{key: u, release: all}}
"""


def test_a_grasp_catches_only_within_its_tolerance(tmp_path):
    probe = make(tmp_path, GRASP.format(fx=5, fy=5, nx=5, ny=5, ox=5, oy=5))
    probe.advance(240)  # standing still: the shade's end stays where it is
    x, y = probe.runtime.chains["shade"].end_world(probe.character)
    s = make(tmp_path, GRASP.format(fx=x + 5.0, fy=y + 5.0, nx=x + 0.02, ny=y,
                                    ox=x, oy=y + 0.045))
    s.advance(240)
    assert s.runtime.chains["shade"].end_world(s.character) == pytest.approx((x, y), abs=1e-6)
    press(s, "f")  # 5 m away (7 m, in fact), 3 cm tolerance
    s.advance(60)
    assert not s.sim.grasps and s.runtime.grasped == {}
    press(s, "o")  # 4.5 cm away: still outside 3 cm
    s.advance(60)
    assert not s.sim.grasps
    press(s, "n")  # 2 cm away: within 3 cm, caught at once and pinned there
    s.advance(1)
    assert "shade" in s.sim.grasps
    assert s.sim.grasp_point("shade") == pytest.approx((x + 0.02, y), abs=1e-9)


# -- clamped maps ---------------------------------------------------------------------------
def test_a_clamped_map_gives_its_end_values_outside_its_from_range(tmp_path):
    maps = """
    maps:
      - {{input: mouse.y, joint: knee, from: [0.4, 0.6], to: [10, 30]{extra}}}
    """
    clamped = make(tmp_path, maps.format(extra=""))
    free = make(tmp_path, maps.format(extra=", clamp: false"))
    for y, end, line in ((1.0, 30, 70), (0.0, 10, -30), (0.5, 20, 20), (0.6, 30, 30)):
        for s in (clamped, free):
            s.handle(ev.mouse(0.5, y))
        assert deg(clamped)["knee"] == pytest.approx(end), y
        assert deg(free)["knee"] == pytest.approx(line), y  # clamp: false extrapolates


# -- servo torque sign ---------------------------------------------------------------------
@pytest.mark.parametrize("offset", [0.6, -0.6])
def test_the_servo_torque_has_the_sign_of_the_push_toward_its_target(offset):
    s = Session(load_setup("luxo-mouse"))
    s.advance(240)
    servo = s.character.servos["knee"]
    servo.target = servo.angle + offset
    before = servo.velocity
    s.advance(1)
    torque = servo.torque(s.sim.dt)
    assert abs(torque) > 0.5
    assert math.copysign(1, torque) == math.copysign(1, offset)
    # and the joint speeds up that way
    assert math.copysign(1, servo.velocity - before) == math.copysign(1, offset)


# -- second tests ---------------------------------------------------------------------------
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
    assert deg(s) == {"ankle": -15, "knee": 35}
    for _ in range(6):  # past every later step of the sequence
        s.advance(25)
        assert deg(s) == {"ankle": -15, "knee": 35}
    assert s.runtime.sequence is None


def test_the_slower_key_climbs_the_table_to_100x_and_stops_there():
    clock = SimClock(1 / 480, 1.0)
    seen = [clock.slowdown]
    for _ in range(len(SLOWDOWNS) + 5):
        clock.slower()
        seen.append(clock.slowdown)
    assert seen[:len(SLOWDOWNS)] == list(SLOWDOWNS)
    assert seen[len(SLOWDOWNS):] == [100] * 6
    steps = sum(clock.steps_for(0.05) for _ in range(200))  # 10 wall s at 100x: 0.1 sim s
    assert steps == 48
    clock.faster()
    assert clock.slowdown == SLOWDOWNS[-2] < 100


@pytest.mark.parametrize("mass", ["-0.5", "0"])
def test_puppet_check_refuses_a_character_with_a_mass_not_above_zero(tmp_path, capsys, mass):
    from puppet.commands import main

    path = tmp_path / "c.yaml"
    path.write_text(textwrap.dedent(f"""\
        name: x
        description: y
        links:
          - name: base
            mass: 1
            shapes: [{{type: circle, radius: 0.1}}]
          - name: arm
            mass: {mass}
            shapes: [{{type: box, size: [0.1, 0.02], center: [0.1, 0]}}]
        joints:
          - {{name: j, parent: base, child: arm, anchor: [0, 0],
              pd: {{stiffness: 10, damping: 1, max_torque: 5}}}}
        start: {{angle: 0, joints: {{j: 0}}}}
        """))
    assert main(["check", str(path)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and f" {path}:8:11: bad value" in err[0], err
    assert "links.1.mass" in err[0] and "kg" in err[0]


def test_a_drag_held_at_a_checkpoint_is_back_after_restore_and_pulls_alike():
    def start():
        s = Session(load_setup("luxo-mouse"))
        s.advance(120)
        x = s.character.bodies["base"].position.x
        s.handle(ev.drag_start("upper_arm", (0.0, 0.43), (x + 0.6, 0.6)))
        s.advance(60)
        s.handle(ev.action("checkpoint"))
        return s, x

    straight, x0 = start()
    at = straight.steps
    straight.advance(360)
    want = straight.sim.state_hash()
    assert straight.character.bodies["base"].position.x > x0 + 0.1  # it pulls

    s, _ = start()
    s.handle(ev.drag_end())
    s.advance(200)
    assert s.sim.drag_spring is None
    s.handle(ev.action("restore"))
    assert s.steps == at and s.sim.drag_spring is not None
    s.advance(360)
    assert s.sim.state_hash() == want


def test_two_link_ik_keeps_the_bend_it_is_told_to_prefer():
    a1, a2 = (0.0, 0.2), (0.0, 0.2)
    for d in ((0.15, 0.25), (-0.1, 0.3), (0.25, 0.05)):
        for prefer in (1.0, -1.0, 0.3, -0.3):
            q = solve_two_link(a1, a2, d, prefer)
            assert math.copysign(1, q[1]) == math.copysign(1, prefer), (d, prefer, q)
            assert forward([a1, a2], q)[1] == pytest.approx(d, abs=1e-9)


def test_a_luxo_reach_keeps_the_knee_bent_the_way_it_stands(tmp_path):
    s = make(tmp_path, """
    chains:
      shade: {joints: [ankle, knee], end: [0.0, 0.43]}
    keys:
      - {key: e, reach: {chain: shade, target: [0.12, 0.30], duration: 0.3, hold: 0.3}}
    """)
    s.advance(240)
    knee = s.character.servos["knee"]
    assert knee.target > 0.2  # Luxo stands with the knee bent forward
    press(s, "e")
    for _ in range(12):
        s.advance(25)
        assert knee.target > 0.05, math.degrees(knee.target)


# -- found by the mutation run (docs/mutation.md) -------------------------------------------
def test_a_grasping_reach_uses_its_own_tolerance(tmp_path):
    """A reach with ``grasp: true`` catches its point once the end is within the reach's
    tolerance (here 20 cm: at once), not the grasp's default 4 cm."""
    reach = """
    chains:
      shade: {{joints: [ankle, knee], end: [0.0, 0.43]}}
    keys:
      - {{key: q, reach: {{chain: shade, target: [{x}, {y}], duration: 0.4, grasp: true,
                          tolerance: {tol}}}}}
    """
    probe = make(tmp_path, reach.format(x=0, y=0, tol=0.2))
    probe.advance(240)
    x, y = probe.runtime.chains["shade"].end_world(probe.character)
    for tol, caught in ((0.2, True), (0.05, False)):
        s = make(tmp_path, reach.format(x=x + 0.10, y=y, tol=tol))
        s.advance(240)
        press(s, "q")
        s.advance(2)  # the end has hardly moved: 10 cm from the point
        assert ("shade" in s.sim.grasps) is caught, tol


@pytest.mark.parametrize("frame", ["world", "lower_arm"])
def test_a_frame_map_holds_the_link_at_its_angle_in_that_frame(tmp_path, frame):
    s = make(tmp_path, f"""
    maps:
      - {{input: mouse.x, joint: knee, frame: {frame}, to: [0, 60]}}
    poses:
      lean: {{joints: {{ankle: -30}}}}
    keys:
      - {{key: l, pose: lean}}
    """)
    press(s, "l")  # the lower arm leans: its frame and the world's differ by 30 degrees
    s.handle(ev.mouse(0.5, 0.5))  # 30 degrees
    s.advance(960)
    c = s.character
    ref = 0.0 if frame == "world" else c.bodies["lower_arm"].angle
    got = math.degrees(c.bodies["upper_arm"].angle - ref)
    assert abs(math.degrees(c.bodies["lower_arm"].angle)) > 15
    assert got == pytest.approx(30, abs=8), got  # the servo sags a little under gravity


def test_a_mouse_button_reads_1_while_down_and_0_when_up(tmp_path):
    s = make(tmp_path, """
    maps:
      - {input: mouse.left, joint: knee, to: [0, 40], clamp: false}
    """)
    s.handle(ev.mouse_button("left", True))
    assert s.runtime.read_input("mouse.left") == 1.0
    assert deg(s)["knee"] == pytest.approx(40)
    s.handle(ev.mouse_button("left", False))
    assert s.runtime.read_input("mouse.left") == 0.0
    assert deg(s)["knee"] == pytest.approx(0)


@pytest.mark.parametrize("linear, angular", [(250.0, 0.0), (0.0, 2.0e4), (150.0, 5000.0)])
def test_a_runaway_linear_or_angular_speed_alone_is_a_blow_up(linear, angular):
    from puppet.physics.simulation import MAX_SPEED

    s = Session(load_setup("luxo-mouse"))
    assert not s.sim.blown_up()
    body = s.character.bodies["upper_arm"]
    body.velocity = (linear, 0.0)
    body.angular_velocity = angular
    runaway = linear > MAX_SPEED or angular > 50 * MAX_SPEED
    assert s.sim.blown_up() is runaway


def test_a_circle_prop_is_a_ball_that_rests_on_the_floor(tmp_path):
    scene = tmp_path / "ball.yaml"
    scene.write_text(textwrap.dedent("""\
        name: ball
        description: a ball dropped ahead of Luxo
        ground:
          - points: [[-10.0, 0.0], [10.0, 0.0]]
        props:
          ball:
            body: dynamic
            mass: 0.2
            position: [0.8, 0.5]
            shapes:
              - {circle: [0.0, 0.0], radius: 0.05}
        """))
    s = Session(load_setup("luxo-mouse", str(scene)))
    ball = s.sim.props["ball"]
    assert [type(sh).__name__ for sh in ball.shapes] == ["Circle"]
    assert ball.shapes[0].radius == 0.05
    s.advance(960)  # 2 s: fallen and settled
    # on the floor (whose segments have a little thickness of their own), at rest
    assert 0.045 < ball.body.position.y < 0.07
    assert abs(ball.body.velocity.y) < 0.01


class _Samples:
    """A trajectory as evaluate() reads it, for one link: angle and contact per sample."""

    def __init__(self, degrees, contact):
        import numpy as np

        self.t = np.arange(len(degrees)) * 0.1
        self.angle = np.radians(np.asarray(degrees, dtype=float))[:, None]
        self.contact = np.asarray(contact, dtype=bool)[:, None]

    def index(self, link):
        assert link == "base"
        return 0


@pytest.mark.parametrize("least, passed", [(350, True), (400, False)])
def test_turned_in_flight_counts_only_the_turn_made_in_the_air(least, passed):
    from puppet.timeline.expectations import evaluate, parse_expectations

    # 90 degrees on the ground, then 360 in one flight, then 45 more on the ground
    degrees = [0, 45, 90, 150, 240, 330, 420, 450, 480, 495]
    contact = [True, True, True, False, False, False, False, True, True, True]
    e, = parse_expectations([{"turned": {"link": "base", "min_degrees": least,
                                         "in_flight": True}}]).items
    outcome = evaluate(e, _Samples(degrees, contact), "")
    assert outcome.passed is passed, str(outcome)
    assert "360" in outcome.measured and "t = 0.20 s" in outcome.measured, str(outcome)


def test_a_frame_target_is_re_solved_at_the_control_rate_not_every_step(tmp_path):
    s = make(tmp_path, """
    control_rate: 60
    maps:
      - {input: mouse.x, joint: knee, frame: world, to: [0, 60]}
    poses:
      lean: {joints: {ankle: -30}}
    keys:
      - {key: l, pose: lean}
    """)
    s.handle(ev.mouse(0.5, 0.5))
    press(s, "l")  # the lower arm swings over: the knee's target must follow it
    knee = s.character.servos["knee"]
    changed = []
    last = knee.target
    for _ in range(240):  # 0.5 s: the lamp moves, so the solved target keeps changing
        s.advance(1)
        if knee.target != last:
            changed.append(s.steps)
            last = knee.target
    period = round(480 / 60)
    assert len(changed) > 10
    assert all((step - 1) % period == 0 for step in changed), changed[:12]
