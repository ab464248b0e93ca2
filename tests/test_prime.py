"""A runtime compiles its states when it is made (``InterfaceRuntime.prime``): the
machines' state plans, the active maps of each mode and state, the poll plan's
tables. A replay then makes none of them between its steps, and runs as one whose
runtime made each at its first use (the same bits, the same runtime states)."""

from __future__ import annotations

from unittest.mock import patch

import pytest

from puppet.interface.runtime import InterfaceRuntime
from puppet.session.playback import play
from puppet.timeline.log import read_log
from puppet.timeline.replay import new_session, setup_for_log

LOGS = ["luxo-back-headspring", "luxo-shuffle", "luxo-kip", "biped-longjump"]


def _replay(name: str, every: int = 13):
    log = read_log(f"assets/logs/{name}.jsonl")
    session, trace = new_session(log, setup_for_log(log)[0]), []

    def on_tick(s):
        trace.append((s.sim.steps, s.sim.state_hash(), s.runtime.get_state()))
    play(session, log.pairs(), None, every, on_tick, end_step=log.last_step)
    return session, trace, log


@pytest.mark.parametrize("name", LOGS)
def test_a_primed_runtime_replays_as_one_that_compiles_at_first_use(name):
    session, trace, log = _replay(name)
    assert session.sim.state_hash() == log.end_hash
    with patch.object(InterfaceRuntime, "prime", lambda self: None):
        cold, cold_trace, _ = _replay(name)
    assert trace == cold_trace


@pytest.mark.parametrize("name", ["luxo-back-headspring", "luxo-shuffle"])
def test_a_replay_finds_its_states_compiled(name, path_of):
    """After the runtime is made, a replay adds no state table, no state plan and no
    active maps (each state's first entry found them made)."""
    if path_of("c") is None:
        pytest.skip("no kernel")
    log = read_log(f"assets/logs/{name}.jsonl")
    session = new_session(log, setup_for_log(log)[0])
    rt = session.runtime
    machine = rt._machine_list[0]
    before = (dict(rt.poll._tables), dict(machine._plans), dict(rt._refreshed))
    play(session, log.pairs(), None, end_step=log.last_step)
    assert session.runtime is rt
    assert dict(rt.poll._tables) == before[0]
    assert dict(machine._plans) == before[1]
    assert dict(rt._refreshed) == before[2]
