"""The maps the kernel's event runs took on beyond one-joint plain maps: the cat's pose
grids (``maps._grid_run``: four legs on the mouse's x and y; ``pk_events`` calls
``pk_grid_run`` after a mouse move's plain rows) and clamped linear maps on several
joints (``maps._compile_linear``'s ``plain_run``: a row a joint; the gymnast's bound
and trot, the rope swing). The kernel's runs give the pure-Python path's bits, a grid
on a joint a controller owns is Python's, an unclamped or curved map is Python's, and
most of those logs' mouse moves are the kernel's."""

from __future__ import annotations

import pytest
from kernel_paths import needs_cc
from stepwise import stepwise
from test_event_runs import _counted, _log, _state, _targets

from puppet.interface.ownership import SEQUENCE
from puppet.session.playback import play
from puppet.timeline.replay import LogFeeder, new_session


def _traced(run, log, setup, end: int, every: int = 11):
    session, trace = new_session(log, setup), []

    def on_tick(s):
        trace.append((s.sim.steps, s.sim.state_hash(), _targets(s),
                      s.runtime.get_state(), dict(s.runtime.inputs)))
    run(session, log.pairs(), None, every, on_tick, end_step=end)
    return trace, _state(session)


@needs_cc
@pytest.mark.parametrize("name", ["cat-trot", "biped-rope-swing", "biped-gymnast-climb-bound"])
def test_the_kernels_runs_are_the_pure_python_maps(name, path_of):
    """The kernel's runs (the grids and the several joints' rows in ``pk_events``)
    against the pure-Python path's event-by-event replay (``apply_grid_run``'s and
    ``apply_linear``'s Python arithmetic), sampled every 11 steps, and on to the log's
    recorded end."""
    assert path_of("c") is not None
    log, setup = _log(name)
    patcher, done = _counted()
    with patcher:
        got = _traced(play, log, setup, log.last_step)
    moves = sum(e["type"] == "mouse" for _, e in log.pairs())
    assert done[0] > moves * 3 // 4, (done[0], moves)
    assert path_of("python") is None
    ref = _traced(stepwise, log, setup, log.last_step)
    assert len(got[0]) == len(ref[0]) > 100
    for a, b in zip(got[0], ref[0]):
        assert a == b, (a[0], b[0])
    assert got[1] == ref[1]
    assert got[1][1] == log.end_hash


@needs_cc
def test_a_grid_on_a_joint_a_controller_owns_is_pythons(path_of):
    """A leg's joint in the owners' table: the grid would take it back (Python's
    ``on_event``), so the kernel starts no run of the mouse's moves."""
    assert path_of("c") is not None
    log, setup = _log("cat-trot")
    session = new_session(log, setup)
    feeder = LogFeeder(session, log)
    feeder.advance(600)
    while feeder.events[feeder.i][1]["type"] != "mouse":
        feeder.advance(1)
    rt, runs, plan = session.runtime, session._idle.runs, session._idle.plan
    assert rt.poll is None and not rt._device_machines  # (the idle loop's runs)
    events, i, cap = feeder.events, feeder.i, session.steps + 500
    assert runs.start(plan, rt, events, i, cap, None) is not None
    plan.n_ev = 0
    grid = next(a for a in rt._mouse_maps if hasattr(a, "grid_run"))
    joint = grid.grid_run[-1][2]
    rt.owners.claim([joint], SEQUENCE)
    assert runs.start(plan, rt, events, i, cap, None) is None
    rt.owners.take([joint])
    assert runs.start(plan, rt, events, i, cap, None) is not None
    plan.n_ev = 0


@needs_cc
@pytest.mark.parametrize("step", [5, 1200])
def test_a_grid_after_a_reseat_writes_the_new_springs(step, path_of):
    """A checkpoint restored (a re-seat: the grids' table bound again to the seat's
    springs before the kernel's next run): the same bits as event by event."""
    assert path_of("c") is not None
    log, setup = _log("cat-trot")
    pairs, done = [], False
    for at, event in log.pairs():
        if at > 2400:
            break
        pairs.append((at, event))
        if not done and at >= step and event["type"] == "mouse":
            pairs.append((at, {"type": "action", "name": "checkpoint"}))
            pairs.append((at + 300, {"type": "action", "name": "restore"}))
            done = True
    pairs.sort(key=lambda p: p[0])
    got = []
    for run in (play, stepwise):
        session = new_session(log, setup)
        run(session, pairs, None, end_step=2400)
        got.append(_state(session))
    assert got[0] == got[1]


def test_a_linear_map_on_several_joints_is_plain_rows_when_clamped_and_straight():
    """``plain_run`` (what the kernel's runs read) only on a clamped map with no curve;
    its rows' arithmetic (``gain * (lo + u * span)``, as ``pk_events``) gives the
    applier's targets to the bit, in range and past both ends."""
    import msgspec

    from puppet.data.interfaces import LinearMapSpec
    from puppet.interface.active_maps import every_map
    from puppet.interface.maps import compile_map

    log, setup = _log("biped-rope-swing")
    session = new_session(log, setup)
    runtime, servos = session.runtime, session.character.servos
    specs = [m for m in every_map(runtime.spec) if isinstance(m, LinearMapSpec)
             and len(m.gains()) > 1]
    assert specs
    for spec in specs:
        apply = compile_map(spec, servos, runtime.pose_targets)
        source, rows = apply.plain_run
        assert source is None and [r[7] for r in rows] == list(spec.gains())
        for v in [-3.0, -0.25, 0.0, 0.1, 1 / 3, 0.5, 0.999, 1.0, 1.7, 2, True]:
            written = apply({spec.input: v})
            for _name, x0, inv, lo, span, gain, servo, joint in rows:
                u = (v - x0) * inv
                u = 0.0 if u < 0.0 else 1.0 if u > 1.0 else u
                assert servo.target == gain * (lo + u * span), (joint, v)
            assert tuple(written) == tuple(spec.gains())
        for other in (msgspec.structs.replace(spec, clamp=False),
                      msgspec.structs.replace(spec, curve="smoothstep")):
            assert not hasattr(compile_map(other, servos, runtime.pose_targets), "plain_run")
