"""Whether a character stayed upright over the last second of a run, not at one instant.

A headless run's summary line (``upright=True``) is read by searches to keep a try or
drop it; the root's tilt at the last step alone passes a figure caught mid-fall or
mid-somersault as it swings through upright. The watch is fed during the run (as an
``on_tick`` or ``on_frame`` callback: anything with ``time`` and ``character``) and
keeps the root's tilt over the last ``seconds``.
"""

from __future__ import annotations

import math
from collections import deque

WATCH_SECONDS = 1.0  # s at the end the root must stay upright
WATCH_HZ = 60.0  # samples a second (the session's frame check's rate)
# s of samples kept: a rewind goes back at most as far as the session's history keeps
# (session.history.KEEP_SECONDS, 180 s), and its last second must still be known
KEEP_SECONDS = 200.0


class UprightWatch:
    """The root link's tilt (deg from its model orientation, modulo full turns) at
    each sample of the last ``seconds`` s; upright means within ``tolerance_deg``
    (``Character.upright``'s default) at every one of them and now."""

    def __init__(self, seconds: float = WATCH_SECONDS, tolerance_deg: float = 45.0):
        self.seconds = seconds
        self.tolerance = tolerance_deg
        self.samples: deque[tuple[float, float]] = deque()  # (time, tilt)

    @staticmethod
    def every(dt: float) -> int:
        """Steps between samples at ``dt`` (WATCH_HZ)."""
        return max(1, round(1.0 / (WATCH_HZ * dt)))

    def __call__(self, session) -> None:
        """Take a sample of ``session`` (``time``, ``character``)."""
        t = session.time
        while self.samples and self.samples[-1][0] >= t - 1e-12:  # a rewind, or again
            self.samples.pop()
        tilt = abs(math.degrees(math.remainder(session.character.root_angle(),
                                               2 * math.pi)))
        self.samples.append((t, tilt))
        while self.samples[0][0] < t - max(self.seconds, KEEP_SECONDS):
            self.samples.popleft()

    def worst(self, session) -> tuple[float, float]:
        """(tilt, time) of the most tipped sample of the last ``seconds`` (now included)."""
        self(session)
        start = session.time - self.seconds - 1e-9
        return max(((tilt, t) for t, tilt in self.samples if t >= start), default=(0.0, 0.0))

    def stayed(self, session) -> bool:
        """Upright at every sample of the last ``seconds`` (the whole run if shorter)."""
        return self.worst(session)[0] <= self.tolerance

    def said(self, session) -> str:
        """``upright=True``, or ``upright=False (root 97 deg from upright at t=4.20s)``."""
        tilt, t = self.worst(session)
        if tilt <= self.tolerance:
            return "upright=True"
        return f"upright=False (root {tilt:.0f} deg from upright at t={t:.2f}s)"
