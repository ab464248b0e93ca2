"""Scene props as pymunk bodies: bars, rungs, a wall, a pendulum, a rope's links.

Each prop is its own body (static or dynamic), so a grasp pins a hand to *that* body
and the hand does not collide with what it holds. Grasp points and segments are in
the prop's frame and are read through its body, so a grasp follows a moving prop.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import pymunk
from pymunk._chipmunk_cffi import lib as _cp

from puppet.data.scenes import SceneSpec

_to_world = _cp.cpBodyLocalToWorld  # what Body.local_to_world calls
BOX_MARGIN = 1e-6  # m: far more than a place's rounding (``beyond``)
_get_position, _get_angle = _cp.cpBodyGetPosition, _cp.cpBodyGetAngle


@dataclass
class Prop:
    name: str
    body: pymunk.Body
    points: dict[str, tuple[float, float]]  # name -> local point
    segments: list[tuple[tuple[float, float], tuple[float, float]]]  # local
    shapes: list[pymunk.Shape]
    pin: pymunk.PivotJoint | None = None

    def point_world(self, name: str) -> tuple[float, float]:
        p = _to_world(self.body._body, self.points[name])
        return (p.x, p.y)

    def nearest(self, world: tuple[float, float], exclude=None, placed=None
                ) -> tuple[float, tuple[float, float], str | None]:
        """(distance, world point, point name or None) of the graspable place nearest
        ``world``: a named point or the nearest point on a grasp segment; with
        ``exclude`` (x, y, r) none closer than r to (x, y). (An armed grasp
        asks this of every prop at every step until it holds: the points go through
        the C call pymunk's ``local_to_world`` makes, without its Vec2d; a static prop's
        are worked out once for where it stands, ``_placed``.)"""
        wx, wy = world
        best = (math.inf, world, None)
        hypot = math.hypot
        points, segments = placed or self._placed()  # (``placed``: _placed's, just made)
        for name, px, py in points:
            if exclude is not None and hypot(px - exclude[0], py - exclude[1]) < exclude[2]:
                continue
            d = hypot(px - wx, py - wy)
            if d < best[0]:
                best = (d, (px, py), name)
        for ax, ay, vx, vy, vv in segments:
            u = ((wx - ax) * vx + (wy - ay) * vy) / vv
            u = min(1.0, max(0.0, u))
            if exclude is not None:
                u = _outside(u, ax, ay, vx, vy, vv, exclude)
                if u is None:
                    continue
            p = (ax + u * vx, ay + u * vy)
            d = hypot(p[0] - wx, p[1] - wy)
            if d < best[0]:
                best = (d, p, None)
        return best

    def placed_within(self, world: tuple[float, float], r: float):
        """None when ``beyond(world, r)``, else where the prop's places are now, for
        ``nearest``: where the prop stands looked at once for both (an armed grasp
        asks at every step)."""
        placed = self._placed()
        return None if self.beyond(world, r, placed) else placed

    def beyond(self, world: tuple[float, float], r: float, placed=None) -> bool:
        """Whether every graspable place of this prop is surely farther than ``r`` from
        ``world`` (so ``nearest``'s answer is too): a static prop's places' box, worked
        out with ``_placed``, with a margin over the rounding of a point on a segment.
        False when unsure (a dynamic prop, a NaN)."""
        box = self._box(placed)
        if box is None:
            return False
        x0, y0, x1, y1 = box
        wx, wy = world
        dx = x0 - wx if wx < x0 else wx - x1 if wx > x1 else 0.0
        dy = y0 - wy if wy < y0 else wy - y1 if wy > y1 else 0.0
        r += BOX_MARGIN
        return dx * dx + dy * dy > r * r

    def _box(self, placed=None) -> tuple[float, float, float, float] | None:
        """A static prop's places' box (x0, y0, x1, y1), for where it stands now
        (``placed``: ``_placed``'s answer, just made)."""
        if not self._static():
            return None
        points, segments = placed or self._placed()
        cached = self._placed_cache
        if len(cached) < 3:
            xs = [x for _, x, _ in points] + [x for x, _, vx, _, _ in segments
                                                for x in (x, x + vx)]
            ys = [y for _, _, y in points] + [y for _, y, _, vy, _ in segments
                                                for y in (y, y + vy)]
            box = (min(xs), min(ys), max(xs), max(ys)) if xs else None
            cached = self._placed_cache = (*cached[:2], box)
        return cached[2]

    def _static(self) -> bool:
        """Whether the prop's body is static (asked once per body)."""
        got = self.__dict__.get("_static_of")
        if got is None or got[0] is not self.body:
            got = self._static_of = (self.body, self.body.body_type == pymunk.Body.STATIC)
        return got[1]

    def _placed(self) -> tuple[list, list]:
        """The grasp points ``(name, x, y)`` and segments ``(ax, ay, vx, vy, vx * vx +
        vy * vy)`` in the world, by the C calls ``nearest`` made for each (the same
        values); kept for a static body while its position and angle stay (its
        transform is made of them alone: a restored copy in the same place gives the
        same points)."""
        body = self.body._body
        static = self._static()
        if static:
            p = _get_position(body)
            key = (p.x, p.y, _get_angle(body))
            cached = self.__dict__.get("_placed_cache")
            if cached is not None and cached[0] == key:
                return cached[1]
        points = []
        for name, local in self.points.items():
            w = _to_world(body, local)
            points.append((name, w.x, w.y))
        segments = []
        for a, b in self.segments:
            pa, pb = _to_world(body, a), _to_world(body, b)
            ax, ay = pa.x, pa.y
            vx, vy = pb.x - ax, pb.y - ay
            segments.append((ax, ay, vx, vy, vx * vx + vy * vy))
        if static:
            self._placed_cache = (key, (points, segments))
        return points, segments


def _outside(u, ax, ay, vx, vy, vv, exclude) -> float | None:
    """The parameter nearest ``u`` (0..1) of a segment's point at least r from (x, y)
    (``exclude``), or None if the whole segment is within r. The distance to a point
    grows away from the nearest parameter, so the nearest allowed one is ``u`` itself
    or an end of the part of the segment inside the circle."""
    cx, cy, r = exclude
    dx, dy = ax - cx, ay - cy
    if (dx + u * vx) ** 2 + (dy + u * vy) ** 2 >= r * r:
        return u
    b = (dx * vx + dy * vy) / vv  # |d + s v|^2 = r^2: s^2 + 2 b s + c = 0
    c = (dx * dx + dy * dy - r * r) / vv
    root = math.sqrt(max(0.0, b * b - c))
    inside = (-b - root, -b + root)
    allowed = [s for s in inside if 0.0 <= s <= 1.0]
    return min(allowed, key=lambda s: abs(s - u)) if allowed else None


def build_props(spec: SceneSpec, space: pymunk.Space) -> dict[str, Prop]:
    """Add the scene's props to ``space`` (nothing at all for a scene without props)."""
    props: dict[str, Prop] = {}
    for name, p in spec.props.items():
        dynamic = p.body == "dynamic"
        body = pymunk.Body(body_type=pymunk.Body.DYNAMIC if dynamic else pymunk.Body.STATIC)
        body.position = p.position
        body.angle = math.radians(p.angle)
        shapes = []
        for s in p.shapes:
            if s.segment is not None:
                shape = pymunk.Segment(body, s.segment[0], s.segment[1], s.radius)
            else:
                shape = pymunk.Circle(body, s.radius, s.circle)
            shape.friction = s.friction
            if not s.collide:
                shape.sensor = True
            if dynamic:
                shape.mass = p.mass / len(p.shapes)
            shapes.append(shape)
        space.add(body, *shapes)
        pin = None
        if p.pivot is not None:
            other = props[p.pivot_to].body if p.pivot_to is not None else space.static_body
            pin = pymunk.PivotJoint(body, other, p.pivot)
            space.add(pin)
        props[name] = Prop(name, body, dict(p.grasp_points), list(p.grasp_segments),
                           shapes, pin)
    return props


def objects(props: dict[str, Prop]) -> list:
    """Every pymunk object of the props, in a fixed order (for snapshots)."""
    out: list = []
    for prop in props.values():
        out += [prop.body, *prop.shapes]
        if prop.pin is not None:
            out.append(prop.pin)
    return out


def bind(props: dict[str, Prop], restored: list) -> None:
    """Point the props at restored copies of ``objects(props)``."""
    it = iter(restored)
    for prop in props.values():
        prop.body = next(it)
        prop.shapes = [next(it) for _ in prop.shapes]
        if prop.pin is not None:
            prop.pin = next(it)
