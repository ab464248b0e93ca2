"""A recorded clip as an input source: its retargeted channels, sampled in sim time.

The clip plays on the session's clock, not the wall's, so a slowed-down window plays
it slowed, a rewind plays it again from the rewound time, and a headless run gives
the same events as the window. Each ``drain(now)`` gives at most one ``channels``
event - the clip at ``now`` - and only when ``now`` has moved on by a sample period
(``rate``, 60 Hz by default: the window's frame rate); the session records it at the
step it acts, so the log replays with no clip at all.
"""

from __future__ import annotations

from puppet.interface.events import channels as channels_event
from puppet.mocap.retarget import RetargetedClip


class ClipSource:
    def __init__(self, clip: RetargetedClip, rate: float = 60.0, start: float = 0.0,
                 speed: float = 1.0, loop: bool = False, name: str = "clip"):
        self.clip = clip
        self.period = 1.0 / rate
        self.start = start  # session time at which the clip's first frame plays
        self.speed = speed
        self.loop = loop
        self.name = name
        self.posted = 0
        self._next = start  # session time of the next sample

    def clip_time(self, now: float) -> float:
        t = (now - self.start) * self.speed
        if self.loop and self.clip.duration > 0:
            t %= self.clip.duration
        return t

    def drain(self, now: float) -> list:
        """The sample due at session time ``now`` (none if one was given for it)."""
        if now + 1e-9 < self._next and now >= self._next - 2 * self.period:
            return []
        self._next = now + self.period  # a rewind (now went back) starts again from now
        self.posted += 1
        return [channels_event(self.clip.at(self.clip_time(now)))]

    def events(self, dt: float, seconds: float) -> list[tuple[int, dict]]:
        """(step, event) for a headless run of ``seconds`` at step ``dt``: a sample at
        every period from ``start``."""
        out = []
        k = 0
        while True:
            now = self.start + k * self.period
            if now > seconds:
                break
            step = round(now / dt)
            out.append((step, channels_event(self.clip.at(self.clip_time(now)))))
            k += 1
        return out

    def status(self) -> str:
        return f"{self.name}: {self.posted} samples"
