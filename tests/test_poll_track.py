"""A tracker following the performer's angles beside state machines, in the kernel's
loop (``interface.poll_track``): the high bar's (two machines holding the grasps,
intentional contacts swinging the figure: ``pk_contacts``) and the walker's arms from
a performer (a machine with frame targets and sensor maps, mouse moves in the event
runs) replay to the same tracker and runtime state, schedule, servo targets and
physics bits, call by call, with the loop, with Python's ticks on the kernel and on
the pure-Python path; whole, and cut into calls of 7 steps (runs that stop between
samples and go on from there). With samples dropped the kernel ticks between them
(the same targets, the contacts with the last rates) and stops where the stream
would be lost, to the same bits.
"""

from __future__ import annotations

from contextlib import ExitStack
from unittest.mock import patch

import pytest
from kernel_paths import agree_without_the_loop, needs_cc, trace

from puppet.interface import poll_plan, poll_track
from puppet.physics import reseat
from puppet.timeline import replay as _replay
from puppet.timeline.log import LogEvent, read_log

LOGS = ["biped-mocap-highbar", "biped-walk-mocap-arms"]
HIGHBAR = "assets/logs/biped-mocap-highbar.jsonl"
TRACKER = 5  # (the tracker's place in InterfaceRuntime.controllers; lost: its state's [2])


def _traced(log, chunk):
    """``trace`` with the loop, and what the kernel's runs did: the tracker's ticks,
    those with contacts, those with some tracked joint not the tracker's (``t_own``)."""
    ran = [0, 0, 0]
    run = poll_plan.PollPlan.run

    def counted(self, *args, **kwargs):
        s = run(self, *args, **kwargs)
        p = self.plan
        if p.track != self.ffi.NULL:
            ran[0] += p.t_ticks
            ran[1] += p.t_ticks if p.c_n else 0
            ran[2] += p.t_ticks if p.t_own != self.ffi.NULL else 0
        return s
    with patch.object(poll_plan.PollPlan, "run", counted):
        out, _, _, _ = trace(log, True, chunk)
    return out, ran


def _edited(extra_keys: str, events: list) -> object:
    """The high bar's log with keys added to its interface's and events added to its
    stream (replayed on its own, edited, interface text)."""
    log = read_log(HIGHBAR)
    text = log.header["interface_text"]
    assert "\nkeys:\n" in text
    log.header["interface_text"] = text.replace("\nkeys:\n", "\nkeys:\n" + extra_keys, 1)
    log.events = sorted(log.events + [LogEvent(s, e, 0) for s, e in events],
                        key=lambda e: e.step)
    return log


def _three_paths(log, path_of, *patches):
    """``log`` (an edited one: its end hash is not the recorded one) with the loop, with
    Python's ticks on the kernel and on the pure-Python path, under ``patches``: they
    agree call by call. Returns the loop's trace and what its runs did (``_traced``)."""
    setup = _replay.setup_for_log
    as_recorded = patch.object(_replay, "setup_for_log",
                               lambda lg, *a, **k: setup(lg, as_recorded=True))
    with ExitStack() as stack:
        for p in (as_recorded, *patches):
            stack.enter_context(p)
        with_loop, ran = _traced(log, None)
        ticks, _, _, _ = trace(log, False)
        assert path_of("python") is None
        in_python, _, _, _ = trace(log, True)
    assert len(with_loop) == len(ticks) == len(in_python)
    for a, b, c in zip(with_loop, ticks, in_python):
        assert a == b == c, a[0]
    return with_loop, ran


@needs_cc
@pytest.mark.parametrize("chunk", [None, 7])
@pytest.mark.parametrize("name", LOGS)
def test_the_loop_tracks_beside_machines_as_the_ticks_do(name, chunk, path_of, monkeypatch):
    # (an angles tracker without contacts is Python's where it would not pay:
    # ANGLES_ALONE; its kernel path is tested here all the same)
    monkeypatch.setattr(poll_track, "ANGLES_ALONE", True)
    assert path_of("c") is not None
    log = read_log(f"assets/logs/{name}.jsonl")
    with_loop, (ticks, contacts, _) = _traced(log, chunk)
    assert ticks > 300, ticks  # the kernel ran the tracker's control steps
    if name == "biped-mocap-highbar":
        assert contacts > 300, contacts  # ... and swung the figure by the contacts
    agree_without_the_loop(log, with_loop, chunk, path_of)


@needs_cc
def test_dropped_samples_tick_in_the_kernel_alike(path_of):
    """Every third sample of the high bar dropped and a gap past ``lost_after``: the
    kernel's ticks between samples and its stop where the stream is lost agree with
    Python's, on both paths."""
    assert path_of("c") is not None
    log = read_log("assets/logs/biped-mocap-highbar.jsonl")
    kept, n = [], 0
    for e in log.events:
        if e.event.get("type") == "channels":
            n += 1
            if n % 3 == 0 or 300 <= n < 340:
                continue
        kept.append(e)
    log.events = kept
    with_loop, (ticks, contacts, _) = _traced(log, None)
    assert contacts > 100, contacts
    lost = [state["controllers"][TRACKER][2] for _, state, *_ in with_loop]
    assert not lost[0] and any(lost) and not lost[-1]  # (lost in the gap, and back)
    ticks_only, _, _, _ = trace(log, False)
    assert path_of("python") is None
    in_python, _, _, _ = trace(log, True)
    assert len(with_loop) == len(ticks_only) == len(in_python)
    for a, b, c in zip(with_loop, ticks_only, in_python):
        assert a == b == c


@needs_cc
def test_a_key_taking_tracked_joints_mid_swing(path_of):
    """A key's ``set`` takes two of the tracked joints from the tracker mid-log (the
    tracker's ownership recomputed: ``t_own``); the three paths agree."""
    assert path_of("c") is not None
    key = "  - {key: j, set: {waist: 20, hip_near: 30}, description: two tracked joints}\n"
    log = _edited(key, [(1500, {"type": "key", "key": "j", "down": True}),
                        (1503, {"type": "key", "key": "j", "down": False})])
    with_loop, (ticks, contacts, owned) = _three_paths(log, path_of)
    assert contacts > 300, contacts
    assert owned > 100, owned  # the kernel ticked with the two joints not the tracker's
    waist = {str(dict((j, (k, n)) for j, k, n in state["owners"]).get("waist"))
             for _, state, *_ in with_loop}
    assert len(waist) > 1, waist


@needs_cc
def test_a_fresh_space_at_each_checkpoint(path_of):
    """Checkpoints that build a new space (``reseat.live_objects`` finding nothing to
    re-seat in place): new bodies, springs and pins, the tracker's rows bound again
    (``AngleTrack._bind``, the pins and centre of mass); the three paths agree."""
    assert path_of("c") is not None
    steps = (600, 1400, 2200, 3000)
    log = _edited("", [(s, {"type": "action", "name": "checkpoint"}) for s in steps])
    fresh, bound = [0], [0]
    bind = poll_track.AngleTrack._bind

    def none(*args):
        fresh[0] += 1

    def counted(self, *args):
        bound[0] += 1
        return bind(self, *args)
    _, (ticks, contacts, _) = _three_paths(
        log, path_of, patch.object(reseat, "live_objects", none),
        patch.object(poll_track.AngleTrack, "_bind", counted))
    assert contacts > 300, contacts
    assert fresh[0] >= 3 * len(steps), fresh  # (each path's checkpoints: a new space)
    assert bound[0] > len(steps), bound  # (the loop's AngleTrack bound to each)
