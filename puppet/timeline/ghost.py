"""A ghost: a recorded log replaying beside the live run, in lock-step with its time.

The ghost is a second, separate Session (its own pymunk space, its own interface
runtime) fed from the log by a ``LogFeeder``. ``sync(live)`` advances it to the live
session's simulated time; nothing of the live session is written to, so the live
simulation and its log are exactly what they would be without a ghost.

When the live time goes back (a rewind), the ghost is rebuilt and fed again from the
start of its log up to the live time (replays run far faster than real time).
"""

from __future__ import annotations

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
            self._start()
        if target > self.fed:
            self.feeder.advance(target - self.fed)
            self.fed = target
