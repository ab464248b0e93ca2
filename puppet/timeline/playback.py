"""Feed (step, event) pairs into a session, stepping the physics between them.

Events are applied in the order given (a log's file order): a recorded rewind makes
the steps go back, and the events after it act on the new branch.

The physics runs in long uninterrupted stretches from one event to the next; a
per-step callback is only paid for when one is asked for.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from typing import TYPE_CHECKING

from puppet.interface.events import Event

if TYPE_CHECKING:  # the session itself plays its history back through here
    from puppet.session import Session


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
    pending = iter(events)
    index = 0
    nxt = next(pending, None)
    ticking = bool(every) and on_tick is not None
    while True:
        while nxt is not None and nxt[0] <= session.steps and (
                until_step is None or session.steps < until_step or nxt[0] == session.steps):
            if on_event is not None:
                on_event(index, nxt[1])
            session.handle(nxt[1])
            index += 1
            nxt = next(pending, None)
        if nxt is None:
            target = until_step if until_step is not None else end_step
            if target is None or session.steps >= target:
                break
            stop = target
        else:
            if until_step is not None and session.steps >= until_step:
                break
            stop = nxt[0] if until_step is None else min(until_step, nxt[0])
        if ticking:
            stop = min(stop, (session.steps // every + 1) * every)
        session.advance(stop - session.steps)
        if ticking and session.steps % every == 0:
            on_tick(session)
