"""A recorded clip as an input source: its retargeted channels, sampled in sim time.

The clip plays on the session's clock, not the wall's, so a slowed-down window plays
it slowed and a rewind plays it again from the rewound time. Samples fall on a grid,
``start + k / rate`` s (60 Hz by default: the window's frame rate): ``events`` gives
them all for a headless run, and ``drain(now)`` gives the window the newest grid
sample ``now`` has reached, once - the session records it at the step it acts, so the
log replays with no clip at all. Looping carries the distance on: each lap's
``root.x`` starts where the last one ended, so a tracked figure walks on instead of
being pulled back to the start. ``drop`` (``play --mocap-drop FROM:UNTIL``) leaves out
the samples of a stretch of time, as a stream that stops does: tracking is lost then.
"""

from __future__ import annotations

import math

from puppet.interface.events import channels as channels_event
from puppet.mocap.retarget import RetargetedClip

LAP_CHANNEL = "root.x"  # the channel a loop carries on from lap to lap


class ClipSource:
    def __init__(self, clip: RetargetedClip, rate: float = 60.0, start: float = 0.0,
                 speed: float = 1.0, loop: bool = False, name: str = "clip",
                 drop: tuple[float, float] | None = None):
        self.clip = clip
        self.period = 1.0 / rate
        self.start = start  # session time at which the clip's first frame plays
        self.speed = speed
        self.loop = loop and clip.duration > 0
        self.name = name
        self.posted = 0
        self.drop = drop  # (from, until) s of session time with no sample: tracking lost
        self._last_k: int | None = None  # the grid sample given last
        self._lap_x = clip.at(clip.duration).get(LAP_CHANNEL, 0.0) - \
            clip.at(0.0).get(LAP_CHANNEL, 0.0)

    def values_at(self, now: float) -> dict[str, float]:
        """The channels at session time ``now``."""
        t = (now - self.start) * self.speed
        laps = 0
        if self.loop and t > 0:
            laps = math.floor(t / self.clip.duration)
            t -= laps * self.clip.duration
        values = self.clip.at(t)
        if laps and LAP_CHANNEL in values:
            values[LAP_CHANNEL] += laps * self._lap_x
        return values

    def drain(self, now: float) -> list:
        """The newest grid sample at or before session time ``now``, if not given yet
        (a rewind, ``now`` gone back, gives it again from there)."""
        k = math.floor((now - self.start) / self.period + 1e-9)
        if k < 0 or k == self._last_k or self._dropped(self.start + k * self.period):
            return []
        self._last_k = k
        self.posted += 1
        return [channels_event(self.values_at(self.start + k * self.period))]

    def events(self, dt: float, seconds: float) -> list[tuple[int, dict]]:
        """(step, event) for a headless run of ``seconds`` at step ``dt``: a sample at
        every grid time from ``start``."""
        out = []
        k = 0
        while True:
            now = self.start + k * self.period
            if now > seconds:
                break
            if not self._dropped(now):
                out.append((round(now / dt), channels_event(self.values_at(now))))
            k += 1
        return out

    def _dropped(self, now: float) -> bool:
        return self.drop is not None and self.drop[0] <= now < self.drop[1]

    def status(self) -> str:
        return f"{self.name}: {self.posted} samples"
