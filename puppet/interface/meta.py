"""Meta actions on the world rather than on joint targets: gravity, friction and
seeded random perturbations (the paper's "modify physical parameters" and "toggle
random motion"). They change the pymunk space, so checkpoints capture them.
"""

from __future__ import annotations

import random

from puppet.data.actions import PerturbSpec


def set_gravity(sim, gravity: tuple[float, float]) -> None:
    sim.space.gravity = tuple(gravity)


def set_friction(sim, friction: float) -> None:
    """Friction of every ground segment (the character's own links keep theirs)."""
    for segment in sim.ground:
        segment.friction = friction


class Perturber:
    """Every ``every`` s, each link gets a random angular kick (Gaussian impulse).

    Seeded and stepped in sim time, so the same performance gives the same kicks;
    the generator's state is part of the runtime state (checkpoints restore it).
    """

    def __init__(self, spec: PerturbSpec, dt: float):
        self.spec = spec
        self.every = max(1, round(spec.every / dt))
        self.reset()

    def reset(self) -> None:
        self.rng = random.Random(self.spec.seed)
        self.used = False  # an unused generator's state is just the seed (cheap snapshots)
        self.on = self.spec.start_on
        self.next_kick: int | None = 0 if self.on else None

    def switch(self, how: str, now: int) -> None:
        self.on = (not self.on) if how == "toggle" else how == "on"
        self.next_kick = now if self.on else None

    def kick(self, character, now: int) -> None:
        sigma = self.spec.impulse
        self.used = True
        for name in character.link_order:
            body = character.bodies[name]
            body.angular_velocity += self.rng.gauss(0.0, sigma) / body.moment
        self.next_kick = now + self.every

    def get_state(self) -> list:
        return [self.on, self.next_kick, self.rng.getstate() if self.used else None]

    def set_state(self, state) -> None:
        self.on, self.next_kick, rng_state = state
        self.used = rng_state is not None
        self.rng = random.Random(self.spec.seed)
        if self.used:
            self.rng.setstate(_as_tuple(rng_state))


def _as_tuple(value):
    return tuple(_as_tuple(v) for v in value) if isinstance(value, list) else value
