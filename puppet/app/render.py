"""Draw a session's world onto any pygame surface (a window or an off-screen image)."""

from __future__ import annotations

import functools
import math

import pygame
import pymunk

from puppet.app.camera import BOTTOM_RESERVED_PX, Camera
from puppet.session import Session


@functools.lru_cache(maxsize=512)
def text(font: pygame.font.Font, words: str, color: tuple) -> pygame.Surface:
    """``font.render(words, True, color)``, kept: most of what a frame writes (a
    ruler's labels, the HUD's lines) is what the frame before wrote. Blitted only."""
    return font.render(words, True, color)

LAYER_ORDER = {"far": 0, "mid": 1, "near": 2}


def _shade(color, f: float):
    return tuple(max(0, min(255, int(c * f))) for c in color)


GHOST_ALPHA = 100  # how opaque a ghost (a log replaying beside the live run) is drawn


def draw_world(surface: pygame.Surface, session: Session, camera: Camera,
               font: pygame.font.Font | None = None, ghost: Session | None = None,
               overlay: bool = False) -> None:
    """The scene and the character; ``ghost`` (another session, e.g. a log replaying
    in lock-step) is drawn translucently behind the live character; ``overlay``: the
    balance overlay (``draw_balance``) on top."""
    scene = session.setup.scene
    surface.fill(scene.sky)
    _draw_grid(surface, camera, None)
    _draw_ground(surface, session, camera)
    taken: list[pygame.Rect] = []  # distance labels drawn: no label goes over another
    for ruler in scene.rulers:  # the rulers' labels first: the grid's give way to them
        _draw_ruler(surface, camera, scene, ruler, font, taken)
    _draw_grid(surface, camera, font, labels_only=True, scene=scene, taken=taken)
    for marker in scene.markers:
        _draw_marker(surface, camera, marker, scene.ground_height(marker.x) or 0.0, font)
    draw_stands(surface, session, camera)
    _draw_props(surface, session, camera)
    if ghost is not None and not ghost.sim.blown_up():
        draw_character(surface, ghost, camera, GHOST_ALPHA)
    draw_character(surface, session, camera)
    _draw_grips(surface, session, camera)
    _draw_drag(surface, session, camera)
    if overlay:
        draw_balance(surface, session, camera, font)


BALANCE_IN = (30, 150, 70)  # the extrapolated centre of mass over the support
BALANCE_OUT = (200, 50, 40)  # ... outside it (or nothing touches the ground)
COM_COLOR = (230, 120, 30)


def draw_balance(surface: pygame.Surface, session: Session, camera: Camera,
                 font: pygame.font.Font | None = None) -> None:
    """The balance overlay: the centre of mass (orange disc) and its plumb line to
    the ground, the support polygon (the thick segment between the outermost ground
    contacts), and the extrapolated centre of mass xcom = com + v * sqrt(l / g) on the
    ground (a triangle: green over the support, red outside it)."""
    from puppet.physics.balance import balance

    scene = session.setup.scene
    b = balance(session.character, scene.gravity, scene.ground_height)
    com = camera.to_screen(b.com)
    foot = camera.to_screen((b.com[0], b.ground_y))
    pygame.draw.line(surface, COM_COLOR, com, foot, 1)
    pygame.draw.circle(surface, COM_COLOR, com, 6, 2)
    pygame.draw.circle(surface, COM_COLOR, foot, 3)
    if b.support is not None:
        a = camera.to_screen((b.support[0], b.ground_y))
        c = camera.to_screen((b.support[1], b.ground_y))
        pygame.draw.line(surface, (40, 90, 200), (a[0], foot[1]), (max(c[0], a[0] + 2), foot[1]), 5)
    x = camera.to_screen((b.xcom, b.ground_y))[0]
    color = BALANCE_IN if b.inside else BALANCE_OUT
    y = foot[1]
    pygame.draw.polygon(surface, color, [(x, y - 2), (x - 7, y - 14), (x + 7, y - 14)])
    pygame.draw.line(surface, color, foot, (x, y), 2)
    if font is not None:
        surface.blit(font.render("xcom", True, color), (x - 14, y - 30))


def _free(rect: pygame.Rect, taken: list[pygame.Rect] | None) -> bool:
    """Whether ``rect`` keeps clear of the labels in ``taken`` (then it is added)."""
    if taken is None:
        return True
    if rect.inflate(6, 2).collidelist(taken) >= 0:
        return False
    taken.append(rect)
    return True


