"""State transitions inside the kernel's stepping loop (``poll_states``,
``kernel_poll_states``): the Luxo logs whose states poll at every step replay call by
call to the same machine states, travelling targets, owners, schedules, servo targets
and physics bits with the loop entering states (and the blend's arrivals), without it
(Python's ticks on the kernel) and on the pure-Python path, fed all at once and a few
steps a call (runs cut at a call's end, and at the history's boundaries, going on from
there); the loop does enter states and chains of them; and what it must leave to
Python (a mode change, a pose, a state's device maps) it leaves (a state's sensor
maps, rate and `for`: test_poll_feed).
"""

from __future__ import annotations

from unittest.mock import patch

import pytest
from kernel_paths import agree_without_the_loop, needs_cc, trace

from puppet.data.actions import ActionSpec
from puppet.interface import poll_feed, poll_plan, poll_states
from puppet.timeline.log import read_log

# the logs, and whether the loop enters states in them (else it takes arrivals alone);
# the kip's at 60 a second (arrivals and entries between control steps), the
# headspring's with sensor maps and rates of their own (poll_feed)
ENTERING = {"luxo-shuffle": True, "luxo-double-backflip": True, "luxo-kip": True,
            "luxo-back-headspring": True}


def _entered(name: str, chunk: int | None):
    """The log traced with the loop; and the states the loop entered, the arrivals
    it handed back, the chains (two or more states entered at one step)."""
    log = read_log(f"assets/logs/{name}.jsonl")
    handed, counts = poll_states.States.handed_back, [0, 0, 0]

    def counted(self, rt, machine):
        st = self.st
        kinds = [st.l_kind[e] for e in range(st.n_log)]
        steps = [st.l_step[e] for e in range(st.n_log) if st.l_kind[e] == 1]
        counts[0] += kinds.count(1)
        counts[1] += kinds.count(0)
        counts[2] += len(steps) - len(set(steps))
        return handed(self, rt, machine)

    with patch.object(poll_states.States, "handed_back", counted):
        with_loop, runs, _, _ = trace(log, True, chunk)
    return log, with_loop, counts


@needs_cc
@pytest.mark.parametrize("chunk", [None, 37])
@pytest.mark.parametrize("name", ENTERING)
def test_the_loop_enters_states_as_the_ticks_do(name, chunk, path_of):
    assert path_of("c") is not None
    log, with_loop, (entered, arrived, chains) = _entered(name, chunk)
    assert (entered > 0) == ENTERING[name] and arrived > 0, (entered, arrived)
    if name == "luxo-shuffle":  # ready -> armed -> fold: a chain at one step
        assert entered > 50 and chains > 0, (entered, chains)
    agree_without_the_loop(log, with_loop, chunk, path_of)


@needs_cc
def test_the_shuffle_leaves_python_few_ticks(path_of):
    """The shuffle's steps (fold, extend, rest, ready, armed) are the loop's: of its
    132 Python ticks a replay (before), only the mode changes and the stand-up's are
    left."""
    assert path_of("c") is not None
    from puppet.interface.runtime import InterfaceRuntime
    from puppet.timeline.replay import LogFeeder, new_session, setup_for_log

    log = read_log("assets/logs/luxo-shuffle.jsonl")
    session = new_session(log, setup_for_log(log)[0])
    tick, ticks = InterfaceRuntime.tick, [0]

    def counted(self, step):
        ticks[0] += 1
        return tick(self, step)

    with patch.object(InterfaceRuntime, "tick", counted):
        LogFeeder(session, log).advance(log.last_step)
    assert session.sim.state_hash() == log.end_hash
    assert 0 < ticks[0] < 15, ticks


def test_which_entries_the_loop_can_run():
    only = poll_states.blend_only
    assert only(ActionSpec(set={"knee": 40.0}, over=0.1), "helper")
    assert only(ActionSpec(mode="helper"), "helper")  # (the mode it is in: nothing)
    assert only(ActionSpec(), "mouse")
    assert not only(ActionSpec(mode="mouse"), "helper")  # a mode change: Python's
    assert not only(ActionSpec(set={"knee": 40.0}), "helper")  # instant: Python's
    assert not only(ActionSpec(set={"knee": {"world": 10.0}}, over=0.1), "helper")
    assert not only(ActionSpec(pose="stand", over=0.1), "helper")
    assert not only(ActionSpec(set={"knee": 40.0}, over=0.1, sequence="s"), "helper")
    assert not only(ActionSpec(set={"knee": 40.0}, over=0.1, adjust={"ankle": 2}), "helper")


@needs_cc
def test_no_states_table_with_other_work(path_of):
    """A state whose maps are not all sensor add maps (the headspring's tucked in the
    mouse's mode) or with a mode change is not one the loop enters; its own sensor maps
    (tucked in the helper's mode) or rate (reaching's 480 from 60) are."""
    assert path_of("c") is not None
    from puppet.timeline.replay import new_session, setup_for_log

    log = read_log("assets/logs/luxo-back-headspring.jsonl")
    rt = new_session(log, setup_for_log(log)[0]).runtime
    plan = rt.poll
    assert isinstance(plan, poll_plan.PollPlan)
    states = plan._states
    machine = rt._machine_list[0]
    assert machine.every == 8 and rt.mode == "mouse"  # (ground: 60 a second)
    def enterable(name, mode, every):
        plan = poll_feed.state_plan(rt, mode, name)
        return states._enterable(rt, machine, name, mode, every, plan)
    assert poll_feed.state_plan(rt, "mouse", "tucked") is False  # (the mouse's maps too)
    assert enterable("tucked", "mouse", 8) is None
    assert enterable("push", "mouse", 8) is None  # (a mode change)
    assert enterable("rising", "mouse", 8) is None  # (the mouse's maps: never armed)
    targets, steps = enterable("rising", "helper", 8)  # (60, a set with over)
    assert [j for j, _ in targets] == ["ankle", "knee"] and steps == 96, (targets, steps)
    assert enterable("reaching", "helper", 8) is not None  # (480 a second: its own)
    assert enterable("reaching", "helper", 1) is not None
    assert enterable("push", "helper", 1) is not None  # (its mode)
    assert enterable("tucked", "helper", 1) is not None  # (its sensor maps: poll_feed)
    assert (rt.roles.binding, "helper", 1, ()) in states._made  # (made with the runtime;
    # () the presses kept: poll_poses)
