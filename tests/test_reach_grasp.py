"""IK chains of any length, the three kinds of reach target (a fixed point, a scene
prop's grasp point counted next/previous, a point steered by two channels) and
grasps of a dynamic prop through checkpoints, rewinds and replays.

The scene ``assets/scenes/pendulum.yaml`` has a fixed rail with three handholds just
ahead of Luxo's shade and a bar (a dynamic prop) swinging from a pivot, its tip
passing at shade height."""

from __future__ import annotations

import itertools
import math
import random
import textwrap

import pytest
from helpers import session_of, tap

from puppet.data.actions import ChainSpec
from puppet.data.catalog import load_character_named, load_setup
from puppet.interface import events as ev
from puppet.interface.ik import Chain, forward, hermite
from puppet.physics.character import Character
from puppet.session import Session
from puppet.session.playback import play
from puppet.timeline.log import read_log, record_events
from puppet.timeline.replay import replay

CAT, _ = load_character_named("cat")
ARM = ("spine", "shoulder_near", "elbow_near")  # chest, upper arm, forearm: three joints
PAW = (0.10, 0.012)  # the near forepaw, model frame


# -- IK: a three-joint chain -------------------------------------------------------------
def cat_arm():
    character = Character(CAT)
    start = character.start_joint_angles()
    character.place(0.0, 0.0, 0.0, start)
    chain = Chain.from_spec("arm", ChainSpec(joints=list(ARM), end=PAW), CAT)
    return character, chain, start


def paw_at(character, chain, start, q):
    """Where the paw is with the arm's joints at ``q`` (the character's bodies placed,
    not the solver's own forward kinematics)."""
    angles = dict(start)
    angles.update(zip(chain.joints, q))
    character.place(0.0, 0.0, 0.0, angles)
    return chain.end_world(character)


def within_limits(chain, q) -> bool:
    return all(lo <= v <= hi for v, (lo, hi) in zip(q, chain.limits))


def test_three_joint_chain_reaches_points_within_1cm_inside_its_limits():
    character, chain, start = cat_arm()
    assert len(chain.joints) == 3 and len(chain.links) == 3
    rng = random.Random(11)
    now = [start.get(j, 0.0) for j in chain.joints]
    # Points the arm can reach: where random angles put it, within the middle 80 % of
    # each joint's range. (Near the ends of the ranges a local solver can stop short:
    # of 200 points drawn over the whole ranges, 2 high over the back were missed.)
    for _ in range(15):
        q = [rng.uniform(lo + 0.1 * (hi - lo), hi - 0.1 * (hi - lo)) for lo, hi in chain.limits]
        target = paw_at(character, chain, start, q)
        character.place(0.0, 0.0, 0.0, start)
        q = chain.solve(character, target, now)
        assert within_limits(chain, q)
        assert math.dist(paw_at(character, chain, start, q), target) < 0.01


def nearest_reachable(chain, target, n: int = 24) -> float:
    """The distance from ``target`` to the nearest place the paw reaches on an n^3 grid
    of joint angles within the limits (an upper bound on the true nearest)."""
    grids = [[lo + (hi - lo) * i / n for i in range(n + 1)] for lo, hi in chain.limits]
    base = chain.anchor  # the first joint's pivot: the character stands at the origin
    d = (target[0] - base[0], target[1] - base[1])
    return min(math.dist(forward(list(chain.links), q)[1], d)
               for q in itertools.product(*grids))


@pytest.mark.parametrize("target", [(1.0, 1.0), (-0.3, -0.2), (0.6, 0.1), (0.3, -0.3)])
def test_out_of_reach_the_limits_hold_and_the_paw_stops_nearest_the_target(target):
    """As a reach does it: re-solved at every point of the eased path from where the
    paw is. Before the solver's step control, the arm reaching up and forward for
    (1, 1) ended pointing back, 1.24 m away (the nearest it can be is 0.98 m)."""
    character, chain, start = cat_arm()
    q = [start.get(j, 0.0) for j in chain.joints]
    p0 = chain.end_world(character)
    for i in range(1, 121):
        h = hermite(i / 120)
        point = (p0[0] + h * (target[0] - p0[0]), p0[1] + h * (target[1] - p0[1]))
        q = chain.solve(character, point, q)
        assert within_limits(chain, q)
    got = math.dist(paw_at(character, chain, start, q), target)
    assert got > 0.25  # truly out of reach
    assert got < nearest_reachable(chain, target) + 0.005


