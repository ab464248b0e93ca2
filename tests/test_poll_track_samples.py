"""A performer's samples inside the kernel's runs of events (``event_runs``' SAMPLE,
``pk_sample``): an angles tracker beside a machine (biped-walk's mocap arms) stores a
sample's channels, its last sample and its phase in C and ticks on across samples;
the runs agree with Python's ticks on the kernel and with the pure-Python path, call
by call (the tracker's and runtime's state, schedule, servo targets, bits), whole and
in calls of 7 steps, and with the edges a run must stop or go on at: a sample and a
key at the same step, two samples at one step, samples off the control steps (the
phase moved), samples lacking channels, values the kernel leaves to Python (past
HUGE) or takes (a bool, an int), a gap past ``lost_after`` (lost and found), a
checkpoint and a restore between samples.
"""

from __future__ import annotations

from contextlib import ExitStack
from unittest.mock import patch

import pytest
from kernel_paths import needs_cc
from stepwise import stepwise
from test_event_runs import _state, _targets

from puppet.interface import poll_plan, poll_track, track_poll
from puppet.session.playback import play
from puppet.timeline.log import LogEvent, read_log
from puppet.timeline.replay import new_session, setup_for_log

ARMS = "assets/logs/biped-walk-mocap-arms.jsonl"
HIGHBAR = "assets/logs/biped-mocap-highbar.jsonl"
TRACKER = 5  # (the tracker's place in InterfaceRuntime.controllers; lost: its state's [2])


def _counting():
    """Patches of ``PollPlan.run`` and ``TrackPoll.run`` counting the samples their
    runs applied (one context); the count."""
    applied = [0]
    stack = ExitStack()
    for cls in (poll_plan.PollPlan, track_poll.TrackPoll):
        def counted(self, *args, run=cls.run, **kwargs):
            s = run(self, *args, **kwargs)
            p = self.plan
            applied[0] += sum(p.ev_kind[k] == poll_track.SAMPLE for k in range(p.ev_done))
            return s
        stack.enter_context(patch.object(cls, "run", counted))
    return stack, applied


def _traced(run, log, every: int):
    """``run`` (play: the kernel's runs of events; stepwise: each event alone) sampled
    every ``every`` steps: the physics, the servos' targets, the runtime's state, its
    inputs and channels; and the session's state at the end (the history too)."""
    session, trace = new_session(log, setup_for_log(log)[0]), []

    def on_tick(s):
        trace.append((s.sim.steps, s.sim.state_hash(), _targets(s), s.runtime.get_state(),
                      dict(s.runtime.inputs), dict(s.runtime.channels)))
    run(session, log.pairs(), None, every, on_tick, end_step=log.last_step)
    return trace, (*_state(session), dict(session.runtime.channels))


def _agree(log, path_of, every: int = 61) -> tuple:
    """``play`` with the kernel's runs against ``stepwise`` on the kernel (Python's
    ticks at each sample) and on the pure-Python path: the same, sample by sample.
    Returns the kernel's trace and the samples its runs applied."""
    counting, applied = _counting()
    with counting:
        got = _traced(play, log, every)
    ticks = _traced(stepwise, log, every)
    assert path_of("python") is None
    ref = _traced(stepwise, log, every)
    assert len(got[0]) == len(ticks[0]) == len(ref[0]) > 50
    for a, b, c in zip(got[0], ticks[0], ref[0]):
        assert a == b == c, a[0]
    assert got[1] == ticks[1] == ref[1]
    return got, applied[0]


def _arms(edit) -> object:
    """The walker's log with its events edited: ``edit(events)`` -> events."""
    log = read_log(ARMS)
    log.events = sorted(edit(list(log.events)), key=lambda e: e.step)
    return log


@needs_cc
@pytest.mark.parametrize("every", [7, 61])
@pytest.mark.parametrize("path", [ARMS, HIGHBAR])
def test_samples_run_in_the_kernel_as_the_ticks_take_them(path, every, path_of):
    assert path_of("c") is not None
    log = read_log(path)
    got, applied = _agree(log, path_of, every)
    # (1345 and 498 samples: most inside the kernel's runs, cut at every 61 steps;
    # each 7 steps, the runs stop before most)
    assert applied >= (0 if every < 8 else 1000 if path == ARMS else 300), applied
    assert got[1][1] == log.end_hash