def _draw_grid(surface, camera: Camera, font, labels_only: bool = False,
               scene=None, taken: list[pygame.Rect] | None = None) -> None:
    """Faint vertical lines every 0.5 m, labelled every metre: shows distance travelled
    (a label that would cover one in ``taken``, a ruler's, is left out)."""
    x0, x1 = camera.visible_x()
    step = 0.5 if camera.view_height <= 3 else 1.0
    k = math.floor(x0 / step)
    while k * step <= x1:
        x = k * step
        sx, _ = camera.to_screen((x, 0))
        whole = abs(x - round(x)) < 1e-9
        if not labels_only:
            pygame.draw.line(surface, (205, 212, 222) if whole else (215, 221, 230),
                             (sx, 0), (sx, surface.get_height()), 1)
        if labels_only and whole and font is not None:  # on the ground, on a light
            label = text(font, f"{x:.0f} m", (40, 44, 52))  # tag: legible on any
            ground = scene.ground_height(x) if scene is not None else None  # ground
            top = camera.to_screen((x, ground))[1] + 6 if ground is not None else 0
            top = min(top, surface.get_height() - BOTTOM_RESERVED_PX - 22)  # above the bar
            tag = label.get_rect(topleft=(sx + 4, top)).inflate(6, 2)
            if not _free(tag, taken):
                k += 1
                continue
            back = pygame.Surface(tag.size, pygame.SRCALPHA)
            back.fill((255, 255, 255, 190))
            surface.blit(back, tag.topleft)
            surface.blit(label, label.get_rect(center=tag.center))
        k += 1


