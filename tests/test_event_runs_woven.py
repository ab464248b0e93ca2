"""Event runs with checkpoints, restores and rewinds woven into a shipped log's mouse
and stick events: the kernel's runs give the event-by-event replay's bits (review2)."""

from __future__ import annotations

import pytest
from kernel_paths import needs_cc
from stepwise import stepwise

from puppet.session.playback import play
from puppet.timeline.log import read_log
from puppet.timeline.replay import new_session, setup_for_log

LOGS = ["luxo-headstand", "luxo-gamepad-hop", "luxo-kip", "luxo-shuffle", "biped-auto-walk",
        "cat-trot"]


def _woven(name):
    log = read_log(f"assets/logs/{name}.jsonl")
    setup = setup_for_log(log)[0]
    out, state = [], 0
    marks = {}
    for step, event in log.pairs():
        if step > 3000:
            break
        out.append((step, event))
        if event["type"] not in ("mouse", "gamepad"):
            continue
        if state == 0 and step > 200:
            out.append((step, {"type": "action", "name": "checkpoint"}))
            marks["cp"], state = step, 1
        elif state == 1 and step > marks["cp"] + 400:
            out.append((step, {"type": "action", "name": "restore"}))
            marks["r"], state = step, 2
        elif state == 2 and step > marks["r"] + 300:
            out.append((step, {"type": "action", "name": "rewind", "to_step": step - 150}))
            state = 3
    return log, setup, out


def _state(session):
    h = session.history
    return (session.sim.steps, session.sim.state_hash(), session.runtime.get_state(),
            dict(session.runtime.inputs), list(h.events), h.next_seq, h.head)


@needs_cc
@pytest.mark.parametrize("name", LOGS)
def test_woven_actions(name):
    log, setup, pairs = _woven(name)
    got = []
    for run in (play, stepwise):
        session = new_session(log, setup)
        run(session, pairs, None, end_step=3200)
        got.append(_state(session))
    assert got[0][:4] == got[1][:4]
    assert got[0] == got[1]
