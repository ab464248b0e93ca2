"""The cat: its character file, its two interfaces (keys: bound; mouse: trot), the
over-extended push, the pose pictures of the key map, and the per-leg pose grids."""

import math
import textwrap
from pathlib import Path

import pygame
import pytest

from puppet.commands.check import check_file
from puppet.data.catalog import find, load_setup
from puppet.data.characters import load_character
from puppet.data.errors import DataError
from puppet.interface import events as ev
from puppet.session import Session

ROOT = Path(__file__).parents[1]
LEGS = {  # pair -> side -> joints from the body down
    "back": {"near": ["hip_near", "knee_near"], "far": ["hip_far", "knee_far"]},
    "front": {"near": ["shoulder_near", "elbow_near"], "far": ["shoulder_far", "elbow_far"]},
}


@pytest.fixture(scope="module")
def cat():
    return load_character(find("character", "cat"))


def deg(servo_value: float) -> float:
    return math.degrees(servo_value)


# -- the character -------------------------------------------------------------------
def test_cat_mass_and_size_are_a_house_cats(cat):
    assert sum(link.mass for link in cat.links) == pytest.approx(5.0, abs=0.05)
    # nose to tail tip, model frame (joints at 0 = head and tail in line)
    xs = []
    for name in ("head", "tail"):
        for s in cat.link(name).shapes:
            pts = [s.a, s.b] if s.type == "segment" else [s.center] if s.type == "circle" \
                else s.points
            r = getattr(s, "radius", 0.0)
            xs += [p[0] + r for p in pts] + [p[0] - r for p in pts]
    assert max(xs) - min(xs) == pytest.approx(0.50, abs=0.03)
    assert "5.0 kg" in cat.notes and "0.51 m" in cat.notes
    # body in two links with a spine hinge; head and tail hinged on
    spine = cat.joint("spine")
    assert {spine.parent, spine.child} == {"hips", "chest"} and spine.pd is not None
    # each leg: at least two links; near and far legs on their layers
    for pair in LEGS.values():
        for side, joints in pair.items():
            links = [cat.joint(j).child for j in joints]
            assert len(links) >= 2
            assert all(cat.link(n).layer == side for n in links)
            assert cat.joint(joints[1]).parent == links[0]  # a chain


def test_cat_stands_still_at_the_default_step():
    s = Session(load_setup("cat-bound"))
    c = s.character
    start_x = c.com()[0]
    s.advance(round(2.0 / s.sim.dt))
    x, y = c.com()
    assert c.upright(10)
    assert abs(x - start_x) < 0.02 and y > 0.15
    paws = ["shin_near", "shin_far", "forearm_near", "forearm_far"]
    assert all(c.in_contact(p) for p in paws)
    assert not any(c.in_contact(n) for n in ("hips", "chest", "head", "tail"))
    vx, vy = c.com_velocity()
    assert abs(vx) < 0.01 and abs(vy) < 0.01


@pytest.mark.parametrize("name", ["characters/cat.yaml", "interfaces/cat-bound.yaml",
                                  "interfaces/cat-trot.yaml", "interfaces/cat-gap.yaml",
                                  "assets/scenes/cat-flat.yaml", "assets/scenes/cat-gap.yaml"])
def test_cat_files_pass_puppet_check(name):
    assert check_file(ROOT / name)


# -- bound: keys ---------------------------------------------------------------------
def test_bound_keys_mirror_the_pose_layout_and_move_near_and_far_together():
    setup = load_setup("cat-bound")
    spec = setup.interface
    assert spec.slowdown == 10
    by_key = {k.key: k for k in spec.keys}
    layout = {"back": ("q", "w", "e", "a", "s", "d"), "front": ("u", "i", "o", "j", "k", "l")}
    for pair, keys in layout.items():
        poses = [spec.poses[by_key[k].pose].joints for k in keys]
        near, far = LEGS[pair]["near"], LEGS[pair]["far"]
        hips = [p[near[0]] for p in poses]
        # columns left to right: leg back, under, forward (the cat faces right)
        assert hips[0] < hips[1] < hips[2] and hips[3] < hips[4] < hips[5]
        for p in poses:  # far leg = near leg with a fixed offset
            assert p[far[0]] - p[near[0]] == -6 and p[far[1]] == p[near[1]]
        assert len({tuple(sorted(p.items())) for p in poses}) == 6