@needs_cc
def test_the_high_bars_samples_off_the_control_steps_and_dropped(path_of):
    """The contacts' rates (``pk_contact_rates``) over samples moved off the control
    steps, every fifth dropped, a gap past ``lost_after`` and samples lacking a
    hand's channels: the three paths agree."""
    assert path_of("c") is not None

    def edit(events):
        out, n = [], 0
        for e in events:
            if e.event.get("type") != "channels":
                out.append(e)
                continue
            n += 1
            if n % 5 == 0 or 200 <= n < 240:
                continue
            values = dict(e.event["values"])
            if n % 9 == 0:
                values.pop("hand_near.x", None)
            step = e.step + (2 if n % 3 == 0 else 0)
            out.append(LogEvent(step, {"type": "channels", "values": values}, 0))
        return out
    log = read_log(HIGHBAR)
    log.events = sorted(edit(list(log.events)), key=lambda e: e.step)
    got, applied = _agree(log, path_of)
    assert applied > 150, applied
    lost = [state["controllers"][TRACKER][2] for _, _, _, state, *_ in got[0]]
    assert any(lost) and not lost[-1]


@needs_cc
def test_samples_at_the_edges_of_a_run(path_of):
    """Keys at a sample's step (before and after it), two samples at one step, samples
    moved off the control steps, samples lacking channels or with values the kernel
    leaves to Python or takes: the three paths agree."""
    assert path_of("c") is not None

    def edit(events):
        out, n = [], 0
        for e in events:
            if e.event.get("type") != "channels":
                out.append(e)
                continue
            n += 1
            values = dict(e.event["values"])
            step = e.step
            if n % 17 == 0:  # a key at the sample's step, before it
                out.append(LogEvent(step, {"type": "key", "key": "x", "down": True}, 0))
                out.append(LogEvent(step + 2, {"type": "key", "key": "x", "down": False},
                                    0))
            if n % 7 == 0:  # off the control steps: the phase moves to it
                step += 3
            if n % 11 == 0:  # the arms' channels missing (kept from the last)
                for name in ("shoulder_near", "elbow_far"):
                    values.pop(name, None)
            if n == 300:
                values["shoulder_near"] = 1e301  # (past HUGE: Python's)
            if n == 301:
                values["elbow_near"] = True  # (a number: the kernel's)
            if n == 302:
                values["shoulder_far"] = 12  # (an int)
            if n == 303:
                values["elbow_far"] = -1e299  # (within HUGE, clamped)
            out.append(LogEvent(step, {"type": "channels", "values": values}, 0))
            if n % 13 == 0:  # a second sample at the same step
                more = {k: v * 0.5 for k, v in values.items()}
                out.append(LogEvent(step, {"type": "channels", "values": more}, 0))
            if n % 19 == 0:  # a key at the sample's step, after it
                out.append(LogEvent(step, {"type": "key", "key": "y", "down": True}, 0))
                out.append(LogEvent(step + 1, {"type": "key", "key": "y", "down": False},
                                    0))
        return out
    _, applied = _agree(_arms(edit), path_of)
    assert applied > 500, applied


@needs_cc
def test_a_lost_stream_and_a_restore_between_samples(path_of):
    """A gap past ``lost_after`` (the run stops where the stream is lost; the
    samples after it are Python's until the tracker is back), a checkpoint and a
    restore between samples: the three paths agree."""
    assert path_of("c") is not None

    def edit(events):
        kept, n = [], 0
        for e in events:
            if e.event.get("type") == "channels":
                n += 1
                if 400 <= n < 460:
                    continue
            kept.append(e)
        steps = [e.step for e in kept if e.event.get("type") == "channels"]
        at = steps[700] + 4  # (between two samples)
        kept += [LogEvent(at, {"type": "action", "name": "checkpoint"}, 0),
                 LogEvent(at + 300, {"type": "action", "name": "restore"}, 0)]
        return kept
    got, applied = _agree(_arms(edit), path_of)
    assert applied > 500, applied
    lost = [state["controllers"][TRACKER][2] for _, _, _, state, *_ in got[0]]
    assert any(lost) and not lost[-1]  # (lost in the gap, and back)


KD = ["biped-mocap-walk", "biped-mocap-push", "biped-mocap-fall", "biped-mocap-lost",
      "biped-mocap-library", "biped-mocap-in-place", "biped-mocap-live"]


