"""A gait's state entries, cheaper in Python and the same: ``poll_fill.fill``'s
pointers kept per binding of the bodies (every row points at the bodies and springs
of now, also right after a checkpoint's re-seat), and ``Actions._run_plain`` (an
entry of a mode, gains, a pose and plain angles) leaving the runtime, the servos and
the frame targets as ``run_action``'s general path does, on every interface."""

from __future__ import annotations

from pathlib import Path
from unittest.mock import patch

import pytest
from kernel_paths import needs_cc

from puppet.data.catalog import load_setup
from puppet.data.interfaces import load_interface
from puppet.interface import actions, poll_fill
from puppet.interface.controllers import feedback_kernel as _fk
from puppet.physics import reseat
from puppet.session import Session
from puppet.timeline.log import read_log
from puppet.timeline.replay import LogFeeder, new_session, setup_for_log

LINKED = {_fk.CONTACT, _fk.ANGLE, _fk.SPIN, _fk.HEIGHT, _fk.COM_DX, _fk.JOINT}


def _address(kern, cdata) -> int:
    return int(kern.ffi.cast("uintptr_t", cdata))


@needs_cc
@pytest.mark.parametrize("name,fresh", [("biped-auto-walk", False), ("biped-auto-walk", True),
                                        ("biped-march-easy", True)])
def test_the_rows_point_at_the_bodies_of_now(name, fresh, path_of):
    """At every fill of a walker's replay (its checkpoints re-seat the bodies every
    3 s: in place, or - ``fresh`` - on a new space with new bodies) each frame row and
    each condition on a link points where a fresh lookup of the runtime's bodies and
    springs does."""
    kern = path_of("c")
    assert kern is not None
    log = read_log(f"assets/logs/{name}.jsonl")
    session = new_session(log, setup_for_log(log)[0])
    fill, checked, seats = poll_fill.fill, [0, 0], set()

    def checking(plan, table, machine, every, seq, states=True):
        until = fill(plan, table, machine, every, seq, states)
        rt, p = plan.runtime, plan.plan
        bodies, servos = rt.character.bodies, rt.character.servos
        joints = rt.frames.joints
        here = lambda cdata: _address(kern, kern.pointer(cdata))  # noqa: E731
        at = lambda ptr: _address(kern, ptr)  # noqa: E731
        for n, (joint, ref, _) in enumerate(plan._frame_rows or ()):
            spec = joints[joint]
            assert at(p.f_parent[n]) == here(bodies[spec.parent]._body)
            assert at(p.f_child[n]) == here(bodies[spec.child]._body)
            assert at(p.f_ref[n]) == (0 if ref is None else here(bodies[ref]._body))
            assert at(p.f_spring[n]) == here(servos[joint].spring._constraint)
            checked[0] += 1
        links = {here(b._body) for b in bodies.values()}
        for k in range(p.n_trans if until is not None else 0):
            for i in range(p.cond0[k], p.cond0[k] + p.n_cond[k]):
                if p.kind[i] in LINKED:  # (a link's sensor: a body of now)
                    assert at(p.body_a[i]) in links
                    checked[1] += 1
        seats.add(rt.sim.seats)
        return until

    with patch.object(poll_fill, "fill", checking), \
            patch("puppet.interface.poll_plan.fill", checking), \
            patch.object(reseat, "live_objects", (lambda *a: None) if fresh
                         else reseat.live_objects):
        LogFeeder(session, log).advance(log.last_step)
    assert session.sim.state_hash() == log.end_hash
    assert checked[0] > 100 and checked[1] > 50 and len(seats) > 3, (checked, seats)


def _entries(spec):
    for machine in spec.state_machines().values():
        for state, s in machine.states.items():
            if s.enter is not None and actions._plain(s.enter):
                yield state, s.enter


def _after(rt, sim):
    servos = rt.character.servos
    return (rt.get_state(), rt.mode, dict(rt.owners.table),
            {j: (t.ref, t.angle, t.hold_parent, o) for j, (t, o) in rt.frames.held.items()},
            [(s.target, s.stiffness, s.damping, s.max_torque) for s in servos.values()],
            sim.state_hash())


@needs_cc
@pytest.mark.parametrize("iface", ["biped-auto", "biped-march", "biped-walk",
                                   "biped-longjump", "luxo-shuffle"])
def test_a_plain_entry_does_what_the_general_path_does(iface, path_of):
    """Each plain state entry of the interface, run on a fresh session from its start
    by ``_run_plain`` and by ``run_action``'s general path: the same runtime state,
    owners, held frame targets, servo targets and gains, and physics."""
    path_of("c")
    got, names = {}, None
    for plain in (True, False):
        seen = []
        with patch.object(actions, "_plain", (lambda a: False) if not plain
                          else actions._plain):
            session = Session(load_setup(iface))
            rt = session.runtime
            names = names or [state for state, _ in _entries(rt.spec)]
            states = {n: s.enter for m in rt.spec.state_machines().values()
                      for n, s in m.states.items()}
            for state in names:
                action = states[state]
                rt.run_action(action, session.sim.steps)
                session.advance(4)
                seen.append((state, _after(rt, session.sim)))
        got[plain] = seen
    assert got[True], iface
    assert got[True] == got[False]


def test_plain_is_what_run_plain_runs():
    """``_plain`` leaves out every part ``_run_plain`` does not run."""
    found = 0
    for path in sorted(Path("interfaces").glob("*.yaml")):
        spec = load_interface(path)[0]
        for _, a in _entries(spec):
            found += 1
            assert all(getattr(a, f) is None for f in actions._RARE)
            assert not a.while_held and not a.adjust
    assert found > 20
