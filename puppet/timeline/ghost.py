"""A ghost: a recorded log replaying beside the live run, in lock-step with its time.

The ghost is a second, separate Session (its own pymunk space, its own interface
runtime) fed from the log by a ``LogFeeder``. ``sync(live)`` advances it to the live
session's simulated time; nothing of the live session is written to, so the live
simulation and its log are exactly what they would be without a ghost.

When the live time goes back (a rewind), the ghost goes back too: through its own
session's history (its checkpoints are exact, so it rewinds to the very state it had
there, re-simulating at most one checkpoint interval), or, for a log that itself
rewinds or restores (its steps are not its clock) or a time older than the history
keeps, by being rebuilt and fed again from the start of its log.
"""

from __future__ import annotations

import bisect
from pathlib import Path

from puppet.session import Session
from puppet.timeline.log import Log, read_log
from puppet.timeline.replay import LogFeeder, new_session, setup_for_log


class Ghost:
    def __init__(self, log: Log | str | Path, allow_truncated: bool = False):
        self.log = log if isinstance(log, Log) else read_log(log, allow_truncated)
        # the run as it was played, whatever the interface file says now
        self.setup, self.warnings = setup_for_log(self.log, as_recorded="interface_text"
                                                  in self.log.header)
        self._steps = [e.step for e in self.log.events]
        self.fed = 0  # steps fed to the ghost so far: its clock (a log's rewinds go back)
        self._start()

    def _start(self) -> None:
        self.session: Session = new_session(self.log, self.setup)
        self.feeder = LogFeeder(self.session, self.log)
        self.fed = 0
        self.feeder.advance(0)  # the events logged at step 0 act before any step

    def sync(self, live: Session) -> None:
        """Bring the ghost to the live session's simulated time."""
        target = round(live.time / self.session.sim.dt)
        if target < self.fed:  # the live run went back in time
            # Its session's step is the ghost's clock as long as the log has not gone
            # back itself (a rewind or restore in it) and has not ended.
            linear = self.session.steps == min(self.fed, self.feeder.end)
            if linear and target >= self.session.steps:
                self.fed = target  # still after the ghost's log ended: it stays there
            elif linear and self.session.history.oldest() <= target:
                self.session.rewind_to(target)  # replays the events before target
                self.feeder.i = bisect.bisect_left(self._steps, target)
                self.fed = target
                self.feeder.advance(0)  # and the events logged at target, as play() does
            else:
                self._start()
        if target > self.fed:
            self.feeder.advance(target - self.fed)
            self.fed = target
