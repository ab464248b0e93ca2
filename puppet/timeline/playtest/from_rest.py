"""Does a single-key move depend on when it starts? A log's first press of one key moved
to other steps, each copy replayed and judged by the log's feat expectations (the end
hash aside), and the landings counted (``puppet playtest LOG --from-rest KEY``).

The press and everything after it - its release, later presses, the end - move together
by the same number of steps; what comes before stays. So a key pressed while the
character stands still in the move's start pose is pressed at ``count`` moments spread
evenly over a stretch of that stillness, each nudged by a step or two so that they fall
at different phases of the control ticks: a move whose phases follow the body lands at
about all of them, a timed sequence into ballistic motion only at some (issue 28 asks
for 9 of 10)."""

from __future__ import annotations

import dataclasses
from pathlib import Path

from puppet.data.errors import DataError
from puppet.timeline.log import Log, LogEvent, read_log

LAND_SHARE = 0.9  # of the presses: below it the move depends on when it starts


def press_step(log: Log, key: str) -> int:
    """The step of the first press of ``key`` in ``log``."""
    for e in log.events:
        if e.event.get("type") == "key" and e.event.get("key") == key and e.event.get("down"):
            return e.step
    raise DataError(str(log.path), 1, None, f"no press of '{key}' in the log: "
                    f"--from-rest moves the first press of a key the log presses")


def moved(log: Log, key: str, step: int) -> Log:
    """``log`` with the first press of ``key`` at ``step``: it and everything after it
    (events and the end) moved by the same number of steps."""
    at = press_step(log, key)
    shift = step - at
    if step < 1 or any(at > e.step >= step for e in log.events):
        raise DataError(str(log.path), 1, None,
                        f"step {step} ({step * float(log.header['dt']):.3f} s) is before "
                        f"an event that comes before the press of '{key}': choose "
                        f"--between after the log's earlier input")
    events = [e if e.step < at else LogEvent(e.step + shift, dict(e.event), e.line)
              for e in log.events]
    end = None if log.end is None else {**log.end, "end": log.end["end"] + shift}
    return dataclasses.replace(log, events=events, end=end)


def steps_between(dt: float, start: float, stop: float, count: int) -> list[int]:
    """``count`` steps evenly from ``start`` to ``stop`` s, the k-th nudged by k % 8
    steps (8 steps are one control tick at 1/480 s and 60 Hz)."""
    if count == 1:
        return [round(start / dt)]
    gap = (stop - start) / (count - 1)
    return [round((start + k * gap) / dt) + k % 8 for k in range(count)]


def failures(task: tuple) -> list[str]:
    """The kinds of the feat expectations that fail with the press of ``key`` at
    ``step`` (``task``: path, key, step, and optionally the ``OtherPhysics`` to replay
    on; one process's work)."""
    from puppet.timeline.replay import replay

    path, key, step, *physics = task
    result = replay(moved(read_log(Path(path)), key, step),
                    physics=physics[0] if physics else None)
    return [o.kind for o in result.outcomes if not o.passed and o.kind != "same_end"]
