"""Grasp and release: a chain's end (a hand, a foot, Luxo's shade) holds a point.

An armed grasp waits until the end comes within its tolerance of one of its points
(world points, or the grasp points and segments of a scene prop), then pins it there.
The pin itself belongs to the Simulation (``attach`` / ``detach``), so checkpoints,
rewinds and replays cover held grasps exactly; this controller keeps only what is
armed.
"""

from __future__ import annotations

import math

from puppet.interface.ownership import Owner


class GraspController:
    BUSY = "armed"

    def __init__(self, chains, character, sim, dt: float):
        self.chains = chains
        self.character = character
        self.sim = sim
        self.dt = dt
        # chain -> [world points or None, prop name ("any") or None, tolerance, until|None,
        #           rigid, max torque|None]
        self.armed: dict[str, list] = {}

    @property
    def held(self) -> dict[str, tuple[float, float]]:
        """chain -> world point it holds now."""
        if self.sim is None:
            return {}
        return {name: self.sim.grasp_point(name) for name in self.sim.grasps
                if name in self.chains}

    def holds(self, chain: str) -> bool:
        return self.sim is not None and chain in self.sim.grasps

    def arm(self, spec, now: int) -> None:
        until = None if spec.within is None else now + round(spec.within / self.dt)
        points = None if spec.points is None else [list(p) for p in spec.points]
        self.armed[spec.chain] = [points, spec.prop, spec.tolerance, until, spec.rigid,
                                  spec.max_torque]

    def try_grasp(self, name: str, points=None, prop: str | None = None,
                  tolerance: float = 0.04, rigid: bool = False,
                  max_torque: float | None = None) -> bool:
        """Hold the first of ``points`` (pinned to the world, or to ``prop`` if one is
        named with them: a reach's target point), or else the nearest graspable place of
        ``prop`` ("any": of every prop), that the chain's end is within ``tolerance`` m
        of; ``rigid``: holding the end link's angle too (``Simulation.attach``). True if
        the chain holds something now."""
        if self.sim is None or self.holds(name):
            return self.holds(name)
        chain = self.chains[name]
        ex, ey = chain.end_world(self.character)
        if points is not None:
            for p in points:
                if math.hypot(ex - p[0], ey - p[1]) <= tolerance:
                    self.sim.attach(name, chain.end_link, chain.end, (p[0], p[1]), prop,
                                    rigid, max_torque)
                    return True
            return False
        props = self.sim.props
        found = [(*props[n].nearest((ex, ey))[:2], n)
                 for n in (props if prop == "any" else [prop])]
        if not found:
            return False
        distance, point, which = min(found, key=lambda f: f[0])
        if distance <= tolerance:
            self.sim.attach(name, chain.end_link, chain.end, point, which, rigid,
                            max_torque)
            return True
        return False

    def release(self, which: str) -> None:
        """Let go: unpin the chain ("all": every chain) and disarm its grasp."""
        names = list(self.chains) if which == "all" else [which]
        for name in names:
            self.armed.pop(name, None)
            if self.sim is not None:
                self.sim.detach(name)

    def tick(self, step: int) -> None:
        for name, (points, prop, tolerance, until, *rigid) in list(self.armed.items()):
            if self.try_grasp(name, points, prop, tolerance, *rigid) or \
                    (until is not None and step >= until):
                del self.armed[name]

    def next_wakeup(self, earliest: int) -> int | None:
        return earliest if self.armed else None

    def owners(self) -> set[Owner]:
        return set()  # a grasp pins a link; it owns no joint target

    def get_state(self):
        return _copy(self.armed)

    def set_state(self, state) -> None:
        self.armed = _copy(state)

    def adopt(self, old: GraspController, same, now: int) -> set[Owner]:
        """Armed and held grasps of chains defined the same way carry on; a chain that
        is gone or changed lets go."""
        self.armed = _copy({n: g for n, g in old.armed.items() if same("chain", n)})
        for name in list(old.held):
            if not same("chain", name):
                old.release(name)
        return set()

    def stop(self) -> None:
        self.armed = {}


def _copy(armed: dict) -> dict:
    return {n: [None if pts is None else [list(p) for p in pts], *rest]
            for n, (pts, *rest) in armed.items()}
