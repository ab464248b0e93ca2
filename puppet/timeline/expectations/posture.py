"""How the character was turned: upright or fallen, links' tilts and signed angles,
lying then getting up, turning over, joints following a performance. Margins in
degrees (seconds for got_up, a share of samples for mostly_within).

"Upright" is a link's angle from its model orientation, taken modulo full turns; a
fall is the root more than 90 deg from upright while any link touches the ground.
"""

from __future__ import annotations

from typing import Annotated, ClassVar, Literal

import numpy as np

from puppet.data.ranges import Num, Time
from puppet.data.validate import Meta, at, field
from puppet.timeline.expectations.base import Check, Checking
from puppet.timeline.expectations.measure import (
    at_least_most,
    interval,
    runs,
    samples_in,
    short_of,
    signed_deg,
    tilt_deg,
    until_text,
    within,
)
from puppet.timeline.expectations.outcome import NOTHING

UPRIGHT_DEG = 45.0  # upright_at_end tolerance (Character.upright's default)
FELL_DEG = 90.0  # never_fell: beyond this from upright is a fall
Links = Annotated[list[str], Meta(min_length=1, max_length=64)]
Measure = Num("measure")


class _YesNo(Check, kw_only=True):
    """A kind written ``KIND: true`` (or false: the opposite expected)."""

    written: ClassVar = bool
    expected: bool = True

    @classmethod
    def from_written(cls, value):
        return cls(expected=value) if isinstance(value, bool) else value

    def describe(self) -> str:
        return f"{self.kind} {'true' if self.expected else 'false'}"


class UprightAtEnd(_YesNo, kw_only=True):
    """The root within 45 deg of upright at the end."""

    kind = "upright_at_end"
    unit = "deg"

    def evaluate(self, traj, at: Checking):
        tilt = float(tilt_deg(traj.root_angle[-1:])[0])
        upright = tilt <= UPRIGHT_DEG
        return self.outcome(upright == self.expected,
                            f"root {tilt:.0f} deg from upright at the end",
                            (UPRIGHT_DEG - tilt) * (1 if self.expected else -1))


class NeverFell(_YesNo, kw_only=True):
    """The root never more than 90 deg from upright while touching the ground."""

    kind = "never_fell"
    unit = "deg"

    def evaluate(self, traj, at: Checking):
        tilt = np.where(traj.contact.any(axis=1), tilt_deg(traj.root_angle), 0.0)
        i = int(np.argmax(tilt))
        fell = bool(tilt[i] > FELL_DEG)
        return self.outcome((not fell) == self.expected,
                            f"largest tilt on the ground {tilt[i]:.0f} deg at "
                            f"t = {traj.t[i]:.2f} s",
                            (FELL_DEG - float(tilt[i])) * (1 if self.expected else -1))


class TiltNeverAbove(Check, kw_only=True):
    """Each of ``links`` stays within ``max`` degrees of its model orientation (upright)
    at every sample: a trunk that never leans past 45 degrees."""

    kind = "tilt_never_above"
    unit = "deg"
    links: Links
    max: Num("angle")  # deg from upright

    def describe(self) -> str:
        return f"tilt_never_above {', '.join(self.links)} max {self.max} deg"

    def evaluate(self, traj, at: Checking):
        worst, when, which = -1.0, 0, self.links[0]
        for name in self.links:
            tilt = tilt_deg(traj.angle[:, traj.index(name)])
            i = int(np.argmax(tilt))
            if tilt[i] > worst:
                worst, when, which = float(tilt[i]), i, name
        return self.outcome(worst <= self.max, f"{which} {worst:.0f} deg from upright at "
                                               f"t = {traj.t[when]:.2f} s (the most)",
                            self.max - worst)