# -- reaches in a session ------------------------------------------------------------------
LUXO = """
name: t
description: reaches and grasps in the pendulum scene
character: luxo
scene: pendulum
gains:
  ankle: {stiffness: 60, damping: 0.6, max_torque: 40}
  knee: {stiffness: 40, damping: 0.4, max_torque: 30}
chains:
  shade: {joints: [ankle, knee], end: [0.0, 0.43]}
  brim: {joints: [ankle, knee], end: [0.06, 0.43]}   # 6 cm ahead of the shade's end
keys:
  - {key: e, reach: {chain: shade, point: {prop: rail}, duration: 0.4, hold: 0.4}}
  - {key: n, reach: {chain: shade, point: {prop: rail, offset: 1}, duration: 0.4, hold: 0.4}}
  - {key: v, reach: {chain: shade, point: {prop: rail, offset: -1}, duration: 0.4, hold: 0.4}}
  - {key: o, reach: {chain: shade, point: {prop: rail, of: brim}, duration: 0.4, hold: 0.4}}
  - key: s
    reach: {chain: shade, steer: {x: channel.hx, y: channel.hy, x_to: [-0.04, 0.06],
            y_to: [0.32, 0.40]}, duration: 0.3}
  - {key: g, reach: {chain: shade, point: {prop: swing}, duration: 0.3, hold: 2.0,
                     grasp: true, tolerance: 0.03}}
  - {key: f, grasp: {chain: shade, points: [[5.0, 5.0]], tolerance: 0.03}}
  - {key: a, grasp: {chain: shade, prop: any, tolerance: 0.03}}
  - {key: u, release: all}
  - {key: "1", pose: stand}
poses:
  stand: {joints: {ankle: -25, knee: 55}}
"""


def session(tmp_path, text: str = LUXO) -> Session:
    path = tmp_path / "t.yaml"
    path.write_text(textwrap.dedent(text))
    return Session(load_setup(str(path)))


def press(s, key):
    s.handle(ev.key(key, True))
    s.handle(ev.key(key, False))


def shade_end(s):
    return s.runtime.chains["shade"].end_world(s.character)


def test_reach_to_a_prop_point_counts_next_and_previous_from_the_nearest(tmp_path):
    s = session(tmp_path)
    s.advance(240)
    rail = s.sim.props["rail"]
    order = list(rail.points)
    assert order == ["back", "middle", "front"]
    picked = []
    for key in ("e", "n", "n", "n", "v", "v", "v", "o"):
        press(s, key)
        picked.append(s.runtime.reaches["shade"].target[2])
        s.advance(400)  # 0.4 s there, 0.4 s held, then the reach ends
        assert math.dist(shade_end(s), rail.point_world(picked[-1])) < 0.01
        assert s.character.upright()
    # nearest, then next until the last, previous until the first, clamped at the ends;
    # "of: brim" counts from the brim's end, 6 cm ahead of the shade's
    assert picked == ["back", "middle", "front", "front", "middle", "back", "back", "middle"]


def test_reach_steered_by_a_channel_pair_follows_the_channels(tmp_path):
    s = session(tmp_path)
    s.advance(240)
    press(s, "s")
    base = s.character.bodies["base"]
    for hx, hy in ((0.5, 0.5), (0.9, 0.2), (0.2, 0.8), (0.0, 0.0), (0.6, 0.9)):
        s.handle(ev.channels({"hx": hx, "hy": hy}))
        s.advance(150)
        want = base.local_to_world((-0.04 + 0.1 * hx, 0.32 + 0.08 * hy))
        assert s.runtime.read_input("channel.hx") == hx
        assert math.dist(shade_end(s), want) < 0.01, (hx, hy)
    assert "shade" in s.runtime.reaches  # steered: held until preempted
    press(s, "1")  # a pose takes both joints back
    s.advance(2)
    assert s.runtime.reaches == {}


