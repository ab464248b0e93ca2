"""Balance, as biomechanics reads it: the centre of mass, its projection on the ground,
the support polygon and the extrapolated centre of mass.

In the plane the support polygon is a segment: from the leftmost to the rightmost point
where the character touches the ground. The extrapolated centre of mass (Hof, Gazendam
and Sinke, "The condition for dynamic stability", J. Biomech. 2005) is
``xcom = x + v / omega0`` with ``omega0 = sqrt(g / l)``: the centre of mass pushed
ahead by its velocity, with ``l`` its height above the ground (an inverted pendulum's
length). A character standing still is statically balanced while its centre of mass
projects inside the support; moving, it can still be brought to rest over its support
while xcom is inside it. Read-only: measuring balance never changes a run.
"""

from __future__ import annotations

import math
from dataclasses import dataclass


@dataclass(frozen=True)
class Balance:
    com: tuple[float, float]  # m, world
    ground_y: float  # the ground's height under the centre of mass, m
    support: tuple[float, float] | None  # (left x, right x) of the ground contacts, m
    xcom: float  # extrapolated centre of mass, x, m

    @property
    def inside(self) -> bool | None:
        """xcom over the support (None when nothing touches the ground)."""
        if self.support is None:
            return None
        return self.support[0] <= self.xcom <= self.support[1]


def ground_contacts(character) -> list[tuple[float, float]]:
    """World points where the character's links touch anything outside it."""
    points: list[tuple[float, float]] = []

    def collect(arbiter) -> None:
        for p in arbiter.contact_point_set.points:
            points.append((p.point_a.x, p.point_a.y))

    from puppet.physics.snapshot import restored_contacts

    for body in character.bodies.values():
        restored = restored_contacts(body)
        if restored is not None:  # right after a restore: the snapshot's contacts
            points += restored
        else:
            body.each_arbiter(collect)
    return points


def balance(character, gravity: tuple[float, float], ground_height) -> Balance:
    """``ground_height(x)``: the ground's height at x, or None (over a gap: the lowest
    contact or the character's lowest point stands in)."""
    com = character.com()
    vx, _ = character.com_velocity()
    contacts = ground_contacts(character)
    ground = ground_height(com[0])
    if ground is None:
        ground = min((p[1] for p in contacts), default=min(
            shape.bb.bottom for shapes in character.shapes.values() for shape in shapes))
    g = math.hypot(*gravity) or 9.81
    height = max(1e-3, com[1] - ground)
    xcom = com[0] + vx * math.sqrt(height / g)
    support = (min(p[0] for p in contacts), max(p[0] for p in contacts)) if contacts else None
    return Balance(com, ground, support, xcom)
