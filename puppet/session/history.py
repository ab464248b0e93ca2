"""Checkpoints and rewind: keyframes of a session plus the input that followed them.

Any earlier step of the current history can be rebuilt: restore the last keyframe at or
before it and re-simulate the recorded input events up to it. That keeps the per-step
cost low (one snapshot per checkpoint interval instead of a dense ring) while scrubbing
stays smooth at any step, and a replay of a log does the very same restores and
re-simulations, so rewinds replay bit-identically.

Kinds of snapshot, all re-seated (``Simulation.checkpoint``: restoring one and feeding
the same input is bit-identical to never restoring, so a rewind rebuilds exactly the
past that was played):
  start   the start pose (step 0)
  auto    every ``checkpoint_interval`` s of simulated time, the last ``keep_seconds``;
          keyframes for rewinding and for blow-up recovery
  manual  the "checkpoint" action (the "restore" action goes back to it)

A snapshot's physics state is kept as captured (``Simulation.keep``), unpickled, while
it is among the ``KEEP_UNPICKLED`` latest taken: taking it and restoring it then skip
the pickle (a replay of a feat log takes a few dozen); older ones are pickled, at a
fifth of the memory.

Snapshots are taken at fixed step boundaries (multiples of the interval) and on the
checkpoint action only, so a replay takes them at the same steps as the recording.
"""

from __future__ import annotations

import gc
from collections import deque
from dataclasses import dataclass, field

from puppet.data.interfaces import CHECKPOINT_EVERY
from puppet.physics.simulation import Kept

KEEP_SECONDS = 180.0  # s of simulated time that can be rewound
KEEP_UNPICKLED = 48  # latest snapshots kept unpickled (~45 kB more each for a biped)
HEALTH_INTERVAL = 0.5  # s between blow-up checks


@dataclass
class Snapshot:
    step: int
    sim: Kept | bytes  # the physics (``Simulation.keep`` or ``snapshot``)
    runtime: dict = field(repr=False)
    event_seq: int = 0  # how many events had been recorded when it was taken


@dataclass
class Branch:
    """A future that was abandoned (new input after a rewind, or going back to a
    checkpoint): its events and keyframes from ``fork`` (the step it left the kept
    history at) to ``head``. Kept, so that it can be taken up again or exported."""
    fork: int
    head: int
    events: list  # (seq, step, event), in order
    auto: list
    manual: list

    @property
    def steps(self) -> int:
        return self.head - self.fork


MAX_BRANCHES = 50  # abandoned futures kept (the oldest go first)