def test_a_grasp_armed_5m_away_with_3cm_tolerance_does_not_catch(tmp_path):
    s = session(tmp_path)
    s.advance(100)
    press(s, "f")
    s.advance(400)
    assert s.runtime.grasped == {} and not s.sim.grasps
    assert "shade" in s.runtime.grasping.armed  # still armed: nothing came near
    press(s, "a")  # any prop, 3 cm: the shade is 4+ cm from the rail, the swing far
    s.advance(20)
    assert s.runtime.grasped == {}


def test_release_lets_go_even_while_the_grasping_reach_runs(tmp_path):
    s = session(tmp_path)
    s.advance(240)
    press(s, "g")
    s.advance(300)
    assert "shade" in s.runtime.grasped
    press(s, "u")  # the reach holds for 2 s more: it must not grab again
    s.advance(100)
    assert s.runtime.grasped == {} and not s.sim.grasps


# -- a grasp on a dynamic prop through checkpoints, rewinds and replays --------------------
EVENTS = [(240, ev.key("g", True)), (241, ev.key("g", False)),
          (520, ev.key("c", True)), (521, ev.key("c", False)),  # a manual checkpoint
          (1300, ev.key("u", True)), (1301, ev.key("u", False))]
END = 1500


def play_on(s, events, until):
    """Play the events after the current step (those at it have happened)."""
    play(s, [e for e in events if e[0] > s.steps], until)


def test_grasp_on_a_swinging_bar_survives_checkpoint_rewind_and_replay(tmp_path):
    straight = session(tmp_path)
    held = {}
    play(straight, EVENTS, END, 100, lambda s: held.setdefault(s.steps, dict(s.runtime.grasped)))
    assert held[500] and held[1200] and not held[1500]  # caught, then let go
    bar = straight.sim.props["swing"].body
    assert abs(bar.angular_velocity) > 0.1  # the bar moves (with the lamp on it)
    want = straight.sim.state_hash()
    spin = bar.angular_velocity
    bar.angular_velocity = spin + 1e-12  # the hash covers the swing (a dynamic prop) too
    assert straight.sim.state_hash() != want
    bar.angular_velocity = spin

    # back to the manual checkpoint (taken while holding) and on again
    s = session(tmp_path)
    play(s, EVENTS, 900)
    assert "shade" in s.sim.grasps
    s.handle(ev.action("restore"))
    assert s.steps == 520 and "shade" in s.sim.grasps
    play_on(s, EVENTS, END)
    assert s.sim.state_hash() == want

    # a rewind to a step between keyframes while holding, then on
    s = session(tmp_path)
    play(s, EVENTS, 1100)
    s.rewind_to(700)
    assert s.steps == 700 and "shade" in s.runtime.grasped
    play_on(s, EVENTS, END)  # playing on drops the rewound future: its events again
    assert s.sim.state_hash() == want

    # a recorded log replays to the same bits
    path = record_events(session(tmp_path), EVENTS, END, tmp_path / "swing.jsonl")
    assert read_log(path).end_hash == want
    assert replay(path, check=False).final_hash == want