def _draw_ground(surface, session: Session, camera: Camera) -> None:
    bottom = surface.get_height() + 10
    for ground in session.setup.scene.ground:
        pts = [camera.to_screen(p) for p in ground.points]
        fill = pts + [(pts[-1][0], bottom), (pts[0][0], bottom)]
        pygame.draw.polygon(surface, _shade(ground.color, 1.25), fill)
        width = max(2, int(ground.thickness * camera.scale))
        pygame.draw.lines(surface, ground.color, False, pts, width)
        # Low friction ground (ice, snow) gets a light top line so it reads as slippery.
        if ground.friction < 0.2:
            pygame.draw.lines(surface, (235, 245, 255), False, pts, max(1, width // 2))


def _draw_ruler(surface, camera: Camera, scene, ruler, font,
                taken: list[pygame.Rect] | None = None) -> None:
    """Ticks standing on the ground, longer and labelled every ``label_every`` (a label
    that would cover one in ``taken`` - a ruler's drawn before - is left out, its tick
    still long)."""
    x0, x1 = camera.visible_x()
    h = camera.view_height
    for x, distance, labelled in ruler.ticks():
        if not x0 - 1.0 <= x <= x1 + 1.0:
            continue
        y = scene.ground_height(x) or 0.0
        a = camera.to_screen((x, y))
        b = camera.to_screen((x, y + (0.035 if labelled else 0.018) * h))
        pygame.draw.line(surface, _shade(ruler.color, 0.55), (a[0] + 1, a[1]), (b[0] + 1, b[1]), 1)
        pygame.draw.line(surface, ruler.color, a, b, 2 if labelled else 1)
        if labelled and font is not None:
            words = (f"{distance:g} m" if abs(distance) >= 1 or distance == 0
                     else f"{distance * 100:.0f} cm")
            label = text(font, words, tuple(ruler.color))
            rect = label.get_rect(midtop=(a[0], a[1] + 4))
            if _free(rect, taken):
                surface.blit(label, rect)


STAND_CLEAR = 1.0  # m: a static prop this far above the ground (out of reach, an
# apparatus) is drawn on a stand; a handhold lower down reads as it is
STAND_NARROW = 0.3  # m: a prop narrower than this stands on one post and two stays
STAY_SPREAD = 0.45  # of the post's height: how far out the stays reach the ground


def prop_stands(session: Session) -> list[tuple[tuple, tuple, int]]:
    """The stands the window draws under floating static props, as (world point,
    world point, width in mm) lines: a post under each end of a wide prop (the monkey
    bars), one post and two stays under a narrow one (a high bar seen end-on). For the
    eye only: nothing of them collides or is held."""
    scene = session.setup.scene
    out = []
    for name, prop in session.sim.props.items():
        spec = scene.props[name]
        if spec.body != "static" or not prop.shapes:
            continue
        points = []
        for shape in prop.shapes:
            if isinstance(shape, pymunk.Circle):
                c = prop.body.local_to_world(shape.offset)
                points += [(c.x - shape.radius, c.y - shape.radius),
                           (c.x + shape.radius, c.y - shape.radius)]
            else:
                a, b = (prop.body.local_to_world(p) for p in (shape.a, shape.b))
                points += [(a.x, a.y - shape.radius), (b.x, b.y - shape.radius)]
        post = round(2000 * max(shape.radius for shape in prop.shapes))  # mm: as thick
        # as the bar it holds
        left, right = min(p[0] for p in points), max(p[0] for p in points)
        bottom = min(p[1] for p in points)
        middle = (left + right) / 2
        ground = scene.ground_height(middle)
        if ground is None or bottom - ground < STAND_CLEAR:
            continue
        if right - left < STAND_NARROW:
            top = (middle, bottom)
            out.append((top, (middle, ground), post))
            spread = STAY_SPREAD * (bottom - ground)
            for side in (-1, 1):
                foot = middle + side * spread
                if scene.ground_height(foot) is not None:
                    out.append((top, (foot, scene.ground_height(foot)), max(1, post // 4)))
        else:
            for x in (left, right):
                under = [p[1] for p in points if abs(p[0] - x) < 1e-9]
                floor = scene.ground_height(x)
                if floor is not None:
                    out.append(((x, min(under)), (x, floor), post))
    return out


def draw_stands(surface, session: Session, camera: Camera) -> None:
    """``prop_stands`` drawn pale, behind the props and the character."""
    pale = _shade(session.setup.scene.sky, 0.82)
    for a, b, mm in prop_stands(session):
        width = max(1, round(mm / 1000 * camera.scale))
        pygame.draw.line(surface, pale, camera.to_screen(a), camera.to_screen(b), width)


def _draw_props(surface, session: Session, camera: Camera) -> None:
    """The scene's props in their colours (shapes the character passes through paler),
    each grasp point a small ring and each pivot a dark dot."""
    specs = session.setup.scene.props
    for name, prop in session.sim.props.items():
        spec = specs[name]
        body = prop.body
        for shape, shape_spec in zip(prop.shapes, spec.shapes):
            color = spec.color if shape_spec.collide else _shade(spec.color, 1.3)
            _draw_shape(surface, camera, body, shape, color, _shade(spec.color, 0.55))
        r = max(2, int(0.006 * camera.scale))
        for point in prop.points:
            pygame.draw.circle(surface, _shade(spec.color, 0.55),
                               camera.to_screen(prop.point_world(point)), r, 1)
        if prop.pin is not None:  # where it hangs (on another prop, it moves with it)
            pin = prop.pin
            pygame.draw.circle(surface, (60, 64, 72),
                               camera.to_screen(pin.a.local_to_world(pin.anchor_a)), r)


GRIP_COLOR = (70, 70, 80)  # a hold on the world (no prop)


def _draw_grips(surface, session: Session, camera: Camera) -> None:
    """Each point the character holds, drawn over the hand or foot holding it (a bar
    seen end-on is smaller than the hand around it): a ring in the prop's colour."""
    sim = session.sim
    if not sim.grasps:
        return
    specs = session.setup.scene.props
    r = max(5, int(0.03 * camera.scale))
    for name, (_, prop) in sim.grasps.items():
        color = specs[prop].color if prop in specs else GRIP_COLOR
        c = camera.to_screen(sim.grasp_point(name))
        pygame.draw.circle(surface, color, c, r)
        pygame.draw.circle(surface, _shade(color, 0.55), c, r, 2)


def _draw_marker(surface, camera: Camera, marker, ground_y: float, font) -> None:
    if marker.style == "line":
        a = camera.to_screen((marker.x, ground_y - 0.01 * camera.view_height))
        b = camera.to_screen((marker.x, ground_y + 0.006 * camera.view_height))
        width = max(3, int(0.05 * camera.scale))
        pygame.draw.line(surface, (250, 250, 250), a, b, width)
        pygame.draw.line(surface, (200, 60, 60), (a[0] + width / 2, a[1]),
                         (b[0] + width / 2, b[1]), 1)
        if font is not None:
            label = font.render(marker.label, True, (160, 40, 40))
            surface.blit(label, (b[0] - label.get_width() / 2, b[1] - 22))
        return
    a = camera.to_screen((marker.x, ground_y))
    b = camera.to_screen((marker.x, ground_y + 0.3 * camera.view_height))
    pygame.draw.line(surface, (200, 60, 60), a, b, 2)
    pygame.draw.polygon(surface, (220, 70, 70), [b, (b[0] + 18, b[1] + 7), (b[0], b[1] + 14)])
    if font is not None:
        surface.blit(font.render(marker.label, True, (160, 40, 40)), (b[0] + 4, b[1] - 20))


_layers: dict[tuple[int, int], pygame.Surface] = {}  # reused translucent layers, by size


def draw_character(surface: pygame.Surface, session: Session, camera: Camera,
                   alpha: int = 255) -> None:
    """Draw ``session``'s character; ``alpha`` < 255 draws it translucently (a ghost):
    drawn opaque on a transparent layer, then blended in as a whole, so overlapping
    links do not show through each other."""
    if alpha >= 255:
        _draw_character(surface, session, camera)
        return
    size = surface.get_size()
    layer = _layers.get(size)
    if layer is None:
        _layers.clear()
        layer = _layers[size] = pygame.Surface(size, pygame.SRCALPHA)
    layer.fill((0, 0, 0, 0))
    _draw_character(layer, session, camera, com_mark=False)
    layer.set_alpha(max(0, int(alpha)))
    surface.blit(layer, (0, 0))


def _draw_character(surface, session: Session, camera: Camera, com_mark: bool = True) -> None:
    character = session.character
    links = sorted(character.spec.links, key=lambda link: LAYER_ORDER[link.layer])
    for link in links:
        body = character.bodies[link.name]
        base = _shade(link.color, 0.72) if link.layer == "far" else link.color
        edge = _shade(base, 0.55)
        for shape in character.shapes[link.name]:
            _draw_shape(surface, camera, body, shape, base, edge)
    for joint in character.spec.joints:
        p = camera.to_screen(character.bodies[joint.parent].local_to_world(joint.anchor))
        r = max(2, int(0.008 * camera.scale))
        pygame.draw.circle(surface, (60, 64, 72), p, r)
    if not com_mark:
        return
    cx, cy = camera.to_screen(character.com())
    pygame.draw.line(surface, (230, 120, 30), (cx - 5, cy), (cx + 5, cy), 2)
    pygame.draw.line(surface, (230, 120, 30), (cx, cy - 5), (cx, cy + 5), 2)


def draw_capsule(surface, color, edge, a, b, r: float) -> None:
    """A segment of radius ``r`` pixels from ``a`` to ``b`` (screen points): a filled
    quad with round ends, its two long sides outlined in ``edge``."""
    dx, dy = b[0] - a[0], b[1] - a[1]
    n = math.hypot(dx, dy) or 1.0
    ox, oy = -dy / n * r, dx / n * r
    quad = [(a[0] + ox, a[1] + oy), (b[0] + ox, b[1] + oy),
            (b[0] - ox, b[1] - oy), (a[0] - ox, a[1] - oy)]
    pygame.draw.polygon(surface, color, quad)
    for p in (a, b):
        pygame.draw.circle(surface, color, p, r)
    pygame.draw.line(surface, edge, quad[0], quad[1], 1)
    pygame.draw.line(surface, edge, quad[2], quad[3], 1)


def _draw_shape(surface, camera: Camera, body: pymunk.Body, shape, color, edge) -> None:
    if isinstance(shape, pymunk.Circle):
        c = camera.to_screen(body.local_to_world(shape.offset))
        r = max(1, int(shape.radius * camera.scale))
        pygame.draw.circle(surface, color, c, r)
        pygame.draw.circle(surface, edge, c, r, 1)
        return
    if isinstance(shape, pymunk.Segment):
        a = camera.to_screen(body.local_to_world(shape.a))
        b = camera.to_screen(body.local_to_world(shape.b))
        draw_capsule(surface, color, edge, a, b, max(1.0, shape.radius * camera.scale))
        return
    pts = [camera.to_screen(body.local_to_world(v)) for v in shape.get_vertices()]
    pygame.draw.polygon(surface, color, pts)
    pygame.draw.polygon(surface, edge, pts, 1)


def _draw_drag(surface, session: Session, camera: Camera) -> None:
    spring = session.sim.drag_spring
    if spring is None:
        return
    a = camera.to_screen(session.sim.drag_body.position)
    b = camera.to_screen(spring.b.local_to_world(spring.anchor_b))
    pygame.draw.line(surface, (40, 120, 220), a, b, 2)
    pygame.draw.circle(surface, (40, 120, 220), a, 5, 2)