def test_front_over_extended_push_is_stiffer_only_while_held():
    s = Session(load_setup("cat-bound"))
    servos = s.character.servos
    joints = LEGS["front"]["near"] + LEGS["front"]["far"]
    before = {j: servos[j].stiffness for j in joints}
    push = s.setup.interface.poses["front_push"]
    s.handle(ev.key("ctrl+j", True))
    for j in joints:
        assert servos[j].stiffness > 2.5 * before[j]
    assert deg(servos["shoulder_near"].target) < push.joints["shoulder_near"] - 15
    s.advance(24)
    assert servos[joints[0]].stiffness > 2.5 * before[joints[0]]  # still held
    s.handle(ev.key("ctrl+j", False))
    assert {j: servos[j].stiffness for j in joints} == before
    assert deg(servos["shoulder_near"].target) < push.joints["shoulder_near"] - 15
    assert all(servos[j].stiffness < 20 for j in LEGS["back"]["near"])


def _state(s: Session) -> str:
    return s.runtime.machines["main"].current


def test_back_over_extended_push_is_stiff_until_the_back_paws_land():
    """ctrl+a (the back pair's over-extended push) raises the back legs' stiffness when
    it goes and the 'landed' phase (a back paw down again, read from the paws) lowers
    it: the key may be tapped, the push lasts as long as the paws push."""
    s = Session(load_setup("cat-bound"))
    servos = s.character.servos
    joints = LEGS["back"]["near"] + LEGS["back"]["far"]
    before = {j: servos[j].stiffness for j in joints}
    push = s.setup.interface.poses["back_push"]
    s.advance(round(0.3 / s.sim.dt))
    s.handle(ev.key("ctrl+a", True))
    s.handle(ev.key("ctrl+a", False))  # a tap
    assert _state(s) == "pushing"
    assert all(servos[j].stiffness > 2.5 * before[j] for j in joints)
    assert deg(servos["hip_near"].target) < push.joints["hip_near"] - 15
    seen = set()
    for _ in range(round(1.0 / s.sim.dt)):
        s.advance(1)
        seen.add(_state(s))
        if _state(s) == "flight":
            assert all(servos[j].stiffness > 2.5 * before[j] for j in joints)
    assert {"flight", "landed", "ready"} <= seen
    assert {j: servos[j].stiffness for j in joints} == before
    assert all(servos[j].stiffness < 20 for j in LEGS["front"]["near"])


def test_a_push_pressed_while_the_cat_lands_waits_for_it():
    """A ctrl+a made before the stride is ready (the cat still in the air or landing) is
    kept (buffer:) and goes the moment the stride's 'ready' phase begins: after the
    landing's phases (landed, planted, gathered), which the stride runs from the paws."""
    s = Session(load_setup("cat-bound"))
    dt = s.sim.dt
    s.advance(round(0.3 / dt))
    s.handle(ev.key("ctrl+a", True))
    s.handle(ev.key("ctrl+a", False))
    while _state(s) != "landed":
        s.advance(1)
        assert s.time < 1.5
    s.handle(ev.key("ctrl+a", True))  # too early: the back legs are not under the cat
    s.handle(ev.key("ctrl+a", False))
    assert _state(s) == "landed"
    seen = []
    while _state(s) in ("landed", "planted", "gathered"):
        seen.append(_state(s))
        s.advance(1)
        assert s.time < 2.0
    assert {"planted", "gathered"} <= set(seen)
    assert _state(s) == "pushing"  # it went at the step 'ready' began


