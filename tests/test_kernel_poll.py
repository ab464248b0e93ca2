"""The kernel's stepping loop (``pk_poll``, ``interface.poll_plan``) does what Python's
ticks do between them: every Luxo log whose states poll at every step replays to the
same state machine states, schedules and physics bits, call by call, with the loop,
without it (Python's ticks on the kernel), and on the pure-Python path.

The logs cover the loop's branches: contact, angle, joint, spin and height
conditions, all of a transition's conditions at once, a transition's ``after`` and
``for``, a running sequence's ``until`` (tested at every step), timers, blend arrivals
and a sequence's next pose that end a run, device-only states between input events,
runs that stop at a call's end and go on from there (``resume``), checkpoints'
re-seats, feedback's add maps on angles, spins and the fall time, the centre of mass
in conditions, and what it leaves to Python.
None reads a clock.
"""

from __future__ import annotations

from unittest.mock import patch

import pytest
from kernel_paths import needs_cc, trace

from puppet.interface import poll_plan, poll_table
from puppet.interface.controllers import feedback_kernel as fk
from puppet.physics import kernel
from puppet.timeline.log import read_log
from puppet.timeline.replay import LogFeeder, new_session, setup_for_log

HOT = ["luxo-shuffle", "luxo-back-headspring", "luxo-double-backflip", "luxo-kip",
       "luxo-backflip", "luxo-designer-try", "luxo-keys-somersaults", "luxo-keys-hops",
       "luxo-keys-forward-somersaults"]


def _trace(name: str, loop: bool):
    """``kernel_paths.trace`` of a shipped log, which ends on its recorded hash."""
    log = read_log(f"assets/logs/{name}.jsonl")
    out, runs, _, _ = trace(log, loop)
    assert out[-1][-1] == log.end_hash, name
    return out, runs


@needs_cc
@pytest.mark.parametrize("name", HOT)
def test_the_loop_does_what_the_ticks_do(name, path_of):
    assert path_of("c") is not None
    with_loop, runs = _trace(name, loop=True)
    assert runs > 0, runs  # the loop ran
    ticks, none = _trace(name, loop=False)
    assert none == 0
    assert path_of("python") is None
    in_python, none = _trace(name, loop=True)
    assert none == 0  # no kernel, no loop
    for a, b, c in zip(with_loop, ticks, in_python):
        assert a == b == c, (a, b, c)
    assert len(with_loop) == len(ticks) == len(in_python)


def test_no_loop_on_the_python_path(path_of):
    assert path_of("python") is None
    log = read_log("assets/logs/luxo-shuffle.jsonl")
    assert new_session(log, setup_for_log(log)[0]).runtime.poll is None


@needs_cc
def test_what_the_table_cannot_express_stays_in_python(path_of):
    """A lean, the support polygon, a lead: no table; a `for` is in it, and so are
    the fall time, the body's spin and an offset from a link."""
    assert path_of("c") is not None
    assert poll_table.condition_kind("root.angle", "base") == (fk.ANGLE, "base")
    assert poll_table.condition_kind("contact.base", "base") == (fk.CONTACT, "base")
    assert poll_table.condition_kind("joint.knee", "base") == (fk.JOINT, "knee")
    assert poll_table.condition_kind("spin.base", "base") == (fk.SPIN, "base")
    assert poll_table.condition_kind("height.base", "base") == (fk.HEIGHT, "base")
    assert poll_table.condition_kind("com.fall_time", "base") == (fk.FALL_TIME, None)
    assert poll_table.condition_kind("com.vy", "base") == (fk.COM_VY, None)
    assert poll_table.condition_kind("com.spin", "base") == (fk.COM_SPIN, None)
    assert poll_table.condition_kind("com.dx.base", "base") == (fk.COM_DX, "base")
    for sensor in ("lean", "com.dx.support", "com.dx.a.b", "lead.base.shade"):
        assert poll_table.condition_kind(sensor, "base") is None, sensor
    log = read_log("assets/logs/luxo-back-headspring.jsonl")
    session = new_session(log, setup_for_log(log)[0])
    plan = session.runtime.poll
    assert plan is not None and kernel.get() is not None
    machine = plan.machine
    assert machine.current == "ground"  # contact, two joint angles, `for` 0.2 s
    ((after, conditions, hold, index),) = poll_table.state_table(plan, machine)
    assert (after, hold, index) == (0, 96, 0)
    assert [c[:2] for c in conditions] == [(fk.CONTACT, "base"), (fk.JOINT, "knee"),
                                           (fk.JOINT, "ankle")]
    machine.current = "tucked"  # (read as if there: the centre of mass's fall time)
    first = poll_table.state_table(plan, machine)[0]  # its root's angle and the fall time
    assert [c[0] for c in first[1]] == [fk.ANGLE, fk.FALL_TIME]
    machine.current = "landed"  # (no more transitions than a contact's and a timer's)
    assert poll_table.state_table(plan, machine) is not None


def _blown_up(step: int, loop: bool):
    """luxo-double-backflip replayed to ``step`` (a polled state), the base's spin
    made infinite, then 5 more steps: the state machine's state and the hash after the
    session's recovery."""
    import math

    log = read_log("assets/logs/luxo-double-backflip.jsonl")
    session = new_session(log, setup_for_log(log)[0])
    LogFeeder(session, log).advance(step)
    if not loop:
        session.runtime.poll = None
    session.sim.character.bodies["base"].angular_velocity = math.inf
    session.advance(5)
    return session.runtime.machines["main"].current, session.sim.state_hash()


@needs_cc
def test_an_infinite_angle_recovers_alike_on_every_path(path_of):
    """A spin blown up to infinity in a polled state: the kernel's libm ``remainder``
    reads the angle as NaN, and Python's reader does too (math.remainder raised), so
    with the loop, without it and on the Python path the session recovers the same."""
    assert path_of("c") is not None
    with_loop, ticks = _blown_up(795, True), _blown_up(795, False)
    assert path_of("python") is None
    assert with_loop == ticks == _blown_up(795, True)


@needs_cc
def test_the_loop_runs_feedbacks_own_compiled_call(path_of):
    """Feedback's add maps between Python's ticks are ``Feedback.tick``'s compiled call:
    the loop is handed Feedback's own struct (one table, one base and last), and it
    ran them (the tucks' fall time, the landings' angles and spins)."""
    assert path_of("c") is not None
    log = read_log("assets/logs/luxo-back-headspring.jsonl")
    session = new_session(log, setup_for_log(log)[0])
    run, seen = poll_plan.PollPlan.run, []

    def checked(self, *args, **kwargs):
        s = run(self, *args, **kwargs)
        if self.plan.fb_ticks:
            seen.append(self.plan.feedback == self.runtime.feedback._fk.f)
        return s
    with patch.object(poll_plan.PollPlan, "run", checked):
        LogFeeder(session, log).advance(log.last_step)
    assert seen and all(seen), seen
    assert session.sim.state_hash() == log.end_hash
