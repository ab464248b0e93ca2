"""Feedback's add maps following the states in the kernel's loop (``poll_feed``,
``kernel_poll_feed``) and states with a control rate or a `for` of their own entered
there: the flips whose states run sensor maps (tucked, landed, balance) and switch
between 60 and 480 a second replay call by call to the same runtime states (the
sensors' readings in the inputs, feedback's bases and last writes, the `for`s'
starts), servo targets and bits as Python's ticks and the pure-Python path, whole,
in the bench's chunks (240 steps: a history boundary at each) and 37 steps a call;
a chain the loop starts out of a state with maps and Python's tick ends at the same
step; checkpoints taken and restored in a state whose maps the loop runs.
"""

from __future__ import annotations

from unittest.mock import patch

import pytest
from kernel_paths import agree_without_the_loop, needs_cc, restored_run, trace, traced_edited

from puppet.interface import poll_states
from puppet.interface.controllers.feedback import Feedback
from puppet.timeline.log import read_log

HEADSPRING = "assets/logs/luxo-back-headspring.jsonl"
BACKFLIP = "assets/logs/luxo-backflip.jsonl"


def _logged(name: str, chunk: int | None):
    """The log traced with the loop; the states it entered with maps (a kind 4 in the
    log: the rows they left ran), and with another period than the one they left."""
    log = read_log(f"assets/logs/{name}.jsonl")
    handed, counts = poll_states.States.handed_back, [0, 0]

    def counted(self, rt, machine):
        st = self.st
        kinds = [st.l_kind[e] for e in range(st.n_log)]
        counts[0] += kinds.count(4)
        every = machine.every
        for e in range(st.n_log):
            if st.l_kind[e] == 1:
                counts[1] += st.e_every[st.l_arg[e]] != every
                every = st.e_every[st.l_arg[e]]
        return handed(self, rt, machine)

    with patch.object(poll_states.States, "handed_back", counted):
        with_loop = trace(log, True, chunk)[0]
    return log, with_loop, counts


@needs_cc
@pytest.mark.parametrize("chunk", [None, 240, 37])
@pytest.mark.parametrize("name", ["luxo-headstand", "luxo-back-headspring"])
def test_the_loop_runs_the_states_maps_and_rates_as_the_ticks_do(name, chunk, path_of):
    assert path_of("c") is not None
    log, with_loop, (fed, rates) = _logged(name, chunk)
    assert fed > 0 and rates > 0, (fed, rates)
    agree_without_the_loop(log, with_loop, chunk, path_of)


@needs_cc
def test_the_flips_leave_python_few_ticks(path_of):
    """The headspring's tuck, reach, landing and rising are the loop's: of its 19
    Python ticks a replay (before), the start, the checkpoint, the mouse's mode
    (crouching, the flick, the stand) and the keyframe's are left."""
    assert path_of("c") is not None
    from puppet.interface.runtime import InterfaceRuntime
    from puppet.timeline.replay import LogFeeder, new_session, setup_for_log

    log = read_log(HEADSPRING)
    session = new_session(log, setup_for_log(log)[0])
    tick, states = InterfaceRuntime.tick, []

    def counted(self, step):
        states.append(self._machine_list[0].current)
        return tick(self, step)

    with patch.object(InterfaceRuntime, "tick", counted):
        LogFeeder(session, log).advance(log.last_step)
    assert session.sim.state_hash() == log.end_hash
    assert not {"tucked", "reaching", "on_shade", "landed"} & set(states), states
    assert len(states) < 14, states


# the back flip's rising (60 a second, as landed) goes on at once (a timer of 0 s) to
# `jolt`, whose entry is an instant set of the knee (Python's): the loop takes landed
# -> rising at a control step (feedback's add with landed's maps on the ankle, then the
# entry) and stops at the same step for Python's tick, which enters `jolt` and must not
# add again (Feedback.done_at)
JOLT = """
  jolt:
    description: the knee at once (an instant set)
    enter: {set: {knee: 55}}
    transitions:
      - {to: ground, after: 0.8}
"""


def _jolted(log):
    text = log.header["interface_text"]
    old = "    enter: {set: {ankle: -25, knee: 55}, over: 0.8}\n    transitions:\n"
    assert text.count(old) == 1
    log.header["interface_text"] = text.replace(old, old + "      - {to: jolt, after: 0.0}\n") \
        .rstrip() + "\n" + JOLT
    return log


@needs_cc
def test_a_chain_out_of_a_state_with_maps_that_python_ends(path_of):
    assert path_of("c") is not None
    tick, skipped = Feedback.tick, []

    def counted(self, step):
        if step == self.done_at:
            skipped.append(step)
        return tick(self, step)

    with patch.object(Feedback, "tick", counted):
        with_loop = traced_edited(_jolted(read_log(BACKFLIP)), True)
    assert skipped, "the loop's add before Python's tick ended the chain"
    ticks = traced_edited(_jolted(read_log(BACKFLIP)), False)
    assert path_of("python") is None
    assert ticks == traced_edited(_jolted(read_log(BACKFLIP)), True)
    # (without done_at: Python's tick at the chain's step took landed's additions back
    # at once, a step early: the ankle's target there its base)
    assert with_loop == ticks


def _restored(loop: bool, checkpoint: int, restore: int):
    """The headspring with a checkpoint at ``checkpoint`` restored at ``restore``, the
    stream again from the checkpoint; the hash and the log entries handed back."""
    session, n = restored_run(HEADSPRING, loop, checkpoint, restore)
    return session.sim.state_hash(), session.runtime.get_state(), n


@needs_cc
def test_a_checkpoint_restored_in_a_state_whose_maps_the_loop_runs(path_of):
    """In tucked (its maps the loop's, the tuck travelling), in landed (its `for`
    holding), restored from later states: the same bits and runtime as Python's ticks
    and the pure path."""
    assert path_of("c") is not None
    cases = [(600, 700), (880, 1000), (900, 905)]
    with_loop = [_restored(True, c, r) for c, r in cases]
    ticks = [_restored(False, c, r) for c, r in cases]
    assert all(n > 0 for *_, n in with_loop) and all(n == 0 for *_, n in ticks)
    assert path_of("python") is None
    in_python = [_restored(True, c, r) for c, r in cases]
    assert [h[:2] for h in with_loop] == [h[:2] for h in ticks] == [h[:2] for h in in_python]
