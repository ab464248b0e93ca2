"""The simulated player's imprecision, as numbers: the human model of ``puppet playtest``.

A playtest replays a log many times, each time moved as a person's hands would move
it (``puppet.timeline.playtest``). How far is set here, by named levels; the sources
of the numbers are in docs/interfaces.md ("The human model"). All times are *real*
(wall) time: at a slowdown of 3 a 30 ms error is 10 ms of simulated time, as it is
for a person playing slowed down. Plain tables (no models to import): the command
line reads them at start-up. The sidecar's ``playtest:`` bar is
``puppet.data.playtest_bar``.
"""

from __future__ import annotations

from dataclasses import dataclass, fields

# the window a mouse error in pixels is measured on: the app's smallest (x, y)
REFERENCE_WINDOW = (1024.0, 640.0)

# each parameter of the model: (least, most, unit, what it is); a command-line flag each
PARAMETERS: dict[str, tuple[float, float, str, str]] = {
    "timing_ms": (0.0, 2000.0, "ms", "each event's time error, real time (a stroke's as a "
                                     "whole; a reactive rule's delay too)"),
    "aim_px": (0.0, 500.0, "px", "a mouse stroke's offset, pixels of a 1024 x 640 window"),
    "tremor_px": (0.0, 500.0, "px", "each mouse sample's own jitter on top of its stroke's"),
    "tempo": (0.0, 0.5, "", "a stroke's length scaled by 1 +- this"),
    "stick_aim": (0.0, 1.0, "", "a stick or trigger stroke's offset, of full deflection"),
    "stick_tremor": (0.0, 1.0, "", "each stick sample's own jitter on top"),
    "stroke_gap_ms": (0.0, 2000.0, "ms", "a pause this long between two samples of the "
                                         "mouse (a stick...) begins a new stroke"),
}


@dataclass(frozen=True)
class Noise:
    """One level of imprecision. Every bound is a half-width: an error is drawn
    uniformly from -bound..+bound (per axis for positions)."""

    timing_ms: float  # real ms
    aim_px: float  # px of the reference window
    tremor_px: float
    tempo: float  # (motor timing's scalar error)
    stick_aim: float
    stick_tremor: float
    stroke_gap_ms: float = 150.0

    def is_off(self) -> bool:
        """No error at all: the tries are the log itself."""
        return not (self.timing_ms or self.aim_px or self.tremor_px or self.tempo
                    or self.stick_aim or self.stick_tremor)


assert [f.name for f in fields(Noise)] == list(PARAMETERS)  # one flag per field

# The named levels (docs/interfaces.md, "The human model", says where each number comes
# from). tremor is a quarter of the aim error, as in the first measurement; tempo's
# standard deviation (a uniform's half-width / sqrt 3) is 2, 4, 8 % of a stroke.
LEVELS: dict[str, Noise] = {
    "steady": Noise(timing_ms=10.0, aim_px=2.0, tremor_px=0.5, tempo=0.035,
                    stick_aim=0.02, stick_tremor=0.005),
    "human": Noise(timing_ms=30.0, aim_px=5.0, tremor_px=1.25, tempo=0.07,
                   stick_aim=0.05, stick_tremor=0.0125),
    "novice": Noise(timing_ms=60.0, aim_px=10.0, tremor_px=2.5, tempo=0.14,
                    stick_aim=0.10, stick_tremor=0.025),
}


def noise_at(level: str = "human", **overrides: float) -> Noise:
    """A named level with some of its parameters replaced (None: keep the level's).
    ValueError naming the levels or the parameters for an unknown one, or the range
    for a value outside it."""
    if level not in LEVELS:
        raise ValueError(f"unknown noise level '{level}'; expected one of: "
                         f"{', '.join(LEVELS)}")
    base = LEVELS[level]
    given = {k: v for k, v in overrides.items() if v is not None}
    unknown = [k for k in given if k not in PARAMETERS]
    if unknown:
        raise ValueError(f"unknown noise parameter '{unknown[0]}'; expected one of: "
                         f"{', '.join(PARAMETERS)}")
    values = {k: getattr(base, k) for k in PARAMETERS}
    for k, v in given.items():
        lo, hi, unit, _ = PARAMETERS[k]
        if not lo <= float(v) <= hi:  # (NaN too)
            raise ValueError(f"{k} must be a number {lo:g}..{hi:g}"
                             f"{' ' + unit if unit else ''}, got {v!r}")
        values[k] = float(v)
    return Noise(**values)
