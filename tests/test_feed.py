"""The session's stepping loop (``session.stepping.feed``) takes a run of events in one
call: a replay through it (``play``, ``LogFeeder``) is the event-by-event one
(``Session.handle`` per event, ``Session.advance`` between: ``tests/stepwise.py``) to
the bit and to the history's bookkeeping, on the kernel (whose ``pk_poll`` runs the
idle steps) and on the pure-Python path. None reads a clock."""

from __future__ import annotations

from functools import cache
from pathlib import Path
from unittest.mock import patch

import pytest
from kernel_paths import needs_cc
from stepwise import stepwise

from puppet.interface import events as ev
from puppet.session.playback import play
from puppet.timeline.log import read_log
from puppet.timeline.replay import LogFeeder, new_session, setup_for_log

# mouse events every few steps (Luxo's polled states, the cat's grids), gamepad sticks,
# key presses, a mocap stream's channels, a designer's keys and reaches
LOGS = ["luxo-shuffle", "cat-trot", "luxo-gamepad-hop", "cat-bound", "luxo-designer-try",
        "biped-mocap-lost", "luxo-back-headspring"]
EVERY = 13  # a trace's sampling period (not a divisor of a frame: ends fall anywhere)


def _log(name: str):
    log = read_log(f"assets/logs/{name}.jsonl")
    return log, setup_for_log(log)[0]


def _state(session) -> tuple:
    """Everything a replay leaves behind: the physics, the runtime's whole state, the
    history's events, keyframes, branches and head, the recoveries."""
    h = session.history
    return (session.sim.steps, session.sim.state_hash(), session.runtime.get_state(),
            list(h.events), h.next_seq, h.head, [s.step for s in h.auto],
            [s.step for s in h.manual], [(b.fork, b.head, b.events) for b in h.branches],
            session.blowups, session.halted, session.message)


def _sample(trace: list):
    def on_tick(session) -> None:
        trace.append((session.sim.steps, session.sim.state_hash(),
                      session.runtime.get_state()))
    return on_tick


def _both(log, setup, pairs, end, every=EVERY):
    """(play's trace and end, the event-by-event trace and end), each sampled every
    ``every`` steps before that step's events, with what a listener heard in another
    run of each (a listener keeps the kernel's loop from running on over events)."""
    out = []
    for run in (play, stepwise):
        session, trace, heard = new_session(log, setup), [], []
        run(session, pairs, None, every, _sample(trace), end_step=end)
        state = _state(session)
        session = new_session(log, setup)
        session.listener = lambda step, event, heard=heard: heard.append((step, event))
        run(session, pairs, None, every, None, end_step=end)
        assert _state(session) == state
        out.append((trace, state, heard))
    return out


@pytest.mark.parametrize("name", LOGS)
@pytest.mark.parametrize("every", [EVERY, 240])
def test_a_replay_in_one_call_is_the_event_by_event_one(name, every):
    log, setup = _log(name)
    (trace, end, heard), (ref_trace, ref_end, ref_heard) = _both(log, setup, log.pairs(),
                                                                  log.last_step, every)
    assert end[1] == log.end_hash
    assert len(trace) == len(ref_trace) >= log.last_step // every > 5
    for a, b in zip(trace, ref_trace):
        assert a == b, (a[0], b[0])
    assert end == ref_end
    assert heard == ref_heard


@cache
def _stepwise_end(name: str) -> tuple:
    """The event-by-event replay's end state (``_state``) of a log: one reference run
    per log for the feeder's three budgets (it depends on the log alone)."""
    log, setup = _log(name)
    ref = new_session(log, setup)
    stepwise(ref, log.pairs(), None, end_step=log.last_step)
    return _state(ref)


@pytest.mark.parametrize("name", ["luxo-shuffle", "cat-trot", "luxo-gamepad-hop"])
@pytest.mark.parametrize("budget", [1, 7, 240])
def test_a_feeder_ends_alike_whatever_its_frames(name, budget):
    """The window's replay, a budget of steps a frame: the same end as event by event,
    and after each frame the same state as the reference at that step."""
    log, setup = _log(name)
    session = new_session(log, setup)
    feeder = LogFeeder(session, log)
    frames = 0
    while not feeder.finished:
        feeder.advance(budget)
        frames += 1
    assert frames >= log.last_step // budget
    assert _state(session) == _stepwise_end(name)
    assert session.sim.state_hash() == log.end_hash


