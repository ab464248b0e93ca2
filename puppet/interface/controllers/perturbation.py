"""Random motion (the paper's "toggle random motion"): every ``every`` s each link gets
a random angular kick (a Gaussian impulse).

Seeded and stepped in sim time, so the same performance gives the same kicks; the
generator's state is part of the runtime state (checkpoints restore it).
"""

from __future__ import annotations

import random

from puppet.data.actions import PerturbSpec
from puppet.interface.controllers.base import WAITED
from puppet.interface.ownership import Owner


class Perturber:
    BUSY = "on"

    def __init__(self, spec: PerturbSpec, character, dt: float):
        self.spec = spec
        self.character = character
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

    def tick(self, step: int) -> str | None:
        if not (self.on and self.next_kick is not None and step >= self.next_kick):
            return WAITED  # no kick due
        sigma = self.spec.impulse
        self.used = True
        character = self.character
        for name in character.link_order:
            body = character.bodies[name]
            body.angular_velocity += self.rng.gauss(0.0, sigma) / body.moment
        self.next_kick = step + self.every
        return None

    def next_wakeup(self, earliest: int) -> int | None:
        return self.next_kick if self.on else None

    def owners(self) -> set[Owner]:
        return set()  # kicks velocities, owns no joint target

    def get_state(self) -> list:
        return [self.on, self.next_kick, self.rng.getstate() if self.used else None]

    def set_state(self, state) -> None:
        self.on, self.next_kick, rng_state = state
        self.used = rng_state is not None
        self.rng = random.Random(self.spec.seed)
        if self.used:
            self.rng.setstate(_as_tuple(rng_state))

    def adopt(self, old: Perturber, same, now: int) -> set[Owner]:
        if same("perturbation", ""):
            self.set_state(old.get_state())
        elif old.on:
            self.switch("on", now)
        return set()

    def stop(self) -> None:
        self.reset()


def _as_tuple(value):
    return tuple(_as_tuple(v) for v in value) if isinstance(value, list) else value
