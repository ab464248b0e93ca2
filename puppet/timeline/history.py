"""Checkpoints and the rewind ring: snapshots of a session kept by step.

Every snapshot is taken with ``Simulation.checkpoint()``, which re-seats the live run
on a restored copy, so restoring a snapshot and feeding the same inputs again is
bit-identical to the run that never restored (pymunk drops the solver's warm-start
state when pickling; re-seating makes the live run drop it at the same moment).

Snapshots are taken at fixed step boundaries only (multiples of the ring and the
checkpoint intervals) and on the "checkpoint" action, so a replay of a log takes the
same snapshots at the same steps as the run that recorded it.

Kinds:
  ring    every ``ring_interval`` s of simulated time, the last ``ring_seconds``;
          what holding the rewind key scrubs through
  auto    every ``checkpoint_interval`` s (bounded); blow-up recovery
  manual  the "checkpoint" action; what the "restore" action goes back to
  start   the start pose (step 0)
"""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass, field

RING_INTERVAL = 0.1  # s of simulated time between rewind snapshots
RING_SECONDS = 180.0  # s of simulated time the rewind ring covers
CHECKPOINT_INTERVAL = 1.0  # s between automatic checkpoints
MAX_AUTO = 600  # automatic checkpoints kept


@dataclass
class Snapshot:
    step: int
    sim: bytes
    runtime: dict = field(repr=False)
    kind: str = "ring"


class History:
    """Snapshots by step. Entries stay sorted by step: after a rewind, the first new
    input (or the next snapshot) drops everything later ("the history branches")."""

    def __init__(self, dt: float, checkpoint_interval: float = CHECKPOINT_INTERVAL,
                 ring_interval: float = RING_INTERVAL, ring_seconds: float = RING_SECONDS):
        self.dt = dt
        self.ring_every = max(1, round(ring_interval / dt))
        self.checkpoint_every = (max(1, round(checkpoint_interval / dt))
                                 if checkpoint_interval and checkpoint_interval > 0 else 0)
        self.ring: deque[Snapshot] = deque(
            maxlen=max(1, round(ring_seconds / (self.ring_every * dt))))
        self.auto: deque[Snapshot] = deque(maxlen=MAX_AUTO)
        self.manual: list[Snapshot] = []
        self.start: Snapshot | None = None

    # -- when ------------------------------------------------------------------------
    def next_boundary(self, step: int) -> int:
        """The first step after ``step`` at which a snapshot is due."""
        b = (step // self.ring_every + 1) * self.ring_every
        if self.checkpoint_every:
            b = min(b, (step // self.checkpoint_every + 1) * self.checkpoint_every)
        return b

    def due(self, step: int) -> tuple[bool, bool]:
        """(ring, auto) snapshots due at ``step``."""
        ring = step % self.ring_every == 0
        auto = bool(self.checkpoint_every) and step % self.checkpoint_every == 0
        return ring, auto

    # -- adding ------------------------------------------------------------------------
    def set_start(self, snap: Snapshot) -> None:
        snap.kind = "start"
        self.start = snap
        self.ring.clear()
        self.auto.clear()
        self.manual.clear()
        self.ring.append(snap)
        self.auto.append(snap)

    def add(self, snap: Snapshot, ring: bool, auto: bool) -> None:
        self.branch(snap.step - 1)
        if ring:
            self.ring.append(snap)
        if auto:
            self.auto.append(snap)

    def add_manual(self, snap: Snapshot) -> None:
        snap.kind = "manual"
        self.branch(snap.step)
        self.manual.append(snap)

    def branch(self, step: int) -> None:
        """Forget every snapshot later than ``step`` (new input after a rewind)."""
        for seq in (self.ring, self.auto, self.manual):
            while seq and seq[-1].step > step:
                seq.pop()

    # -- finding -----------------------------------------------------------------------
    def at(self, step: int) -> Snapshot | None:
        """The snapshot taken at exactly ``step`` (ring first, then checkpoints)."""
        for seq in (self.ring, self.manual, self.auto):
            for snap in reversed(seq):
                if snap.step == step:
                    return snap
                if snap.step < step:
                    break
        if self.start is not None and self.start.step == step:
            return self.start
        return None

    def ring_before(self, step: float) -> Snapshot | None:
        """The latest ring snapshot at or before ``step`` (the oldest if none)."""
        best = None
        for snap in self.ring:
            if snap.step <= step:
                best = snap
            else:
                break
        return best if best is not None else (self.ring[0] if self.ring else None)

    def last_manual(self, step: int) -> Snapshot | None:
        for snap in reversed(self.manual):
            if snap.step <= step:
                return snap
        return None

    def last_checkpoint(self, before: int) -> Snapshot | None:
        """The latest manual or automatic checkpoint strictly before step ``before``."""
        best = None
        for seq in (self.manual, self.auto):
            for snap in reversed(seq):
                if snap.step < before:
                    if best is None or snap.step > best.step:
                        best = snap
                    break
        return best if best is not None else self.start

    # -- for the HUD's timeline bar ----------------------------------------------------
    def span(self) -> tuple[int, int] | None:
        """(oldest, newest) step the ring can scrub to."""
        if not self.ring:
            return None
        return self.ring[0].step, self.ring[-1].step

    def checkpoint_steps(self) -> list[int]:
        return [s.step for s in self.manual]


SCRUB_RATE = 1.0  # s of simulated time per wall s when a scrub starts (it speeds up)


class Scrubber:
    """Holding the rewind key: move through the ring (back, or forward with shift),
    showing each snapshot; on release, commit with a logged "rewind" action so that a
    replay of the log branches at the same place. Pure logic, no pygame."""

    def __init__(self, session):
        self.session = session
        self.active = False
        self.forward = False
        self.moved = False
        self.pos = 0.0
        self.held = 0.0

    def start(self, forward: bool = False) -> None:
        if self.active:
            self.forward = forward
            return
        self.active, self.forward, self.moved = True, forward, False
        self.pos = float(self.session.steps)
        self.held = 0.0

    def update(self, wall_dt: float, forward: bool = False) -> None:
        """One frame of scrubbing; ``forward``: a modifier says go the other way."""
        if not self.active:
            return
        history = self.session.history
        span = history.span()
        if span is None:
            return
        self.held += wall_dt
        rate = SCRUB_RATE * (1.0 + self.held)  # the longer it is held, the faster
        direction = 1.0 if (self.forward or forward) else -1.0
        self.pos += direction * rate * wall_dt / history.dt
        self.pos = min(max(self.pos, float(span[0])), float(span[1]))
        if direction < 0 and not self.moved:  # show the first step back at once
            self.pos = min(self.pos, self.session.steps - 1)
        snap = history.ring_before(self.pos)
        if snap is not None and snap.step != self.session.steps:
            self.session.preview(snap.step)
            self.moved = True

    def release(self) -> None:
        """Play on from the snapshot shown (a logged rewind action)."""
        if not self.active:
            return
        self.active = False
        if self.moved:
            self.session.handle({"type": "action", "name": "rewind",
                                 "to_step": self.session.steps})
