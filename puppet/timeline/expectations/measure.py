"""Reading a sampled run: the stretches, windows, tilts and margins every check shares.

Functions of arrays and of anything shaped like a ``Trajectory`` (tests build small
ones by hand), so that "the longest flight" or "the samples from 2 s to 5 s" mean one
thing in every kind.
"""

from __future__ import annotations

import math

import numpy as np

EPS = 1e-9  # s, m or deg: a bound met to the last bits of a float is met


def tilt_deg(angle: np.ndarray) -> np.ndarray:
    """Degrees from upright (0..180), whatever the number of full turns."""
    return np.abs(np.degrees(np.remainder(angle + np.pi, 2 * np.pi) - np.pi))


def signed_deg(angle: np.ndarray) -> np.ndarray:
    """Degrees from upright, -180..180, counter-clockwise positive."""
    return np.degrees(np.remainder(angle + np.pi, 2 * np.pi) - np.pi)


def runs(flags: np.ndarray) -> list[tuple[int, int]]:
    """(first, last) sample index of each stretch of consecutive true samples: the
    flights (or times out of contact) that airborne, turned and landed_at measure."""
    edges = np.diff(np.concatenate(([0], np.asarray(flags, dtype=np.int8), [0])))
    return list(zip(np.flatnonzero(edges == 1).tolist(),
                    (np.flatnonzero(edges == -1) - 1).tolist()))


def interval(t: np.ndarray) -> float:
    """The sampling interval (s): the median time between samples (0 for one sample)."""
    return float(np.median(np.diff(t))) if len(t) > 1 else 0.0


def longest_run(flags: np.ndarray, t: np.ndarray) -> tuple[float, int, int]:
    """Longest (first if tied) stretch of true samples: (seconds, first, last index);
    (0.0, -1, -1) if there is none. Longest by its number of samples, which ties
    exactly: the seconds (t[last] - t[first] + the median interval) of two equally long
    stretches differ in the last bit by where they are in the run, and the later one
    would win by rounding."""
    best, count = (0.0, -1, -1), 0
    dt = interval(t)
    for i, j in runs(flags):
        if j - i + 1 > count:
            best, count = (float(t[j] - t[i] + dt), i, j), j - i + 1
    return best


def longest_flight(traj) -> tuple[float, int, int]:
    """The longest stretch with no link of the character touching (see longest_run):
    the flight took_off, first_touch, landed_at, bent_after_flight and run_up speak of."""
    return longest_run(~traj.contact.any(axis=1), traj.t)


def samples_in(t: np.ndarray, start: float | None, end: float | None) -> np.ndarray:
    """The indices of the samples from ``start`` to ``end`` (s, both included; None:
    the run's start or end)."""
    lo = -np.inf if start is None else start - EPS
    hi = np.inf if end is None else end + EPS
    return np.flatnonzero((t >= lo) & (t <= hi))


def seconds_of(count: int, t: np.ndarray) -> float:
    """``count`` samples as seconds (each worth the sampling interval)."""
    return count * interval(t)


def within(value: float, low: float | None = None, high: float | None = None) -> float:
    """How far ``value`` is inside low..high (either None: no such bound): the nearer
    of value - low and high - value, negative outside."""
    out = math.inf
    if low is not None:
        out = min(out, value - low)
    if high is not None:
        out = min(out, high - value)
    return float(out)


def at_least_most(low: float | None, high: float | None) -> str:
    """"at least LOW and at most HIGH" (either left out when None), as bounds are said."""
    return " and ".join(f"{w} {b:g}" for w, b in (("at least", low), ("at most", high))
                        if b is not None)


def min_max(low, high, unit: str = "") -> str:
    """"min LOW max HIGH" (either left out when None), as a bound pair is written."""
    return " ".join(f"{k} {b}{unit}" for k, b in (("min", low), ("max", high))
                    if b is not None)


def until_text(v) -> str:
    """A window's end as said: 'the end' or 'N s'."""
    return "the end" if v.until is None else f"{v.until:g} s"


def window_text(v) -> str:
    """' from A s until B s' for the bounds a window has (none: '')."""
    return "".join(f" {k} {b} s" for k, b in (("from", v.from_), ("until", v.until))
                   if b is not None)


def holds(traj) -> list[tuple]:
    """What the chains hold at each sample (``Trajectory.held``; () for none)."""
    return list(traj.held) if traj.held is not None else [()] * len(traj.t)


def held_at(traj, chain: str) -> list:
    """Per sample: (x, y, prop) of what ``chain`` held, or None."""
    return [next(((x, y, prop) for name, prop, _, x, y in row if name == chain), None)
            for row in holds(traj)]


def named(x) -> str:
    """A state or mode for a message; none for an interface (version) without them."""
    return "none" if x is None else f"'{x}'"


def short_of(amount: float) -> float:
    """The margin of a failure that fell ``amount`` short of its bound: -amount, or -inf
    when the bound was 0 (a stretch of 0 s that was never there at all)."""
    return -float(amount) if amount > 0 else -math.inf
