"""Pose sequences: a key starts a list of (pose, hold) steps played in sim time.

Times are whole simulation steps so a sequence replays bit-identically. Only one
sequence runs at a time: starting one replaces the running one (the paper's "the
most recent action preempts an ongoing one"). A sequence may repeat (n times, or
until preempted). It writes only the joints it still owns.
"""

from __future__ import annotations

from dataclasses import dataclass

from puppet.data.actions import SequenceStepSpec
from puppet.interface.controllers.base import WAITED
from puppet.interface.ownership import SEQUENCE, JointOwners, Owner
from puppet.interface.poses import Pose, apply_pose


def compile_sequences(specs: dict[str, list[SequenceStepSpec]],
                      dt: float) -> dict[str, list[tuple[str, int]]]:
    """name -> [(pose name, hold in steps >= 1)]."""
    return {name: [(s.pose, max(1, round(s.hold / dt))) for s in steps]
            for name, steps in specs.items()}


@dataclass
class RunningSequence:
    """Where a running sequence is: its name, current step index, the sim step at which
    the next pose begins (or the sequence ends) and the plays left (None: forever)."""

    name: str
    index: int
    until: int
    plays_left: int | None = 1

    def to_state(self) -> list:
        return [self.name, self.index, self.until, self.plays_left]

    @classmethod
    def from_state(cls, state) -> RunningSequence | None:
        return None if state is None else cls(*state)


class SequenceController:
    BUSY = "running"  # the attribute that is truthy while it has work (the arbiter reads it)

    def __init__(self, specs, poses: dict[str, Pose], servos, owners: JointOwners, dt: float):
        self.specs = specs
        self.plans = compile_sequences(specs, dt)
        self.poses = poses
        self.servos = servos
        self.owners_table = owners
        self.running: RunningSequence | None = None
        self.frames = None  # the frame-target controller, for poses in other frames

    def start(self, name: str, now: int, repeat: int | str | None = None) -> None:
        """Start sequence ``name`` (replacing the running one); ``repeat``: plays in
        all, or "forever"."""
        self.owners_table.drop(SEQUENCE)
        plan = self.plans[name]
        plays = None if repeat == "forever" else (repeat or 1)
        self.running = RunningSequence(name, 0, now + plan[0][1], plays)
        self.owners_table.claim(self._joints_of(name), SEQUENCE)
        apply_pose(self.servos, self.poses[plan[0][0]], None, self.frames, SEQUENCE)

    def _joints_of(self, name: str) -> set[str]:
        """Every joint sequence ``name``'s poses set, worked out once per set of poses
        (the runtime replaces ``poses`` when the roles are bound anew)."""
        cache = self.__dict__.get("_joints")
        if cache is None or cache[0] is not self.poses:
            cache = self._joints = (self.poses, {})
        joints = cache[1].get(name)
        if joints is None:
            joints = set()
            for pose_name, _ in self.plans[name]:
                joints |= self.poses[pose_name].joints
            cache[1][name] = joints
        return joints

    def _next_pose(self, running: RunningSequence) -> str | None:
        """Move on to the next step; its pose name, or None when the sequence is over."""
        steps = self.plans[running.name]
        running.index += 1
        if running.index >= len(steps):
            if running.plays_left is not None:
                running.plays_left -= 1
                if running.plays_left <= 0:
                    return None
            running.index = 0
        running.until += steps[running.index][1]
        return steps[running.index][0]

    def tick(self, step: int) -> str | None:
        seq = self.running
        if seq is None:
            return None
        owners = self.owners_table
        if step < seq.until:  # holding a pose
            if SEQUENCE in owners.table.values():  # (holds_any, inline)
                return WAITED
            self.running = None  # every joint taken back: it has ended
            return None
        while seq is not None and step >= seq.until:
            pose_name = self._next_pose(seq)
            if pose_name is None:
                owners.drop(SEQUENCE)
                self.running = seq = None
            else:
                apply_pose(self.servos, self.poses[pose_name], owners.owned(SEQUENCE),
                           self.frames, SEQUENCE)
        if seq is not None and SEQUENCE not in owners.table.values():  # (holds_any, inline)
            self.running = None  # every joint taken back: it has ended
        return None

    def next_wakeup(self, earliest: int) -> int | None:
        return None if self.running is None else self.running.until

    def owners(self) -> set[Owner]:
        return {SEQUENCE} if self.running is not None else set()

    def get_state(self):
        return self.running.to_state() if self.running else None

    def set_state(self, state) -> None:
        self.running = RunningSequence.from_state(state)

    def adopt(self, old: SequenceController, same, now: int) -> set[Owner]:
        seq = old.running
        if seq is not None and same("sequence", seq.name):
            self.running = RunningSequence.from_state(seq.to_state())
            return {SEQUENCE}
        return set()

    def stop(self) -> None:
        self.running = None
