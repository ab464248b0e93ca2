"""Flights: a link out of contact, the longest flight's take-off, landing and the body's
fold at the landing, the run's flights, the run-up before a jump.

"The flight" of took_off, first_touch, landed_at, bent_after_flight, run_up and
touched's before_flight is the longest stretch with no link of the character touching
(``measure.longest_flight``), so a log's entries all speak of one flight. Margins in
seconds, metres, degrees or flights, each kind's own.
"""

from __future__ import annotations

from typing import Annotated

import numpy as np

from puppet.data.ranges import Num, Time
from puppet.data.validate import Meta, at, field
from puppet.timeline.expectations.base import Check, Checking
from puppet.timeline.expectations.measure import (
    at_least_most,
    longest_flight,
    longest_run,
    runs,
    samples_in,
    until_text,
    within,
)
from puppet.timeline.expectations.outcome import NOTHING

Links = Annotated[list[str], Meta(min_length=1, max_length=64)]
Measure = Num("measure")


def _links_or_all(at: Checking, traj, links: list[str] | None) -> list[str]:
    """The links named (each checked) or, without a list, all of the character's."""
    for k, name in enumerate(links or []):
        at.check_link(traj, name, "links", k)
    return traj.links if links is None else links


def _nearest(*parts: tuple[float, str]) -> tuple[float, str]:
    """(margin, unit) of the bound nearest to failing, of several in their units."""
    return min(parts, key=lambda p: p[0]) if parts else (0.0, "")


class Airborne(Check, kw_only=True):
    """The link out of contact for at least ``min_seconds`` in one stretch (a hop), and
    (``max_seconds``) never longer at a time (a shuffle)."""

    kind = "airborne"
    unit = "s"
    link: str
    min_seconds: Time | None = None  # s out of contact in one stretch, at least
    max_seconds: Time | None = None  # s out of contact in one stretch, at most (every stretch)

    def __post_init__(self):
        if self.min_seconds is None and self.max_seconds is None:
            raise ValueError("give 'min_seconds', 'max_seconds' or both")

    def describe(self) -> str:
        bounds = " ".join(f"{k} {b} s" for k, b in (("min", self.min_seconds),
                                                    ("max", self.max_seconds)) if b is not None)
        return f"airborne {self.link} {bounds}"

    def evaluate(self, traj, at: Checking):
        free = ~traj.contact[:, traj.index(self.link)]
        length, i, _ = longest_run(free, traj.t)
        ok = ((self.min_seconds is None or length >= self.min_seconds - 1e-9)
              and (self.max_seconds is None or length <= self.max_seconds + 1e-9))
        return self.outcome(ok, f"longest time out of contact {length:.3f} s"
                            + (f" (from t = {traj.t[i]:.2f} s)" if length > 0 else ""),
                            within(length, self.min_seconds, self.max_seconds))


class LandedAt(Check, kw_only=True):
    """Where the longest flight ended: the link's x at touchdown, at least ``min``."""

    kind = "landed_at"
    unit = "m"
    link: str
    min: Measure  # m: x of the link when the longest flight ended

    def describe(self) -> str:
        return f"landed_at {self.link} min x {self.min} m"

    def evaluate(self, traj, at: Checking):
        length, first, last = longest_flight(traj)
        if length <= 0:
            return self.outcome(False, "never in the air", None)
        i = min(last + 1, len(traj.t) - 1)  # the first sample touching again (or the last)
        x = float(traj.x[i, traj.index(self.link)])
        return self.outcome(x >= self.min, f"longest flight {length:.2f} s from t = "
                                           f"{traj.t[first]:.2f} s, touched down at x = "
                                           f"{x:.3f} m (t = {traj.t[i]:.2f} s)", x - self.min)


def _flight_end(check: Check, traj, before: bool):
    """(the outcome if the flight has no such end, else None; the flight's length and
    first index, the sample index, the links touching there, 'LINK at x = ...')."""
    length, first, last = longest_flight(traj)
    if length <= 0:
        return check.outcome(False, "never in the air", None), None
    i = first - 1 if before else last + 1
    if i < 0 or i >= len(traj.t):
        return check.outcome(False, f"the longest flight ({length:.2f} s) "
                                    + ("began" if i < 0 else "had not ended")
                                    + " within the run", None), None
    touching = [n for k, n in enumerate(traj.links) if traj.contact[i, k]]
    where = ", ".join(f"{n} at x = {traj.x[i, traj.index(n)]:.3f}" for n in touching)
    return None, (length, first, i, touching, where)


