"""The reference replay: each event through ``Session.handle`` and the steps between
them through ``Session.advance``, one call each, by ``playback.next_move``'s rule
(what ``play`` and ``LogFeeder`` did before ``stepping.feed`` took a run of events in
one call). Tests compare the stepping loop with it, and trace a session per call."""

from __future__ import annotations

from puppet.session.playback import next_move


def stepwise(session, pairs, until_step, every: int = 0, on_tick=None,
             end_step=None) -> None:
    """``play``'s old loop: each event through ``Session.handle``, the steps between
    through ``Session.advance`` (cut at multiples of ``every``, where ``on_tick`` is
    called before that step's events)."""
    pairs = list(pairs)
    i = 0
    ticking = bool(every) and on_tick is not None
    while (move := next_move(session.steps, pairs[i][0] if i < len(pairs) else None,
                             until_step, end_step)) is not None:
        if move == 0:
            session.handle(pairs[i][1])
            i += 1
            continue
        if ticking:
            move = min(move, every - session.steps % every)
        session.advance(move)
        if ticking and session.steps % every == 0:
            on_tick(session)
