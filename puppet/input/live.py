"""A thread-safe door for live input: other threads post, the frame loop drains.

A live source (a motion-capture stream over the network, a plugin) runs on its own
thread and must never touch the Session: it ``post``s events here. The window (or a
headless loop) calls ``drain`` once a frame and hands what it gets to
``Session.handle``, which records each event at the step it acts, so the take replays
exactly with no network. Events are checked as a log's are: a malformed one, or one
with a non-finite number, is dropped and counted, never raised into the frame loop.
"""

from __future__ import annotations

import collections
import threading

from puppet.interface.event_checks import event_problem
from puppet.interface.events import Event

DEFAULT_CAPACITY = 4096  # events held between two drains before the oldest are dropped


class LiveQueue:
    """Events from other threads, in the order posted, until the next ``drain``."""

    def __init__(self, name: str = "live", capacity: int = DEFAULT_CAPACITY):
        self.name = name
        self._lock = threading.Lock()
        self._events: collections.deque = collections.deque()
        self.capacity = capacity
        self.posted = 0
        self.dropped_bad = 0  # malformed or non-finite
        self.dropped_overflow = 0  # the frame loop did not drain in time
        self.merged = 0  # channels frames merged into one still waiting (post_merged)
        self.last_problem = ""

    def post(self, event: Event) -> bool:
        """Queue an event (any thread). False, and counted, if it is malformed."""
        problem = event_problem(event)
        with self._lock:
            self.posted += 1
            if problem is not None:
                self.dropped_bad += 1
                self.last_problem = problem
                return False
            if len(self._events) >= self.capacity:
                self._events.popleft()
                self.dropped_overflow += 1
            self._events.append(event)
        return True

    def post_merged(self, event: Event) -> bool:
        """``post`` a ``channels`` event, merged into one still waiting at the end of the
        queue (its values updated by these: the newest value of each channel), so a
        stream faster than the frame loop keeps at most one frame here. What a drain
        that merges its events hands over is the same either way."""
        problem = event_problem(event)
        with self._lock:
            self.posted += 1
            if problem is not None:
                self.dropped_bad += 1
                self.last_problem = problem
                return False
            events = self._events
            if events and events[-1].get("type") == "channels" == event.get("type"):
                values = dict(events[-1]["values"])
                values.update(event["values"])
                events[-1] = {**event, "values": values}
                self.merged += 1
                return True
            if len(events) >= self.capacity:
                events.popleft()
                self.dropped_overflow += 1
            events.append(event)
        return True

    def pending(self) -> int:
        """How many events wait for the next drain."""
        with self._lock:
            return len(self._events)

    def drain(self, now: float | None = None) -> list[Event]:
        """Every event posted since the last drain (the frame loop's thread). ``now``
        (the session's time, which a clip source plays by) is not needed here."""
        with self._lock:
            events = list(self._events)
            self._events.clear()
        return events

    def feed(self, session) -> int:
        """Drain into ``session``; the number of events handed over."""
        events = self.drain()
        for event in events:
            session.handle(event)
        return len(events)

    def status(self) -> str:
        """One line for the HUD: what arrived and what was dropped."""
        dropped = self.dropped_bad + self.dropped_overflow
        text = f"{self.name}: {self.posted} events"
        if dropped:
            text += f", {dropped} dropped"
            if self.last_problem:
                text += f" (last: {self.last_problem})"
        return text
