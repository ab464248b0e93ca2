"""A replay's runs of mouse moves and stick events applied inside the kernel's stepping
loop (``session.event_runs``, ``pk_poll``'s ``pk_events``): the same bits as the
event-by-event replay (``tests/stepwise.py``: ``Session.handle`` per event, which
runs ``InterfaceRuntime.on_event``'s maps in Python), the runtime's inputs, its held
frame targets and the history's events alike, on the shipped logs and on events
edited to test the edges (clamped values, integers, a joint a controller owns, a
frame target held otherwise, the steps going back)."""

from __future__ import annotations

from unittest.mock import patch

import pytest
from kernel_paths import needs_cc
from stepwise import stepwise

from puppet.interface import events as ev
from puppet.session import event_runs
from puppet.session.playback import play
from puppet.timeline.log import read_log
from puppet.timeline.replay import LogFeeder, new_session, setup_for_log

# mouse maps with no state polling (the headstand), sticks (the gamepad hop), plain
# maps in states a poll plan runs (the flips, the kip), a state polling the mouse; the
# walkers' frame maps (hips held in the world) with feedback's add maps on the same
# joints, states polling the mouse's x
LOGS = ["luxo-headstand", "luxo-gamepad-hop", "luxo-backflip", "luxo-double-backflip",
        "luxo-kip", "luxo-back-headspring", "luxo-shuffle", "biped-auto-walk",
        "biped-auto-run", "biped-walk"]
WALKERS = ["biped-auto-walk", "biped-auto-run", "biped-walk"]
EVERY = 13


def _log(name: str):
    log = read_log(f"assets/logs/{name}.jsonl")
    return log, setup_for_log(log)[0]


def _state(session) -> tuple:
    h = session.history
    return (session.sim.steps, session.sim.state_hash(), session.runtime.get_state(),
            dict(session.runtime.inputs), list(h.events), h.next_seq, h.head,
            [s.step for s in h.auto], [s.step for s in h.manual], session.blowups)


def _targets(session) -> tuple:
    return tuple(s.target for s in session.sim.character.servos.values())


def _counted():
    """Patches ``EventRuns.applied`` to count the events the kernel applied."""
    applied, done = event_runs.EventRuns.applied, [0]

    def counted(self, session, plan, *args, **kwargs):
        done[0] += plan.ev_done
        return applied(self, session, plan, *args, **kwargs)
    return patch.object(event_runs.EventRuns, "applied", counted), done


def _compare(log, setup, pairs, end, every=EVERY) -> int:
    """play (the kernel's runs) against stepwise, sampled every ``every`` steps: the
    physics, every servo's target, the runtime's state and inputs. The events the
    kernel applied."""
    traces, states = [], []
    patcher, done = _counted()
    for run in (play, stepwise):
        session, trace = new_session(log, setup), []

        def on_tick(s, trace=trace):
            trace.append((s.sim.steps, s.sim.state_hash(), _targets(s),
                          s.runtime.get_state(), dict(s.runtime.inputs)))
        with patcher:
            run(session, pairs, None, every, on_tick, end_step=end)
        traces.append(trace)
        states.append(_state(session))
    assert len(traces[0]) == len(traces[1]) > 5
    for a, b in zip(*traces):
        assert a == b, (a[0], b[0])
    assert states[0] == states[1]
    return done[0]


@needs_cc
@pytest.mark.parametrize("name", LOGS)
def test_the_kernels_event_runs_are_the_event_by_event_replay(name, path_of):
    assert path_of("c") is not None
    log, setup = _log(name)
    applied = _compare(log, setup, log.pairs(), log.last_step)
    moves = sum(e["type"] in ("mouse", "gamepad") for _, e in log.pairs())
    if name != "luxo-shuffle":  # (its polled mouse stops the loop: few in runs)
        assert applied > moves // 4, (applied, moves)


@needs_cc
@pytest.mark.parametrize("name", WALKERS)
def test_the_walkers_long_runs_of_frame_maps_are_the_event_by_event_replay(name, path_of):
    """Sampled every 240 steps (runs of a hundred events and more), the frame maps'
    holds in the kernel: most mouse moves are its, the same bits as Python's."""
    assert path_of("c") is not None
    log, setup = _log(name)
    applied = _compare(log, setup, log.pairs(), log.last_step, 240)
    moves = sum(e["type"] == "mouse" for _, e in log.pairs())
    assert applied > moves * 3 // 4, (applied, moves)