def _edited(name: str):
    """A log's first events with the rarer ones woven in: a checkpoint, a push, keys,
    a reload of the same interface, a rewind (the steps go back; the events after it
    rewrite the future, a branch), a restore, a reset, a drag."""
    log, setup = _log(name)
    pairs = [p for p in log.pairs() if p[0] < 1500]
    link = setup.character.root
    extra = [(200, ev.action("checkpoint")), (260, ev.push(link, (0.0, 0.6))),
             (300, ev.key("space", True)), (303, ev.key("space", False)),
             (420, ev.reload(Path(setup.interface_path).read_text(), str(setup.interface_path))),
             (700, {"type": "action", "name": "rewind", "to_step": 350}),
             (900, ev.action("restore")), (1100, ev.action("reset")),
             (1200, ev.drag_start(link, (0.0, 0.0), (0.1, 0.5))),
             (1210, ev.drag_move((0.2, 0.6))), (1230, ev.drag_end())]
    merged = sorted(pairs + extra, key=lambda p: p[0])  # (stable: the log's first)
    cut = next(k for k, (s, e) in enumerate(merged) if e.get("name") == "rewind") + 1
    again = [(s - 700 + 350, e) for s, e in merged[cut:] if s - 700 + 350 >= 350]
    return log, setup, merged[:cut] + again


@pytest.mark.parametrize("name", ["luxo-shuffle", "cat-trot", "luxo-gamepad-hop"])
def test_rare_events_in_a_run_act_as_event_by_event(name):
    log, setup, pairs = _edited(name)
    (trace, end, heard), (ref_trace, ref_end, ref_heard) = _both(log, setup, pairs, 1600, 7)
    assert end[8], "the rewind left a branch"
    assert [a[:2] for a in trace] == [b[:2] for b in ref_trace]
    assert trace == ref_trace
    assert end == ref_end
    assert heard == ref_heard


@needs_cc
@pytest.mark.parametrize("name", ["luxo-hop", "cat-trot", "luxo-shuffle"])
def test_the_kernel_steps_the_idle_steps_as_python_does(name, path_of):
    """The idle steps (nothing of the interface due) run in ``pk_poll`` with an empty
    table; the same trace as Python's loop over them, and on the pure-Python path."""
    log, setup = _log(name)
    assert path_of("c") is not None
    traces, calls = [], []
    for idle in (True, False):
        session, trace = new_session(log, setup), []
        if idle:
            poll = session._idle.poll
            session._idle.poll = lambda *a, poll=poll: calls.append(a[2]) or poll(*a)
        else:
            session._idle = None
        play(session, log.pairs(), None, EVERY, _sample(trace), end_step=log.last_step)
        traces.append(trace)
    assert len(calls) > 10  # (the shuffle's waiting states poll the mouse in the plan's
    assert path_of("python") is None  # loop now: 21 idle calls a replay, 300 before)
    session, trace = new_session(log, setup), []
    assert session._idle is None
    play(session, log.pairs(), None, EVERY, _sample(trace), end_step=log.last_step)
    assert traces[0] == traces[1] == trace
    assert trace[-1][1] == log.end_hash or log.last_step % EVERY


def test_a_recovery_in_the_idle_steps_is_pythons(path_of):
    """A blow-up between two events, found by the frame check where the kernel's loop
    stops: the session recovers from the same checkpoint at the same step either way."""
    import math

    log, setup = _log("luxo-hop")
    ends = []
    for how in ("c", "python"):
        if path_of(how) is None and how == "c":
            pytest.skip("no kernel")
        session = new_session(log, setup)
        feeder = LogFeeder(session, log)
        feeder.advance(1003)
        session.sim.character.bodies["base"].velocity = (math.inf, 0.0)
        feeder.advance(300)
        ends.append((session.steps, session.blowups, session.message, session.sim.state_hash()))
    assert ends[0] == ends[1] and ends[0][1] == 1, ends


