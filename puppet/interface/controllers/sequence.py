"""Pose sequences: a key starts a list of (pose, hold) steps played in sim time.

Times are whole simulation steps so a sequence replays bit-identically. Only one
sequence runs at a time: starting one replaces the running one (the paper's "the
most recent action preempts an ongoing one"). A sequence may repeat (n times, or
until preempted). It writes only the joints it still owns.

A step with ``until`` ends early when its sensor condition holds: the condition is
tested at every simulation step once ``after`` has passed (a push that ends as the base
leaves the floor ends within a step of it, on any step length); ``hold`` is then the
longest the step waits.
"""

from __future__ import annotations

from dataclasses import dataclass

from puppet.data.actions import SequenceStepSpec
from puppet.interface.conditions import compile_bounds, compile_test
from puppet.interface.controllers.base import WAITED
from puppet.interface.ownership import SEQUENCE, JointOwners, Owner
from puppet.interface.poses import Pose, apply_pose


def compile_sequences(specs: dict[str, list[SequenceStepSpec]],
                      dt: float) -> dict[str, list[tuple[str, int]]]:
    """name -> [(pose name, hold in steps >= 1)]."""
    return {name: [(s.pose, max(1, round(s.hold / dt))) for s in steps]
            for name, steps in specs.items()}


def compile_untils(specs: dict[str, list[SequenceStepSpec]],
                   dt: float) -> dict[str, list[tuple[int, list] | None]]:
    """name -> per step, None or (steps into the step before ``until`` is tested, its
    conditions as [(sensor name, test, lo, hi)]: a range condition holds when lo <
    value < hi (compared without a call: what ``test`` does), an ``is`` when ``test``)."""
    return {name: [None if s.until is None else
                   (round((s.after or 0.0) / dt),
                    [(c.sensor, compile_test(c), *(compile_bounds(c) or (None, None)))
                     for c in s.conditions])
                   for s in steps]
            for name, steps in specs.items()}


@dataclass
class RunningSequence:
    """Where a running sequence is: its name, current step index, the sim step at which
    the next pose begins (or the sequence ends) and the plays left (None: forever)."""

    name: str
    index: int
    until: int
    plays_left: int | None = 1
    began: int | None = None  # the sim step the current step began (for ``after``)

    def to_state(self) -> list:
        return [self.name, self.index, self.until, self.plays_left, self.began]

    @classmethod
    def from_state(cls, state) -> RunningSequence | None:
        return None if state is None else cls(*state)


class SequenceController:
    BUSY = "running"  # the attribute that is truthy while it has work (the arbiter reads it)

    def __init__(self, specs, poses: dict[str, Pose], servos, owners: JointOwners, dt: float,
                 sensor=None):
        self.specs = specs
        self.plans = compile_sequences(specs, dt)
        self.untils = compile_untils(specs, dt)
        self.sensor = sensor  # sensor name -> a reader of its value (the runtime's)
        self.readers: dict = {}  # sensor name -> reader (emptied when the roles re-bind)
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
        self.running = RunningSequence(name, 0, now + plan[0][1], plays, now)
        self.owners_table.claim(self._joints_of(name), SEQUENCE)
        apply_pose(self.servos, self.poses[plan[0][0]], None, self.frames, SEQUENCE)

    def _joints_of(self, name: str) -> tuple[str, ...]:
        """Every joint sequence ``name``'s poses set, worked out once per set of poses
        (the runtime replaces ``poses`` when the roles are bound anew); sorted, so the
        owners' table (and a saved runtime state) is the same in every process."""
        cache = self.__dict__.get("_joints")
        if cache is None or cache[0] is not self.poses:
            cache = self._joints = (self.poses, {})
        joints = cache[1].get(name)
        if joints is None:
            joints = set()
            for pose_name, _ in self.plans[name]:
                joints |= self.poses[pose_name].joints
            cache[1][name] = joints = tuple(sorted(joints))
        return joints

    def _next_pose(self, running: RunningSequence) -> str | None:
        """Move on to the next step; its pose name, or None when the sequence is over."""
        steps = self.plans[running.name]
        running.index += 1
        running.began = running.until
        if running.index >= len(steps):
            if running.plays_left is not None:
                running.plays_left -= 1
                if running.plays_left <= 0:
                    return None
            running.index = 0
        running.until += steps[running.index][1]
        return steps[running.index][0]

    def _until_holds(self, seq: RunningSequence, step: int) -> bool | None:
        """Whether the current step's ``until`` ends it at ``step``; None when it is not
        tested at ``step`` (no ``until``, or before its ``after``)."""
        until = self.untils[seq.name][seq.index]
        if until is None or step - (seq.began or 0) < until[0]:
            return None
        readers = self.readers
        for sensor, test, lo, hi in until[1]:
            read = readers.get(sensor)
            if read is None:
                read = readers[sensor] = self.sensor(sensor)
            if lo is None:
                if not test(read()):
                    return False
            elif not lo < read() < hi:
                return False
        return True

    def tick(self, step: int) -> str | None:
        seq = self.running
        if seq is None:
            return None
        owners = self.owners_table
        if step < seq.until:  # holding a pose
            if SEQUENCE not in owners.table.values():  # (holds_any, inline)
                self.running = None  # every joint taken back: it has ended
                return None
            holds = self._until_holds(seq, step)
            if holds is None:
                return WAITED  # (its next_wakeup stands)
            if not holds:  # tested: the next wake-up is the next step, which is what the
                return WAITED  # arbiter's schedule moves on to (base.WAITED)
            seq.until = step  # the condition holds: the next step begins now
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
        seq = self.running
        if seq is None:
            return None
        until = self.untils[seq.name][seq.index]
        if until is None:
            return seq.until
        at = max(earliest, (seq.began or 0) + until[0])  # the next test of ``until``
        return at if at < seq.until else seq.until

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
