"""Pose sequences: a key starts a list of (pose, hold) steps played in sim time.

Times are whole simulation steps so a sequence replays bit-identically. Only one
sequence runs at a time: starting one replaces the running one (the paper's "the
most recent action preempts an ongoing one"). Which joints it may still write is
decided by the runtime's joint ownership, not here.
"""

from __future__ import annotations

from dataclasses import dataclass

from puppet.data.actions import SequenceStepSpec


def compile_sequences(specs: dict[str, list[SequenceStepSpec]],
                      dt: float) -> dict[str, list[tuple[str, int]]]:
    """name -> [(pose name, hold in steps >= 1)]."""
    return {name: [(s.pose, max(1, round(s.hold / dt))) for s in steps]
            for name, steps in specs.items()}


@dataclass
class RunningSequence:
    """Where a running sequence is: its name, current step index, and the sim step at
    which the next pose begins (or the sequence ends)."""

    name: str
    index: int
    until: int

    def to_state(self) -> list:
        return [self.name, self.index, self.until]

    @classmethod
    def from_state(cls, state) -> RunningSequence | None:
        return None if state is None else cls(*state)


def start(plans: dict[str, list[tuple[str, int]]], name: str, now: int) -> RunningSequence:
    return RunningSequence(name, 0, now + plans[name][0][1])


def next_pose(plans: dict[str, list[tuple[str, int]]], running: RunningSequence) -> str | None:
    """Move on to the next step; its pose name, or None when the sequence is over."""
    steps = plans[running.name]
    running.index += 1
    if running.index >= len(steps):
        return None
    running.until += steps[running.index][1]
    return steps[running.index][0]
