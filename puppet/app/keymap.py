"""Pictures of poses for the key map: each key bound to a pose shows the posed limb.

A pose is drawn as a small stick figure of the links its joints move, worked out by
forward kinematics from the character spec (model frame, root link unrotated; joints
the pose does not set stay at the start pose). The parent link of the pose's topmost
joint is drawn faintly for orientation. Near and far layers are drawn as in the
world view: far behind and darker.

The key map lays out the pose keys as they sit on the keyboard (a row of keys above
another), so a designer who arranged the poses to mirror the keys sees that
arrangement; keys with modifiers (ctrl+a) get their own strip, labelled.
"""

from __future__ import annotations

import math

import pygame

from puppet.app.describe import live_keys
from puppet.app.render import LAYER_ORDER
from puppet.data.characters import CharacterSpec
from puppet.data.keys import MODIFIERS, normalize_key
from puppet.physics.kinematics import joint_order, link_poses

KEY_ROWS = ("1234567890-=", "qwertyuiop[]", "asdfghjkl;'", "zxcvbnm,./")
ROW_STAGGER = (0.0, 0.5, 0.75, 1.25)  # key widths each row is shifted right
FAR_SHADE = 0.6
CONTEXT = (170, 174, 182)
CAP = (246, 247, 250)
CAP_EDGE = (150, 156, 168)
LABEL = (40, 44, 52)


def link_frames(spec: CharacterSpec, angles: dict[str, float]) -> dict[str, tuple]:
    """Link -> (angle, (tx, ty)): model point p of the link is at R(angle) p + t, with
    the root link at the identity and joint angles in radians (``link_poses``)."""
    poses = link_poses(spec, joint_order(spec), (0.0, 0.0), 0.0, angles)
    return {name: (a, (x, y)) for name, (x, y, a) in poses.items()}


def _apply(frame, p):
    a, (tx, ty) = frame
    c, s = math.cos(a), math.sin(a)
    return (c * p[0] - s * p[1] + tx, s * p[0] + c * p[1] + ty)


def pose_links(spec: CharacterSpec, joints) -> tuple[list[str], list[str], tuple]:
    """(links the pose moves, context links, pivot): the children of the posed joints,
    the parents of the topmost posed joints, and the first topmost joint's anchor."""
    posed = [spec.joint(j) for j in joints if any(x.name == j for x in spec.joints)]
    children = {j.child for j in posed}
    top = [j for j in posed if j.parent not in children]
    context = sorted({j.parent for j in top})
    moved = [link.name for link in spec.links if link.name in children]
    pivot = tuple(top[0].anchor) if top else (0.0, 0.0)
    return moved, context, pivot


def _shape_points(shape) -> list[tuple[float, float]]:
    if shape.type == "segment":
        return [tuple(shape.a), tuple(shape.b)]
    if shape.type == "circle":
        return [tuple(shape.center)]
    if shape.type == "box":
        w, h = shape.size
        a = math.radians(shape.angle)
        c, s = math.cos(a), math.sin(a)
        return [(shape.center[0] + c * x - s * y, shape.center[1] + s * x + c * y)
                for x, y in ((-w / 2, -h / 2), (w / 2, -h / 2), (w / 2, h / 2), (-w / 2, h / 2))]
    return [tuple(p) for p in shape.points]


def pose_extent(spec: CharacterSpec, pose_joints_deg: dict[str, float]) -> float:
    """Largest distance (m) from the pivot to any point of the moved links."""
    moved, _, pivot = pose_links(spec, pose_joints_deg)
    frames = _frames_for(spec, pose_joints_deg)
    best = 0.0
    for name in moved:
        for shape in spec.link(name).shapes:
            r = getattr(shape, "radius", 0.0) or 0.0
            for p in _shape_points(shape):
                x, y = _apply(frames[name], p)
                best = max(best, math.hypot(x - pivot[0], y - pivot[1]) + r)
    return best


def _frames_for(spec: CharacterSpec, pose_joints_deg: dict[str, float]):
    angles = {n: math.radians(v) for n, v in spec.start.joints.items()}
    angles.update({n: math.radians(v) for n, v in pose_joints_deg.items()})
    return link_frames(spec, angles)


