"""The physical range of every number a data file or a log may hold.

Every number is finite (no ``.nan``, ``.inf``, ``1e308``) and inside a range that a
real character, scene or performance can use; outside it the file is refused with one
line naming the range, e.g. ``bad value for 'links.0.mass': must be a finite number
in 0.001..1000 kg (got nan)``. The ranges are generous (shipped files sit well inside
them) but bounded, so that nothing accepted can overflow the physics or run for ever.
The table is in docs/ranges.md (a test keeps the two in step).
"""

from __future__ import annotations

import math
from typing import Annotated

from msgspec import Meta

# name -> (low, high, unit, low end open). Units: metres, kilograms, seconds, degrees.
RANGES: dict[str, tuple[float, float, str, bool]] = {
    "mass": (0.001, 1000.0, "kg", False),
    "inertia": (1.0e-7, 1.0e4, "kg*m^2", False),  # a link's moment about its centre
    "size": (0.001, 10.0, "m", False),  # a shape's width, height or radius
    "corner": (0.0, 10.0, "m", False),  # a rounded corner or polygon radius (>= 0)
    "slop": (0.0, 0.01, "m", True),  # collision slop: overlap allowed in contact
    "model_xy": (-10.0, 10.0, "m", False),  # a point in a character's model frame
    "world_xy": (-10000.0, 10000.0, "m", False),  # a point in the world (10 km)
    "lift": (-10.0, 100.0, "m", False),
    "view_height": (0.05, 1000.0, "m", False),
    "angle": (-360.0, 360.0, "deg", False),  # joint targets, limits, start angles
    "angle_change": (-720.0, 720.0, "deg", False),  # adjust by, map ends
    "coupling": (-100.0, 100.0, "", False),  # a map's joint gain
    "stiffness": (0.0, 1.0e6, "N*m/rad", False),
    "damping": (0.0, 1.0e5, "N*m*s/rad", False),
    "torque": (0.0, 1.0e6, "N*m", True),  # max_torque (> 0)
    "friction": (0.0, 10.0, "", False),
    "elasticity": (0.0, 1.0, "", False),
    "gravity": (-1000.0, 1000.0, "m/s^2", False),  # each component (about 100 g)
    "thickness": (0.001, 10.0, "m", False),
    "time": (0.0, 3600.0, "s", False),  # a moment of a performance, a run's length
    "duration": (0.0, 600.0, "s", False),  # a glide, hold, reach, sequence step
    "positive_duration": (0.0, 600.0, "s", True),
    "period": (0.001, 3600.0, "s", False),  # perturbation interval
    "impulse": (0.0, 10.0, "N*m*s", True),
    "shove": (-10000.0, 10000.0, "N*s", False),  # a push's impulse, each component
    "power": (0.01, 100.0, "", False),  # a response curve's exponent
    "input": (-1.0e6, 1.0e6, "", False),  # a device or channel value, a map's 'from'
    "sensor": (-1.0e6, 1.0e6, "", False),  # a condition's threshold
    "tolerance": (0.001, 10.0, "m", False),
    "mouse": (-10.0, 10.0, "", False),  # a mouse position in a log (0..1 in the window)
    "measure": (-1.0e6, 1.0e6, "", False),  # an expectation's threshold (m)
    "turn": (0.0, 1.0e6, "deg", False),  # an expectation's accumulated rotation
    "turns": (0.0, 1.0e4, "turns", False),  # full revolutions (an expectation)
    "source_unit": (1.0e-6, 1000.0, "m", True),  # metres per unit of a mocap source
    "ratio": (0.01, 1000.0, "", False),  # a mocap mapping's size, a gain's multiplier
    "gain": (0.0, 1.0e6, "", False),  # a tracking gain (kp, dp, kq, dq)
    "fraction": (0.0, 1.0, "", False),  # a reaction's weight
    "speed": (0.0, 100.0, "m/s", False),  # a get-up's largest rise
    "axis_scale": (0.0, 1000.0, "", False),  # a mocap source axis's length in its units
    "cutoff": (0.0, 1000.0, "Hz", False),  # a stream filter's cutoff (0: no filter)
    "cutoff_slope": (0.0, 10.0, "Hz per deg/s", False),  # how a filter's cutoff rises with speed
}


def fmt(v: float) -> str:
    """A number as ranges are written: 1e6, 1e-5, 0.05."""
    return f"{v:g}".replace("e+0", "e").replace("e+", "e").replace("e-0", "e-")


def describe(name: str) -> str:
    """The range as the error and docs/ranges.md say it, e.g. ``0.001..1000 kg``."""
    lo, hi, unit, open_lo = RANGES[name]
    span = f"{fmt(lo)}..{fmt(hi)}" + (f" {unit}" if unit else "")
    return span + (f", more than {fmt(lo)}" if open_lo else "")


def problem(name: str, value) -> str | None:
    """What is wrong with ``value`` as a ``name`` number, or None."""
    lo, hi, _, open_lo = RANGES[name]
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return f"must be a number in {describe(name)}"
    try:
        finite = math.isfinite(value)
    except OverflowError:  # a whole number past any float (10**400)
        finite = False
    if not (finite and lo <= value <= hi) or (open_lo and value == lo):
        return f"must be a finite number in {describe(name)}"
    return None


_NUMS: dict[str, object] = {}


def Num(name: str):
    """A float type for msgspec: finite and inside RANGES[name] (NaN fails every bound;
    true/false is not a number to msgspec). The range's name rides in the Meta's
    ``extra``, for the error message (``puppet.data.validate``)."""
    num = _NUMS.get(name)
    if num is None:
        lo, hi, _, open_lo = RANGES[name]  # a KeyError here is a programming mistake
        low = {"gt": lo} if open_lo else {"ge": lo}
        num = _NUMS[name] = Annotated[float, Meta(le=hi, extra={"range": name}, **low)]
    return num


Mass = Num("mass")
Size = Num("size")
Corner = Num("corner")
ModelXY = tuple[Num("model_xy"), Num("model_xy")]
WorldXY = tuple[Num("world_xy"), Num("world_xy")]
Angle = Num("angle")
AngleChange = Num("angle_change")
Stiffness = Num("stiffness")
Damping = Num("damping")
Torque = Num("torque")
Friction = Num("friction")
Elasticity = Num("elasticity")
Gravity = tuple[Num("gravity"), Num("gravity")]
Time = Num("time")
Duration = Num("duration")
PositiveDuration = Num("positive_duration")




_Channel = Annotated[int, Meta(ge=0, le=255, extra={
    "message": "a colour is [red, green, blue], each a whole number 0..255"})]
Color = tuple[_Channel, _Channel, _Channel]
Seed = Annotated[int, Meta(ge=0, lt=2**32, extra={
    "message": f"a seed is a whole number 0..{2**32 - 1}"})]


STEP_RANGE = (1 / 2000, 1 / 30)  # s: the simulation steps a character, replay or try may take


def parse_step(text) -> float:
    """A simulation step in seconds, written 0.0041667 or "1/240"; ValueError (what was
    expected, in words) outside 1/2000..1/30 s or not a number."""
    try:
        if isinstance(text, str) and "/" in text:
            num, den = text.split("/", 1)
            value = float(num) / float(den)
        else:
            value = float(text)
    except (ValueError, ZeroDivisionError, TypeError):
        value = None
    if value is None or not STEP_RANGE[0] <= value <= STEP_RANGE[1]:
        raise ValueError(f"'{text}' is not a simulation step from 1/2000 to 1/30 s (e.g. "
                         f"1/240 or 0.0041667)")
    return value