class TiltAtEnd(Check, kw_only=True):
    """Each of ``links`` within ``max`` degrees of its model orientation (upright) at
    every sample of the last ``held`` s (0: the last sample): standing up straight at
    the end, not only not having fallen."""

    kind = "tilt_at_end"
    unit = "deg"
    links: Links
    max: Num("angle")  # deg from upright
    held: Num("duration") = 0.0  # s at the end it must stay within

    def describe(self) -> str:
        return (f"tilt_at_end {', '.join(self.links)} max {self.max} deg"
                + (f" held {self.held} s" if self.held else ""))

    def evaluate(self, traj, at: Checking):
        window = traj.t >= traj.t[-1] - self.held - 1e-9
        worst, which = -1.0, self.links[0]
        for name in self.links:
            tilt = float(tilt_deg(traj.angle[window, traj.index(name)]).max())
            if tilt > worst:
                worst, which = tilt, name
        return self.outcome(worst <= self.max, f"{which} at most {worst:.1f} deg from "
                            "upright " + (f"over the last {self.held:g} s" if self.held
                                          else "at the end"), self.max - worst)


def _signed_range(low: float | None, high: float | None) -> None:
    """A signed angle range's own checks (angle_within's and mean_angle's): one end at
    least, the max above the min."""
    if low is None and high is None:
        raise ValueError("give 'min' and/or 'max' (deg)")
    if low is not None and high is not None and high <= low:
        raise ValueError(f"'max' ({high:g}) must be greater than 'min' ({low:g})")


class AngleWithin(Check, kw_only=True):
    """The link's signed angle from upright (deg, -180..180, counter-clockwise positive:
    tipped backward for a character facing +x) within ``min``..``max`` at every sample
    from ``from`` to ``until`` s: on its back at the start, never on its front."""

    kind = "angle_within"
    unit = "deg"
    link: str
    min: Annotated[float, Meta(ge=-180, le=180)] | None = None  # deg, signed
    # deg, signed; over 180 the angle is taken in max-360..max: a range across upside down
    max: Annotated[float, Meta(ge=-180, le=540)] | None = None
    from_: Time = field(name="from", default=0.0)  # s: window start
    until: Time | None = None  # s: window end (default: the end)

    def __post_init__(self):
        _signed_range(self.min, self.max)
        # a range that holds every angle checks nothing: the angle is taken in
        # max-360..max (-180..180 without a max)
        low = -180.0 if self.max is None else max(-180.0, self.max - 360.0)
        if (self.min is None or self.min <= low) and (self.max is None or self.max >= 180):
            raise ValueError("this range holds every angle; expected a 'min' above "
                             f"{low:g} or a 'max' under 180")

    def describe(self) -> str:
        return (f"angle_within {self.link} {at_least_most(self.min, self.max)} deg (signed) "
                f"from {self.from_:g} s to {until_text(self)}")

    def evaluate(self, traj, at: Checking):
        """The samples of the window whose signed angle is out of bounds: the first of
        them and the range the angle took."""
        idx = samples_in(traj.t, self.from_, self.until)
        if len(idx) == 0:
            return self.no_samples(traj.t)
        # in (top - 360, top]: -180..180, or across upside down when max is over 180
        top = 180.0 if self.max is None or self.max <= 180 else self.max
        angle = top - np.remainder(top - np.degrees(traj.angle[idx, traj.index(self.link)]),
                                   360.0)
        out = np.zeros(len(idx), dtype=bool)
        if self.min is not None:
            out |= angle < self.min
        if self.max is not None:
            out |= angle > self.max
        margin = min(within(float(angle.min()), self.min), within(float(angle.max()), None,
                                                                  self.max))
        span = (f"{self.link} {angle.min():.0f}..{angle.max():.0f} deg from t = "
                f"{traj.t[idx[0]]:.2f} to {traj.t[idx[-1]]:.2f} s")
        if not out.any():
            return self.outcome(True, span, margin)
        k = int(np.flatnonzero(out)[0])
        return self.outcome(False, f"{span}; out at t = {traj.t[idx[k]]:.2f} s "
                                   f"({angle[k]:.0f} deg)", margin)


