"""Grasp and release: a chain's end (a hand, a foot, Luxo's shade) holds a point.

An armed grasp waits until the end comes within its tolerance of one of its points
(world points, or the grasp points and segments of a scene prop), then pins it there.
The pin itself belongs to the Simulation (``attach`` / ``detach``), so checkpoints,
rewinds and replays cover held grasps exactly; this controller keeps only what is
armed,
and where each chain last let go (a grasp with ``skip_released`` catches any place but
that one: a climber's "let go and take the next rung" on one press).
"""

from __future__ import annotations

import math

from pymunk._chipmunk_cffi import lib as _cp

from puppet.interface.controllers.base import WAITED
from puppet.interface.ownership import Owner

_to_world = _cp.cpBodyLocalToWorld


def _distance(found: tuple) -> float:
    return found[0]


class GraspController:
    BUSY = "armed"

    def __init__(self, chains, character, sim, dt: float):
        self.chains = chains
        self.character = character
        self.sim = sim
        self.dt = dt
        # chain -> [world points or None, prop name ("any") or None, tolerance, until|None,
        #           rigid, max torque|None, skip_released]
        self.armed: dict[str, list] = {}
        # chain -> (prop name or None: the world, the point it held in the prop's frame)
        # at its last let-go
        self.released: dict[str, tuple[str | None, tuple[float, float]]] = {}

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
                                  spec.max_torque, spec.skip_released]

    def try_grasp(self, name: str, points=None, prop: str | None = None,
                  tolerance: float = 0.04, rigid: bool = False,
                  max_torque: float | None = None, skip_released: bool = False) -> bool:
        """Hold the first of ``points`` (pinned to the world, or to ``prop`` if one is
        named with them: a reach's target point), or else the nearest graspable place of
        ``prop`` ("any": of every prop), that the chain's end is within ``tolerance`` m
        of; ``rigid``: holding the end link's angle too (``Simulation.attach``);
        ``skip_released``: not a place within ``tolerance`` of where the chain last let
        go (``released_point``). True if the chain holds something now."""
        sim = self.sim
        if sim is None or name in sim.grasps:  # (holds)
            return sim is not None
        chain = self.chains[name]
        ex, ey = chain.end_world(self.character)
        props = sim.props
        if points is None:
            # (a prop whose places are all farther than the tolerance cannot be the one
            # caught: not asked, ``Prop.beyond``; with none left, none is caught)
            near = []
            for n in (props if prop == "any" else [prop]):
                placed = props[n].placed_within((ex, ey), tolerance)
                if placed is not None:
                    near.append((n, placed))
            if not near:
                return False
        skip = self.released_point(name) if skip_released else None
        exclude = None if skip is None else (skip[0], skip[1], tolerance)
        if points is not None:
            for p in points:
                if exclude is not None and math.hypot(p[0] - skip[0], p[1] - skip[1]) < tolerance:
                    continue
                if math.hypot(ex - p[0], ey - p[1]) <= tolerance:
                    sim.attach(name, chain.end_link, chain.end, (p[0], p[1]), prop,
                               rigid, max_torque)
                    return True
            return False
        found = [(*props[n].nearest((ex, ey), exclude, placed)[:2], n) for n, placed in near]
        distance, point, which = min(found, key=_distance)
        if distance <= tolerance:
            self.sim.attach(name, chain.end_link, chain.end, point, which, rigid,
                            max_torque)
            return True
        return False

    def released_point(self, name: str) -> tuple[float, float] | None:
        """Where (world, m) the chain last let go, following a moving prop; None if it
        has not let go of anything (since the start or a reset)."""
        if name not in self.released or self.sim is None:
            return None
        prop, (x, y) = self.released[name]
        if prop is None or prop not in self.sim.props:
            return (x, y)
        p = _to_world(self.sim.props[prop].body._body, (x, y))  # (Body.local_to_world's)
        return (p.x, p.y)

    def release(self, which: str) -> None:
        """Let go: unpin the chain ("all": every chain) and disarm its grasp; a chain
        that held something remembers where (``released``)."""
        names = list(self.chains) if which == "all" else [which]
        for name in names:
            self.armed.pop(name, None)
            if self.sim is not None:
                held = self.sim.grasps.get(name)
                if held is not None:
                    joint, prop = held
                    self.released[name] = (prop, (joint.anchor_b[0], joint.anchor_b[1]))
                self.sim.detach(name)

    def tick(self, step: int) -> str | None:
        """Each armed grasp tries to catch; WAITED when none caught or ran out (no
        change: its next wake-up is the next step, as before), so that a climber's
        feet armed at every step leave the arbiter's schedule as it was."""
        changed = False
        for name, (points, prop, tolerance, until, *rigid) in list(self.armed.items()):
            if self.try_grasp(name, points, prop, tolerance, *rigid) or \
                    (until is not None and step >= until):
                del self.armed[name]
                changed = True
        return None if changed or not self.armed else WAITED

    def next_wakeup(self, earliest: int) -> int | None:
        return earliest if self.armed else None

    def owners(self) -> set[Owner]:
        return set()  # a grasp pins a link; it owns no joint target

    def get_state(self):
        return {"armed": _copy(self.armed), "released": dict(self.released)}

    def set_state(self, state) -> None:
        if "armed" not in state:  # a snapshot from before 'released' was kept
            state = {"armed": state, "released": {}}
        self.armed = _copy(state["armed"])
        self.released = dict(state["released"])

    def adopt(self, old: GraspController, same, now: int) -> set[Owner]:
        """Armed and held grasps of chains defined the same way carry on; a chain that
        is gone or changed lets go."""
        self.armed = _copy({n: g for n, g in old.armed.items() if same("chain", n)})
        self.released = {n: r for n, r in old.released.items() if same("chain", n)}
        for name in list(old.held):
            if not same("chain", name):
                old.release(name)
        return set()

    def stop(self) -> None:
        self.armed = {}
        self.released = {}


def _copy(armed: dict) -> dict:
    return {n: [None if pts is None else [list(p) for p in pts], *rest]
            for n, (pts, *rest) in armed.items()}
