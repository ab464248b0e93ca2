"""What KD tracking's pulls read at each control step, read fast and to the bit.

The pulls (``tracking.Tracker._pull``) need the performed pose's links (forward
kinematics of the channels) and every pulled link's centre of gravity and velocity
in the world. ``performed_pose`` is ``physics.kinematics.link_poses`` with each link's
turn's cosine and sine kept (worked out once, for its children, its centre and its
sole, as the same calls on the same angle give the same values); ``FigureRows`` reads
the figure in one call (``physics.body_state``) and says where each link's values are.
Each link's centre is then ``body_state.to_world``'s sums: Chipmunk's own.
"""

from __future__ import annotations

import math

from puppet.physics.body_state import BodyReader
from puppet.physics.kinematics import beyond


def joint_chain(order) -> list[tuple]:
    """``kinematics.joint_order``'s joints as plain values: (name, parent, child, anchor
    x, anchor y)."""
    return [(j.name, j.parent, j.child, j.anchor[0], j.anchor[1]) for j in order]


def radians_clamped(joints: dict, channels: dict, limits: dict) -> dict:
    """joint -> its channel's value in radians within the joint's limits (``Tracker.
    _clamped`` of ``math.radians``), for the joints whose channel has a value."""
    radians, get = math.radians, limits.get
    q = {}
    for j, n in joints.items():
        if n in channels:
            v = radians(channels[n])
            lim = get(j)
            q[j] = v if lim is None else lim[0] if v < lim[0] else lim[1] if v > lim[1] else v
    return q


def performed_pose(chain, root: str, origin, angle: float, cos: float, sin: float,
                   q: dict) -> dict:
    """link -> (x, y, angle, cos angle, sin angle): ``link_poses`` (the same arithmetic)
    with the root link at ``origin``/``angle`` (``cos``, ``sin`` its cosine and sine)
    and the joints at ``q`` (radians; a joint not given is 0)."""
    poses = {root: (origin[0], origin[1], angle, cos, sin)}
    mcos, msin = math.cos, math.sin
    for name, parent, child, ax, ay in chain:
        px, py, pa, c, s = poses[parent]
        wx, wy = px + c * ax - s * ay, py + s * ax + c * ay  # the hinge in the world
        a = pa + q.get(name, 0.0)
        c, s = mcos(a), msin(a)
        poses[child] = (wx - (c * ax - s * ay), wy - (s * ax + c * ay), a, c, s)
    return poses


def tracked_chain(chain, joints: dict, limits: dict) -> list[tuple]:
    """``chain`` (``joint_chain``) with each joint's channel (None: not tracked) and
    limits (radians, or None): what ``channel_pose`` reads."""
    return [(*row, joints.get(row[0]), limits.get(row[0])) for row in chain]


def channel_pose(chain, root: str, origin, angle: float, cos: float, sin: float,
                 channels: dict) -> dict:
    """``performed_pose`` with the joints at ``radians_clamped(joints, channels,
    limits)``, read straight from ``channels`` along ``chain`` (``tracked_chain``):
    the same values, without building the joint angles first."""
    poses = {root: (origin[0], origin[1], angle, cos, sin)}
    mcos, msin, radians = math.cos, math.sin, math.radians
    for _, parent, child, ax, ay, channel, lim in chain:
        px, py, pa, c, s = poses[parent]
        wx, wy = px + c * ax - s * ay, py + s * ax + c * ay  # the hinge in the world
        if channel is not None and channel in channels:
            v = radians(channels[channel])
            if lim is not None:
                v = lim[0] if v < lim[0] else lim[1] if v > lim[1] else v
            a = pa + v
        else:
            a = pa + 0.0  # (a joint not given is 0)
        c, s = mcos(a), msin(a)
        poses[child] = (wx - (c * ax - s * ay), wy - (s * ax + c * ay), a, c, s)
    return poses


def link_plan(rows, preset, scale: dict, joint_of: dict, period: float, feet) -> list:
    """``FigureRows.rows()`` with what the pulls work out per link that does not change:
    the joint above it, ``kp * scale``, ``dp * sqrt(scale)``, mass / control period
    (the same products and quotient as worked out each time: the same bits), and
    whether it is one of ``feet``."""
    plan = []
    for name, cb, i, m, gx, gy in rows:
        s = scale.get(name, 1.0)
        plan.append((name, cb, i, m, gx, gy, joint_of.get(name), preset.kp * s,
                     preset.dp * math.sqrt(s), m / period, name in feet))
    return plan


class FigureRows:
    """The pulled links of a character, read in bulk: ``rows()`` gives per link (name,
    C body, where its six values start in ``read()``, mass, centre of gravity x, y),
    worked out again when a restore re-binds the bodies."""

    def __init__(self, character, links: list[str]):
        self.character = character
        self.links = links
        self.reader = BodyReader()
        self._cached: tuple | None = None

    def _space(self):
        return self.character.bodies[self.character.root].space

    def rows(self) -> list[tuple]:
        bodies = self.character.bodies
        space = self._space()
        cached = self._cached
        if cached is None or cached[0] is not bodies or cached[1] is not space:
            rows = []
            for name in self.links:
                body = bodies[name]
                gx, gy = body.center_of_gravity
                rows.append((name, body._body, self.reader.offset(space, body), body.mass,
                             gx, gy))
            cached = self._cached = (bodies, space, rows)
        return cached[2]

    def read(self) -> list[float]:
        """Every body's ``x, y, angle, vx, vy, spin`` (``BodyReader.read``)."""
        return self.reader.read(self._space())


def mix(a: dict, b: dict, w: float) -> dict:
    """``b``'s channels, a fraction ``w`` of the way from ``a``'s (a channel ``a``
    lacks is ``b``'s)."""
    if w >= 1.0:
        return b
    out = {}
    for name, v in b.items():
        u = a.get(name, v)
        out[name] = u + (v - u) * w
    return out


def lowest_points(character, link: str) -> list[tuple[float, float, float]]:
    """A link's shape points (model frame) with the radius to take off: polygon
    vertices, segment ends, circle centres."""
    import pymunk

    out = []
    for shape in character.shapes[link]:
        if isinstance(shape, pymunk.Poly):
            out += [(v.x, v.y, shape.radius) for v in shape.get_vertices()]
        elif isinstance(shape, pymunk.Segment):
            out += [(shape.a.x, shape.a.y, shape.radius), (shape.b.x, shape.b.y, shape.radius)]
        elif isinstance(shape, pymunk.Circle):
            out.append((shape.offset.x, shape.offset.y, shape.radius))
    return out


def inertia_beyond(character, joint: str) -> float:
    """kg*m^2: the links a joint moves, about its hinge, with the figure straight (the
    tracker's gain scale; ZH02 and Nguyen use a constant)."""
    spec = character.spec
    ax, ay = spec.joint(joint).anchor
    total = 0.0
    for link in beyond(spec, joint):
        body = character.bodies[link]
        gx, gy = body.center_of_gravity  # model frame: the link's frame at rest
        total += body.moment + body.mass * ((gx - ax) ** 2 + (gy - ay) ** 2)
    return total