def draw_pose_icon(surface: pygame.Surface, rect: pygame.Rect, spec: CharacterSpec,
                   pose_joints_deg: dict[str, float], extent: float | None = None) -> None:
    """Draw the links a pose moves, the pivot centred a third down the rect, scaled
    so ``extent`` metres (default: this pose's) fit."""
    moved, context, pivot = pose_links(spec, pose_joints_deg)
    if not moved:
        return
    frames = _frames_for(spec, pose_joints_deg)
    extent = extent or pose_extent(spec, pose_joints_deg) or 1.0
    # the pivot a third down from the top: limbs mostly hang below their joint
    scale = min(0.5 * rect.width, 0.68 * rect.height) / extent * 0.95
    cx, cy = rect.centerx, rect.top + round(0.3 * rect.height)

    def to_px(p):
        return (round(cx + (p[0] - pivot[0]) * scale), round(cy - (p[1] - pivot[1]) * scale))

    clip = surface.get_clip()
    surface.set_clip(rect)
    for name in context:
        for shape in spec.link(name).shapes:
            pts = [to_px(_apply(frames[name], p)) for p in _shape_points(shape)]
            _draw_stick(surface, shape, pts, CONTEXT, 1, scale)
    for name in sorted(moved, key=lambda n: LAYER_ORDER[spec.link(n).layer]):
        link = spec.link(name)
        far = link.layer == "far"
        color = tuple(int(c * FAR_SHADE) for c in link.color) if far else link.color
        width = 2 if far else 3
        for shape in link.shapes:
            pts = [to_px(_apply(frames[name], p)) for p in _shape_points(shape)]
            _draw_stick(surface, shape, pts, color, width, scale)
    for joint in spec.joints:
        if joint.child in moved:
            p = to_px(_apply(frames[joint.parent], joint.anchor))
            pygame.draw.circle(surface, (60, 64, 72), p, 2)
    surface.set_clip(clip)


def _draw_stick(surface, shape, pts, color, width, scale) -> None:
    if shape.type == "segment":
        pygame.draw.line(surface, color, pts[0], pts[1], width)
    elif shape.type == "circle":
        pygame.draw.circle(surface, color, pts[0], max(2, round(shape.radius * scale)))
    else:
        pygame.draw.polygon(surface, color, pts, width)


def _split_chord(chord: str) -> tuple[str, str]:
    parts = chord.split("+")
    mods = [p for p in parts[:-1] if p in MODIFIERS]
    return "+".join(mods), parts[-1] if parts[-1] else "+"


def _key_place(key: str) -> tuple[int, float] | None:
    for r, row in enumerate(KEY_ROWS):
        i = row.find(key) if len(key) == 1 else -1
        if i >= 0:
            return r, i + ROW_STAGGER[r]
    return None


def pose_key_bindings(interface, state: str | None = None,
                      scene: str | None = None) -> list[tuple[str, str]]:
    """(key chord, pose name) for the keys live in ``state`` that set a pose (on the
    scene named ``scene``: see ``live_keys``)."""
    return [(normalize_key(k.key), k.pose) for k in live_keys(interface, state, scene)
            if k.pose is not None]


def reach_key_bindings(interface, state: str | None = None,
                       scene: str | None = None) -> list[tuple[str, object]]:
    """(key chord, reach) for the keys live in ``state`` that reach for a prop's grasp
    point (``point: {prop, offset}``) and set no pose: the key map draws their target."""
    return [(normalize_key(k.key), k.reach) for k in live_keys(interface, state, scene)
            if k.pose is None and k.reach is not None and k.reach.point is not None]


def _pose_joints(interface, pose: str, state: str | None) -> dict[str, float]:
    """The pose's joint angles (degrees) with its role names read as the joints they
    mean in ``state`` (its ``roles`` binding, else the interface's starting one)."""
    binding = interface.start_binding
    if state is not None and interface.states.get(state) is not None:
        binding = interface.states[state].roles or binding
    rename = interface.renamer(binding)
    return {rename(j): v for j, v in interface.poses[pose].joint_degrees().items()}


TARGET = (214, 96, 40)  # the bar or rung a reach key goes for
HELD = (60, 64, 72)     # the one the hand counts from


def draw_reach_icon(surface: pygame.Surface, rect: pygame.Rect, points, offset: int) -> None:
    """A reach key's picture: the prop's grasp points near the one counted from (dark,
    the hand's), the target ringed and an arrow to it; a prop whose points run more
    across than up (monkey bars) is drawn across, a ladder's rungs upward."""
    show = sorted({-1, 0, 1, 2, offset})
    n = len(show)
    across = True
    if len(points) > 1:
        xs, ys = [p[0] for p in points], [p[1] for p in points]
        across = max(xs) - min(xs) >= max(ys) - min(ys)
    cx, cy = rect.center

    def place(k: int) -> tuple[int, int]:
        i = show.index(k)
        if across:
            step = rect.width / (n + 0.5)
            return (round(rect.left + step * (i + 0.75)), round(rect.top + rect.height * 0.45))
        step = rect.height / (n + 0.5)
        return (round(rect.left + rect.width * 0.55), round(rect.bottom - step * (i + 0.75)))

    a, b = place(show[0]), place(show[-1])
    pygame.draw.line(surface, CONTEXT, a, b, 1)  # the bar frame / the ladder's rail
    for k in show:
        pygame.draw.circle(surface, CONTEXT, place(k), 3)
    pygame.draw.circle(surface, HELD, place(0), 4)
    target = place(offset)
    pygame.draw.circle(surface, TARGET, target, 6, 2)
    if offset != 0:
        start = place(0)
        bend = (round((start[0] + target[0]) / 2), round((start[1] + target[1]) / 2) - 8) \
            if across else (round((start[0] + target[0]) / 2) - 8,
                            round((start[1] + target[1]) / 2))
        pygame.draw.lines(surface, TARGET, False, [start, bend, target], 1)


