"""The timeline's costs: a checkpoint (snapshot, restore, re-seat), the Session's history
over a long play and a rewind 60 s back, and the scrub's frames."""

from __future__ import annotations

import gc
import math
import tracemalloc

from puppet.commands.bench.config import FRAME_HZ, clock, median_ms
from puppet.commands.bench.speed import control_run
from puppet.commands.bench.subjects import Subject, gesture


def play_frames(subject: Subject, obj, inputs) -> None:
    run = control_run(subject, inputs, obj=obj)
    next(run)
    run.send(len(inputs))


def measure_checkpoint(subject: Subject, repeats: int) -> dict:
    """Snapshot/restore/checkpoint of a state in mid-motion (1 s into the gesture)."""
    obj = subject.session()
    sim = subject.sim_of(obj)
    play_frames(subject, obj, gesture(subject.frames(1.0), subject.interface_spec))
    data = sim.snapshot()
    out = {
        "bytes": len(data),
        "snapshot_ms": median_ms(sim.snapshot, repeats),
        "restore_ms": median_ms(lambda: sim.restore(data), repeats),
        "checkpoint_ms": median_ms(sim.checkpoint, repeats),
        "repeats": repeats,
    }
    return out


def measure_session_rewind(subject: Subject, seconds: float, repeats: int) -> dict:
    """Play with the Session's history, weigh it, and ``Session.rewind_to`` 60 s back,
    to the worst step: just before a keyframe, so that the rewind restores the keyframe
    before it and re-simulates a whole interval of input (the play runs that much
    longer than ``seconds``, so the target is ``seconds`` back or more)."""
    interval = subject.session().history.checkpoint_every * subject.dt
    frames = subject.frames(seconds + interval + 0.5)
    inputs = gesture(frames, subject.interface_spec)
    sim_seconds = frames * subject.steps_per_frame * subject.dt
    gc.collect()
    tracemalloc.start()
    try:
        base, _ = tracemalloc.get_traced_memory()
        tracemalloc.reset_peak()
        session = subject.session()
        play_frames(subject, session, inputs)
        current, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    history = session.history
    keyframes = list(history.auto)
    back = session.steps - round(seconds / session.sim.dt)
    target = back - back % history.checkpoint_every - 1
    assert target >= history.oldest(), "the history does not reach back that far"
    age = (session.steps - target) * session.sim.dt
    n = subject.steps_per_frame
    head = session.steps

    def restore() -> None:
        session.rewind_to(target)

    def resume() -> None:
        session.rewind_to(target)
        session.advance(n)  # the first frame after the rewind (this branches the history)

    restore_ms = median_ms(restore, repeats)
    assert session.history.head == head  # rewinding alone keeps the future

    resume_ms = median_ms(resume, repeats)
    return {
        "source": "Session.history", "seconds": sim_seconds,
        "interval_s": history.checkpoint_every * session.sim.dt, "entries": len(keyframes),
        "rewound_s": age, "keyframe_bytes": sum(len(snap.sim) for snap in keyframes),
        "traced_current_bytes": current - base, "traced_peak_bytes": peak - base,
        "restore_ms": restore_ms, "resume_ms": resume_ms, "repeats": repeats,
    }


def measure_rewind(subject: Subject, seconds: float, repeats: int) -> dict:
    out = measure_session_rewind(subject, seconds, repeats)
    frames = subject.frames(seconds)
    inputs = gesture(frames, subject.interface_spec)
    gc.collect()
    session = subject.session()
    t0 = clock()
    play_frames(subject, session, inputs)
    wall = clock() - t0
    out["control_with_history_speed_x"] = frames * subject.steps_per_frame * subject.dt / wall
    return out


def measure_scrub(subject: Subject, played_s: float, frames: int) -> dict:
    """Holding the rewind key after ``played_s`` s of play: the wall time of each scrub
    frame (``Scrubber.update`` at 60 Hz: the preview's cache work and the pose shown),
    ``frames`` of them (the scrub speeds up the longer it is held, crossing keyframe
    intervals: 600 frames go 60 s back), then the release (the one exact rewind).
    Frames after the scrub reached the oldest step are not counted."""
    from puppet.session.history import Scrubber

    session = subject.session()
    play_frames(subject, session, gesture(subject.frames(played_s), subject.interface_spec))
    gc.collect()
    scrub = Scrubber(session)
    scrub.start()
    times, start = [], session.steps
    oldest = session.history.oldest()
    for _ in range(frames):
        if session.steps <= oldest:
            break
        t0 = clock()
        scrub.update(1.0 / FRAME_HZ)
        times.append((clock() - t0) * 1e3)
    t0 = clock()
    scrub.release()
    release_ms = (clock() - t0) * 1e3
    times.sort()
    return {"frames": len(times), "p50_ms": times[len(times) // 2],
            "p99_ms": times[min(len(times) - 1, math.ceil(0.99 * len(times)) - 1)],
            "max_ms": times[-1], "release_ms": release_ms,
            "scrubbed_s": (start - session.steps) * session.sim.dt}