def test_the_over_extended_push_from_rest_lands_whenever_it_is_pressed():
    """The single-key move (issue 28): ctrl+a pressed at ten different steps while the
    cat stands at rest in its start pose. Each push throws the back paws up (0.1 s or
    more in the air) and the cat lands on its legs (a back paw and a front leg at
    least), upright, the body never on the ground, 'ready' for the next press: the
    stride's phases gather it (back legs standing, front legs folded under, so it rests
    on a forearm or on the folded upper arms, about 17 deg nose-down). At least 9 of 10
    must land (all 10 do)."""
    landed = []
    for k in range(10):
        s = Session(load_setup("cat-bound"))
        c, dt = s.character, s.sim.dt
        s.advance(round(0.4 / dt) + 29 * k)  # at rest: 0.4 s to 1.0 s after the start
        s.handle(ev.key("ctrl+a", True))
        air = tilt = 0.0
        body_down = False
        paws = set()  # the paws that touch in the last 0.2 s (a standing paw flickers)
        for i in range(round(1.5 / dt)):
            if i == round(0.15 / dt):        # a person's press: held a moment
                s.handle(ev.key("ctrl+a", False))
            s.advance(1)
            if not (c.in_contact("shin_near") or c.in_contact("shin_far")):
                air += dt
            tilt = max(tilt, abs(math.degrees(c.root_angle())))
            body_down |= any(c.in_contact(n) for n in ("hips", "chest", "head"))
            if i >= round(1.3 / dt):
                paws |= {p for p in ("shin_near", "shin_far", "forearm_near", "forearm_far",
                                     "upper_arm_near", "upper_arm_far") if c.in_contact(p)}
        landed.append(air >= 0.1 and tilt < 45 and not body_down and c.upright(25)
                      and bool(paws & {"shin_near", "shin_far"})
                      and bool(paws - {"shin_near", "shin_far"}) and _state(s) == "ready")
    assert sum(landed) >= 9, landed


# -- the key map's pose pictures -----------------------------------------------------
def _leg_pixels(surface, rect, colors) -> int:
    n = 0
    for x in range(rect.left, rect.right):
        for y in range(rect.top, rect.bottom):
            c = surface.get_at((x, y))[:3]
            if any(sum(abs(a - b) for a, b in zip(c, col)) < 30 for col in colors):
                n += 1
    return n


def test_key_map_draws_each_pose_key_as_a_picture_of_the_leg():
    from puppet.app.keymap import draw_keymap, draw_pose_icon, pose_key_bindings

    pygame.font.init()
    setup = load_setup("cat-bound")
    font = pygame.font.Font(None, 18)
    surface = pygame.Surface((900, 400))
    surface.fill((0, 0, 0))
    rect = draw_keymap(surface, setup.interface, setup.character, font, (0, 0), cap=60)
    assert rect is not None and rect.width > 6 * 60
    bindings = dict(pose_key_bindings(setup.interface))
    assert len(bindings) == 14 and bindings["ctrl+a"] == "back_over_push"
    leg = tuple(setup.character.link("thigh_near").color)
    assert _leg_pixels(surface, rect, [leg]) > 14 * 20  # leg strokes in every cap
    # different poses give different pictures; one picture is the leg, not text
    pictures = []
    for pose in ("back_up_back", "back_push", "back_reach"):
        icon = pygame.Surface((60, 60))
        icon.fill((255, 255, 255))
        draw_pose_icon(icon, icon.get_rect(), setup.character,
                       setup.interface.poses[pose].joints)
        assert _leg_pixels(icon, icon.get_rect(), [leg]) > 20
        pictures.append(pygame.image.tobytes(icon, "RGB"))
    assert len(set(pictures)) == 3


def test_hud_shows_the_pose_pictures_with_the_key_map():
    from puppet.app.headless import FrameRenderer

    s = Session(load_setup("cat-bound"))
    r = FrameRenderer(s, size=(1024, 640))
    leg = tuple(s.setup.character.link("thigh_near").color)
    panel = pygame.Rect(8, 110, 300, 240)  # under the status panel, left of the cat
    r.info.show_help = False
    off = _leg_pixels(r.render(s), panel, [leg])
    r.info.show_help = True
    on = _leg_pixels(r.render(s), panel, [leg])
    assert on > off + 150  # (ctrl+a's picture is its state's, 'ready': one fewer here)


# -- trot: one mouse, four legs, diagonal pairs in anti-phase ----------------------------
def test_trot_grid_keeps_the_phase_relation():
    s = Session(load_setup("cat-trot"))
    servos = s.character.servos

    def at(x, y):
        s.handle(ev.mouse(x, y))
        return {j: deg(servo.target) for j, servo in servos.items()}

    for x, y in [(0.1, 0.9), (0.3, 0.2), (0.5, 0.5), (0.8, 0.6), (1.0, 0.0)]:
        a, b = at(x, y), at(1 - x, 1 - y)
        # diagonal pair A (near back, far front) at (x, y) = pair B at the reflection
        assert b["hip_far"] == pytest.approx(a["hip_near"] - 6)
        assert b["knee_far"] == pytest.approx(a["knee_near"])
        assert b["shoulder_near"] == pytest.approx(a["shoulder_far"] + 6)
        assert b["elbow_near"] == pytest.approx(a["elbow_far"])
    # a circling mouse: left/right legs of a pair alternate (one forward, one back)
    top_right = at(0.9, 0.9)
    assert top_right["hip_near"] > 40 and top_right["hip_far"] < 0
    assert top_right["shoulder_far"] > 15 and top_right["shoulder_near"] < -30