def draw_keymap(surface: pygame.Surface, interface, character: CharacterSpec,
                font: pygame.font.Font, topleft: tuple[int, int], cap: int = 58,
                state: str | None = None, scene=None) -> pygame.Rect | None:
    """Draw the pose keys as keycaps in their keyboard places, each with its pose's
    picture; one strip per modifier (none, ctrl, ...). With the ``scene``, keys that
    reach for a prop's grasp point are drawn too, as the bar or rung they go for.
    Returns the rect drawn (None if no key sets a pose)."""
    named = scene.name if scene is not None else None
    bindings = pose_key_bindings(interface, state, named)
    reaches = dict(reach_key_bindings(interface, state, named)) if scene is not None else {}
    reaches = {k: r for k, r in reaches.items() if r.point.prop in scene.props} \
        if reaches else {}
    bindings += [(chord, "") for chord in reaches]
    if not bindings:
        return None
    strips: dict[str, list] = {}
    loose: list = []
    for chord, pose in bindings:
        mods, key = _split_chord(chord)
        place = _key_place(key)
        if place is None:
            loose.append((chord, pose))
        else:
            strips.setdefault(mods, []).append((chord, pose, place))
    # one scale for every picture, so the poses compare
    by_pose = {p: _pose_joints(interface, p, state) for _, p in bindings if p}
    extent = max((pose_extent(character, j) for j in by_pose.values()), default=0) or 1.0
    gap, label_h = 4, 16
    x0, y = topleft
    blocks = []  # (label, [(chord, pose, (px, py))]) laid out relative to the block
    for mods in sorted(strips, key=lambda m: (m != "", m)):
        items = strips[mods]
        cols = [c for _, _, (r, c) in items]
        rows = sorted({r for _, _, (r, c) in items})
        cmin = min(cols)
        placed = [(chord, pose, ((c - cmin) * (cap + gap), rows.index(r) * (cap + gap)))
                  for chord, pose, (r, c) in items]
        blocks.append((mods + "+" if mods else "", placed, len(rows)))
    pads = [(ch, p) for ch, p in loose if ch.startswith("gamepad.")]
    loose = [(ch, p) for ch, p in loose if not ch.startswith("gamepad.")]
    if pads:  # gamepad buttons, labelled by their own name (a, b, start ...)
        blocks.append(("gamepad", [(ch, p, (i * (cap + gap), 0)) for i, (ch, p) in
                                   enumerate(pads)], 1))
    if loose:
        blocks.append(("other", [(ch, p, (i * (cap + gap), 0)) for i, (ch, p) in
                                 enumerate(loose)], 1))
    width = max(max(px for _, _, (px, _) in placed) + cap for _, placed, _ in blocks) + 16
    height = sum(label_h + n * (cap + gap) for _, _, n in blocks) + 12
    rect = pygame.Rect(x0, y, max(width, 120), height)
    panel = pygame.Surface(rect.size, pygame.SRCALPHA)
    panel.fill((255, 255, 255, 215))
    surface.blit(panel, rect.topleft)
    y += 6
    for label, placed, nrows in blocks:
        heading = {"": "pose keys" + (" and reach targets" if reaches else ""),
                   "gamepad": "gamepad buttons"}.get(label, label)
        surface.blit(font.render(heading, True, (20, 60, 120)), (x0 + 8, y))
        y += label_h
        for chord, pose, (px, py) in placed:
            cap_rect = pygame.Rect(x0 + 8 + px, y + py, cap, cap)
            pygame.draw.rect(surface, CAP, cap_rect, border_radius=5)
            pygame.draw.rect(surface, CAP_EDGE, cap_rect, 1, border_radius=5)
            if pose:
                draw_pose_icon(surface, cap_rect.inflate(-6, -6).move(3, 4), character,
                               by_pose[pose], extent)
            else:
                point = reaches[chord].point
                spots = list(scene.props[point.prop].grasp_points.values())
                draw_reach_icon(surface, cap_rect.inflate(-8, -14).move(0, 6), spots,
                                point.offset)
            key = chord.removeprefix("gamepad.") if label == "gamepad" else \
                _split_chord(chord)[1] if label != "other" else chord
            text = font.render(key, True, LABEL)
            if text.get_width() > cap - 6:  # a long name: as much as fits the cap
                text = text.subsurface((0, 0, cap - 6, text.get_height()))
            surface.blit(text, (cap_rect.x + 4, cap_rect.y + 2))
        y += nrows * (cap + gap)
    return rect