def test_the_window_draws_the_props_where_they_are():
    """The swinging bar is drawn along its length, and follows the bar (paler than its
    colour: the character passes through it, ``collide: false``)."""
    from puppet.app.headless import FrameRenderer

    s = Session(load_setup("luxo-mouse", "pendulum"))
    renderer = FrameRenderer(s)
    renderer.camera.base_height = 3.0  # a wide view: the bar hangs above Luxo's frame
    swing = s.sim.props["swing"]
    colour = tuple(min(255, int(c * 1.3)) for c in s.setup.scene.props["swing"].color)

    def bar_pixels() -> set:
        image = renderer.render(s, hud=False)
        cam = renderer.camera
        points = [swing.body.local_to_world((0.0, -0.1 * k)) for k in range(1, 5)]
        return {tuple(image.get_at([round(v) for v in cam.to_screen(p)]))[:3] for p in points}

    assert bar_pixels() == {colour}
    s.advance(240)  # half a second later the bar has swung elsewhere: still drawn on it
    assert bar_pixels() == {colour}
    flat = Session(load_setup("luxo-mouse"))
    image = FrameRenderer(flat).render(flat, hud=False)
    assert colour not in {tuple(image.get_at((x, y)))[:3]
                          for x in range(0, 1280, 4) for y in range(0, 720, 4)}


def test_channels_frames_are_one_log_line_each_and_replay_to_the_same_bits(tmp_path):
    """A stream of channel frames (a tracked hand steering the shade, and a channel no
    map reads) is logged one line per frame and replays exactly."""
    frames = [(240 + 8 * i, ev.channels({"hx": 0.5 + 0.4 * math.sin(i / 10),
                                          "hy": 0.5 + 0.4 * math.cos(i / 7), "spare": i}))
              for i in range(100)]
    events = [(240, ev.key("s", True)), (241, ev.key("s", False))] + frames
    live = session(tmp_path)
    path = record_events(live, sorted(events, key=lambda e: e[0]), 1100,
                         tmp_path / "hand.jsonl")
    lines = [line for line in path.read_text().splitlines() if '"channels"' in line]
    assert len(lines) == 100
    assert live.runtime.read_input("channel.spare") == 99
    want = live.sim.state_hash()
    assert replay(path, check=False).final_hash == want == read_log(path).end_hash
    # the end followed the hand (the last frame's target, held since)
    hx, hy = frames[-1][1]["values"]["hx"], frames[-1][1]["values"]["hy"]
    base = live.character.bodies["base"]
    target = base.local_to_world((-0.04 + 0.1 * hx, 0.32 + 0.08 * hy))
    assert math.dist(shade_end(live), target) < 0.01


def test_a_hot_reload_naming_a_prop_the_scene_lacks_is_refused(tmp_path):
    """Checked against the running scene, like play does (it was accepted, and pressing
    the key then failed with a KeyError)."""
    from puppet.data.errors import DataError

    s = session(tmp_path)
    s.advance(100)
    with pytest.raises(DataError) as info:
        s.reload(LUXO.replace("point: {prop: rail}", "point: {prop: rial}"),
                 str(tmp_path / "t.yaml"))
    assert str(info.value).startswith(f"{tmp_path / 't.yaml'}:13:")
    assert "unknown prop 'rial' in scene 'pendulum'" in str(info.value)
    press(s, "e")  # the running interface goes on
    s.advance(10)
    assert s.runtime.reaches["shade"].target[:2] == ["prop", "rail"]


# -- a three-joint arm of our own, in a session ----------------------------------------------
ARM3 = """
name: arm3
description: >-
  a very heavy base (it hardly moves without gravity) and a three-link arm (test character)
links:
  - name: base
    mass: 1000.0
    shapes: [{type: box, center: [0.0, 0.05], size: [0.4, 0.1]}]
  - name: upper
    mass: 1.0
    shapes: [{type: segment, a: [0.0, 0.1], b: [0.0, 0.3], radius: 0.01}]
  - name: fore
    mass: 0.6
    shapes: [{type: segment, a: [0.0, 0.3], b: [0.0, 0.45], radius: 0.01}]
  - name: hand
    mass: 0.3
    shapes: [{type: segment, a: [0.0, 0.45], b: [0.0, 0.55], radius: 0.01}]
joints:
  - {name: shoulder, parent: base, child: upper, anchor: [0.0, 0.1], limits: [-80, 80],
     pd: {stiffness: 40, damping: 1.0, max_torque: 60}}
  - {name: elbow, parent: upper, child: fore, anchor: [0.0, 0.3], limits: [-120, 120],
     pd: {stiffness: 20, damping: 0.4, max_torque: 40}}
  - {name: wrist, parent: fore, child: hand, anchor: [0.0, 0.45], limits: [-60, 60],
     pd: {stiffness: 5, damping: 0.08, max_torque: 20}}
start: {joints: {shoulder: 0, elbow: 20, wrist: 10}}
"""
ARM3_SCENE = """
name: arm3-floor
description: a floor and no gravity (test scene)
gravity: [0.0, 0.0]
ground:
  - points: [[-5.0, 0.0], [5.0, 0.0]]
"""