@needs_cc
@pytest.mark.parametrize("name", ["luxo-headstand", "luxo-gamepad-hop", "luxo-kip",
                                  "biped-auto-walk"])
@pytest.mark.parametrize("budget", [1, 7, 240])
def test_a_feeders_frames_end_where_event_by_event_does(name, budget, path_of):
    """The window's replay, a budget of steps a frame: within it, and the reference's end."""
    assert path_of("c") is not None
    log, setup = _log(name)
    ref = new_session(log, setup)
    session = new_session(log, setup)
    feeder = LogFeeder(session, log)
    while not feeder.finished:
        before = session.steps
        feeder.advance(budget)
        assert session.steps - before <= budget
    stepwise(ref, log.pairs(), None, end_step=log.last_step)
    assert _state(session) == _state(ref)
    assert session.sim.state_hash() == log.end_hash


def _edged(name: str, stride: int = 5):
    """A log's mouse or stick events with every ``stride``-th value out of range, an
    integer or exactly a bound (clamps, conversions)."""
    log, setup = _log(name)
    out = []
    for k, (step, event) in enumerate(log.pairs()):
        e = dict(event)
        if k % stride == 0 and e["type"] == "mouse":
            e["x"], e["y"] = [(2, -1), (0, 1), (-0.5, 1.5), (1.0, 0.0)][k // stride % 4]
        elif k % stride == 0 and e["type"] == "gamepad":
            e["value"] = [3, -2, 1, 0][k // stride % 4]
        out.append((step, e))
    return log, setup, out


@needs_cc
@pytest.mark.parametrize("name", ["luxo-headstand", "luxo-gamepad-hop", "luxo-backflip",
                                  "biped-auto-walk", "cat-trot"])
def test_values_clamped_or_whole_apply_as_pythons(name, path_of):
    assert path_of("c") is not None
    log, setup, pairs = _edged(name)
    assert _compare(log, setup, pairs, min(log.last_step, 2400), 7) > 20


@needs_cc
def test_a_joint_a_controller_owns_is_pythons(path_of):
    """A mouse map on a joint the owners' table holds takes it back (Python's
    ``on_event``): the kernel does not start a run, and the replay is the same."""
    assert path_of("c") is not None
    from puppet.interface.ownership import SEQUENCE

    log, setup = _log("luxo-headstand")
    session = new_session(log, setup)
    feeder = LogFeeder(session, log)
    feeder.advance(300)
    rt = session.runtime
    joint = next(iter(rt.gestures.mouse_joints))
    runs = session._idle.runs
    i = feeder.i
    plan = session._idle.plan
    assert runs.start(plan, rt, feeder.events, i, session.steps + 500, None) is not None
    plan.n_ev = 0
    rt.owners.claim([joint], SEQUENCE)
    assert runs.start(plan, rt, feeder.events, i, session.steps + 500, None) is None
    rt.owners.take([joint])
    assert runs.start(plan, rt, feeder.events, i, session.steps + 500, None) is not None
    plan.n_ev = 0


def _walking(steps: int = 4000):
    """biped-auto-walk fed to ``steps`` (walking, its hips held in the world by the
    mouse's frame maps) and on to a step where its poll plan is ready, a mouse move
    coming."""
    log, setup = _log("biped-auto-walk")
    session = new_session(log, setup)
    feeder = LogFeeder(session, log)
    feeder.advance(steps)
    rt = session.runtime
    while rt.poll.ready(session.steps) is None or not rt.frames.held \
            or feeder.events[feeder.i][0] <= session.steps:
        feeder.advance(1)
    return session, feeder


@needs_cc
def test_a_frame_map_on_a_joint_held_otherwise_is_pythons(path_of):
    """A frame map on a joint the plan holds in another frame, under another owner,
    travelling in a blend, or with no plan (the idle loop): its hold changes what the
    plan holds, so the kernel does not start a run (Python's ``hold_at``)."""
    assert path_of("c") is not None
    from puppet.interface.ownership import SEQUENCE
    from puppet.interface.poses import made_frame_target

    session, feeder = _walking()
    rt, runs, poll = session.runtime, session._idle.runs, session.runtime.poll
    events, i, cap = feeder.events, feeder.i, session.steps + 500

    def start(ready=True):  # (the stepping loop's order: the plan made, then the run)
        if ready and poll.ready(session.steps) is None:
            return None
        got = runs.start(poll.plan, rt, events, i, cap, None, poll)
        poll.plan.n_ev = 0
        return got
    assert start() is not None
    assert runs._holds and all(k == 0 for k, *_ in runs._holds)  # (the mouse's)
    _, joint, n, _, _ = runs._holds[0]
    target, owner = rt.frames.held[joint]
    assert poll._frame_rows[n][0] == joint
    for changed in [(made_frame_target("head", target.angle, target.hold_parent), owner),
                    (made_frame_target(target.ref, target.angle, not target.hold_parent),
                     owner), (target, SEQUENCE)]:
        rt.frames.held[joint] = changed
        assert start() is None, changed
        if changed[1] == owner:  # (the plan holds it so: the run's check refuses it)
            assert poll.ready(session.steps) is not None and poll._frame_rows[n] != \
                (joint, target.ref, target.hold_parent)
        rt.frames.held[joint] = (target, owner)
        assert start() is not None
    rt.owners.table[joint] = SEQUENCE
    assert start() is None and start(ready=False) is None
    rt.owners.table[joint] = owner
    assert start() is not None
    poll._travelling[joint] = 0
    assert start(ready=False) is None
    del poll._travelling[joint]
    assert runs.start(session._idle.plan, rt, events, i, cap, None) is None
    assert start() is not None


@needs_cc
def test_mouse_steps_that_go_back_end_a_run_at_the_last_step(path_of):
    """A scrub's mouse (steps that go back inside a run of moves): the run ends at the
    last step it passed; the same end as event by event."""
    assert path_of("c") is not None
    log, setup = _log("luxo-headstand")
    pairs = []
    for k, (step, event) in enumerate(log.pairs()):
        pairs.append((step, event))
        if k % 17 == 0 and step > 100 and event["type"] == "mouse":
            pairs.append((step - 1, ev.mouse(0.3, 0.7)))  # (a step behind)
    ref = new_session(log, setup)
    stepwise(ref, pairs, None, end_step=3000)
    session = new_session(log, setup)
    play(session, pairs, None, end_step=3000)
    assert _state(session) == _state(ref)


def test_event_arrays_break_runs_where_the_kernel_cannot_go_on():
    from cffi import FFI

    pairs = [(1, ev.mouse(0.1, 0.2)), (3, ev.mouse(0.3, 0.4)), (3, ev.key("a")),
             (4, {"type": "gamepad", "name": "left_x", "value": 0.5}),
             (6, {"type": "gamepad", "name": "a", "value": 1.0}), (5, ev.mouse(0.5, 0.5)),
             (7, ev.mouse(0.5, 0.5))]
    arrays = event_runs.EventArrays(FFI(), pairs)
    assert [arrays.kind[k] for k in range(len(pairs))] == [0, 0, -1, 1, 2, 0, 0]
    assert arrays.names == ["left_x", "a"]
    assert arrays.brk[:len(pairs)] == [2, 2, 5, 5, 5, 7, 7]
    assert (arrays.v[0], arrays.v[1], arrays.v[6]) == (0.1, 0.2, 0.5)


def test_event_arrays_leave_values_past_a_doubles_range_to_python():
    """An int too big for a double (a hand-built events list: logs and live events
    refuse it) is Python's, which raises only if it reaches it; the arrays, made ahead
    of the run, must not raise (reviewer: OverflowError past ``until_step``)."""
    from cffi import FFI

    huge = 10 ** 400
    pairs = [(1, {"type": "mouse", "x": huge, "y": 0.2}),
             (2, {"type": "gamepad", "name": "x", "value": huge}),
             (3, ev.mouse(float("nan"), 0.2)), (4, ev.mouse(0.1, 0.2))]
    arrays = event_runs.EventArrays(FFI(), pairs)
    assert [arrays.kind[k] for k in range(len(pairs))] == [-1, -1, -1, 0]