class TookOff(Check, kw_only=True):
    """The longest flight (no link of the character touching) began from ``links`` only
    (those touching at the last sample before it), each with its centre of mass at
    ``max_x`` or less and its lowest point ``min_height`` or more up, and lasted
    ``min_seconds``: a take-off behind a line; off a wall, not the floor below it."""

    kind = "took_off"
    unit = "m"
    links: Links
    max_x: Measure | None = None  # m: x of each take-off link, at most
    min_height: Measure | None = None  # m: each take-off link's lowest point, at least
    min_seconds: Time = 0.0  # s the flight lasted, at least

    def describe(self) -> str:
        return (f"took_off from {', '.join(self.links)} only"
                + (f", each at x <= {self.max_x:g} m" if self.max_x is not None else "")
                + (f", each lowest point >= {self.min_height:g} m"
                   if self.min_height is not None else "")
                + (f", flight min {self.min_seconds:g} s" if self.min_seconds else ""))

    def evaluate(self, traj, at: Checking):
        missing, found = _flight_end(self, traj, before=True)
        if missing is not None:
            return missing
        length, first, i, touching, where = found
        xs = [float(traj.x[i, traj.index(n)]) for n in touching]
        lows = ([float(traj.lowest[i, traj.index(n)]) for n in touching]
                if self.min_height is not None else [])
        ok = not [n for n in touching if n not in self.links]
        ok = ok and length >= self.min_seconds - 1e-9 and (
            self.max_x is None or all(x <= self.max_x for x in xs)) and (
            self.min_height is None or all(y >= self.min_height - 1e-9 for y in lows))
        parts = ([(length - self.min_seconds, "s")] if self.min_seconds else []) + (
            [(self.max_x - max(xs), "m")] if self.max_x is not None and xs else []) + (
            [(min(lows) - self.min_height, "m")] if self.min_height is not None and lows
            else [])
        if self.min_height is not None and lows:
            where += f" (lowest point {min(lows):.3f} m up)"
        margin, unit = _nearest(*parts)
        if [n for n in touching if n not in self.links]:
            margin, unit = NOTHING, self.unit
        return self.outcome(ok, f"longest flight {length:.2f} s from t = "
                                f"{traj.t[first]:.2f} s; on the ground before it: {where}",
                            margin, unit)


class FirstTouch(Check, kw_only=True):
    """When the longest flight ended, only ``links`` touched (at the first sample on
    the ground again), each with its centre of mass at ``min_x`` or more: feet first,
    in the pit."""

    kind = "first_touch"
    unit = "m"
    links: Links
    min_x: Measure | None = None  # m: x of each touching link, at least

    def describe(self) -> str:
        return (f"first_touch {', '.join(self.links)} only"
                + (f", each at x >= {self.min_x:g} m" if self.min_x is not None else ""))

    def evaluate(self, traj, at: Checking):
        missing, found = _flight_end(self, traj, before=False)
        if missing is not None:
            return missing
        length, _, i, touching, where = found
        xs = [float(traj.x[i, traj.index(n)]) for n in touching]
        others = [n for n in touching if n not in self.links]
        ok = not others and (self.min_x is None or all(x >= self.min_x for x in xs))
        margin = (NOTHING if others else
                  min(xs) - self.min_x if self.min_x is not None and xs else 0.0)
        return self.outcome(ok, f"longest flight {length:.2f} s ended at t = "
                                f"{traj.t[i]:.2f} s; touching first: {where}", margin)


