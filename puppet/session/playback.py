"""Feed (step, event) pairs into a session, stepping the physics between them.

Events are applied in the order given (a log's file order): a recorded rewind makes
the steps go back, and the events after it act on the new branch. ``next_move`` is
the rule of when to apply, advance or stop; every replay (headless ``play``, the
window's and the export's ``LogFeeder``) follows it, so they all end alike.

The physics runs in long uninterrupted stretches from one event to the next; a
per-step callback is only paid for when one is asked for.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable
from typing import TYPE_CHECKING

from puppet.interface.events import Event
from puppet.session.stepping import feed

if TYPE_CHECKING:  # the session itself plays its history back through here
    from puppet.session.session import Session


def next_move(steps: int, next_event: int | None, until_step: int | None,
              end_step: int | None) -> int | None:
    """The one stepping rule of a replay, shared by ``play`` (headless) and
    ``LogFeeder`` (the window, the video export, the ghost) so that they stop at the
    same step in the same state. At ``steps``, with the next pending event logged at
    ``next_event`` (None: no more): 0 means apply that event now; n > 0 means advance
    n steps first (to the event, ``until_step`` or ``end_step``); None means stop.
    ``until_step`` and ``end_step`` mean what they mean for ``play``."""
    if until_step is not None and steps >= until_step:
        return 0 if next_event == steps else None  # the events logged at it act first
    if next_event is not None:
        if next_event <= steps:
            return 0
        target = next_event if until_step is None else min(next_event, until_step)
    else:  # the events ran out: on to until_step, else to end_step
        target = end_step if until_step is None else until_step
    return None if target is None or target <= steps else target - steps


def play(session: Session, events: Iterable[tuple[int, Event]], until_step: int | None,
         every: int = 0, on_tick: Callable[[Session], None] | None = None,
         end_step: int | None = None,
         on_event: Callable[[int, Event], None] | None = None) -> None:
    """Apply events in the order given (file order, not sorted: after a rewind the
    steps go back), advancing the physics to each event's step first.

    ``until_step``: stop the first time the session is at this step with no more
    events for it (the events logged at it act first; if one of them rewinds, the
    replay goes on from there); if the events run out first, run on to it.
    ``None``: apply every event, then run on to ``end_step`` (if given).
    ``on_tick`` (if given) is called every ``every`` steps, e.g. to render frames.
    ``on_event`` (if given) is called with the index and event before each is applied.
    """
    events = events if isinstance(events, (list, tuple)) else list(events)
    every = every if every and on_tick is not None else 0
    i, ticked = feed(session, events, 0, until_step, end_step, every=every, on_event=on_event)
    while ticked:  # (a stretch of steps ended on a multiple of ``every``)
        on_tick(session)
        i, ticked = feed(session, events, i, until_step, end_step, every=every,
                         on_event=on_event)


def ticks(*pairs: tuple[int, Callable | None]) -> tuple[int, Callable | None]:
    """One (every, on_tick) for ``play`` out of several (each ``every`` 0 or its
    callback None: left out): ticks at their steps' greatest common divisor, each
    callback at its own multiples (a replay's trajectory samples and its frames; a
    session's steps do not depend on how they are split between calls)."""
    pairs = tuple((n, f) for n, f in pairs if n and f is not None)
    if len(pairs) < 2:
        return pairs[0] if pairs else (0, None)
    every = math.gcd(*(n for n, _ in pairs))

    def on_tick(session: Session) -> None:
        for n, f in pairs:
            if session.steps % n == 0:
                f(session)
    return every, on_tick