def arm3_session(tmp_path) -> Session:
    (tmp_path / "arm3.yaml").write_text(ARM3)
    (tmp_path / "arm3-floor.yaml").write_text(ARM3_SCENE)
    iface = tmp_path / "arm3-reach.yaml"
    iface.write_text(textwrap.dedent(f"""
    name: arm3-reach
    description: the arm reaches
    character: {tmp_path / 'arm3.yaml'}
    scene: {tmp_path / 'arm3-floor.yaml'}
    chains:
      arm: {{joints: [shoulder, elbow, wrist], end: [0.0, 0.55]}}
    keys:
      - {{key: e, reach: {{chain: arm, target: [0.25, 0.3], duration: 0.5, hold: 1.0}}}}
      - {{key: f, reach: {{chain: arm, target: [-0.2, 0.4], duration: 0.5, hold: 1.0}}}}
      - {{key: g, reach: {{chain: arm, target: [0.2, -0.5], duration: 0.5, hold: 1.0}}}}
      - {{key: h, reach: {{chain: arm, target: [0.15, 0.45], duration: 0.5, hold: 1.0}}}}
      - {{key: k, set: {{shoulder: 0, elbow: -40, wrist: 0}}}}
    """))
    return Session(load_setup(str(iface)))


def test_a_three_joint_arm_reaches_within_1cm_and_keeps_its_limits_out_of_reach(tmp_path):
    s = arm3_session(tmp_path)
    chain = s.runtime.chains["arm"]
    base = s.character.bodies["base"]
    # (0.25, 0.3) from the start pose (elbow bent +20 deg) stalls 5 cm short with the
    # shoulder and wrist at their limits: the way there bends the elbow the other way.
    # The guide's advice: bend the limb the right way first (key k).
    for key, target in (("f", (-0.2, 0.4)), ("h", (0.15, 0.45)), ("k", None),
                        ("e", (0.25, 0.3))):
        goal = target and base.local_to_world(target)  # the root frame at the press
        press(s, key)
        s.advance(480)
        if goal is not None:
            assert math.dist(chain.end_world(s.character), goal) < 0.01, key
    press(s, "g")  # far below the floor: out of reach
    limits = [tuple(math.degrees(v) for v in lim) for lim in chain.limits]
    for _ in range(48):
        s.advance(10)
        for joint, (lo, hi) in zip(chain.joints, limits):
            target = math.degrees(s.character.servos[joint].target)
            assert lo <= target <= hi
            assert lo - 1.0 <= math.degrees(s.character.joint_angle(joint)) <= hi + 1.0
    # stretched toward it: the shoulder at its limit, pointing down-forward
    assert math.degrees(s.character.servos["shoulder"].target) == pytest.approx(-80)