class BentAfterFlight(Check, kw_only=True):
    """At some sample from the end of the longest flight (the first sample down again)
    to ``within`` s later, each of ``links`` was turned from ``from_link`` by at most
    ``max`` (and at least ``min``) deg: the link's angle minus ``from_link``'s, in
    -180..180, counter-clockwise positive. For a figure facing +x, thighs from the
    chest: how far the hips and waist together are folded (+ forward), a landing with
    the trunk up, not folded over the legs."""

    kind = "bent_after_flight"
    unit = "deg"
    links: Links
    from_link: str
    min: Annotated[float, Meta(ge=-180, le=180)] | None = None  # deg, at least
    max: Annotated[float, Meta(ge=-180, le=180)] | None = None  # deg, at most
    within: Time  # s after the touch-down, at most

    def __post_init__(self):
        if self.min is None and self.max is None:
            raise ValueError("give 'min' and/or 'max' (deg)")
        if self.min is not None and self.max is not None and self.max <= self.min:
            raise ValueError(f"'max' ({self.max:g}) must be greater than 'min' ({self.min:g})")

    def describe(self) -> str:
        return (f"bent_after_flight {', '.join(self.links)} from {self.from_link} "
                f"{at_least_most(self.min, self.max)} deg within {self.within:g} s of the "
                "landing")

    def evaluate(self, traj, at: Checking):
        """The first sample after the longest flight, within ``within`` s of its end,
        with every link in range; else each link's range over that window."""
        for k, name in enumerate(self.links):
            at.check_link(traj, name, "links", k)
        at.check_link(traj, self.from_link, "from_link")
        length, first, last = longest_flight(traj)
        if length <= 0:
            return self.outcome(False, "never in the air", None)
        i = last + 1
        if i >= len(traj.t):
            return self.outcome(False, f"the longest flight ({length:.2f} s) had not ended "
                                       "within the run", None)
        window = np.arange(i, len(traj.t))[traj.t[i:] <= traj.t[i] + self.within + 1e-9]
        base = traj.angle[window, traj.index(self.from_link)]
        bend = np.stack([np.degrees(np.remainder(traj.angle[window, traj.index(n)] - base
                                                 + np.pi, 2 * np.pi) - np.pi)
                         for n in self.links], axis=1)
        ok = np.ones(len(window), dtype=bool)
        room = np.full(len(window), np.inf)
        if self.min is not None:
            ok &= (bend >= self.min - 1e-9).all(axis=1)
            room = np.minimum(room, (bend - self.min).min(axis=1))
        if self.max is not None:
            ok &= (bend <= self.max + 1e-9).all(axis=1)
            room = np.minimum(room, (self.max - bend).min(axis=1))
        spans = ", ".join(f"{n} {bend[:, k].min():.0f}..{bend[:, k].max():.0f}"
                          for k, n in enumerate(self.links))
        where = (f"the flight ended at t = {traj.t[i]:.2f} s; from {self.from_link}: {spans} "
                 f"deg to t = {traj.t[window[-1]]:.2f} s")
        margin = float(room.max())
        if ok.any():
            return self.outcome(True, f"{where}; in range at t = "
                                      f"{traj.t[window[int(np.argmax(ok))]]:.2f} s", margin)
        return self.outcome(False, where, margin)


class FlightPhases(Check, kw_only=True):
    """At least ``min_count`` (and at most ``max_count``) flights that begin inside the
    window: stretches of samples with none of ``links`` touching (default: no link of
    the character), each at least ``min_seconds`` long (from the first sample off to the
    first sample down again). Exactly two hops: ``min_count: 2, max_count: 2``.
    ``min_clearance``: a flight counts only if the lowest point of those links rose that
    far (m) above where it was as the flight began - a flight you can see, not a foot
    skimming the ground."""

    kind = "flight_phases"
    unit = "flights"
    from_: Time = field(name="from", default=0.0)  # s: window start
    until: Time | None = None  # s: window end (default: the end)
    min_count: Annotated[int, Meta(ge=1, le=100000)] | None = None  # flights, at least
    max_count: Annotated[int, Meta(ge=0, le=100000)] | None = None  # flights, at most
    min_seconds: Time  # s a flight lasts, at least
    links: Links | None = None  # the links off the ground (default: all)
    min_clearance: Annotated[float, Meta(ge=0, le=100)] | None = None  # m the lowest rose

    def __post_init__(self):
        if self.min_count is None and self.max_count is None:
            raise ValueError("give 'min_count', 'max_count' or both (flights)")

    def describe(self) -> str:
        what = "no link" if self.links is None else f"none of {', '.join(self.links)}"
        clear = ("" if self.min_clearance is None
                 else f", {self.min_clearance * 100:g} cm clear or more")
        return (f"flight_phases {at_least_most(self.min_count, self.max_count)} of "
                f"{self.min_seconds:g} s or more{clear} ({what} touching) from "
                f"{self.from_:g} s to {until_text(self)}")

    def evaluate(self, traj, at: Checking):
        names = _links_or_all(at, traj, self.links)
        cols = [traj.index(n) for n in names]
        free = ~traj.contact[:, cols].any(axis=1)
        hi = np.inf if self.until is None else self.until + 1e-9
        lengths, clears = [], []
        for i, j in runs(free):
            if not (self.from_ - 1e-9 <= traj.t[i] <= hi):
                continue
            end = traj.t[j + 1] if j + 1 < len(traj.t) else traj.t[j]  # first sample down
            lengths.append(float(end - traj.t[i]))
            clears.append(0.0 if self.min_clearance is None else _clearance(traj, i, j, cols))
        long = [d for d, c in zip(lengths, clears) if d >= self.min_seconds - 1e-9
                and (self.min_clearance is None or c >= self.min_clearance - 1e-9)]
        longest = f", the longest {max(lengths):.3f} s" if lengths else ""
        if self.min_clearance is not None and clears:
            longest += f", the highest {max(clears) * 100:.1f} cm clear"
        ok = ((self.min_count is None or len(long) >= self.min_count)
              and (self.max_count is None or len(long) <= self.max_count))
        clear = ("" if self.min_clearance is None
                 else f" and {self.min_clearance * 100:g} cm clear")
        return self.outcome(ok, f"{len(long)} flights of {self.min_seconds:g} s or more"
                                f"{clear} ({len(lengths)} in all{longest})",
                            within(len(long), self.min_count, self.max_count))