class MeanAngle(Check, kw_only=True):
    """The link's signed angle from upright (deg, -180..180, counter-clockwise positive)
    averaged over the samples from ``from`` to ``until`` s, within ``min``..``max``: a
    posture held on average through a gait that swings about it (a run's forward lean),
    which ``angle_within`` at every sample cannot say."""

    kind = "mean_angle"
    unit = "deg"
    link: str
    min: Annotated[float, Meta(ge=-180, le=180)] | None = None  # deg, signed
    max: Annotated[float, Meta(ge=-180, le=180)] | None = None  # deg, signed
    from_: Time = field(name="from", default=0.0)  # s: window start
    until: Time | None = None  # s: window end (default: the end)

    def __post_init__(self):
        _signed_range(self.min, self.max)
        if self.until is not None and self.until <= self.from_:
            raise at("until", "'until' must be later than 'from'")

    def describe(self) -> str:
        return (f"mean_angle {self.link} {at_least_most(self.min, self.max)} deg (signed) "
                f"from {self.from_:g} s to {until_text(self)}")

    def evaluate(self, traj, at: Checking):
        idx = samples_in(traj.t, self.from_, self.until)
        if len(idx) == 0:
            return self.no_samples(traj.t)
        angle = signed_deg(traj.angle[idx, traj.index(self.link)])
        mean = float(angle.mean())
        margin = within(mean, self.min, self.max)
        return self.outcome(margin >= 0, f"{self.link} {mean:.1f} deg on average "
                                         f"({angle.min():.0f}..{angle.max():.0f}) from t = "
                                         f"{traj.t[idx[0]]:.2f} to {traj.t[idx[-1]]:.2f} s", margin)


class MostlyWithin(Check, kw_only=True):
    """``link`` within every bound given at at least ``min_fraction`` of the samples from
    ``from`` to ``until`` s: ``max_tilt`` deg from upright, its centre of mass's x within
    ``x_min``..``x_max`` m, and lower than ``below``'s. A posture held most of the time
    (the trunk upright and close to a ladder), not at every sample: a climb's strokes
    pass through other postures."""

    kind = "mostly_within"
    unit = "share"
    link: str
    max_tilt: Annotated[float, Meta(ge=0, le=180)] | None = None  # deg from upright, at most
    x_min: Measure | None = None  # m: x of the centre of mass, at least
    x_max: Measure | None = None  # m: x of the centre of mass, at most
    below: str | None = None  # a link whose centre of mass is higher
    min_fraction: Annotated[float, Meta(gt=0, le=1)]  # share of the window's samples
    from_: Time = field(name="from", default=0.0)  # s: window start
    until: Time | None = None  # s: window end (default: the end)

    def __post_init__(self):
        if all(b is None for b in (self.max_tilt, self.x_min, self.x_max, self.below)):
            raise ValueError("give at least one of 'max_tilt', 'x_min', 'x_max', 'below'")
        if self.until is not None and self.until <= self.from_:
            raise at("until", "'until' must be later than 'from'")
        if self.x_min is not None and self.x_max is not None and self.x_max <= self.x_min:
            raise ValueError(f"'x_max' ({self.x_max:g}) must be greater than 'x_min' "
                             f"({self.x_min:g})")

    def describe(self) -> str:
        bounds = ", ".join(b for b in (
            f"within {self.max_tilt:g} deg of upright" if self.max_tilt is not None else "",
            f"x >= {self.x_min:g} m" if self.x_min is not None else "",
            f"x <= {self.x_max:g} m" if self.x_max is not None else "",
            f"below {self.below}" if self.below is not None else "") if b)
        return (f"mostly_within {self.link} {bounds} at {self.min_fraction:g} of the samples "
                f"from {self.from_:g} s to {until_text(self)}")

    def evaluate(self, traj, at: Checking):
        if self.below is not None:
            at.check_link(traj, self.below, "below")
        idx = samples_in(traj.t, self.from_, self.until)
        if len(idx) == 0:
            return self.no_samples(traj.t)
        k = traj.index(self.link)
        ok = np.ones(len(idx), dtype=bool)
        parts = []
        if self.max_tilt is not None:
            tilt = tilt_deg(traj.angle[idx, k])
            ok &= tilt <= self.max_tilt
            parts.append(f"tilt within {self.max_tilt:g} deg at "
                         f"{np.mean(tilt <= self.max_tilt):.0%}")
        if self.x_min is not None or self.x_max is not None:
            x = traj.x[idx, k]
            lo = -np.inf if self.x_min is None else self.x_min
            hi = np.inf if self.x_max is None else self.x_max
            inside = (x >= lo) & (x <= hi)
            ok &= inside
            parts.append(f"x {x.min():.2f}..{x.max():.2f} m, in bounds at {np.mean(inside):.0%}")
        if self.below is not None:
            under = traj.y[idx, k] < traj.y[idx, traj.index(self.below)]
            ok &= under
            parts.append(f"below {self.below} at {np.mean(under):.0%}")
        share = float(np.mean(ok))
        return self.outcome(share >= self.min_fraction - 1e-9,
                            f"all bounds met at {share:.1%} of {len(idx)} samples ("
                            + "; ".join(parts) + ")", share - self.min_fraction)