def test_a_steered_reach_that_grasps_takes_hold_of_the_prop_it_is_steered_to(tmp_path):
    text = LUXO.replace("""y_to: [0.32, 0.40]}, duration: 0.3}""",
                        """y_to: [0.32, 0.40]}, duration: 0.3,
            grasp: true, tolerance: 0.01}""")
    s = session(tmp_path, text)
    s.advance(240)
    base = s.character.bodies["base"]
    middle = s.sim.props["rail"].point_world("middle")
    lx, ly = base.world_to_local(middle)  # the rail's middle handhold, in the steer's frame
    s.handle(ev.channels({"hx": (lx + 0.04) / 0.1, "hy": (ly - 0.32) / 0.08}))
    press(s, "s")
    s.advance(20)
    assert s.runtime.grasped == {}  # on its way: not yet within 1 cm
    s.advance(400)
    assert s.sim.grasps["shade"][1] == "rail"  # caught the rail (no point was named)
    assert math.dist(s.runtime.grasped["shade"], middle) < 0.012


LUXO_HEADER = "name: t\ndescription: a test interface\ncharacter: luxo\n"


def luxo_session(tmp_path, body: str) -> Session:
    path = tmp_path / "iface.yaml"
    path.write_text(LUXO_HEADER + textwrap.dedent(body))
    return Session(load_setup(str(path)))


GRASP = """
chains:
  shade: {{joints: [ankle, knee], end: [0.0, 0.43]}}
keys:
  - {{key: f, grasp: {{chain: shade, points: [[{fx}, {fy}]], tolerance: 0.03}}}}
  - {{key: n, grasp: {{chain: shade, points: [[{nx}, {ny}]], tolerance: 0.03}}}}
  - {{key: o, grasp: {{chain: shade, points: [[{ox}, {oy}]], tolerance: 0.03}}}}
  - {{key: u, release: all}}
"""


PENDULUM = """
name: t
description: the pendulum scene, mouse on the knee
character: luxo
scene: pendulum
maps:
  - {input: mouse.y, joint: knee, from: [0, 1], to: [0, 90]}
"""


LUXO_STEERED = """
name: t
description: reaches and grasps in the pendulum scene
character: luxo
scene: pendulum
gains:
  ankle: {stiffness: 60, damping: 0.6, max_torque: 40}
  knee: {stiffness: 40, damping: 0.4, max_torque: 30}
chains:
  shade: {joints: [ankle, knee], end: [0.0, 0.43]}
keys:
  - key: s
    reach: {chain: shade, steer: {x: channel.hx, y: channel.hy, x_to: [-0.04, 0.06],
            y_to: [0.32, 0.40]}, duration: 0.3}
  - {key: g, reach: {chain: shade, point: {prop: rail}, duration: 0.4, hold: 0.4,
                     grasp: true, tolerance: 0.03}}
  - {key: u, release: all}
"""


def test_a_grasp_catches_only_within_its_tolerance(tmp_path):
    probe = luxo_session(tmp_path, GRASP.format(fx=5, fy=5, nx=5, ny=5, ox=5, oy=5))
    probe.advance(240)  # standing still: the shade's end stays where it is
    x, y = probe.runtime.chains["shade"].end_world(probe.character)
    s = luxo_session(tmp_path, GRASP.format(fx=x + 5.0, fy=y + 5.0, nx=x + 0.02, ny=y,
                                    ox=x, oy=y + 0.045))
    s.advance(240)
    assert s.runtime.chains["shade"].end_world(s.character) == pytest.approx((x, y), abs=1e-6)
    tap(s, "f")  # 5 m away (7 m, in fact), 3 cm tolerance
    s.advance(60)
    assert not s.sim.grasps and s.runtime.grasped == {}
    tap(s, "o")  # 4.5 cm away: still outside 3 cm
    s.advance(60)
    assert not s.sim.grasps
    tap(s, "n")  # 2 cm away: within 3 cm, caught at once and pinned there
    s.advance(1)
    assert "shade" in s.sim.grasps
    assert s.sim.grasp_point("shade") == pytest.approx((x + 0.02, y), abs=1e-9)


