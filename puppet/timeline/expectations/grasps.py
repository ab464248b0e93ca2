"""Hanging on and swinging: chains holding props (a bar, the next rung, hand over hand)
and the centre of mass turning or swinging about a point (giant swings, a rope).

What the chains hold is ``Trajectory.held``: per sample, (chain, prop, grasp point,
x, y) of each grasp. Margins in seconds (how long a hold was missing), grasps, turns
or degrees.
"""

from __future__ import annotations

from typing import Annotated, Literal

import numpy as np

from puppet.data.ranges import Num, Time
from puppet.data.validate import Meta, field
from puppet.timeline.expectations.base import Check, Checking
from puppet.timeline.expectations.measure import (
    held_at,
    holds,
    samples_in,
    seconds_of,
    until_text,
    window_text,
)

Chains = Annotated[list[str], Meta(min_length=1, max_length=64)]


class Held(Check, kw_only=True):
    """Each of ``chains`` held a grasp (on ``prop``) at every sample of the window."""

    kind = "held"
    unit = "s"
    chains: Annotated[list[str], Meta(min_length=1, max_length=16)]
    prop: str | None = None  # the prop held (default: any, or the world)
    from_: Time | None = field(name="from", default=None)  # s: window start
    until: Time | None = None  # s: window end (default: the end)

    def describe(self) -> str:
        on = f" on {self.prop}" if self.prop else ""
        return f"held {', '.join(self.chains)}{on}{window_text(self)}"

    def evaluate(self, traj, at: Checking):
        t = traj.t
        idx = samples_in(t, self.from_, self.until)
        if len(idx) == 0:
            return self.no_samples(t)
        first, missing = None, np.zeros(len(idx), dtype=bool)
        for chain in self.chains:
            grips = held_at(traj, chain)
            if all(a is None for a in grips):
                if first is None:  # (a failure of a chain before it is said first)
                    return self.outcome(False, f"{chain} never held anything (a chain of "
                                               "the interface that grasps?)", None)
                missing[:] = True
                continue
            for n, i in enumerate(idx):
                if grips[i] is None or (self.prop is not None and grips[i][2] != self.prop):
                    missing[n] = True
                    if first is None:
                        what = "nothing" if grips[i] is None else (grips[i][2] or "the world")
                        first = f"{chain} held {what} at t = {t[i]:.2f} s"
        if first is not None:
            return self.outcome(False, first, -seconds_of(int(missing.sum()), t))
        return self.outcome(True, f"all held from t = {t[idx[0]]:.2f} s to "
                                  f"{t[idx[-1]]:.2f} s", 0.0)


class HeldPoint(Check, kw_only=True):
    """A grasp point of a prop held at some sample (by ``chain``, or by any chain)."""

    kind = "held_point"
    unit = "s"
    prop: str
    point: str  # the prop's grasp point (its name in the scene)
    chain: str | None = None  # the chain that held it (default: any)

    def describe(self) -> str:
        return f"held_point {self.prop} {self.point}" + (f" by {self.chain}" if self.chain
                                                         else "")

    def evaluate(self, traj, at: Checking):
        found = [i for i, row in enumerate(holds(traj))
                 if any(prop == self.prop and point == self.point and self.chain in (None, c)
                        for c, prop, point, *_ in row)]
        if found:
            i = found[0]
            chain = next(c for c, prop, point, *_ in holds(traj)[i]
                         if prop == self.prop and point == self.point
                         and self.chain in (None, c))
            return self.outcome(True, f"{chain} held it at t = {traj.t[i]:.2f} s",
                                seconds_of(len(found), traj.t))
        seen = sorted({p for row in holds(traj) for c, pr, p, *_ in row
                       if pr == self.prop and p is not None and self.chain in (None, c)})
        return self.outcome(False, "never held; held " + (", ".join(seen)
                                                          or "none of its points"), None)


class AlwaysHolding(Check, kw_only=True):
    """At every sample of the window at least one of ``chains`` holds something (a grasp
    point, a segment or a world point): hanging on, never fallen off."""

    kind = "always_holding"
    unit = "s"
    chains: Chains
    from_: Time | None = field(name="from", default=None)  # s (default: the start)
    until: Time | None = None  # s (default: the end)

    def describe(self) -> str:
        return f"always_holding one of {', '.join(self.chains)}{window_text(self)}"

    def evaluate(self, traj, at: Checking):
        chains = set(self.chains)
        idx = samples_in(traj.t, self.from_, self.until).tolist()
        if not idx:
            return self.no_samples(traj.t)
        rows = holds(traj)
        off = [i for i in idx if not any(chain in chains for chain, *_ in rows[i])]
        if off:
            return self.outcome(False, f"none of them held anything at t = "
                                       f"{traj.t[off[0]]:.2f} s",
                                -seconds_of(len(off), traj.t))
        return self.outcome(True, f"held on from t = {traj.t[idx[0]]:.2f} s to "
                                  f"{traj.t[idx[-1]]:.2f} s", 0.0)


