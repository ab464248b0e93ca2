"""The reference replay: each event through ``Session.handle`` and the steps between
them through ``Session.advance``, one call each, by ``playback.next_move``'s rule
(what ``play`` and ``LogFeeder`` did before ``stepping.feed`` took a run of events in
one call). Tests compare the stepping loop with it, and trace a session per call."""

from __future__ import annotations

from puppet.session.playback import next_move


def stepwise(session, pairs, end_step, until_step=None, on_advance=None) -> None:
    """Play ``pairs`` into ``session`` event by event; ``on_advance(session)`` after
    each ``advance`` call."""
    i = 0
    while (move := next_move(session.steps, pairs[i][0] if i < len(pairs) else None,
                             until_step, end_step)) is not None:
        if move == 0:
            session.handle(pairs[i][1])
            i += 1
            continue
        session.advance(move)
        if on_advance is not None:
            on_advance(session)