class History:
    """Keyframes and events by step on the current branch. Rewinding moves the session
    back without forgetting; new input (or stepping on) from an earlier step branches:
    everything later is dropped."""

    def __init__(self, dt: float, checkpoint_interval: float = CHECKPOINT_EVERY,
                 keep_seconds: float = KEEP_SECONDS, keyframes: bool = True):
        self.dt = dt
        self.keyframes = keyframes  # False: rewinds reach back to manual checkpoints only
        interval = checkpoint_interval if checkpoint_interval and checkpoint_interval > 0 \
            else CHECKPOINT_EVERY
        self.checkpoint_every = max(1, round(interval / dt))
        # Health checks and keyframes share boundaries: a keyframe falls on a health check.
        self.health_every = max(1, min(self.checkpoint_every, round(HEALTH_INTERVAL / dt)))
        self.checkpoint_every -= self.checkpoint_every % self.health_every
        self.auto: deque[Snapshot] = deque(
            maxlen=max(2, round(keep_seconds / (self.checkpoint_every * dt)) + 1))
        self.manual: list[Snapshot] = []
        self.events: list[tuple[int, int, dict]] = []  # (seq, step, event)
        self.next_seq = 0
        self.start: Snapshot | None = None
        self.head = 0  # the furthest step of the current branch
        self.branches: list[Branch] = []  # abandoned futures, oldest first
        self._unpickled: deque[Snapshot] = deque()  # the latest taken, oldest first

    # -- when ------------------------------------------------------------------------
    def keyframe_due(self, step: int) -> bool:
        return self.keyframes and step % self.checkpoint_every == 0

    # -- adding ------------------------------------------------------------------------
    def _taken(self, snap: Snapshot) -> None:
        """Pickle the snapshot taken ``KEEP_UNPICKLED`` before this one (if kept)."""
        if type(snap.sim) is Kept:
            kept = self._unpickled
            kept.append(snap)
            if len(kept) > KEEP_UNPICKLED:
                kept.popleft().sim.freeze()

    def set_start(self, snap: Snapshot) -> None:
        self._taken(snap)
        snap.event_seq = self.next_seq
        self.start = snap
        self.auto.clear()
        self.manual.clear()
        self.events.clear()
        self.branches.clear()
        self.auto.append(snap)
        self.head = snap.step

    def add(self, snap: Snapshot) -> None:
        """An automatic keyframe (at the head of the history)."""
        self._taken(snap)
        snap.event_seq = self.next_seq
        self.auto.append(snap)
        oldest = self.auto[0].event_seq
        if self.events and self.events[0][0] < oldest:
            self.events = [e for e in self.events if e[0] >= oldest]

    def add_manual(self, snap: Snapshot) -> None:
        self._taken(snap)
        snap.event_seq = self.next_seq
        self.manual.append(snap)

    def record(self, step: int, event: dict) -> None:
        self.events.append((self.next_seq, step, event))
        self.next_seq += 1

    def branch(self, step: int) -> None:
        """Leave everything after ``step`` (keyframes later than it, events at or after
        it: the abandoned future) out of the history, kept as a ``Branch``."""
        dropped: dict[str, list] = {"auto": [], "manual": [], "events": []}
        for name, seq in (("auto", self.auto), ("manual", self.manual)):
            while seq and seq[-1].step > step:
                dropped[name].insert(0, seq.pop())
        while self.events and self.events[-1][1] >= step:
            dropped["events"].insert(0, self.events.pop())
        if self.head > step:
            self.branches.append(Branch(step, self.head, dropped["events"], dropped["auto"],
                                        dropped["manual"]))
            del self.branches[:-MAX_BRANCHES]
        self.head = step

    def branches_near(self, step: int, n: int = 5) -> list[int]:
        """Indices of the ``n`` branches whose fork is nearest ``step``, nearest first."""
        order = sorted(range(len(self.branches)),
                       key=lambda i: (abs(self.branches[i].fork - step), -i))
        return order[:n]

    # -- finding -----------------------------------------------------------------------
    def oldest(self) -> int:
        return self.auto[0].step if self.auto else 0

    def keyframe_before(self, step: int) -> Snapshot | None:
        """The latest snapshot at or before ``step`` (the later-taken one on a tie)."""
        best = None
        for seq in (self.auto, self.manual):
            for snap in reversed(seq):
                if snap.step <= step:
                    if best is None or (snap.step, snap.event_seq) > (best.step, best.event_seq):
                        best = snap
                    break
        return best

    def events_after(self, snap: Snapshot, stop: int) -> list[tuple[int, dict]]:
        """(step, event) recorded after ``snap`` was taken and before step ``stop``."""
        return [(step, e) for seq, step, e in self.events
                if seq >= snap.event_seq and step < stop]

    def last_manual(self, step: int) -> Snapshot | None:
        for snap in reversed(self.manual):
            if snap.step <= step:
                return snap
        return None

    def last_checkpoint(self, before: int) -> Snapshot | None:
        """The latest manual or automatic checkpoint strictly before step ``before``
        (the start, if the automatic ones that old have been dropped)."""
        return self.keyframe_before(before - 1) or self.start

    # -- for the HUD's timeline bar ----------------------------------------------------
    def span(self) -> tuple[int, int] | None:
        """(oldest, newest) step that can be rewound to."""
        if not self.auto:
            return None
        return self.oldest(), self.head

    def checkpoint_steps(self) -> list[int]:
        return [s.step for s in self.manual]


SCRUB_RATE = 1.0  # s of simulated time per wall s when a scrub starts (it speeds up)


class Scrubber:
    """Holding the rewind key: move through the history (back, or forward with shift),
    showing cached poses of it (``puppet.session.preview``: each frame within its
    budget); on release, commit with a logged "rewind" action, the one exact rewind, so
    that a replay of the log branches at the same place. Pure logic, no pygame."""

    def __init__(self, session):
        from puppet.session.preview import PoseCache

        self.session = session
        self.cache = PoseCache(session)  # the preview: cached poses, budgeted per frame
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
        self.origin = self.session.steps  # where the run is (the preview only shows)
        self.pos = float(self.session.steps)
        self.held = 0.0
        # No full garbage collection in a scrub frame (a pass over the whole heap takes
        # tens of ms): only the young generation, each frame, until the release.
        self._gc_was_on = gc.isenabled()
        gc.disable()

    def update(self, wall_dt: float, forward: bool = False) -> None:
        """One frame of scrubbing; ``forward``: a modifier says go the other way."""
        if not self.active:
            return
        history = self.session.history
        span = history.span()
        if span is None:
            return
        self.held += wall_dt
        gc.collect(0)
        rate = SCRUB_RATE * (1.0 + self.held)  # the longer it is held, the faster
        direction = 1.0 if (self.forward or forward) else -1.0
        self.pos += direction * rate * wall_dt / history.dt
        self.pos = min(max(self.pos, float(span[0])), float(span[1]))
        if direction < 0 and not self.moved:  # show the first step back at once
            self.pos = min(self.pos, self.session.steps - 1)
        step = int(self.pos)
        if (step != self.session.steps  # a cached pose (the exact rewind comes on commit)
                and self.cache.show(step, forward=direction > 0) is not None):
            self.moved = True

    def commit(self) -> None:
        """Log the step shown as a rewind action (if the scrub moved), so that input
        handled from here on is logged after it and a replay applies it there too."""
        if self.active and self.moved:
            self.moved = False
            # Logged at the step the run is at, not the one shown: a replay plays on to
            # there first, as the run did, so the future left is the same branch there.
            shown, self.session.sim.steps = self.session.steps, self.origin
            self.session.handle({"type": "action", "name": "rewind", "to_step": shown})
            self.origin = self.session.steps

    def release(self) -> None:
        """Play on from the snapshot shown (a logged rewind action)."""
        self.commit()
        if self.active and self._gc_was_on:
            gc.enable()
        self.active = False
