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
from puppet.app.render import LAYER_ORDER, draw_capsule
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
    left, bottom, right, top = pose_box(spec, pose_joints_deg)
    return max(math.hypot(x, y) for x in (left, right) for y in (bottom, top))


def pose_box(spec: CharacterSpec, pose_joints_deg: dict[str, float]) -> tuple:
    """(left, bottom, right, top) m of what a pose's picture draws (the moved links and
    their context), relative to its pivot: what must fit in the keycap."""
    moved, context, pivot = pose_links(spec, pose_joints_deg)
    frames = _frames_for(spec, pose_joints_deg)
    xs, ys = [0.0], [0.0]
    for name in moved + context:
        for shape in spec.link(name).shapes:
            r = getattr(shape, "radius", 0.0) or 0.0
            for p in _shape_points(shape):
                x, y = _apply(frames[name], p)
                xs += [x - pivot[0] - r, x - pivot[0] + r]
                ys += [y - pivot[1] - r, y - pivot[1] + r]
    return min(xs), min(ys), max(xs), max(ys)


def _frames_for(spec: CharacterSpec, pose_joints_deg: dict[str, float]):
    angles = {n: math.radians(v) for n, v in spec.start.joints.items()}
    angles.update({n: math.radians(v) for n, v in pose_joints_deg.items()})
    return link_frames(spec, angles)


def draw_pose_icon(surface: pygame.Surface, rect: pygame.Rect, spec: CharacterSpec,
                   pose_joints_deg: dict[str, float], extent: float | None = None,
                   box: tuple | None = None) -> None:
    """Draw the links a pose moves, filled as the window draws them (far links darker,
    behind), with the link they hang from in grey for orientation and their hinges as
    dots. ``box``: the (left, bottom, right, top) around the pivot that all the key
    map's pictures fit (one scale, so they compare; default: this pose's own box);
    ``extent``: instead, metres from the pivot that fit (the pivot a third down)."""
    moved, context, pivot = pose_links(spec, pose_joints_deg)
    if not moved:
        return
    frames = _frames_for(spec, pose_joints_deg)
    if extent is not None and box is None:
        box = (-extent, -1.4 * extent, extent, 0.6 * extent)
    left, bottom, right, top = box or pose_box(spec, pose_joints_deg)
    scale = min(rect.width / max(1e-6, right - left), rect.height / max(1e-6, top - bottom))
    cx = rect.centerx - (left + right) / 2 * scale  # the pivot's place: the box centred
    cy = rect.centery + (bottom + top) / 2 * scale

    def to_px(p):
        return (round(cx + (p[0] - pivot[0]) * scale), round(cy - (p[1] - pivot[1]) * scale))

    clip = surface.get_clip()
    surface.set_clip(rect)
    for name in context:
        for shape in spec.link(name).shapes:
            _fill(surface, shape, [to_px(_apply(frames[name], p)) for p in _shape_points(shape)],
                  CONTEXT, scale)
    for name in sorted(moved, key=lambda n: LAYER_ORDER[spec.link(n).layer]):
        link = spec.link(name)
        color = tuple(int(c * FAR_SHADE) for c in link.color) if link.layer == "far" \
            else tuple(link.color)
        for shape in link.shapes:
            _fill(surface, shape, [to_px(_apply(frames[name], p)) for p in _shape_points(shape)],
                  color, scale)
    dot = max(2, round(0.012 * scale))
    for joint in spec.joints:
        if joint.child in moved:
            pygame.draw.circle(surface, (60, 64, 72), to_px(_apply(frames[joint.parent],
                                                                    joint.anchor)), dot)
    surface.set_clip(clip)


MIN_STROKE = 3  # pixels: the thinnest limb a picture draws (a thin limb stays visible)


def _fill(surface, shape, pts, color, scale) -> None:
    """A shape filled as the world view draws it: a segment as a capsule of its radius
    (at least MIN_STROKE wide), a circle a disc, a box or polygon a filled outline."""
    edge = tuple(max(0, int(c * 0.55)) for c in color)
    if shape.type == "segment":
        draw_capsule(surface, color, edge, *pts, max(MIN_STROKE / 2, shape.radius * scale))
    elif shape.type == "circle":
        r = max(2, round(shape.radius * scale))
        pygame.draw.circle(surface, color, pts[0], r)
        pygame.draw.circle(surface, edge, pts[0], r, 1)
    else:
        pygame.draw.polygon(surface, color, pts)
        pygame.draw.polygon(surface, edge, pts, 1)


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


