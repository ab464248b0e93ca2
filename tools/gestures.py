"""Shared helpers for the gesture search tools (tune_hops.py, tune_flip.py, tune_ski.py).

A *gesture* is a list of script entries (the dicts of ``assets/scripts/*.yaml``:
``{t, mouse, over}``...). ``Runner`` plays entries into a real ``Session`` (the same
code path as ``puppet play --input``/``puppet replay``), can checkpoint the session
with the script's ``checkpoint`` action and try many continuations from that
checkpoint; a continuation tried from a checkpoint gives the same bits as the full
script replayed from the start, because the checkpoint action re-seats the live run
(see ``Session.checkpoint``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from puppet.data.catalog import load_setup
from puppet.interface import events as ev
from puppet.session import Session
from puppet.session.playback import play
from puppet.timeline.script import ScriptSpec, compile_script

SAMPLE = 8  # steps between samples in searches (60 Hz)


def compile_entries(entries: list[dict], dt: float, mouse_from=(0.5, 0.5)):
    """(step, event) pairs of script entries; glides start at ``mouse_from``."""
    spec = ScriptSpec.model_validate({"events": [{"t": 0.0, "mouse": list(mouse_from)}]
                                      + list(entries)})
    pairs = compile_script(spec, dt)
    return pairs[1:]  # drop the seed position (it only sets where glides start from)


@dataclass
class Outcome:
    """What a tried stretch did (sampled every SAMPLE steps)."""

    x_end: float  # base centre of mass x at the end, m
    tilt_end: float  # root from upright at the end, deg
    max_tilt_ground: float  # largest root tilt while touching the ground, deg
    turned: float  # accumulated root rotation, deg (+ = backward, counter-clockwise)
    airborne: float  # longest stretch with no link touching, s
    peak_y: float  # highest base lowest point, m
    blowups: int
    still: bool  # nearly at rest at the end
    flight_x: tuple  # base x where the longest stretch with nothing touching began, ended
    motion_end: float  # base speed (m/s) + 0.1 * |angular speed| (rad/s) at the end
    xs: np.ndarray
    ts: np.ndarray

    @property
    def upright(self) -> bool:
        return self.tilt_end <= 45.0

    @property
    def fell(self) -> bool:
        return self.max_tilt_ground > 90.0 or self.blowups > 0


def tilt_deg(angle: float) -> float:
    return abs(math.degrees(math.remainder(angle, 2 * math.pi)))


class SessionRunner:
    """A live Session that searches play into, checkpoint and go back to (the base of
    every tool's runner)."""

    def __init__(self, interface: str, scene: str | None = None):
        self.session = Session(load_setup(interface, scene))
        self.dt = self.session.sim.dt
        self.mark = None  # the step of the last checkpoint

    def steps(self, t: float) -> int:
        return round(t / self.dt)

    def checkpoint(self) -> None:
        """Checkpoint now: the script's ``{action: checkpoint}``, through the session."""
        self.session.handle(ev.action("checkpoint"))
        self.mark = self.session.steps

    def back(self) -> None:
        """Back to the last checkpoint (the ``restore`` action), to try another
        continuation; the restored run gives the same bits as the recorded script."""
        self.session.handle(ev.action("restore"))
        assert self.session.steps == self.mark


class Runner(SessionRunner):

    def run(self, pairs, until_step: int) -> Outcome:
        s = self.session
        c = s.character
        rows = []
        blow0 = s.blowups

        def sample(sess):
            low = min(sh.cache_bb().bottom for sh in c.shapes["base"])
            touching = any(c.in_contact(n) for n in c.link_order)
            rows.append((sess.time, c.bodies["base"].position.x, c.root_angle(), touching,
                         low))

        sample(s)
        play(s, pairs, until_step, SAMPLE, sample)
        if rows[-1][0] != s.time:
            sample(s)
        t = np.array([r[0] for r in rows])
        x = np.array([r[1] for r in rows])
        a = np.array([r[2] for r in rows])
        touch = np.array([r[3] for r in rows])
        low = np.array([r[4] for r in rows])
        tilts = np.abs(np.degrees(np.remainder(a + np.pi, 2 * np.pi) - np.pi))
        ground_tilt = float(np.max(np.where(touch, tilts, 0.0)))
        # longest airborne stretch
        best = run = 0
        flight = (float(x[0]), float(x[0]))
        for i, f in enumerate(touch):
            run = 0 if f else run + 1
            if run > best:
                best = run
                flight = (float(x[i - run]), float(x[min(i + 1, len(x) - 1)]))
        v = c.bodies["base"].velocity
        w = abs(c.bodies["base"].angular_velocity)
        still = abs(v.x) + abs(v.y) < 0.05 and w < 0.3
        motion = math.hypot(v.x, v.y) + 0.1 * w
        return Outcome(float(x[-1]), float(tilts[-1]), ground_tilt,
                       float(np.degrees(a[-1] - a[0])), best * SAMPLE * self.dt,
                       float(low.max()), s.blowups - blow0, still, flight, motion, x, t)


def climb(evaluate, score, bounds, best_s, best_p, best_o, budget):
    """Coordinate hill climb from ``best_p`` (a dict within ``bounds``): try a step up
    and down each coordinate, keep the first that improves the score; when none does,
    halve the steps. ``evaluate(p)`` gives an Outcome. Returns (score, p, outcome)."""
    step = {k: (hi - lo) / 8 for k, (lo, hi) in bounds.items()}
    tries = 0
    while tries < budget and max(step[k] / (bounds[k][1] - bounds[k][0])
                                 for k in step) > 1e-3:
        improved = False
        for k in bounds:
            for sign in (1, -1):
                q = dict(best_p)
                lo, hi = bounds[k]
                q[k] = min(hi, max(lo, q[k] + sign * step[k]))
                o = evaluate(q)
                tries += 1
                s = score(o)
                if s > best_s:
                    best_p, best_o, best_s, improved = q, o, s, True
                    break
        if not improved:
            step = {k: v / 2 for k, v in step.items()}
    return best_s, best_p, best_o


def search(evaluate, score, bounds, rng, tries: int, climbs: int, refine: int, report):
    """Random restarts then hill climbs: ``tries`` random points within ``bounds``, then
    ``climb`` from each of the best ``climbs``; ``report(rank, s0, s1, outcome)`` after
    each climb. Returns (score, p, outcome) of the best."""
    pool = []
    for _ in range(tries):
        p = {k: rng.uniform(lo, hi) for k, (lo, hi) in bounds.items()}
        o = evaluate(p)
        pool.append((score(o), p, o))
    pool.sort(key=lambda item: -item[0])
    best_s, best_p, best_o = pool[0]
    for rank, (s0, p0, o0) in enumerate(pool[:climbs]):
        s1, p1, o1 = climb(evaluate, score, bounds, s0, p0, o0, refine)
        report(rank, s0, s1, o1)
        if s1 > best_s:
            best_s, best_p, best_o = s1, p1, o1
    return best_s, best_p, best_o
