"""What touched the ground, and what did not: feet down at the end, balanced on some
links alone, sat on a seat, a foot on a wall, and never touching a prop, a ground
polyline or a region (the hurdles cleared). Margins in seconds (a share of samples for
touching_at_end, metres for touched).

A link touches when it is in contact with anything outside the character. The first
sample (step 0, before the first step) takes the contacts of the next one: pymunk has
none yet, and a standing start would read as a flight.
"""

from __future__ import annotations

from typing import Annotated

import numpy as np

from puppet.data.ranges import Num, Time
from puppet.data.validate import Meta, field
from puppet.timeline.expectations.base import Check, Checking
from puppet.timeline.expectations.measure import (
    at_least_most,
    longest_flight,
    longest_run,
    samples_in,
    seconds_of,
    short_of,
    signed_deg,
    tilt_deg,
    until_text,
)
from puppet.timeline.expectations.outcome import NOTHING

Links = Annotated[list[str], Meta(min_length=1, max_length=64)]
Names = Annotated[list[str], Meta(min_length=1, max_length=64)]
Measure = Num("measure")
Tilt = Annotated[float, Meta(ge=0, le=180)]
Signed = Annotated[float, Meta(ge=-180, le=180)]


def _stretch(check: Check, on: np.ndarray, traj, said: str):
    """The outcome of 'for min_seconds in one stretch': the longest stretch of ``on``."""
    length, i, j = longest_run(on, traj.t)
    return check.outcome(length > 0 and length >= check.min_seconds - 1e-9,
                         f"{said}: {length:.3f} s"
                         + (f" (t = {traj.t[i]:.2f} to {traj.t[j]:.2f} s)" if length > 0
                            else ""),
                         length - check.min_seconds if length > 0
                         else short_of(check.min_seconds))


class TouchingAtEnd(Check, kw_only=True):
    """Each of ``links`` touching the ground at the samples of the last ``held`` s (0:
    the last sample), at least ``min_fraction`` of them: both feet down at the end. A
    fraction, because a checkpoint re-seats the space and the sample at that step sees
    no contacts yet (pymunk rebuilds them in the next step)."""

    kind = "touching_at_end"
    unit = "share"
    links: Links
    held: Num("duration") = 0.0  # s at the end
    # share of those samples touching, at least
    min_fraction: Annotated[float, Meta(ge=0, le=1)] = 1.0

    def describe(self) -> str:
        share = f" at {self.min_fraction:g} of the samples" if self.min_fraction < 1 else ""
        return (f"touching_at_end {', '.join(self.links)}"
                + (f" held {self.held} s{share}" if self.held else ""))

    def evaluate(self, traj, at: Checking):
        window = traj.t >= traj.t[-1] - self.held - 1e-9
        shares = {name: float(traj.contact[window, traj.index(name)].mean())
                  for name in self.links}
        least = min(shares, key=shares.get)
        return self.outcome(shares[least] >= self.min_fraction - 1e-9,
                            f"{least} touching at {shares[least]:.0%} of the samples "
                            + (f"of the last {self.held:g} s" if self.held else "at the end")
                            + " (the least)", shares[least] - self.min_fraction)


class StoodOn(Check, kw_only=True):
    """Balanced on ``link`` alone (the only one touching), the root at least
    ``min_tilt`` from upright, for ``min_seconds`` in one stretch: a headstand."""

    kind = "stood_on"
    unit = "s"
    link: str  # the one link touching the ground
    min_seconds: Time  # s in one stretch
    min_tilt: Tilt = 135.0  # deg the root is from upright at least (135: upside down)

    def describe(self) -> str:
        return (f"stood_on {self.link} alone, root >= {self.min_tilt:g} deg from upright, "
                f"min {self.min_seconds} s")

    def evaluate(self, traj, at: Checking):
        k = traj.index(self.link)
        others = np.delete(traj.contact, k, axis=1).any(axis=1)
        on = traj.contact[:, k] & ~others & (tilt_deg(traj.root_angle) >= self.min_tilt)
        return _stretch(self, on, traj, f"longest stretch on {self.link} alone, upside down")