def test_a_luxo_reach_keeps_the_knee_bent_the_way_it_stands(tmp_path):
    s = luxo_session(tmp_path, """
    chains:
      shade: {joints: [ankle, knee], end: [0.0, 0.43]}
    keys:
      - {key: e, reach: {chain: shade, target: [0.12, 0.30], duration: 0.3, hold: 0.3}}
    """)
    s.advance(240)
    knee = s.character.servos["knee"]
    assert knee.target > 0.2  # Luxo stands with the knee bent forward
    tap(s, "e")
    for _ in range(12):
        s.advance(25)
        assert knee.target > 0.05, math.degrees(knee.target)


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
    probe = luxo_session(tmp_path, reach.format(x=0, y=0, tol=0.2))
    probe.advance(240)
    x, y = probe.runtime.chains["shade"].end_world(probe.character)
    for tol, caught in ((0.2, True), (0.05, False)):
        s = luxo_session(tmp_path, reach.format(x=x + 0.10, y=y, tol=tol))
        s.advance(240)
        tap(s, "q")
        s.advance(2)  # the end has hardly moved: 10 cm from the point
        assert ("shade" in s.sim.grasps) is caught, tol


def test_the_nearest_place_on_a_grasp_segment_is_the_foot_of_the_perpendicular(tmp_path):
    s = session_of(tmp_path, PENDULUM)
    swing = s.sim.props["swing"]
    (a, b), = swing.segments
    pa, pb = swing.body.local_to_world(a), swing.body.local_to_world(b)  # the bar, slanted
    mid = ((pa[0] + pb[0]) / 2, (pa[1] + pb[1]) / 2)
    ux, uy = (pb[0] - pa[0]) / math.dist(pa, pb), (pb[1] - pa[1]) / math.dist(pa, pb)
    beside = (mid[0] - 0.02 * uy, mid[1] + 0.02 * ux)  # 2 cm off the bar's middle
    distance, point, name = swing.nearest(beside)
    assert distance == pytest.approx(0.02) and point == pytest.approx(mid) and name is None


def test_a_steering_input_not_sent_yet_counts_as_the_middle_of_its_range(tmp_path):
    s = session_of(tmp_path, LUXO_STEERED)
    s.advance(120)
    s.handle(ev.channels({"hx": 1.0}))  # hy never sent
    tap(s, "s")
    s.advance(2)
    x, y = s.runtime.reaching.target_now(s.runtime.reaches["shade"].target)
    base = s.character.bodies["base"]
    want = base.local_to_world((0.06, 0.36))  # x at its top, y in the middle of [0.32, 0.40]
    assert math.dist((x, y), want) < 1e-9


@pytest.mark.parametrize("scene", ["ladder", "monkey-bars", "pendulum"])
def test_a_prop_said_to_be_beyond_reach_has_no_place_within_it(scene):
    """``Prop.beyond`` (an armed grasp skips a static prop whose places' box is out of
    reach) never says so of a prop with a place within the distance, at points near
    and on its places and bars, with and without a place excluded; a dynamic prop is
    never said to be."""
    import pymunk

    from puppet.data.catalog import load_scene_named
    from puppet.physics.props import build_props

    space = pymunk.Space()
    props = build_props(load_scene_named(scene)[0], space)
    rng = random.Random(7)
    skipped = 0
    for prop in props.values():
        points, segments = prop._placed()
        places = [(x, y) for _, x, y in points] + [
            (ax + u * vx, ay + u * vy) for ax, ay, vx, vy, _ in segments
            for u in (0.0, 0.5, 1.0)]
        if not places:  # (nothing to grasp: never beyond, nearest says inf)
            assert not prop.beyond((0.0, 0.0), 0.1)
            continue
        for _ in range(400):
            px, py = rng.choice(places)
            w = (px + rng.uniform(-0.3, 0.3), py + rng.uniform(-0.3, 0.3))
            r = rng.choice([0.03, 0.05, 0.1, 0.2])
            exclude = rng.choice([None, (px, py, r)])
            if prop.beyond(w, r):
                skipped += 1
                assert prop.nearest(w, exclude)[0] > r
                assert prop.body.body_type == pymunk.Body.STATIC
    assert skipped > 100
