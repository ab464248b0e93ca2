"""The bench's settings: its clock, how long each measurement runs, the targets.

Every in-process time is read through ``clock()``: wall time (``time.perf_counter``),
or with ``--cpu`` the CPU time of the measuring thread (``time.thread_time``), which
leaves out the time the process waited for a core on a shared machine (the
whole-process figures show both, always).
"""

from __future__ import annotations

import gc
import statistics
import time

FRAME_HZ = 60.0  # the window's frame rate: one batch of input per frame

_CLOCKS = {"wall": time.perf_counter, "cpu": time.thread_time}
_clock = [time.perf_counter]


def clock() -> float:
    return _clock[0]()


def use_clock(name: str) -> None:
    """Time everything from now on by the ``wall`` or the ``cpu`` clock."""
    _clock[0] = _CLOCKS[name]


# Targets (the report's PASS/MISS). Speeds are simulated seconds per wall second.
SPEED_TARGET = {"luxo": 100.0, "biped": 150.0, "biped-small": 150.0}
SPEED_TARGET_DEFAULT = 50.0
OVERHEAD_TARGET_PCT = 25.0
CHECKPOINT_TARGET_MS = 2.0
REWIND_TARGET_MS = 100.0
# the human figure's own budgets (issue 10): tighter than the defaults
CHECKPOINT_TARGET = {"biped": 1.0, "biped-small": 1.0}
REWIND_TARGET = {"biped": 30.0, "biped-small": 30.0}
SCRUB_FRAME_TARGET_MS = 1000.0 / 60.0  # every scrub frame within a 60 Hz frame
PROCESS_TARGET_MS = 150.0  # a short headless replay or a check, end to end
BVH_READ_TARGET_MS = 200.0  # a 2 MB motion-capture clip
# the control layer on the shipped feat logs (issue 29): each log, and their median
FEAT_OVERHEAD_TARGET_PCT = 15.0
FEAT_MEDIAN_TARGET_PCT = 10.0
FRAME_P99_TARGET_MS = 8.0  # a frame with the HUD and F1 open, biped scenes (issue 29)

FULL = {"seconds": 20.0, "repeats": 9, "checkpoint_repeats": 300, "rewind_seconds": 60.0,
        "rewind_repeats": 21, "log_repeats": 3, "scrub_played_s": 90.0, "scrub_frames": 600,
        "process_repeats": 5, "log_seconds": None, "feat_rounds": 3, "feat_seconds": None,
        "hud_frames": 600}
QUICK = {"seconds": 0.25, "repeats": 1, "checkpoint_repeats": 5, "rewind_seconds": 1.0,
         "rewind_repeats": 2, "log_repeats": 1, "scrub_played_s": 4.0, "scrub_frames": 30,
         "process_repeats": 1, "log_seconds": 1.0, "feat_rounds": 1, "feat_seconds": 0.5,
         "hud_frames": 20}


def median_ms(fn, repeats: int) -> float:
    samples = []
    for _ in range(repeats):
        t0 = clock()
        fn()
        samples.append(clock() - t0)
    return statistics.median(samples) * 1e3


def target(name: str, value: float, op: str, limit: float, unit: str) -> dict:
    ok = value >= limit if op == ">=" else value <= limit if op == "<=" else value < limit
    return {"name": name, "value": value, "op": op, "limit": limit, "unit": unit,
            "pass": bool(ok)}


def in_turns(runs: dict, units: int, chunk: int) -> tuple[dict, dict]:
    """Play the runs (name -> a primed generator that takes how many units to play:
    steps or frames) in turns, ``chunk`` units each, the order rotating so that none
    always goes first; the clock's seconds each took and what each yielded last."""
    last = {name: next(run) for name, run in runs.items()}
    spent = dict.fromkeys(runs, 0.0)
    order = list(runs)
    gc.collect()
    done = 0
    while done < units:
        k = min(chunk, units - done)
        for name in order:
            t0 = clock()
            last[name] = runs[name].send(k)
            spent[name] += clock() - t0
        order.append(order.pop(0))
        done += k
    return spent, last