def _clearance(traj, i: int, j: int, cols) -> float:
    """How far the links' lowest point rose over samples i..j above where it was at
    the first (read only when a clearance is asked: a trajectory of contacts alone,
    as some tests build, has no heights)."""
    low = traj.lowest[i:j + 1, cols].min(axis=1)
    return float(low.max() - low[0])


class RunUp(Check, kw_only=True):
    """Before the longest flight (no link of the character touching: the jump), at
    least ``min_flights`` flights with none of ``links`` touching (default: no link),
    each ``flight_seconds`` or longer and over before the jump began (``within``: only
    those begun at most that long before it), and the centre of mass's mean speed along
    +x over the ``over`` s before the jump at least ``min_speed``: a run-up.

    The jump is the longest flight, as it is for took_off, first_touch, landed_at,
    bent_after_flight and touched's before_flight: none of them picks the flight by a
    take-off line (took_off's ``max_x`` and first_touch's ``min_x`` check where the
    longest flight began and ended, they do not choose it), so a log's entries all speak
    of one flight. A longer flight elsewhere (a bounce out of the pit, a short jump)
    moves all of them to it together, and took_off's and first_touch's bounds then fail
    the log; picking the flight across a line here would need a line run_up does not
    have, and could pass a run-up to a flight the other entries do not measure."""

    kind = "run_up"
    unit = "m/s"
    links: Links | None = None  # the links off the ground (default: all)
    min_flights: Annotated[int, Meta(ge=0, le=100000)] = 0  # flights, at least
    flight_seconds: Time = 0.04  # s a flight lasts, at least
    within: Time | None = None  # s before the jump a flight begins, at most
    min_speed: Measure | None = None  # m/s over the last 'over' s, at least
    over: Time = 1.0  # s before the jump the speed is measured over

    def __post_init__(self):
        if self.min_flights == 0 and self.min_speed is None:
            raise ValueError("give 'min_flights', 'min_speed' or both")
        if self.over <= 0:
            raise at("over", "'over' must be more than 0 s")

    def describe(self) -> str:
        what = "no link" if self.links is None else f"none of {', '.join(self.links)}"
        parts = ([f"at least {self.min_flights} flights of {self.flight_seconds:g} s or "
                  f"more ({what} touching)"
                  + (f" begun within {self.within:g} s of it" if self.within is not None
                     else "")] if self.min_flights else [])
        if self.min_speed is not None:
            parts.append(f"mean_speed min {self.min_speed:g} m/s over its last "
                         f"{self.over:g} s")
        return "run_up before the longest flight: " + ", ".join(parts)

    def evaluate(self, traj, at: Checking):
        names = _links_or_all(at, traj, self.links)
        length, jump, _ = longest_flight(traj)
        if length <= 0:
            return self.outcome(False, "never in the air", None)
        start = float(traj.t[jump])
        free = ~traj.contact[:, [traj.index(n) for n in names]].any(axis=1)
        flights = []
        for i, j in runs(free[:jump]):
            if j + 1 >= jump:  # still off the ground when the jump began: part of it
                continue
            if self.within is not None and traj.t[i] < start - self.within - 1e-9:
                continue
            if traj.t[j + 1] - traj.t[i] >= self.flight_seconds - 1e-9:
                flights.append(float(traj.t[i]))
        ok = len(flights) >= self.min_flights
        parts = [(float(len(flights) - self.min_flights), "flights")] if self.min_flights \
            else []
        said = [f"the jump from t = {start:.2f} s; {len(flights)} flights of "
                f"{self.flight_seconds:g} s or more before it"]
        if self.min_speed is not None:
            if start - float(traj.t[0]) < self.over - 1e-9:
                return self.outcome(False, said[0] + f"; the jump began {start:.2f} s into "
                                    f"the run, less than {self.over:g} s", None)
            idx = samples_in(traj.t, start - self.over, start)
            if len(idx) < 2 or traj.t[idx[-1]] <= traj.t[idx[0]]:
                return self.outcome(False, said[0] + f"; fewer than two samples in the "
                                    f"{self.over:g} s before the jump", None)
            i, j = int(idx[0]), int(idx[-1])
            speed = float((traj.com[j, 0] - traj.com[i, 0]) / (traj.t[j] - traj.t[i]))
            ok = ok and speed >= self.min_speed
            parts.append((speed - self.min_speed, "m/s"))
            said.append(f"{speed:.3f} m/s over t = {traj.t[i]:.2f} to {traj.t[j]:.2f} s")
        margin, unit = _nearest(*parts)
        return self.outcome(ok, "; ".join(said), margin, unit)