class BalancedOn(Check, kw_only=True):
    """Only ``links`` touch the ground (at least one of them), the root at least
    ``min_tilt`` from upright and each of ``above`` higher than ``over``, for
    ``min_seconds`` in one stretch: a handstand, on both hands, feet above the head."""

    kind = "balanced_on"
    unit = "s"
    links: Links  # the links that may touch; nothing else does
    min_seconds: Time  # s in one stretch
    min_tilt: Tilt = 135.0  # deg the root is from upright at least
    # links whose centre of mass is above over's
    above: Annotated[list[str], Meta(max_length=64)] = field(default_factory=list)
    over: str | None = None  # the link they are above (the head)

    def __post_init__(self):
        if bool(self.above) != (self.over is not None):
            raise ValueError("give 'above' (a list of links) and 'over' (a link) together")

    def describe(self) -> str:
        feet = f", {', '.join(self.above)} above {self.over}" if self.above else ""
        return (f"balanced_on {', '.join(self.links)} only, root >= {self.min_tilt:g} deg "
                f"from upright{feet}, min {self.min_seconds} s")

    def evaluate(self, traj, at: Checking):
        for i, name in enumerate(self.above):
            at.check_link(traj, name, "above", i)
        if self.over:
            at.check_link(traj, self.over, "over")
        k = [traj.index(n) for n in self.links]
        on = (traj.contact[:, k].any(axis=1) & ~np.delete(traj.contact, k, axis=1).any(axis=1)
              & (tilt_deg(traj.root_angle) >= self.min_tilt))
        for name in self.above:
            on &= traj.y[:, traj.index(name)] > traj.y[:, traj.index(self.over)]
        return _stretch(self, on, traj,
                        f"longest stretch on {', '.join(self.links)} alone, upside down")


class OnGround(Check, kw_only=True):
    """All of ``links`` touching the ground at every sample of one stretch of at least
    ``min_seconds``, the root's signed angle (deg, counter-clockwise positive: tipped
    backward for a character facing +x) within ``min_root_angle``..``max_root_angle``
    over it: sat down on the seat and leaning back, not only touching."""

    kind = "on_ground"
    unit = "s"
    links: Links
    min_seconds: Time  # s in one stretch
    min_root_angle: Signed | None = None  # deg, signed (+ = tipped backward)
    max_root_angle: Signed | None = None  # deg, signed (+ = tipped backward)

    def describe(self) -> str:
        tilt = at_least_most(self.min_root_angle, self.max_root_angle)
        return (f"on_ground {', '.join(self.links)} min {self.min_seconds:g} s"
                + (f", root {tilt} deg (signed)" if tilt else ""))

    def evaluate(self, traj, at: Checking):
        angle = signed_deg(traj.root_angle)
        on = traj.contact[:, [traj.index(n) for n in self.links]].all(axis=1)
        if self.min_root_angle is not None:
            on &= angle >= self.min_root_angle
        if self.max_root_angle is not None:
            on &= angle <= self.max_root_angle
        length, i, j = longest_run(on, traj.t)
        return self.outcome(length > 0 and length >= self.min_seconds - 1e-9,
                            f"longest stretch: {length:.2f} s"
                            + (f" (t = {traj.t[i]:.2f} to {traj.t[j]:.2f} s, root "
                               f"{angle[i:j + 1].min():.0f}..{angle[i:j + 1].max():.0f} deg)"
                               if length > 0 else ""),
                            length - self.min_seconds if length > 0
                            else short_of(self.min_seconds))


class Touched(Check, kw_only=True):
    """At some sample one of ``links`` touched the ground with its lowest point at least
    ``min_height`` m up and its centre of mass at x >= ``min_x`` (when given): a foot
    planted on a wall, not on the floor below it."""

    kind = "touched"
    unit = "m"
    links: Links
    min_height: Measure  # m: the link's lowest point above y = 0, at least
    min_x: Measure | None = None  # m: x of the link, at least
    before_flight: bool = False  # only the samples before the longest flight count (pushed off it)

    def describe(self) -> str:
        return (f"touched with {', '.join(self.links)}, lowest point >= {self.min_height:g} m"
                + (f", x >= {self.min_x:g} m" if self.min_x is not None else "")
                + (", before the longest flight" if self.before_flight else ""))

    def evaluate(self, traj, at: Checking):
        """The first sample where one of the links touches that high (and that far on);
        the margin is the best touch's (the nearer of its two bounds)."""
        window = np.ones(len(traj.t), dtype=bool)
        if self.before_flight:
            length, first, _ = longest_flight(traj)
            if length <= 0:
                return self.outcome(False, "no flight (nothing touching) to touch before",
                                    None)
            window[first:] = False
        best = NOTHING
        hit_at = None
        for name in self.links:
            k = traj.index(name)
            room = traj.lowest[:, k] - self.min_height
            if self.min_x is not None:
                room = np.minimum(room, traj.x[:, k] - self.min_x)
            touching = window & traj.contact[:, k]
            if touching.any():
                best = max(best, float(room[touching].max()))
            hit = touching & (traj.lowest[:, k] >= self.min_height - 1e-9)
            if self.min_x is not None:
                hit &= traj.x[:, k] >= self.min_x - 1e-9
            if hit.any() and hit_at is None:
                hit_at = (name, k, int(np.argmax(hit)))
        if hit_at is not None:
            name, k, i = hit_at
            return self.outcome(True, f"{name} touched at t = {traj.t[i]:.2f} s, lowest "
                                      f"point {traj.lowest[i, k]:.3f} m up, x = "
                                      f"{traj.x[i, k]:.3f} m", best)
        up = [float(traj.lowest[window & traj.contact[:, traj.index(n)], traj.index(n)]
                    .max(initial=-1)) for n in self.links]
        high = max(up)
        return self.outcome(False, "never touched that high" + (
            f" (highest touch {high:.3f} m up)" if high > -1 else " (never touched)"), best)