def _grid_iface(tmp_path, extra: str) -> Path:
    path = tmp_path / "g.yaml"
    path.write_text(textwrap.dedent("""\
        name: g
        description: grid test
        character: luxo
        poses:
          a: {joints: {ankle: -20, knee: 10}}
          b: {joints: {ankle: 20, knee: 90}}
        maps:
          - grid: [[a, b]]
        """) + extra)
    return path


def test_grid_map_joints_and_mirror_are_validated(tmp_path):
    with pytest.raises(DataError, match=r"g.yaml:9:\d+: unknown joint 'elbow'"):
        check_file(_grid_iface(tmp_path, "    joints: [ankle, elbow]\n"))
    with pytest.raises(DataError, match="names an axis twice"):
        check_file(_grid_iface(tmp_path, "    mirror: [x, x]\n"))
    with pytest.raises(DataError, match="mirror"):
        check_file(_grid_iface(tmp_path, "    mirror: [z]\n"))
    ok = _grid_iface(tmp_path, "    joints: [knee]\n    mirror: [x]\n")
    assert check_file(ok) == "interface"
    s = Session(load_setup(str(ok)))
    ankle = s.character.servos["ankle"].target
    s.handle(ev.mouse(0.0, 0.5))  # mirrored: pose b's knee; the ankle is not driven
    assert deg(s.character.servos["knee"].target) == pytest.approx(90)
    assert s.character.servos["ankle"].target == ankle


def test_the_gap_log_leaps_the_gap_rather_than_stepping_across_it():
    """assets/logs/cat-gap.jsonl (its expectations are checked by test_logs.py) really
    leaps: replayed step by step, the cat never touches the gap's walls or floor, never
    touches both sides of the gap at once (a 25 cm gap is short enough for a stretched
    cat to bridge), and is wholly in the air between its last touch on the near side and
    its first on the far side - the back feet leave before the front feet land."""
    import yaml

    from puppet.timeline.log import read_log
    from puppet.timeline.replay import apply_log, new_session, setup_for_log

    scene = yaml.safe_load((ROOT / "assets/scenes/cat-gap.yaml").read_text())
    pit = next(g["points"] for g in scene["ground"] if g["name"] == "gap floor")
    near, far, rim = pit[0][0], pit[-1][0], 0.005
    log = read_log(ROOT / "assets/logs/cat-gap.jsonl")
    setup, _ = setup_for_log(log)
    s = new_session(log, setup)
    c = s.character
    seen = {"pit": [], "bridge": [], "last_near": None, "first_far": None, "between": []}

    def tick(sess):
        pts = []
        for n in c.link_order:
            c.bodies[n].each_arbiter(lambda arb: pts.extend(
                (p.point_a.x, p.point_a.y) for p in arb.contact_point_set.points))
        if any(y < -rim for _, y in pts):
            seen["pit"].append(sess.time)
        on_near = any(x <= near + rim for x, _ in pts)
        on_far = any(x >= far - rim for x, _ in pts)
        if on_near and on_far:
            seen["bridge"].append(sess.time)
        if on_near:
            seen["last_near"] = sess.time
        if on_far and seen["first_far"] is None:
            seen["first_far"] = sess.time
        if pts and not on_near and not on_far:
            seen["between"].append(sess.time)

    apply_log(s, log, every=1, on_tick=tick)
    assert not seen["pit"], f"touched the gap's walls or floor at t = {seen['pit'][:3]}"
    assert not seen["bridge"], f"touched both sides at once at t = {seen['bridge'][:3]}"
    assert not seen["between"]
    flight = seen["first_far"] - seen["last_near"]
    assert flight >= 0.05, f"in the air over the gap for {flight:.3f} s only"
    assert c.com()[0] > 3.6 + 0.15  # and on, past the top step's edge
