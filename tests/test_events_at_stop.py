"""A kernel run that stops at a timer's step applies the input events at that step
first (``pk_poll``'s ``ev_at_stop``), as the session's loop applies them before
Python's tick there: the walkers' timers (on_X -> down_X) fall on a mouse move one
time in two. Replayed as the window and the bench replay (``LogFeeder``, a few steps
a call or half a second), the runtime, the servo targets and the physics agree call
by call with the pure-Python path, and such stops happen; a stop at the call's end
or at a history boundary leaves its events to the loop (Python's, or the next run's)."""

from __future__ import annotations

from unittest.mock import patch

import pytest
from kernel_paths import needs_cc

from puppet.interface import poll_plan
from puppet.timeline.log import read_log
from puppet.timeline.replay import LogFeeder, new_session, setup_for_log


def _replayed(log, chunk: int, stops: list | None = None) -> list:
    """Per ``LogFeeder.advance(chunk)`` call: the step, the runtime's state, every
    servo's target and the physics' hash; ``stops`` gets, per kernel run, whether it
    stopped at its ``until`` with events applied there, and whether it stopped at a
    history boundary before it with events applied at that step."""
    session = new_session(log, setup_for_log(log)[0])
    run = poll_plan.PollPlan.run

    def watched(self, ptr, dt, now, until, end, health, frame, tick_first=False):
        s = run(self, ptr, dt, now, until, end, health, frame, tick_first)
        p = self.plan
        at_s = p.ev_done > 0 and p.ev_step[p.ev_done - 1] == s
        stops.append((s == until and at_s, s % health == 0 and s < until and at_s))
        return s

    feeder, out = LogFeeder(session, log), []
    with patch.object(poll_plan.PollPlan, "run", watched if stops is not None else run):
        while session.sim.steps < log.last_step:
            feeder.advance(min(chunk, log.last_step - session.sim.steps))
            rt = session.runtime
            out.append((session.sim.steps, rt.get_state(),
                        [s.target for s in session.character.servos.values()],
                        session.sim.state_hash()))
    return out


@needs_cc
@pytest.mark.parametrize("name,chunk,least", [("biped-auto-walk", 240, 50),
                                              ("biped-auto-walk", 37, 10),
                                              ("biped-auto-run", 240, 20),
                                              ("biped-march-easy", 240, 0),
                                              ("biped-march-easy", 8, 0)])
def test_events_at_a_timer_stop_as_the_loop_applies_them(name, chunk, least, path_of):
    """(A frame a call, ``chunk`` 8, as the window replays: the events come at the
    calls' ends, the loop's.)"""
    log = read_log(f"assets/logs/{name}.jsonl")
    assert path_of("c") is not None
    stops: list = []
    in_c = _replayed(log, chunk, stops)
    assert sum(a for a, _ in stops) >= least  # (the walk's timers on mouse moves)
    assert not any(b for _, b in stops)  # (a boundary's check comes before its events)
    assert path_of("python") is None
    in_python = _replayed(log, chunk)
    assert len(in_c) == len(in_python)
    for a, b in zip(in_c, in_python):
        assert a == b, (a[0], b[0])
    assert in_c[-1][-1] == log.end_hash
