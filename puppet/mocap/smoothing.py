"""Filtering a live stream's channels: the 1-euro filter (Casiez, Roussel & Vogel, CHI
2012), the one MediaPipe itself smooths landmarks with.

Nguyen et al. 2010 time-stamp the live samples, throw out the poor ones and "filter
the data as well", without saying how. Here the poor ones are the guard's
(``puppet.mocap.guard``: a sample further from the last kept one than a body moves in
the time between is an outlier, ``too_fast``); what is kept is filtered per channel by
a first-order low-pass whose cutoff rises with the channel's speed:

    cutoff = min_cutoff + beta * |speed|     (Hz; speed in deg/s, or cm/s for metres)
    alpha = 1 / (1 + 1 / (2 pi cutoff dt))   value += alpha * (sample - value)

(the speed itself low-passed at 1 Hz). So a performer holding still is smoothed hard
(the jitter of a webcam's landmarks, of a suit's sensors: 1 degree of noise becomes
less than half of one) and one moving fast is followed closely. The lag is a low-pass's time
constant, 1 / (2 pi cutoff): 40 ms with the default cutoff of 4 Hz for a performer
holding still, 20 ms at 200 deg/s with the default beta of 0.02, 7 ms at 1000 deg/s;
on the CMU walk (hips, knees, shoulders, elbows, root, feet) the filtered channels
follow the raw ones 12-19 ms late streamed at 120 Hz, 15-23 ms at 30 Hz
(tests/test_mocap_clean.py measures it). A channel whose name ends ``.x`` / ``.y`` or
is ``root.x`` / ``root.y`` / ``clearance`` is metres (its speed counted in cm/s, so a
centimetre weighs as a degree).

Why not a library: the filter is ten lines; the PyPI packages of it are unmaintained
single files.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from puppet.data.mappings import FilterSpec

MIN_CUTOFF = FilterSpec().cutoff  # Hz: the cutoff while still (a mapping's filter.cutoff)
BETA = FilterSpec().beta  # Hz per deg/s (or cm/s): how the cutoff rises with speed
SPEED_CUTOFF = 1.0  # Hz: the speed's own low-pass
METRE_CHANNELS = ("root.x", "root.y", "clearance")
LONGEST_GAP = 0.5  # s: after a gap this long a channel starts again from its sample


def _alpha(cutoff: float, dt: float) -> float:
    return 1.0 / (1.0 + 1.0 / (2.0 * math.pi * cutoff * dt))


@dataclass
class OneEuro:
    """One channel's filter state."""

    value: float
    time: float
    speed: float = 0.0

    def step(self, sample: float, now: float, min_cutoff: float, beta: float,
             per_unit: float) -> float:
        dt = now - self.time
        if dt == 0.0:  # two samples at once: the first stands
            return self.value
        if not 0.0 < dt <= LONGEST_GAP:  # after a silence (or a sender that started
            # its clock again): no speed to speak of, start here
            self.value, self.time, self.speed = sample, now, 0.0
            return sample
        speed = (sample - self.value) / dt
        self.speed += _alpha(SPEED_CUTOFF, dt) * (speed - self.speed)
        cutoff = min_cutoff + beta * abs(self.speed) * per_unit
        self.value += _alpha(cutoff, dt) * (sample - self.value)
        self.time = now
        return self.value


class StreamFilter:
    """Filters the channels of each frame (``apply``); ``min_cutoff`` 0 turns it off."""

    def __init__(self, min_cutoff: float = MIN_CUTOFF, beta: float = BETA):
        self.min_cutoff = min_cutoff
        self.beta = beta
        self.channels: dict[str, OneEuro] = {}

    @property
    def on(self) -> bool:
        return self.min_cutoff > 0.0

    def apply(self, values: dict[str, float], now: float) -> dict[str, float]:
        if not self.on:
            return values
        out = {}
        for name, sample in values.items():
            state = self.channels.get(name)
            if state is None:
                self.channels[name] = OneEuro(sample, now)
                out[name] = sample
                continue
            metres = name in METRE_CHANNELS or name.endswith((".x", ".y"))
            out[name] = state.step(sample, now, self.min_cutoff, self.beta,
                                   100.0 if metres else 1.0)
        return out

    def lag(self, speed: float) -> float:
        """s: the filter's time constant at ``speed`` (deg/s or cm/s)."""
        return 1.0 / (2.0 * math.pi * (self.min_cutoff + self.beta * abs(speed)))