CAPS = (120, 108, 96, 84, 72, 64, 58)  # keycap sizes tried, largest first, to fit the room
GAP, LABEL_H = 4, 16  # pixels between caps; a strip's heading


def _blocks(interface, state: str | None, scene):
    """(strips, reaches, poses): the pose keys (and reach keys, with the ``scene``) in
    strips - one per modifier, then gamepad buttons, then other keys - each a
    (label, [(chord, pose, (column, row))], rows) with places counted in keys."""
    named = scene.name if scene is not None else None
    bindings = pose_key_bindings(interface, state, named)
    reaches = dict(reach_key_bindings(interface, state, named)) if scene is not None else {}
    reaches = {k: r for k, r in reaches.items() if r.point.prop in scene.props} \
        if reaches else {}
    bindings += [(chord, "") for chord in reaches]
    strips: dict[str, list] = {}
    loose: list = []
    for chord, pose in bindings:
        mods, key = _split_chord(chord)
        place = _key_place(key)
        if place is None:
            loose.append((chord, pose))
        else:
            strips.setdefault(mods, []).append((chord, pose, place))
    blocks = []
    for mods in sorted(strips, key=lambda m: (m != "", m)):
        items = strips[mods]
        cmin = min(c for _, _, (r, c) in items)
        rows = sorted({r for _, _, (r, c) in items})
        blocks.append((mods + "+" if mods else "",
                       [(chord, pose, (c - cmin, rows.index(r)))
                        for chord, pose, (r, c) in items], len(rows)))
    pads = [(ch, p) for ch, p in loose if ch.startswith("gamepad.")]
    loose = [(ch, p) for ch, p in loose if not ch.startswith("gamepad.")]
    if pads:  # gamepad buttons, labelled by their own name (a, b, start ...)
        blocks.append(("gamepad", [(ch, p, (i, 0)) for i, (ch, p) in enumerate(pads)], 1))
    if loose:
        blocks.append(("other", [(ch, p, (i, 0)) for i, (ch, p) in enumerate(loose)], 1))
    poses = {p: _pose_joints(interface, p, state) for _, p in bindings if p}
    return blocks, reaches, poses


def _size(blocks, cap: int) -> tuple[int, int]:
    """The panel's (width, height) with keycaps ``cap`` pixels wide."""
    width = max(max(c for _, _, (c, _) in placed) * (cap + GAP) + cap
                for _, placed, _ in blocks) + 16
    height = sum(LABEL_H + n * (cap + GAP) for _, _, n in blocks) + 12
    return max(width, 120), height


KEYBOARD_ENOUGH = 84  # pixels: keycaps this large on the keyboard's layout are legible;
# smaller, the keys go in rows (keyboard order) with larger pictures if that fits