class Regrasps(Check, kw_only=True):
    """New grasps that make progress along a prop: a chain of ``chains`` taking hold of
    a grasp point later in the prop's list than any point those chains held before (the
    next bar, the rung above). ``alternate``: counted only in a row of turns, each by
    another chain than the one before (hand over hand); the longest such row counts."""

    kind = "regrasps"
    unit = "grasps"
    chains: Chains
    prop: str
    min: Annotated[int, Meta(ge=1)]  # progressing grasps, at least
    alternate: bool = False

    def describe(self) -> str:
        return (f"regrasps {', '.join(self.chains)} along {self.prop} min {self.min}"
                + (" by turns" if self.alternate else ""))

    def evaluate(self, traj, at: Checking):
        """The progressing grasps (chain, point, t): the first point any of the chains
        holds is where they start; a new grasp of a point later in the prop's list than
        any held so far is one. Then the longest row of them (by turns if alternate)."""
        chains = set(self.chains)
        names = (traj.prop_points or {}).get(self.prop)
        if names is None:
            return self.outcome(False, f"no prop '{self.prop}' in the scene", None)
        order = {n: k for k, n in enumerate(names)}
        best = None  # the furthest place held so far
        moves: list[tuple[str, str, float]] = []
        before: dict[str, str | None] = {}
        for i, row in enumerate(holds(traj)):
            now = {c: p for c, pr, p, *_ in row if c in chains and pr == self.prop
                   and p in order}
            for chain, point in sorted(now.items()):
                k = order[point]
                if best is None:
                    best = k
                elif before.get(chain) != point and k > best:
                    moves.append((chain, point, float(traj.t[i])))
                    best = k
            before = now
        longest: list = []
        current: list = []
        for m in moves:
            if self.alternate and current and m[0] == current[-1][0]:
                current = [m]
            else:
                current.append(m)
            if len(current) > len(longest):
                longest = list(current)
        what = ", ".join(f"{c} {p} at {t:.2f} s" for c, p, t in longest[:12])
        return self.outcome(len(longest) >= self.min, f"{len(longest)} progressing grasps"
                            + (" by turns" if self.alternate else "")
                            + (f": {what}" if what else ""), len(longest) - self.min)


class Revolutions(Check, kw_only=True):
    """Full turns in a row of the centre of mass about a point: giant swings. The
    unwrapped angle of the centre of mass about the point; the longest stretch that
    never turns back more than ``slack`` degrees from its furthest; its turn / 360.
    About a chain: only samples where it holds count (a release ends a stretch)."""

    kind = "revolutions"
    unit = "turns"
    # a chain (the point it holds, at each sample) or [x, y] in the scene, m
    about: str | tuple[Num("world_xy"), Num("world_xy")]
    min: Num("turns")  # full turns in one stretch, at least
    # backward = counter-clockwise (the model faces +x)
    direction: Literal["either", "backward", "forward"] = "either"
    slack: Num("turn") = 10.0  # deg it may turn back inside the stretch (jitter at the top)

    def describe(self) -> str:
        about = (self.about if isinstance(self.about, str)
                 else f"[{self.about[0]:g}, {self.about[1]:g}]")
        way = "" if self.direction == "either" else f" {self.direction}"
        return f"revolutions about {about}{way} min {self.min:g} in a row"

    def evaluate(self, traj, at: Checking):
        n = len(traj.t)
        if isinstance(self.about, str):
            point = held_at(traj, self.about)
            if all(a is None for a in point):
                return self.outcome(False, f"'{self.about}' never held anything (a chain "
                                           "of the interface that grasps?)", None)
        else:
            point = [(self.about[0], self.about[1], None)] * n
        best, where = 0.0, ""
        ways = {"backward": (1.0,), "forward": (-1.0,), "either": (1.0, -1.0)}[self.direction]
        slack = np.radians(self.slack)
        for sign in ways:
            prev = start = top = None
            i0 = 0
            for i in range(n):
                if point[i] is None:
                    prev = None
                    continue
                a = float(np.arctan2(traj.com[i, 1] - point[i][1],
                                     traj.com[i, 0] - point[i][0]))
                if prev is None:
                    u = a
                    start = top = sign * u
                    i0 = i
                else:
                    u = prev_u + (np.remainder(a - prev + np.pi, 2 * np.pi) - np.pi)  # noqa: F821
                prev, prev_u = a, u  # noqa: F841 (read on the next sample)
                s = sign * u
                if s > top:
                    top = s
                elif s < top - slack:  # turned back: a new stretch from here
                    start = top = s
                    i0 = i
                turns = (top - start) / (2 * np.pi)
                if turns > best:
                    best = turns
                    way = "backward" if sign > 0 else "forward"
                    where = f" {way}, from t = {traj.t[i0]:.2f} s to {traj.t[i]:.2f} s"
        return self.outcome(best >= self.min - 1e-9, f"{best:.2f} turns in a row{where}",
                            float(best - self.min))


class Swung(Check, kw_only=True):
    """The centre of mass's angle about ``about`` (deg from straight below it, positive
    toward +x) reached at least ``min`` on both sides (forward and back) between
    ``from`` and ``until`` s: the body swings (on a rope, under a bar) that far, not a
    still hang."""

    kind = "swung"
    unit = "deg"
    about: tuple[Num("world_xy"), Num("world_xy")]  # m: the point
    min: Num("angle")  # deg each way, at least
    from_: Time = field(name="from", default=0.0)  # s: window start
    until: Time | None = None  # s: window end (default: the end)

    def describe(self) -> str:
        return (f"swung min {self.min:g} deg each way about [{self.about[0]:g}, "
                f"{self.about[1]:g}] from {self.from_:g} s to {until_text(self)}")

    def evaluate(self, traj, at: Checking):
        idx = samples_in(traj.t, self.from_, self.until)
        if len(idx) == 0:
            return self.no_samples(traj.t)
        dx = traj.com[idx, 0] - self.about[0]
        dy = traj.com[idx, 1] - self.about[1]
        angle = np.degrees(np.arctan2(dx, -dy))
        lo, hi = float(angle.min()), float(angle.max())
        return self.outcome(hi >= self.min - 1e-9 and -lo >= self.min - 1e-9,
                            f"{lo:.1f}..{hi:.1f} deg from t = {traj.t[idx[0]]:.2f} to "
                            f"{traj.t[idx[-1]]:.2f} s", min(hi, -lo) - self.min)