class NeverTouched(Check, kw_only=True):
    """None of ``links`` (default: any link) touched ``props``, the named ``ground``
    polylines or, with a box (``x_min``..``x_max``, ``y_min``..``y_max``: where the
    contact point is, m), anything in it, at any sample from ``from`` to ``until``: the
    hurdles cleared, not stood on."""

    kind = "never_touched"
    unit = "s"
    touches = True
    links: Links | None = None  # the links watched (default: all of the character's)
    props: Names | None = None  # props of the scene (any of their shapes)
    ground: Names | None = None  # named ground polylines of the scene
    x_min: Measure | None = None  # m: a contact point's x, at least
    x_max: Measure | None = None
    y_min: Measure | None = None  # m: a contact point's y, at least
    y_max: Measure | None = None
    from_: Time = field(name="from", default=0.0)  # s: window start
    until: Time | None = None  # s: window end (default: the end)

    def __post_init__(self):
        if self.props is None and self.ground is None and self._box() == (None,) * 4:
            raise ValueError("give what must not be touched: 'props', 'ground' (names) "
                             "and/or a box ('x_min', 'x_max', 'y_min', 'y_max')")

    def _box(self) -> tuple:
        return (self.x_min, self.x_max, self.y_min, self.y_max)

    def check_scene(self, at: Checking, props: list[str], ground: list[str]) -> None:
        """DataError at the name for a prop or ground polyline the scene does not have."""
        for i, name in enumerate(self.props or []):
            if name not in props:
                raise at.error(f"unknown prop '{name}'; the scene has: "
                               f"{', '.join(props) or 'no props'}", "props", i)
        named = [g for g in ground if g]
        for i, name in enumerate(self.ground or []):
            if name not in named:
                raise at.error(f"unknown ground '{name}'; the scene has: "
                               f"{', '.join(named) or 'no named ground'} (a ground "
                               "polyline's 'name')", "ground", i)

    def describe(self) -> str:
        what = [f"prop {', '.join(self.props)}" if self.props else "",
                f"ground {', '.join(self.ground)}" if self.ground else ""]
        what = " or ".join(w for w in what if w) or "anything"
        box = ", ".join(b for b in (_span("x", self.x_min, self.x_max),
                                    _span("y", self.y_min, self.y_max)) if b)
        who = "any link" if self.links is None else ", ".join(self.links)
        return (f"never_touched {what}{' in ' + box if box else ''} with {who} from "
                f"{self.from_:g} s to {until_text(self)}")

    def evaluate(self, traj, at: Checking):
        if getattr(traj, "touches", None) is None:
            raise at.error("never_touched reads what each link touched, which this "
                           "trajectory did not record (Sampler(session, touches=True))")
        self.check_scene(at, list(traj.prop_points or {}), traj.ground_names or [])
        links = (None if self.links is None
                 else {traj.index(n) for n in self.links})
        things = ({("prop", n) for n in self.props or []}
                  | {("ground", n) for n in self.ground or []}) or None
        lo_x = -np.inf if self.x_min is None else self.x_min
        hi_x = np.inf if self.x_max is None else self.x_max
        lo_y = -np.inf if self.y_min is None else self.y_min
        hi_y = np.inf if self.y_max is None else self.y_max
        idx = samples_in(traj.t, self.from_, self.until)
        if len(idx) == 0:
            return self.no_samples(traj.t)
        first, count = None, 0
        for i in idx:
            hit = next(((k, what, name, x, y) for k, what, name, x, y in traj.touches[i]
                        if (links is None or k in links)
                        and (things is None or (what, name) in things)
                        and lo_x <= x <= hi_x and lo_y <= y <= hi_y), None)
            if hit is not None:
                count += 1
                if first is None:
                    first = (int(i), hit)
        span = f"from t = {traj.t[idx[0]]:.2f} to {traj.t[idx[-1]]:.2f} s"
        if first is None:
            return self.outcome(True, f"no such touch in {len(idx)} samples {span}", 0.0)
        i, (k, what, name, x, y) = first
        thing = f"{what} {name}" if name else ("the ground" if what == "ground" else what)
        seconds = seconds_of(count, traj.t)
        return self.outcome(False, f"{traj.links[k]} touched {thing} at t = {traj.t[i]:.2f} "
                                   f"s (x = {x:.2f}, y = {y:.2f} m); touching at {count} "
                                   f"samples ({seconds:.2f} s) {span}",
                            -seconds if seconds > 0 else NOTHING)


def _span(axis: str, low, high) -> str:
    """'x 3..4 m', 'y <= 0.6 m'... of a box's bounds on one axis ('' for none)."""
    if low is not None and high is not None:
        return f"{axis} {low:g}..{high:g} m"
    if low is not None:
        return f"{axis} >= {low:g} m"
    return f"{axis} <= {high:g} m" if high is not None else ""