@needs_cc
@pytest.mark.parametrize("name", ["luxo-shuffle", "luxo-kip", "luxo-backflip"])
def test_the_kernels_loop_runs_on_over_inert_mouse_events(name, path_of):
    """A mouse event that only moves the mouse or runs plain maps (or stirs a state
    polling the mouse alone, which the kernel polls: ``session.event_runs``) does not
    stop the kernel's loop: fewer runs than event by event, the same end and the same
    trace (the other tests)."""
    from puppet.interface import poll_plan

    assert path_of("c") is not None
    log, setup = _log(name)
    run, counts = poll_plan.PollPlan.run, []
    for replay in (play, stepwise):
        calls = [0]

        def counted(self, *args, calls=calls, **kwargs):
            calls[0] += 1
            return run(self, *args, **kwargs)
        with patch.object(poll_plan.PollPlan, "run", counted):
            session = new_session(log, setup)
            replay(session, log.pairs(), None, end_step=log.last_step)
        assert session.sim.state_hash() == log.end_hash
        counts.append(calls[0])
    assert counts[0] < 0.8 * counts[1], counts


def _scrubbed(name: str):
    """A log's events as the window writes them when the scrub key is held in a rewound
    history while the mouse moves: mouse events at the steps shown (s+1, s+2, then s:
    steps that go back, which ``read_log`` accepts between the key's down and up)."""
    from puppet.timeline.log import SCRUB_KEYS

    log, setup = _log(name)
    out, n = [], 0
    for step, event in log.pairs():
        if event["type"] == "mouse" and step > 300:
            n += 1
            if n % 3 == 0:
                out.append((step, {"type": "key", "key": SCRUB_KEYS[1], "down": True}))
                out.extend((s, dict(event)) for s in (step + 1, step + 2, step))
                out.append((step, {"type": "key", "key": SCRUB_KEYS[1], "down": False}))
                continue
        out.append((step, event))
    return log, setup, out


@needs_cc
@pytest.mark.parametrize("budget", [None, 5])
def test_mouse_steps_that_go_back_end_a_run_where_it_was(budget):
    """The kernel's loop running on over mouse events stops at the last step it
    passed when the next event's step is behind it (it ran backwards and ticked the same
    step for ever): the same end as event by event, and a feeder's frame within its
    budget."""
    from puppet.interface import poll_plan

    log, setup, pairs = _scrubbed("luxo-shuffle")
    ref = new_session(log, setup)
    stepwise(ref, pairs, None, end_step=log.last_step)
    run, calls = poll_plan.PollPlan.run, [0]

    def counted(self, *args, **kwargs):
        calls[0] += 1
        assert calls[0] < 20_000, "the kernel's loop does not move on"
        return run(self, *args, **kwargs)
    with patch.object(poll_plan.PollPlan, "run", counted):
        session = new_session(log, setup)
        if budget is None:
            play(session, pairs, None, end_step=log.last_step)
        else:
            feeder = LogFeeder(session, log)
            feeder.events = pairs
            while not feeder.finished:
                before = session.steps
                feeder.advance(budget)
                assert session.steps - before <= budget
    assert _state(session) == _state(ref)


def test_a_feeder_keeps_its_place_when_a_frame_raises():
    """An exception in the middle of a frame (here the runtime's, at the 5th mouse event)
    leaves the feeder's index past the events taken, the raising one included: the next
    frames go on from the event after it and none is applied twice (the index was
    written only when ``feed`` returned: it stayed at 0 and the frame after replayed the
    first events again, into the history twice). The kernel's runs of mouse events are
    off here, so every event reaches the runtime's ``on_event``, where it raises."""
    from unittest.mock import patch

    from puppet.session import event_runs

    with patch.object(event_runs.EventRuns, "start", lambda *args, **kwargs: None):
        _feeder_after_a_raise()


def _feeder_after_a_raise():
    log, setup = _log("luxo-hop")
    session = new_session(log, setup)
    feeder = LogFeeder(session, log)
    runtime, seen = session.runtime, []

    def on_event(event, real=runtime.on_event):
        seen.append(event)
        if len(seen) == 5:
            raise RuntimeError("the 5th event")
        return real(event)
    runtime.on_event = on_event
    with pytest.raises(RuntimeError, match="the 5th event"):
        feeder.advance(log.last_step)
    taken = next(k for k, (_, event) in enumerate(feeder.events) if event is seen[-1]) + 1
    assert feeder.i == taken == 5
    del runtime.on_event  # (the class's again)
    while not feeder.finished:
        feeder.advance(240)
    assert [(step, event) for _, step, event in session.history.events] == log.pairs()
    assert session.steps == log.last_step
