"""Does a single-key move depend on when it starts? A log's press of one key, moved to
other steps, each copy replayed and judged by the log's feat expectations (its sidecar;
the end hash aside), and the landings counted.

    python tools/press_sweep.py assets/logs/biped-backflip.jsonl --key f
    python tools/press_sweep.py LOG --key w --from 0.5 --to 3.0 --count 10 [--jobs 2]

The press (the first down of ``--key``) and everything after it - its release, later
presses, the end - move together by the same number of steps; what comes before stays.
So a key pressed from rest (the figure standing still in the move's start pose) is
pressed at ``--count`` moments evenly spread from ``--from`` to ``--to`` (seconds),
each nudged by a step or two so that they fall at different phases of the 60 Hz control
ticks; a move whose phases change on what the body does lands at about all of them, a
timed sequence into ballistic motion only at some (issue 28: at least 9 of 10 presses
from rest should land). Exit 0 when every copy lands, 1 otherwise.
"""

from __future__ import annotations

import argparse
import dataclasses
import sys
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from puppet.timeline.log import Log, LogEvent, read_log  # noqa: E402
from puppet.timeline.replay import replay  # noqa: E402


def press_step(log: Log, key: str) -> int:
    """The step of the first press of ``key`` in ``log``."""
    for e in log.events:
        if e.event.get("type") == "key" and e.event.get("key") == key and e.event.get("down"):
            return e.step
    raise ValueError(f"{log.path}: no press of '{key}'")


def moved(log: Log, key: str, step: int) -> Log:
    """``log`` with the first press of ``key`` at ``step``: it and everything after it
    (events and the end) moved by the same number of steps."""
    at = press_step(log, key)
    shift = step - at
    if step < 1:
        raise ValueError(f"step {step}: the press must come after step 0")
    events = [e if e.step < at else LogEvent(e.step + shift, dict(e.event), e.line)
              for e in log.events]
    if any(e.step < at and e.step >= step for e in log.events):
        raise ValueError(f"step {step}: earlier than an event before the press")
    end = None if log.end is None else {**log.end, "end": log.end["end"] + shift}
    return dataclasses.replace(log, events=events, end=end)


def steps_between(dt: float, start: float, stop: float, count: int) -> list[int]:
    """``count`` steps evenly from ``start`` to ``stop`` s, the k-th nudged by k % 8
    steps (8 steps are one control tick at 1/480 s and 60 Hz)."""
    if count < 1:
        raise ValueError("count must be at least 1")
    if count == 1:
        return [round(start / dt)]
    gap = (stop - start) / (count - 1)
    return [round((start + k * gap) / dt) + k % 8 for k in range(count)]


def failures(path: Path, key: str, step: int) -> list[str]:
    """The kinds of the feat expectations that fail with the press of ``key`` at
    ``step``."""
    result = replay(moved(read_log(path), key, step))
    return [o.kind for o in result.outcomes if not o.passed and o.kind != "same_end"]


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("log", type=Path)
    ap.add_argument("--key", required=True, help="the key whose first press moves")
    ap.add_argument("--from", dest="start", type=float, default=0.5, help="s (default 0.5)")
    ap.add_argument("--to", dest="stop", type=float, default=3.0, help="s (default 3.0)")
    ap.add_argument("--count", "-n", type=int, default=10)
    ap.add_argument("--jobs", "-j", type=int, default=2)
    args = ap.parse_args(argv)
    log = read_log(args.log)
    dt = float(log.header["dt"])
    steps = steps_between(dt, args.start, args.stop, args.count)
    with ProcessPoolExecutor(max_workers=max(1, args.jobs)) as pool:
        results = list(pool.map(failures, [args.log] * len(steps), [args.key] * len(steps),
                                steps))
    for step, failed in zip(steps, results):
        words = "lands" if not failed else "fails: " + ", ".join(failed)
        print(f"  {args.key} at step {step} ({step * dt:.3f} s): {words}")
    landed = sum(1 for f in results if not f)
    print(f"{args.log.stem}: {landed}/{len(steps)} presses of {args.key} land")
    return 0 if landed == len(steps) else 1


if __name__ == "__main__":
    sys.exit(main())