class GotUp(Check, kw_only=True):
    """The last stretch lying (root >= min_tilt from upright while touching), at least
    lay_seconds long; then standing (root <= upright_tilt) from some sample to the end,
    reached within within_seconds of the end of lying."""

    kind = "got_up"
    unit = "s"
    lay_seconds: Time  # s lying first, in one stretch
    within_seconds: Time  # s from the end of the last lying stretch to standing up for good
    # deg from upright, touching the ground: lying
    min_tilt: Annotated[float, Meta(ge=0, le=180)] = 80.0
    upright_tilt: Annotated[float, Meta(ge=0, le=180)] = 20.0  # deg from upright at most: standing

    def describe(self) -> str:
        return (f"got_up: lay (>= {self.min_tilt:g} deg) min {self.lay_seconds} s, up "
                f"(<= {self.upright_tilt:g} deg) within {self.within_seconds} s")

    def evaluate(self, traj, at: Checking):
        tilt = tilt_deg(traj.root_angle)
        lying = (tilt >= self.min_tilt) & traj.contact.any(axis=1)
        stretches = runs(lying)
        if not stretches:
            return self.outcome(False, f"never lay (root >= {self.min_tilt:g} deg on the "
                                       "ground)", short_of(self.lay_seconds))
        i, j = stretches[-1]
        lay = float(traj.t[j] - traj.t[i] + interval(traj.t))
        up = tilt <= self.upright_tilt
        after = np.flatnonzero(~up)
        first_up = (int(after[-1]) + 1) if len(after) else 0  # standing from here to the end
        if first_up >= len(up) or first_up <= j:
            return self.outcome(False, f"lay {lay:.2f} s until t = {traj.t[j]:.2f} s, not "
                                       f"standing at the end ({tilt[-1]:.0f} deg)", NOTHING)
        took = float(traj.t[first_up] - traj.t[j])
        ok = lay >= self.lay_seconds - 1e-9 and took <= self.within_seconds + 1e-9
        return self.outcome(ok, f"lay {lay:.2f} s (t = {traj.t[i]:.2f} to {traj.t[j]:.2f} "
                                f"s), standing from t = {traj.t[first_up]:.2f} s: up in "
                                f"{took:.2f} s",
                            min(lay - self.lay_seconds, self.within_seconds - took))


