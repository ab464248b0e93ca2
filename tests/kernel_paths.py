"""Shared by the compiled kernel's tests: ``needs_cc`` skips where no C compiler is on
the PATH (the ``path_of`` fixture, which switches a test between the kernel and the
pure-Python path, is in conftest.py); ``trace`` replays a log call by call, with or
without the kernel's stepping loop (``pk_poll``)."""

from __future__ import annotations

import os
import shutil
from unittest.mock import patch

import pytest

needs_cc = pytest.mark.skipif(shutil.which(os.environ.get("CC", "cc")) is None
                              and shutil.which("gcc") is None, reason="no C compiler")


def trace(log, loop: bool, chunk: int | None = None):
    """Replay ``log`` (a read log), ``chunk`` steps a call (None: all in one); after
    each of the session's advance calls: the step, the runtime's whole state (its
    inputs, with the sensors feedback read; the controllers' states, with feedback's
    bases and last writes and the held frame targets; the machines', with their `for`s'
    starts; the next wake-up), the controllers with work, every servo's target and the
    physics' hash. ``loop``: the kernel's loop may run (it needs the kernel); else every
    tick is Python's. Returns (trace, the loop's runs, those of them that re-solved
    frame targets, those with a frame target's angle travelling in a blend)."""
    from stepwise import stepwise

    from puppet.interface import poll_plan
    from puppet.timeline.replay import new_session, setup_for_log

    session = new_session(log, setup_for_log(log)[0])
    runs = [0, 0, 0]
    advance, run = session.advance, poll_plan.PollPlan.run
    out = []

    def counted(self, *args, **kwargs):
        runs[0] += 1
        p = self.plan
        runs[1] += p.n_frame > 0
        runs[2] += any(p.f_blend[j] >= 0 for j in range(p.n_frame))
        return run(self, *args, **kwargs)

    def traced(steps=1):
        if not loop:
            session.runtime.poll = None
        advance(steps)
        rt = session.runtime
        out.append((session.sim.steps, rt.get_state(), [type(c) for c in rt._active],
                    [s.target for s in session.character.servos.values()],
                    session.sim.state_hash()))
    session.advance = traced
    with patch.object(poll_plan.PollPlan, "run", counted):
        # the reference loop (an advance call between events, cut every ``chunk``
        # steps): LogFeeder's stepping loop hands runs of events to one call
        stepwise(session, log.pairs(), None, every=chunk or 0,
                 on_tick=(lambda _s: None) if chunk else None, end_step=log.last_step)
    return out, runs[0], runs[1], runs[2]


def traced_edited(log, loop: bool):
    """``trace``'s first part for a log whose interface a test edited (played as
    recorded: the header's interface text, not the file's); ``loop`` False: not even
    the loop's ``ready`` (the plan never armed), so every tick is Python's."""
    from puppet.interface import poll_plan
    from puppet.timeline import replay as _replay

    setup = _replay.setup_for_log
    with patch.object(_replay, "setup_for_log", lambda lg, *a, **k: setup(lg, as_recorded=True)):
        if loop:
            return trace(log, True)[0]
        with patch.object(poll_plan.PollPlan, "ready", lambda *a, **k: None):
            return trace(log, True)[0]


def restored_run(path, loop: bool, checkpoint: int, restore: int):
    """The log at ``path`` with a checkpoint at step ``checkpoint`` restored at
    ``restore``, the stream again from the checkpoint, with the kernel's loop or (``loop``
    False) every tick Python's; the session at the end and how many entries (states,
    arrivals) the loop handed back."""
    from puppet.interface import poll_plan, poll_states
    from puppet.session.playback import play
    from puppet.timeline import replay as _replay
    from puppet.timeline.log import read_log

    log = read_log(path)
    ev = log.pairs()
    pre = sorted([(s, e) for s, e in ev if s < restore]
                 + [(checkpoint, {"type": "action", "name": "checkpoint"})], key=lambda p: p[0])
    pre.append((restore, {"type": "action", "name": "restore"}))
    handed, n = poll_states.States.handed_back, [0]

    def counted(self, rt, machine):
        n[0] += self.st.n_log
        return handed(self, rt, machine)
    ready = poll_plan.PollPlan.ready if loop else (lambda *a, **k: None)
    with patch.object(poll_plan.PollPlan, "ready", ready), \
            patch.object(poll_states.States, "handed_back", counted):
        session = _replay.new_session(log, _replay.setup_for_log(log)[0])
        play(session, pre + [(s, e) for s, e in ev if s >= checkpoint], None,
             end_step=log.last_step)
    return session, n[0]


def agree_without_the_loop(log, with_loop, chunk: int | None, path_of) -> None:
    """``with_loop`` (``trace(log, True, chunk)`` on the kernel) agrees, call by call,
    with the trace where every tick is Python's on the kernel and with the one on the
    pure-Python path (``path_of`` switched to it here), and ends on the log's hash."""
    ticks, none, _, _ = trace(log, False, chunk)
    assert none == 0
    assert path_of("python") is None
    from puppet.physics import kernel

    assert kernel.get() is None
    in_python, none, _, _ = trace(log, True, chunk)
    assert none == 0  # no kernel, no loop
    assert len(with_loop) == len(ticks) == len(in_python)
    for a, b, c in zip(with_loop, ticks, in_python):
        assert a == b == c, (a, b, c)
    assert with_loop[-1][-1] == log.end_hash, log.path
