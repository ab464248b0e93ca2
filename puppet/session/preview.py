"""The scrub's preview: poses of the re-simulated history, cached, shown within a frame.

Scrubbing shows an earlier moment every frame. Rebuilding it exactly (restore the
keyframe before it, re-simulate the input up to it) costs up to a whole keyframe
interval of physics (3 s: 20-50 ms for the cat), too much for a 60 Hz frame, and it
would restore the live space each frame. Instead a scratch session re-simulates the
keyframe intervals the scrub reaches, a slice of at most ``budget`` seconds per frame,
recording every body's position and angle every ``POSE_EVERY`` steps; the preview
puts the live bodies in a recorded pose and the step count at its step, touching
nothing else (the HUD, the camera and the timeline read them as usual). The interval
ahead of the scrub is prefetched with the frame time left. On release (or a key), the
scrubber's logged "rewind" action does the one exact rewind, to the step shown.

The scratch session replays exactly what ``Session.rewind_to`` replays (the same
snapshot, the same events, the same machinery), so the poses are the poses played.
"""

from __future__ import annotations

import time
from array import array

POSE_EVERY = 4  # steps between cached poses (1/120 s at the default step)
BUDGET = 0.004  # wall s of re-simulation per scrub frame (a frame is 16.7 ms)
CHUNK = 32  # steps re-simulated between clock reads


class _Interval:
    """One keyframe interval of the history being (or having been) re-simulated."""

    def __init__(self, snap, end: int):
        self.snap = snap
        self.end = end  # the last step to pose (the next keyframe's step, or the head)
        self.poses: dict[int, tuple] = {}
        self.events: list | None = None
        self.next = 0  # index of the next event to apply
        self.done = False
        self.reached = -1  # the last step posed


class PoseCache:
    """Poses of a session's history by step, filled on demand in budgeted slices."""

    def __init__(self, session, budget: float = BUDGET):
        self.session = session
        self.budget = budget
        self.scratch = None
        self.intervals: dict[int, _Interval] = {}  # by keyframe identity
        self.running: _Interval | None = None  # the one the scratch session is in
        self._valid = None
        self._plan = None  # the live bodies (and their shapes) the poses are put on
        self._scratch()  # made now, not in a scrub frame (it builds a whole session)

    # -- which interval ----------------------------------------------------------------
    def _validate(self) -> None:
        """Forget the cache when the history changed (new input, a new branch, a reload)."""
        h = self.session.history
        key = (h.head, h.next_seq, len(h.events), len(self.session.versions),
               h.auto[0].step if h.auto else None, len(h.manual))
        if key != self._valid:
            self._valid = key
            self.intervals.clear()
            self.running = None

    def _interval(self, step: int) -> _Interval:
        history = self.session.history
        snap = history.keyframe_before(step)
        found = self.intervals.get(id(snap))
        if found is None or found.snap is not snap:
            later = [s.step for seq in (history.auto, history.manual) for s in seq
                     if s.step > snap.step]
            end = min(later) if later else history.head
            found = self.intervals[id(snap)] = _Interval(snap, max(end, snap.step))
        return found

    # -- re-simulating -------------------------------------------------------------------
    def _scratch(self):
        live = self.session
        if self.scratch is None:
            from puppet.session.session import Session

            self.scratch = Session(live.setup, dt=live.sim.dt,  # the same steps
                                   checkpoint_interval=live.checkpoint_interval)
        scratch = self.scratch
        scratch.versions = list(live.versions)  # hot reloads: the snapshots name them
        scratch._version_of = dict(live._version_of)
        return scratch

    def _begin(self, iv: _Interval) -> None:
        scratch = self._scratch()
        scratch._restore(iv.snap)
        scratch.sim.steps = iv.snap.step
        scratch._rebuilding = True
        iv.events = self.session.history.events_after(iv.snap, iv.end + 1)
        iv.next = 0
        iv.poses.clear()
        iv.reached = -1
        self.running = iv

    def _pose(self, iv: _Interval) -> None:
        s = self.scratch
        c = s.character
        steps = s.sim.steps
        flat = array("d")  # x, y, angle per body: one object, not tracked by the GC
        for b in c.bodies.values():
            p = b.position
            flat.extend((p.x, p.y, b.angle))
        iv.poses[steps] = (flat, s.runtime.state, s.runtime.mode)
        iv.reached = steps

    def _work(self, iv: _Interval, deadline: float) -> None:
        """Re-simulate ``iv`` until it is done or the deadline passes. The pose at a step
        is the state before the events logged at that step act (as a rewind to it)."""
        if iv.done:
            return
        if self.running is not iv:
            self._begin(iv)
        s, events = self.scratch, iv.events
        while time.perf_counter() < deadline:
            now = s.sim.steps
            if ((now % POSE_EVERY == 0 or now == iv.snap.step or now == iv.end)
                    and iv.reached != now):
                self._pose(iv)
            if now >= iv.end:
                iv.done = True
                self.running = None
                return
            while iv.next < len(events) and events[iv.next][0] <= now:
                s.handle(events[iv.next][1])
                iv.next += 1
            stop = min(iv.end, now + CHUNK)
            if iv.next < len(events):
                stop = min(stop, events[iv.next][0])
            stop = min(stop, now - now % POSE_EVERY + POSE_EVERY)
            s.advance(stop - now)

    # -- showing -------------------------------------------------------------------------
    def show(self, step: int, forward: bool) -> int | None:
        """Put the live character in the cached pose nearest at or before ``step`` in its
        interval, working on the cache for at most ``budget`` first (``forward``: the
        scrub's direction, for what to prefetch). Returns the step shown, or None when
        nothing near enough is ready yet (the frame keeps what it showed)."""
        self._validate()
        deadline = time.perf_counter() + self.budget
        iv = self._interval(step)
        if iv.reached < step and not iv.done:
            self._work(iv, deadline)
        shown = None
        if iv.reached >= min(step, iv.end) or iv.done:
            best = max((k for k in iv.poses if k <= step), default=None)
            if best is not None:
                self._apply(best, iv.poses[best])
                shown = best
        # prefetch with the time left: the interval the scrub moves into next
        history = self.session.history
        if forward:
            ahead = iv.end + 1 if iv.end < history.head else None
        else:
            ahead = iv.snap.step - 1 if iv.snap.step > history.oldest() else None
        # (only with half the budget left: beginning an interval restores a snapshot)
        if ahead is not None and deadline - time.perf_counter() > self.budget / 2:
            self._work(self._interval(ahead), deadline)
        return shown

    def _apply(self, step: int, pose: tuple) -> None:
        """The live bodies in ``pose``; the step count at ``step``. Nothing else: the
        exact rewind on release rebuilds the state."""
        live = self.session
        c = live.character
        bodies = list(c.bodies.values())
        if self._plan is None or self._plan[0] is not bodies[0]:
            self._plan = (bodies[0], [s for shapes in c.shapes.values() for s in shapes])
        flat = pose[0]
        for i, body in enumerate(bodies):
            body.angle = flat[3 * i + 2]  # first: setting the angle keeps the centre of
            body.position = (flat[3 * i], flat[3 * i + 1])  # gravity, so the origin goes
            # where it was after it
        for shape in self._plan[1]:
            shape.cache_bb()  # for the camera's framing
        live.sim.steps = step
