"""Where the character got to: x and height at the end, how high a link rose, how fast
the centre of mass moved. Margins in metres (m/s for a speed)."""

from __future__ import annotations

import numpy as np

from puppet.data.ranges import Num, Time
from puppet.data.validate import field
from puppet.timeline.expectations.base import Check, Checking
from puppet.timeline.expectations.measure import min_max, samples_in, until_text, within

Measure = Num("measure")


class XAtEnd(Check, kw_only=True):
    """x of a link's centre of mass (or the whole character's) at the end, m."""

    kind = "x_at_end"
    unit = "m"
    link: str | None = None  # link whose centre of mass is measured
    com: bool = False  # measure the whole character's centre of mass
    min: Measure | None = None
    max: Measure | None = None

    def __post_init__(self):
        if (self.link is None) == (not self.com):
            raise ValueError("give either 'link: NAME' or 'com: true'")
        if self.min is None and self.max is None:
            raise ValueError("give 'min', 'max' or both")

    def describe(self) -> str:
        return f"x_at_end {'com' if self.com else self.link} {min_max(self.min, self.max)}"

    def evaluate(self, traj, at: Checking):
        x = float(traj.com[-1, 0]) if self.com else float(traj.x[-1, traj.index(self.link)])
        ok = (self.min is None or x >= self.min) and (self.max is None or x <= self.max)
        return self.outcome(ok, f"x = {x:.3f} m at t = {traj.t[-1]:.2f} s",
                            within(x, self.min, self.max))


class HeightAtEnd(Check, kw_only=True):
    """The link's centre of mass (m above y = 0) within bounds at the end, and (``held``)
    over the last ``held`` s: standing, not fallen or crouched."""

    kind = "height_at_end"
    unit = "m"
    link: str
    min: Measure | None = None
    max: Measure | None = None
    held: Num("duration") = 0.0  # s at the end it must stay in bounds

    def __post_init__(self):
        if self.min is None and self.max is None:
            raise ValueError("give 'min' and/or 'max' (m)")

    def describe(self) -> str:
        return (f"height_at_end {self.link} {min_max(self.min, self.max)}"
                + (f" held {self.held} s" if self.held else ""))

    def evaluate(self, traj, at: Checking):
        y = traj.y[:, traj.index(self.link)]
        window = y[traj.t >= traj.t[-1] - self.held - 1e-9]
        lo, hi = float(window.min()), float(window.max())
        ok = (self.min is None or lo >= self.min) and (self.max is None or hi <= self.max)
        return self.outcome(ok, f"y = {lo:.3f}..{hi:.3f} m over the last {self.held:g} s"
                            if self.held else f"y = {lo:.3f} m at t = {traj.t[-1]:.2f} s",
                            min(within(lo, self.min), within(hi, None, self.max)))


class ReachedHeight(Check, kw_only=True):
    """The link's lowest point rose at least ``min`` m above where it started."""

    kind = "reached_height"
    unit = "m"
    link: str
    min: Measure  # m the link's lowest point must rise above its start

    def describe(self) -> str:
        return f"reached_height {self.link} min {self.min} m"

    def evaluate(self, traj, at: Checking):
        low = traj.lowest[:, traj.index(self.link)]
        rise = low - low[0]
        i = int(np.argmax(rise))
        return self.outcome(bool(rise[i] >= self.min),
                            f"rose {rise[i]:.3f} m (at t = {traj.t[i]:.2f} s)",
                            float(rise[i] - self.min))


class MeanSpeed(Check, kw_only=True):
    """The centre of mass's mean speed along +x over a window: how far it moved between
    the samples nearest ``from`` and ``until`` divided by the time between them (m/s)."""

    kind = "mean_speed"
    unit = "m/s"
    from_: Time = field(name="from", default=0.0)  # s: window start
    until: Time | None = None  # s: window end (default: the end)
    min: Measure | None = None
    max: Measure | None = None

    def __post_init__(self):
        if self.min is None and self.max is None:
            raise ValueError("give 'min', 'max' or both (m/s)")
        if self.until is not None and self.until <= self.from_:
            raise ValueError("'until' must be later than 'from'")

    def describe(self) -> str:
        return (f"mean_speed {min_max(self.min, self.max)} m/s from {self.from_:g} s to "
                f"{until_text(self)}")

    def evaluate(self, traj, at: Checking):
        idx = samples_in(traj.t, self.from_, self.until)
        if len(idx) < 2 or traj.t[idx[-1]] <= traj.t[idx[0]]:
            return self.outcome(False, f"fewer than two samples in the window (the run is "
                                       f"{traj.t[-1]:.2f} s)", None)
        i, j = int(idx[0]), int(idx[-1])
        speed = float((traj.com[j, 0] - traj.com[i, 0]) / (traj.t[j] - traj.t[i]))
        ok = (self.min is None or speed >= self.min) and (self.max is None
                                                          or speed <= self.max)
        return self.outcome(ok, f"{speed:.3f} m/s (x {traj.com[i, 0]:.2f} to "
                                f"{traj.com[j, 0]:.2f} m, t = {traj.t[i]:.2f} to "
                                f"{traj.t[j]:.2f} s)", within(speed, self.min, self.max))
