"""A log replayed on other physics settings: fewer (or more) solver passes, another
collision slop, another simulation step. The end state cannot match the recording's
(any setting changes the bits), so what is judged is the feat: the log's own
expectations. A feat that holds only on the settings it was recorded on is a knife
edge; one that still holds on 36 passes and a 1/240 s step leaves the physics settings
free to be chosen for speed (``puppet replay --headless --check --solver-passes 36
--step 1/240``).

On another step every event (and a rewind's target, and the end) moves to the step
nearest its recorded time, in the recorded order: the same performance, in time.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

from puppet.data.ranges import STEP_RANGE, parse_step  # (re-exported: their home was here)
from puppet.timeline.log import Log, LogEvent


@dataclass(frozen=True)
class OtherPhysics:
    iterations: int | None = None  # solver passes per step (None: the character's)
    slop: float | None = None  # collision slop, m (None: the character's)
    dt: float | None = None  # the simulation step, s (None: the log's)

    def __bool__(self) -> bool:
        return any(v is not None for v in (self.iterations, self.slop, self.dt))

    def label(self) -> str:
        """What is changed, in words: '36 solver passes, a 1/240 s step'."""
        parts = []
        if self.iterations is not None:
            parts.append(f"{self.iterations} solver passes")
        if self.slop is not None:
            parts.append(f"a collision slop of {self.slop:g} m")
        if self.dt is not None:
            hz = 1.0 / self.dt
            step = f"1/{round(hz)}" if abs(hz - round(hz)) < 1e-6 else f"{self.dt:g}"
            parts.append(f"a {step} s step")
        return ", ".join(parts)

    def log(self, log: Log) -> Log:
        """The log on this step (itself when the step is not changed)."""
        return log if self.dt is None else rescaled(log, self.dt)

    def adjust(self, setup):
        """The Setup with the character's solver changed (``replay``'s ``adjust``)."""
        if self.iterations is None and self.slop is None:
            return setup
        from puppet.data.characters import SolverSpec

        old = setup.character.solver
        solver = SolverSpec(
            iterations=old.iterations if self.iterations is None else self.iterations,
            collision_slop=old.collision_slop if self.slop is None else self.slop,
            step=old.step)  # (the step a replay takes is its log's, or --step's)
        return dataclasses.replace(
            setup, character=setup.character.model_copy(update={"solver": solver}))


def rescaled_pairs(pairs, ratio: float) -> list:
    """(step, event) pairs at ``ratio`` times their steps (the nearest step; a rewind's
    target too), in their order: input on another simulation step."""
    out = []
    for step, event in pairs:
        if "to_step" in event:
            event = {**event, "to_step": round(event["to_step"] * ratio)}
        out.append((round(step * ratio), event))
    return out


def rescaled(log: Log, dt: float) -> Log:
    """``log`` on a simulation step of ``dt`` s: each event (and a rewind's target, and
    the end) at the step nearest its recorded time, in the recorded order."""
    ratio = float(log.header["dt"]) / dt

    def at(step: int) -> int:
        return round(step * ratio)

    events = []
    for e in log.events:
        event = dict(e.event)
        if "to_step" in event:
            event["to_step"] = at(event["to_step"])
        events.append(LogEvent(at(e.step), event, e.line))
    end = None if log.end is None else {**log.end, "end": at(log.end["end"])}
    return dataclasses.replace(log, header={**log.header, "dt": dt}, events=events, end=end)


__all__ = ["STEP_RANGE", "OtherPhysics", "parse_step", "rescaled", "rescaled_pairs"]
