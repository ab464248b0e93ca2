"""Two-link analytic IK and the reach primitive: a limb's end follows a Hermite-eased
path to a target point, with IK re-solved every step (the paper's "IK target select").

The chain is two actuated joints in a row (for Luxo: ankle, knee) and an end point on
the second joint's child link, all in the character's model frame, so link vectors
come straight from the joint anchors.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from puppet.data.actions import ChainSpec
from puppet.data.characters import CharacterSpec

Vec = tuple[float, float]


def _wrap(a: float) -> float:
    return math.remainder(a, 2.0 * math.pi)


def hermite(u: float) -> float:
    """Cubic Hermite ease from 0 to 1 with zero end velocities: 3u^2 - 2u^3."""
    u = min(1.0, max(0.0, u))
    return u * u * (3.0 - 2.0 * u)


def solve_two_link(a1: Vec, a2: Vec, d: Vec, prefer_q2: float = 0.0) -> tuple[float, float]:
    """Joint angles (q1, q2) putting the chain's end at ``d``.

    ``a1``, ``a2`` are the two link vectors at zero joint angles and ``d`` the target
    relative to the first joint, in the first joint's parent frame. Out-of-reach
    targets give the straightest (or most folded) reach toward them. Of the two
    bends, the one nearer ``prefer_q2`` is chosen (continuity with the current pose).
    """
    l1, l2 = math.hypot(*a1), math.hypot(*a2)
    p1, p2 = math.atan2(a1[1], a1[0]), math.atan2(a2[1], a2[0])
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


@dataclass(frozen=True)
class Chain:
    """A named two-joint limb of a character, in model coordinates."""

    name: str
    joints: tuple[str, str]
    parent_link: str  # the first joint's parent
    end_link: str  # the second joint's child
    anchor: Vec  # first joint's pivot
    a1: Vec
    a2: Vec
    end: Vec
    limits: tuple[tuple[float, float] | None, tuple[float, float] | None]

    @classmethod
    def from_spec(cls, name: str, spec: ChainSpec, character: CharacterSpec) -> Chain:
        j1, j2 = (character.joint(j) for j in spec.joints)
        lim = tuple(None if j.limits is None else tuple(math.radians(v) for v in j.limits)
                    for j in (j1, j2))
        return cls(name, tuple(spec.joints), j1.parent, j2.child, tuple(j1.anchor),
                   (j2.anchor[0] - j1.anchor[0], j2.anchor[1] - j1.anchor[1]),
                   (spec.end[0] - j2.anchor[0], spec.end[1] - j2.anchor[1]),
                   tuple(spec.end), lim)

    def end_world(self, character) -> Vec:
        p = character.bodies[self.end_link].local_to_world(self.end)
        return (p[0], p[1])

    def solve(self, character, target: Vec, prefer_q2: float) -> tuple[float, float]:
        """Joint targets (radians, within limits) reaching for a world point."""
        parent = character.bodies[self.parent_link]
        base = parent.local_to_world(self.anchor)
        c, s = math.cos(-parent.angle), math.sin(-parent.angle)
        dx, dy = target[0] - base[0], target[1] - base[1]
        d = (c * dx - s * dy, s * dx + c * dy)
        q = solve_two_link(self.a1, self.a2, d, prefer_q2)
        return tuple(q if lim is None else min(lim[1], max(lim[0], q))
                     for q, lim in zip(q, self.limits))


@dataclass
class Reach:
    """A running reach: from p0 to p1 (world, m) over steps [start, start + steps],
    then held until ``end``; may grasp p1 within ``tolerance`` m."""

    chain: str
    p0: Vec
    p1: Vec
    start: int
    steps: int
    end: int
    grasp: bool = False
    tolerance: float = 0.04

    def point(self, now: int) -> Vec:
        h = hermite((now - self.start) / self.steps)
        return (self.p0[0] + h * (self.p1[0] - self.p0[0]),
                self.p0[1] + h * (self.p1[1] - self.p0[1]))

    def to_state(self) -> list:
        return [self.chain, list(self.p0), list(self.p1), self.start, self.steps, self.end,
                self.grasp, self.tolerance]

    @classmethod
    def from_state(cls, s) -> Reach:
        return cls(s[0], tuple(s[1]), tuple(s[2]), *s[3:])