@needs_cc
@pytest.mark.parametrize("name", KD)
def test_a_kd_trackers_samples_run_in_the_kernel(name, path_of):
    """A KD tracker with no machine (``TrackPoll``): its samples in the kernel's runs
    (``pk_fresh``: the performed velocities and the lift at each sample's tick),
    through pushes, reactions, a fall's get-up and a lost stream (Python's there)."""
    assert path_of("c") is not None
    log = read_log(f"assets/logs/{name}.jsonl")
    got, applied = _agree(log, path_of)
    assert applied > 200, applied
    assert got[1][1] == log.end_hash


@needs_cc
@pytest.mark.parametrize("name", ["biped-mocap-walk", "biped-mocap-library",
                                  "biped-mocap-fall"])
def test_a_kd_trackers_samples_at_the_edges_of_a_run(name, path_of):
    """Samples off the control steps, doubled, lacking the clearance or a joint's
    channel, a clearance that lifts (the view's too: a mix back to the performer, a
    library's window blending in), values past HUGE (Python's), keys at a sample's
    step (the pulls off and on: ``f``), a restore between samples: the three agree."""
    assert path_of("c") is not None

    def edit(events):
        out, n = [], 0
        for e in events:
            if e.event.get("type") != "channels":
                out.append(e)
                continue
            n += 1
            values = dict(e.event["values"])
            step = e.step + (3 if n % 7 == 0 else 0)
            if n % 5 == 0:
                values.pop("clearance", None)
            if n % 11 == 0:
                values.pop("knee_near", None)
            if 100 <= n < 130:
                values["clearance"] = 0.02 * (n - 100)
            if n == 200:
                values["hip_far"] = -1e301  # (past HUGE: Python's)
            out.append(LogEvent(step, {"type": "channels", "values": values}, 0))
            if n % 13 == 0:
                more = {k: v * 0.9 for k, v in values.items()}
                out.append(LogEvent(step, {"type": "channels", "values": more}, 0))
            if n in (250, 262):  # the pulls off, then on again, at a sample's step
                out.append(LogEvent(step, {"type": "key", "key": "f", "down": True}, 0))
                out.append(LogEvent(step + 1, {"type": "key", "key": "f", "down": False},
                                    0))
            if n % 3 == 0 and "clearance" in values:  # (lifting through a reaction)
                values["clearance"] = 0.01 * (n % 4)
        steps = [e.step for e in out if e.event.get("type") == "channels"]
        out += [LogEvent(steps[300] + 2, {"type": "action", "name": "checkpoint"}, 0),
                LogEvent(steps[360] + 1, {"type": "action", "name": "restore"}, 0)]
        return out
    log = read_log(f"assets/logs/{name}.jsonl")
    log.events = sorted(edit(list(log.events)), key=lambda e: e.step)
    _, applied = _agree(log, path_of)
    assert applied > 200, applied


@needs_cc
def test_walking_in_place_steps_read_in_the_kernel(path_of):
    """The walk in place's step detection at a sample's tick (``pk_walk_step``): samples
    off the control steps, doubled, the root's angle or a knee missing, a pause past
    ``stop_after`` (the walk stops, then starts again), a restore: the three agree, and
    the walk's state (side, last step, period, speed) is handed back alike."""
    assert path_of("c") is not None

    def edit(events):
        out, n = [], 0
        for e in events:
            if e.event.get("type") != "channels":
                out.append(e)
                continue
            n += 1
            values = dict(e.event["values"])
            step = e.step + (2 if n % 7 == 0 else 0)
            if n % 17 == 0:
                values.pop("root.angle", None)
            if n % 19 == 0:
                values.pop("knee_far", None)
            if 300 <= n < 340:  # standing still: the feet level
                values = {k: (0.0 if k.startswith(("hip", "knee", "ankle")) else v)
                          for k, v in values.items()}
            out.append(LogEvent(step, {"type": "channels", "values": values}, 0))
            if n % 13 == 0:
                out.append(LogEvent(step, {"type": "channels", "values": dict(values)}, 0))
        steps = [e.step for e in out if e.event.get("type") == "channels"]
        out += [LogEvent(steps[200] + 1, {"type": "action", "name": "checkpoint"}, 0),
                LogEvent(steps[250] + 3, {"type": "action", "name": "restore"}, 0)]
        return out
    log = read_log("assets/logs/biped-mocap-in-place.jsonl")
    log.events = sorted(edit(list(log.events)), key=lambda e: e.step)
    got, applied = _agree(log, path_of)
    assert applied > 200, applied
    walking = [state["controllers"][TRACKER][10][7][3] for _, _, _, state, *_ in got[0]]
    assert any(walking) and not all(walking), walking
