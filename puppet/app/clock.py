"""Wall clock to simulation steps: slowdown, pause, single step, measured rate.

The slowdown factor is how many wall seconds one simulated second takes (the paper's
"simulation rate"). The keys move it in log-spaced steps from 1x to 100x; a chosen
value (``--slowdown``) may also be below 1, down to 0.1: a replay watched fast.
"""

from __future__ import annotations

from collections import deque

from puppet.data.bounds import SLOWDOWNS, nearest_slowdown_index, stepped_slowdown
from puppet.data.interfaces import MAX_SLOWDOWN, MIN_SLOWDOWN
from puppet.interface.app_keys import SetSlowdown

__all__ = ["SLOWDOWNS", "SimClock", "nearest_slowdown_index"]
MAX_CATCH_UP = 0.1  # wall s of simulation one frame may owe; more is dropped (no spiral)


class SimClock:
    def __init__(self, dt: float, slowdown: float = 1.0):
        self.dt = dt
        self.set_slowdown(slowdown)
        self.paused = False
        self._owed = 0.0  # simulated seconds owed to the wall clock
        self._history: deque[tuple[float, float]] = deque()  # (wall, sim) samples

    def slower(self) -> None:
        self.slowdown, self.index = stepped_slowdown(self.slowdown, self.index, True)

    def faster(self) -> None:  # at real time or a chosen fast-forward the keys stop at 1x
        self.slowdown, self.index = stepped_slowdown(self.slowdown, self.index, False)

    def set_slowdown(self, value: float) -> None:
        """Set the slowdown directly (an interface's ``slowdown:`` key), 0.1..100."""
        self.slowdown = min(MAX_SLOWDOWN, max(MIN_SLOWDOWN, float(value)))
        self.index = nearest_slowdown_index(self.slowdown)

    def apply(self, action) -> bool:
        """Apply a speed action: "slower", "faster" (the app keys) or ``SetSlowdown`` (an
        interface key). One place for the live window, its replay and the video export,
        which pass on the actions a log's events return. False for any other action;
        pause is not one: it is the viewer's own (a log's steps already hold what a
        pause did: nothing), so a replay must not stop at a recorded pause."""
        if action == "slower":
            self.slower()
        elif action == "faster":
            self.faster()
        elif isinstance(action, SetSlowdown):
            self.set_slowdown(action.value)
        else:
            return False
        return True

    def toggle_pause(self) -> None:
        self.paused = not self.paused
        self._owed = 0.0

    def steps_for(self, wall_dt: float) -> int:
        """Steps to run for ``wall_dt`` seconds of wall time."""
        if self.paused:
            return 0
        self._owed += min(wall_dt, MAX_CATCH_UP) / self.slowdown
        n = int(self._owed / self.dt)
        self._owed -= n * self.dt
        return n

    def sample(self, wall_time: float, sim_time: float) -> None:
        self._history.append((wall_time, sim_time))
        while self._history and wall_time - self._history[0][0] > 1.0:
            self._history.popleft()

    def measured_slowdown(self) -> float | None:
        """Wall seconds per simulated second over the last second, or None if unknown."""
        if len(self._history) < 2:
            return None
        (w0, s0), (w1, s1) = self._history[0], self._history[-1]
        if s1 <= s0 or w1 - w0 < 0.25:
            return None
        return (w1 - w0) / (s1 - s0)