class Turned(Check, kw_only=True):
    """The link's accumulated rotation, start to end (or within one flight), at least
    ``min_degrees`` in ``direction``."""

    kind = "turned"
    unit = "deg"
    link: str
    min_degrees: Num("turn")  # deg of accumulated rotation
    # backward = counter-clockwise (the model faces +x)
    direction: Literal["backward", "forward"] = "backward"
    # count only the turn made in one stretch with no link of the character touching
    in_flight: bool = False

    def describe(self) -> str:
        return (f"turned {self.link} {self.direction} min {self.min_degrees} deg"
                + (" in flight" if self.in_flight else ""))

    def evaluate(self, traj, at: Checking):
        sign = 1.0 if self.direction == "backward" else -1.0
        turn = sign * np.degrees(np.unwrap(traj.angle[:, traj.index(self.link)]))
        where = ""
        if self.in_flight:
            free = ~traj.contact.any(axis=1)
            best, best_t0 = 0.0, None
            for i, j in runs(free):
                # from the last sample on the ground before to the first after
                a, b = max(i - 1, 0), min(j + 1, len(free) - 1)
                if turn[b] - turn[a] > best:
                    best, best_t0 = float(turn[b] - turn[a]), float(traj.t[a])
            amount = best
            if best_t0 is not None:
                where = f" in the flight from t = {best_t0:.2f} s"
        else:
            amount = float(turn[-1] - turn[0])
        return self.outcome(amount >= self.min_degrees,
                            f"turned {amount:.0f} deg {self.direction}{where}",
                            amount - self.min_degrees)


class FollowedChannels(Check, kw_only=True):
    """Each of ``joints`` moved like the performance: its angle within ``max_rms``
    degrees RMS of the input channel of its name (the retargeted mocap angle) over the
    samples from ``from`` to ``until`` s that have a value for it. ``min_rms``: at least
    one of them strayed that far (the figure reacted to something: a push)."""

    kind = "followed_channels"
    unit = "deg"
    joints: Links
    from_: Time = field(name="from", default=0.0)
    until: Time | None = None
    max_rms: Num("angle") | None = None  # deg
    min_rms: Num("angle") | None = None  # deg

    def __post_init__(self):
        if self.max_rms is None and self.min_rms is None:
            raise ValueError("give 'max_rms' and/or 'min_rms' (deg)")

    def describe(self) -> str:
        bounds = " and ".join(b for b in (
            f"each within {self.max_rms:g}" if self.max_rms is not None else "",
            f"one at least {self.min_rms:g}" if self.min_rms is not None else "") if b)
        return (f"followed_channels {', '.join(self.joints)}: {bounds} deg RMS "
                f"from {self.from_:g} s to {until_text(self)}")

    def evaluate(self, traj, at: Checking):
        window = (traj.t >= self.from_ - 1e-9) & (traj.t <= (np.inf if self.until is None
                                                            else self.until + 1e-9))
        worst, which, parts = -1.0, self.joints[0], []
        for name in self.joints:
            if name not in traj.joints:
                raise at.error(f"no joint named '{name}' in this character (joints: "
                               f"{', '.join(traj.joints)})", "joints")
            k = traj.joints.index(name)
            have = window & ~np.isnan(traj.joint_channel[:, k])
            if not have.any():
                return self.outcome(False, f"no channel '{name}' came in the window", None)
            diff = np.degrees(np.remainder(traj.joint_angle[have, k]
                                           - traj.joint_channel[have, k] + np.pi, 2 * np.pi)
                              - np.pi)
            rms = float(np.sqrt(np.mean(diff ** 2)))
            parts.append(f"{name} {rms:.1f}")
            if rms > worst:
                worst, which = rms, name
        ok = (self.max_rms is None or worst <= self.max_rms) and (self.min_rms is None
                                                                  or worst >= self.min_rms)
        return self.outcome(ok, f"RMS deg: {', '.join(parts)} (worst {which})",
                            within(worst, self.min_rms, self.max_rms))
