"""Inverse kinematics for limbs of any length, solved at every control step of a reach.

A chain is two or more actuated joints in a row (Luxo's ankle and knee; an arm with
shoulder and elbow; a leg with hip, knee and ankle) and an end point on the last
joint's child link, all in the character's model frame, so link vectors come straight
from the joint anchors.

The solver is damped least squares (Levenberg-Marquardt on the end point), with the
joint limits enforced by projection after every iteration and a joint that sits at a
limit pushing outward left out of the next one. Why DLS rather than cyclic coordinate
descent: it moves all joints together (CCD curls the distal joints first, which looks
wrong on an arm), it degrades gracefully at singularities (a straight arm) and out of
reach (the end stops at the nearest reachable point), and in the plane each iteration
only inverts a 2x2 matrix. It starts from the joints' current targets, so a limb keeps
its bend from one step to the next; a two-joint chain starts from the closed-form
solution nearest its current bend, which is already exact when no limit is in the way.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from pymunk._chipmunk_cffi import lib as _cp

from puppet.data.actions import ChainSpec
from puppet.data.characters import CharacterSpec
from puppet.interface.ik_two import TwoLink as _TwoLink
from puppet.physics.kernel import cos as _cos
from puppet.physics.kernel import sin as _sin

Vec = tuple[float, float]
_to_world, _angle = _cp.cpBodyLocalToWorld, _cp.cpBodyGetAngle  # what pymunk's Body calls
DAMPING = 0.02  # m: the DLS damping lambda (small: accurate; larger: smoother near singular)
MAX_ITERATIONS = 40
TOLERANCE = 1e-5  # m: close enough


def _wrap(a: float) -> float:
    return math.remainder(a, 2.0 * math.pi)


def hermite(u: float) -> float:
    """Cubic Hermite ease from 0 to 1 with zero end velocities: 3u^2 - 2u^3."""
    u = min(1.0, max(0.0, u))
    return u * u * (3.0 - 2.0 * u)


def solve_two_link(a1: Vec, a2: Vec, d: Vec, prefer_q2: float = 0.0) -> tuple[float, float]:
    """Joint angles (q1, q2) putting a two-link chain's end at ``d``, in closed form.

    ``a1``, ``a2`` are the two link vectors at zero joint angles and ``d`` the target
    relative to the first joint, in the first joint's parent frame. Out-of-reach
    targets give the straightest (or most folded) reach toward them. Of the two
    bends, the one nearer ``prefer_q2`` is chosen (continuity with the current pose).
    """
    return _two_link(math.hypot(*a1), math.hypot(*a2), math.atan2(a1[1], a1[0]),
                     math.atan2(a2[1], a2[0]), d, prefer_q2)


def _two_link(l1: float, l2: float, p1: float, p2: float, d: Vec,
              prefer_q2: float) -> tuple[float, float]:
    """``solve_two_link`` with the links' lengths and directions worked out already
    (a Chain keeps them: a reach solves at every control step)."""
    dist = math.hypot(*d)
    c = (dist * dist - l1 * l1 - l2 * l2) / (2.0 * l1 * l2)
    c = min(1.0, max(-1.0, c))
    best = None
    for beta in (math.acos(c), -math.acos(c)):
        q2 = _wrap(beta + p1 - p2)
        reach_angle = p1 + math.atan2(l2 * math.sin(beta), l1 + l2 * math.cos(beta))
        q1 = _wrap(math.atan2(d[1], d[0]) - reach_angle)
        cost = abs(_wrap(q2 - prefer_q2))
        if best is None or cost < best[0]:
            best = (cost, q1, q2)
    return best[1], best[2]


def forward(links: list[Vec], q) -> tuple[list[Vec], Vec]:
    """Joint positions and the end point of a chain with link vectors ``links`` (at
    zero angles) turned by joint angles ``q``, from the first joint at the origin."""
    x = y = angle = 0.0
    joints = []
    for (ax, ay), qi in zip(links, q):
        joints.append((x, y))
        angle += qi
        c, s = math.cos(angle), math.sin(angle)
        x += c * ax - s * ay
        y += s * ax + c * ay
    return joints, (x, y)


def solve_dls(links: list[Vec], d: Vec, start, limits) -> list[float]:
    """Joint angles putting the end of the chain ``links`` at (or nearest to) ``d``,
    within ``limits`` ((lo, hi) radians or None per joint), from ``start``.

    A step is taken only if it brings the end nearer (else it is halved, down to a
    thousandth): far out of reach a full DLS step is large, and clamped to the limits
    it can throw the limb to the far side, where the limits then hold it (a cat's arm
    reaching up and forward ended pointing back, 1.24 m from a target 0.98 m beyond
    its reach)."""
    q = [_clamp(v, lim) for v, lim in zip(start, limits)]
    lam2 = DAMPING * DAMPING
    joints, (ex, ey) = forward(links, q)
    rx, ry = d[0] - ex, d[1] - ey
    err2 = rx * rx + ry * ry
    for _ in range(MAX_ITERATIONS):
        if err2 < TOLERANCE * TOLERANCE:
            break
        # Column i of the Jacobian: the end's velocity for a unit turn of joint i.
        cols = [(-(ey - jy), ex - jx) for jx, jy in joints]
        for i, (lim, (cx, cy)) in enumerate(zip(limits, cols)):
            if lim is not None:  # at a limit and the error pushes past it: leave it out
                push = cx * rx + cy * ry
                if (q[i] <= lim[0] and push < 0) or (q[i] >= lim[1] and push > 0):
                    cols[i] = (0.0, 0.0)
        a = lam2 + sum(cx * cx for cx, _ in cols)
        b = sum(cx * cy for cx, cy in cols)
        c = lam2 + sum(cy * cy for _, cy in cols)
        det = a * c - b * b
        w0, w1 = (c * rx - b * ry) / det, (a * ry - b * rx) / det
        steps = [cx * w0 + cy * w1 for cx, cy in cols]
        scale = 1.0
        while True:
            new = [_clamp(v + scale * step, lim) for v, step, lim in zip(q, steps, limits)]
            new_joints, (nx, ny) = forward(links, new)
            nrx, nry = d[0] - nx, d[1] - ny
            new_err2 = nrx * nrx + nry * nry
            if new_err2 < err2 or scale < 1e-3:
                break
            scale *= 0.5
        if new_err2 >= err2:  # no step brings it nearer: as near as it gets
            break
        moved = sum(abs(v - w) for v, w in zip(new, q))
        q, joints, ex, ey, rx, ry, err2 = new, new_joints, nx, ny, nrx, nry, new_err2
        if moved < 1e-9:  # stuck against limits: as near as it gets
            break
    return q


def _clamp(v: float, lim) -> float:
    return v if lim is None else min(lim[1], max(lim[0], v))


@dataclass(frozen=True)
class Chain:
    """A named limb of a character (two or more joints in a row), in model coordinates."""

    name: str
    joints: tuple[str, ...]
    parent_link: str  # the first joint's parent
    end_link: str  # the last joint's child
    anchor: Vec  # first joint's pivot
    links: tuple[Vec, ...]  # joint to joint, then last joint to the end point
    end: Vec
    limits: tuple[tuple[float, float] | None, ...]

    def __post_init__(self):
        # a two-joint chain's lengths and zero-angle directions, for the closed form
        if len(self.links) == 2:
            (x1, y1), (x2, y2) = self.links
            object.__setattr__(self, "_closed", (math.hypot(x1, y1), math.hypot(x2, y2),
                                                 math.atan2(y1, x1), math.atan2(y2, x2)))
            object.__setattr__(self, "_two", _TwoLink(self._closed, self.links, self.limits,
                                                      DAMPING, TOLERANCE, MAX_ITERATIONS))

    @classmethod
    def from_spec(cls, name: str, spec: ChainSpec, character: CharacterSpec) -> Chain:
        joints = [character.joint(j) for j in spec.joints]
        lim = tuple(None if j.limits is None else tuple(math.radians(v) for v in j.limits)
                    for j in joints)
        points = [tuple(j.anchor) for j in joints] + [tuple(spec.end)]
        links = tuple((b[0] - a[0], b[1] - a[1]) for a, b in zip(points, points[1:]))
        return cls(name, tuple(spec.joints), joints[0].parent, joints[-1].child,
                   points[0], links, tuple(spec.end), lim)

    def two_params(self, k):
        """A two-link chain's numbers as the compiled kernel ``k`` reads them
        (``pk_two_link``)."""
        got = self._two._c
        if got is None or got[0] is not k:
            got = self._two._compiled(k)
        return got[2]

    def end_world(self, character) -> Vec:
        p = _to_world(character.bodies[self.end_link]._body, self.end)  # (local_to_world's)
        return (p.x, p.y)

    def solve(self, character, target: Vec, current) -> tuple[float, ...]:
        """Joint targets (radians, within limits) reaching for a world point, starting
        from ``current`` (the joints' targets now)."""
        parent = character.bodies[self.parent_link]._body  # (pymunk's own C calls)
        base = _to_world(parent, self.anchor)
        angle = -_angle(parent)
        c, s = _cos(angle), _sin(angle)  # (NaN for a blown-up angle, as the kernel's)
        dx, dy = target[0] - base.x, target[1] - base.y
        if len(self.links) == 2:  # (ik_two: the same arithmetic, unrolled)
            return self._two.solve(c * dx - s * dy, s * dx + c * dy, current[1])
        d = (c * dx - s * dy, s * dx + c * dy)
        return tuple(solve_dls(list(self.links), d, current, self.limits))
