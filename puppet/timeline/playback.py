"""Feed (step, event) pairs into a session, stepping the physics between them.

The physics runs in long uninterrupted stretches from one event to the next; a
per-step callback is only paid for when one is asked for.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable

from puppet.interface.events import Event
from puppet.session import Session


def play(session: Session, events: Iterable[tuple[int, Event]], until_step: int,
         every: int = 0, on_tick: Callable[[Session], None] | None = None) -> None:
    """Run until ``until_step``, applying each event when its step comes.

    ``on_tick`` (if given) is called every ``every`` steps, e.g. to render frames.
    """
    pending = iter(sorted(events, key=lambda item: item[0]))
    nxt = next(pending, None)
    while True:
        while nxt is not None and nxt[0] <= session.steps:
            session.handle(nxt[1])
            nxt = next(pending, None)
        if session.steps >= until_step:
            break
        stop = until_step
        if nxt is not None:
            stop = min(stop, nxt[0])
        if every and on_tick is not None:
            stop = min(stop, (session.steps // every + 1) * every)
        session.advance(stop - session.steps)
        if every and on_tick is not None and session.steps % every == 0:
            on_tick(session)
