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

from unittest.mock import patch

import pytest
from kernel_paths import agree_without_the_loop, needs_cc, trace

from puppet.interface import poll_plan, poll_track
from puppet.timeline.log import read_log

LOGS = ["biped-mocap-highbar", "biped-walk-mocap-arms"]


def _traced(log, chunk):
    """``trace`` with the loop, and what the kernel's runs did: the tracker's ticks,
    those with contacts."""
    ran = [0, 0]
    run = poll_plan.PollPlan.run

    def counted(self, *args, **kwargs):
        s = run(self, *args, **kwargs)
        p = self.plan
        if p.track != self.ffi.NULL:
            ran[0] += p.t_ticks
            ran[1] += p.t_ticks if p.c_n else 0
        return s
    with patch.object(poll_plan.PollPlan, "run", counted):
        out, _, _, _ = trace(log, True, chunk)
    return out, ran


@needs_cc
@pytest.mark.parametrize("chunk", [None, 7])
@pytest.mark.parametrize("name", LOGS)
def test_the_loop_tracks_beside_machines_as_the_ticks_do(name, chunk, path_of, monkeypatch):
    # (an angles tracker without contacts is Python's where it would not pay:
    # ANGLES_ALONE; its kernel path is tested here all the same)
    monkeypatch.setattr(poll_track, "ANGLES_ALONE", True)
    assert path_of("c") is not None
    log = read_log(f"assets/logs/{name}.jsonl")
    with_loop, (ticks, contacts) = _traced(log, chunk)
    assert ticks > 300, ticks  # the kernel ran the tracker's control steps
    if name == "biped-mocap-highbar":
        assert contacts > 300, contacts  # ... and swung the figure by the contacts
    agree_without_the_loop(log, with_loop, chunk, path_of)


@needs_cc
def test_angles_alone_stay_pythons(path_of):
    """Without contacts an angles tracker beside a machine ticks in Python (ANGLES_ALONE
    off): the kernel runs none of its ticks."""
    assert path_of("c") is not None
    _, (ticks, _) = _traced(read_log("assets/logs/biped-walk-mocap-arms.jsonl"), None)
    assert ticks == 0


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
    with_loop, (ticks, contacts) = _traced(log, None)
    assert contacts > 100, contacts
    tracker = [state for _, state, *_ in with_loop]
    assert any(s != tracker[0] for s in tracker)
    ticks_only, _, _, _ = trace(log, False)
    assert path_of("python") is None
    in_python, _, _, _ = trace(log, True)
    assert len(with_loop) == len(ticks_only) == len(in_python)
    for a, b, c in zip(with_loop, ticks_only, in_python):
        assert a == b == c
