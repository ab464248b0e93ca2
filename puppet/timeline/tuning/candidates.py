"""Which parameter values a stage tries: the first guess, random draws (near the best
so far or anywhere), a grid, and the neighbours of a hill climb.

Every draw comes from a ``random.Random`` seeded by the spec's seed and the stage's
place, and a batch is drawn before any of it is played: the tries asked for do not
depend on which finished first, so the search is the same on one process or many.
Numbers are rounded to 1e-4 (a range with a ``step`` to its grid): the values the
script shows are the values played.
"""

from __future__ import annotations

import itertools
import random

from puppet.timeline.tuning.spec import Param, SearchSpec

MAX_GRID = 20000  # grid points a stage may have


def complete(params: list[Param], given: dict) -> dict:
    """``given`` with every missing parameter at its middle (a choice's first)."""
    return {p.name: (given[p.name] if p.name in given else p.middle()) for p in params}


def draw(params: list[Param], rng: random.Random, centre: dict | None, around: float,
         sigma: float) -> dict:
    """One random try: near ``centre`` (Gaussian steps of ``sigma`` of each range; a
    choice kept with probability 1 - ``sigma``) with probability ``around``, else
    uniformly anywhere."""
    near = centre is not None and rng.random() < around
    out = {}
    for p in params:
        if p.choose is not None:
            keep = near and rng.random() >= sigma
            out[p.name] = centre[p.name] if keep else rng.choice(p.choose)
        elif near:
            out[p.name] = p.clamp(centre[p.name] + rng.gauss(0.0, sigma * p.span))
        else:
            out[p.name] = p.clamp(rng.uniform(*p.range))
    return out


def grid(params: list[Param]) -> list[dict]:
    axes = [p.grid() for p in params]
    size = 1
    for a in axes:
        size *= len(a)
    if size > MAX_GRID:
        raise ValueError(f"the grid has {size} points (at most {MAX_GRID}): a coarser "
                         "'step' or fewer parameters")
    names = [p.name for p in params]
    return [dict(zip(names, combo, strict=True)) for combo in itertools.product(*axes)]


def rounds(search: SearchSpec, tries: int) -> list[int]:
    """How many tries each round has (the first round also holds the first guess)."""
    n = max(1, min(search.rounds, tries)) if tries else 1
    base, extra = divmod(tries, n)
    return [base + (1 if i < extra else 0) for i in range(n)]


class Climb:
    """A coordinate hill climb from a point: each step tries every parameter a step
    up and down (a choice: each other option) as one batch and moves to the best that
    beats the point; when none does, the steps halve. It ends when the budget is spent
    or the steps are below 1/1000 of each range (a grid's own step)."""

    def __init__(self, params: list[Param], start: dict):
        self.params = params
        self.point = dict(start)
        self.steps = {p.name: p.span / 8 for p in params if p.choose is None}

    def neighbours(self) -> list[dict]:
        out = []
        for p in self.params:
            cur = self.point[p.name]
            if p.choose is not None:
                values = [c for c in p.choose if c != cur]
            else:
                step = self.steps[p.name]
                if p.step is not None:
                    step = max(step, p.step)
                values = [p.clamp(cur + step), p.clamp(cur - step)]
            for v in values:
                if v != cur:
                    q = dict(self.point)
                    q[p.name] = v
                    if q not in out:
                        out.append(q)
        return out

    def shrink(self) -> bool:
        """Halve the steps; False when they are all as fine as they go."""
        alive = False
        for p in self.params:
            if p.choose is not None:
                continue
            self.steps[p.name] /= 2
            floor = p.step / 2 if p.step is not None else 1e-3 * p.span
            if self.steps[p.name] >= floor and p.span > 0:
                alive = True
        return alive