def _as_rows(blocks, cap: int, width: int):
    """``blocks`` with each strip's keys in keyboard order (its rows top to bottom, each
    left to right), as many to a row as fit ``width`` pixels."""
    per = max(1, (width - 16 + GAP) // (cap + GAP))
    out = []
    for label, placed, _ in blocks:
        ordered = sorted(placed, key=lambda item: (item[2][1], item[2][0]))
        out.append((label, [(chord, pose, (i % per, i // per))
                            for i, (chord, pose, _) in enumerate(ordered)],
                    (len(ordered) + per - 1) // per))
    return out


def keymap_layout(blocks, room: tuple[int, int] | None) -> tuple[int, list]:
    """(keycap size, blocks placed): the largest of CAPS whose panel fits ``room``
    (width, height) on the keyboard's layout; if that is under KEYBOARD_ENOUGH, the
    keys in rows instead when that fits larger pictures. None: the smallest caps."""
    if room is None:
        return CAPS[-1], blocks
    keyboard = next((cap for cap in CAPS if _fits(blocks, cap, room)), CAPS[-1])
    if keyboard >= KEYBOARD_ENOUGH:
        return keyboard, blocks
    for cap in CAPS:
        if cap <= keyboard:
            break
        rows = _as_rows(blocks, cap, room[0])
        if _fits(rows, cap, room):
            return cap, rows
    return keyboard, blocks


def _fits(blocks, cap: int, room: tuple[int, int]) -> bool:
    w, h = _size(blocks, cap)
    return w <= room[0] and h <= room[1]


KEYMAPS_KEPT = 8  # key map panels kept (draw_keymap's cache): one per state of a gait


def draw_keymap(surface: pygame.Surface, interface, character: CharacterSpec,
                font: pygame.font.Font, topleft: tuple[int, int], cap: int | None = None,
                state: str | None = None, scene=None, room: tuple[int, int] | None = None,
                cache: dict | None = None) -> pygame.Rect | None:
    """Draw the pose keys as keycaps in their keyboard places, each with its pose's
    picture; one strip per modifier (none, ctrl, ...). With the ``scene``, keys that
    reach for a prop's grasp point are drawn too, as the bar or rung they go for.
    ``cap``: the keycaps' size in pixels; default the largest that fits ``room`` (the
    pixels the panel may take). ``cache``: a dict that keeps the panel drawn, by all it
    depends on, so that a frame with the key map shown costs one blit.
    Returns the rect drawn (None if no key sets a pose)."""
    # (the specs by identity, checked on a hit: they are not hashable)
    key = (id(interface), state, scene.name if scene is not None else None, cap, room,
           font, id(character))
    got = cache.get(key) if cache is not None else None
    if got is not None and got[0] is interface and got[1] is character:
        panel = got[2]
    else:
        panel = _render_keymap(interface, character, font, cap, state, scene, room)
        if cache is not None:  # one panel per state: a gait goes round its states
            if len(cache) >= KEYMAPS_KEPT:
                del cache[next(iter(cache))]  # the oldest
            cache[key] = (interface, character, panel)
    if panel is None:
        return None
    surface.blit(panel, topleft)
    return panel.get_rect(topleft=topleft)


def _render_keymap(interface, character, font, cap, state, scene, room):
    """The key map's panel, drawn on a surface of its own (None: no pose keys)."""
    blocks, reaches, by_pose = _blocks(interface, state, scene)
    if not blocks:
        return None
    if cap is None:
        cap, blocks = keymap_layout(blocks, room)
    width, height = _size(blocks, cap)
    panel = pygame.Surface((width, height), pygame.SRCALPHA)
    panel.fill((255, 255, 255, 215))
    # one box for every picture, so the poses compare
    boxes = [pose_box(character, j) for j in by_pose.values()]
    box = (min(b[0] for b in boxes), min(b[1] for b in boxes), max(b[2] for b in boxes),
           max(b[3] for b in boxes)) if boxes else None
    y = 6
    for label, placed, nrows in blocks:
        heading = {"": "pose keys" + (" and reach targets" if reaches else ""),
                   "gamepad": "gamepad buttons"}.get(label, label)
        panel.blit(font.render(heading, True, (20, 60, 120)), (8, y))
        y += LABEL_H
        for chord, pose, (col, row) in placed:
            cap_rect = pygame.Rect(8 + col * (cap + GAP), y + row * (cap + GAP), cap, cap)
            pygame.draw.rect(panel, CAP, cap_rect, border_radius=5)
            pygame.draw.rect(panel, CAP_EDGE, cap_rect, 1, border_radius=5)
            if pose:  # the picture below the key's name
                draw_pose_icon(panel, pygame.Rect(cap_rect.x + 4, cap_rect.y + 16,
                                                  cap - 8, cap - 20), character,
                               by_pose[pose], box=box)
            else:
                point = reaches[chord].point
                spots = list(scene.props[point.prop].grasp_points.values())
                draw_reach_icon(panel, cap_rect.inflate(-8, -14).move(0, 6), spots,
                                point.offset)
            name = chord.removeprefix("gamepad.") if label == "gamepad" else \
                _split_chord(chord)[1] if label != "other" else chord
            text = font.render(name, True, LABEL)
            if text.get_width() > cap - 6:  # a long name: as much as fits the cap
                text = text.subsurface((0, 0, cap - 6, text.get_height()))
            panel.blit(text, (cap_rect.x + 4, cap_rect.y + 2))
        y += nrows * (cap + GAP)
    return panel
