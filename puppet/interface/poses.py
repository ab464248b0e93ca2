"""Named poses, compiled once to radians: what "set a pose" writes to the servos.

A pose may be partial (only some joints) and may carry gains for its joints; a
pose's gains apply together with its targets, so a "push" pose can also be stiffer.
A joint's target may be given in another frame (a link's angle in the world, or
relative to another link): those are handed to the frame-target controller, which
re-solves them from the figure's state at the control rate.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from puppet.data.actions import FrameTargetSpec, PoseSpec
from puppet.physics.servo import SET_MAX_FORCE, SET_STIFFNESS, SET_TARGET


@dataclass(frozen=True)
class FrameTarget:
    """A target in another frame: ``ref`` link's angle (None: the world) + ``angle``
    (radians) for the joint's child link, or (``hold_parent``) for its parent."""

    ref: str | None
    angle: float
    hold_parent: bool = False

    def to_state(self) -> list:
        return [self.ref, self.angle, self.hold_parent]


_new = object.__new__


def made_frame_target(ref: str | None, angle: float, hold_parent: bool) -> FrameTarget:
    """``FrameTarget(ref, angle, hold_parent)`` without the frozen dataclass's
    ``__init__`` (an ``object.__setattr__`` a field): a frame map makes one per joint
    at every mouse event, a blend at every control step."""
    target = _new(FrameTarget)
    fields = target.__dict__
    fields["ref"], fields["angle"], fields["hold_parent"] = ref, angle, hold_parent
    return target


def frame_target(spec: FrameTargetSpec) -> FrameTarget:
    if spec.world is not None:
        return FrameTarget(None, math.radians(spec.world), spec.hold == "parent")
    return FrameTarget(spec.relative_to, math.radians(spec.angle), spec.hold == "parent")


@dataclass(frozen=True)
class Pose:
    targets: dict[str, float]  # joint -> radians (joint frame)
    stiffness: dict[str, float] = field(default_factory=dict)
    damping: dict[str, float] = field(default_factory=dict)
    frames: dict[str, FrameTarget] = field(default_factory=dict)  # joint -> in another frame
    max_torque: dict[str, float] = field(default_factory=dict)  # joint -> N*m

    @property
    def joints(self) -> set[str]:
        return (set(self.targets) | set(self.stiffness) | set(self.damping)
                | set(self.frames) | set(self.max_torque))


def compile_pose(spec: PoseSpec, rename=lambda n: n) -> Pose:
    """``rename``: joint and link names as the roles bind them now."""
    targets, frames = {}, {}
    for j, v in spec.joints.items():
        if isinstance(v, FrameTargetSpec):
            t = frame_target(v)
            frames[rename(j)] = FrameTarget(None if t.ref is None else rename(t.ref), t.angle,
                                            t.hold_parent)
        else:
            targets[rename(j)] = math.radians(v)
    return Pose(targets, {rename(j): k for j, k in spec.stiffness.items()},
                {rename(j): d for j, d in spec.damping.items()}, frames,
                {rename(j): t for j, t in spec.max_torque.items()})


def compile_poses(specs: dict[str, PoseSpec], rename=lambda n: n) -> dict[str, Pose]:
    return {name: compile_pose(spec, rename) for name, spec in specs.items()}


def apply_pose(servos, pose: Pose, only: set[str] | None = None, frames=None,
               owner=None) -> None:
    """Write a pose's targets and gains to the servos (only the joints in ``only``);
    its frame targets go to ``frames`` (the frame-target controller) under ``owner``."""
    for joint, angle in pose.targets.items():
        if only is None or joint in only:
            servos[joint].target = angle
            if frames is not None and frames.held:
                frames.forget(joint)
    for joint, k in pose.stiffness.items():
        if only is None or joint in only:
            servos[joint].stiffness = k
    for joint, d in pose.damping.items():
        if only is None or joint in only:
            servos[joint].damping = d
    for joint, t in pose.max_torque.items():
        if only is None or joint in only:
            servos[joint].max_torque = t
    if pose.frames and frames is not None:
        for joint, target in pose.frames.items():
            if only is None or joint in only:
                frames.hold(joint, target, owner)


def pose_writer(servos, pose: Pose):
    """``apply_pose(servos, pose, frames=frames, owner=owner)`` (every joint) as a
    function of (frames, owner), its servos' springs looked up once: a gait's state
    entry writes a pose every few control steps. The same calls in the same order;
    made again when the springs are re-bound (a restore: the caller keys it on the
    character's bodies)."""
    targets = tuple((j, servos[j].spring._constraint, a) for j, a in pose.targets.items())
    stiffness = tuple((servos[j].spring._constraint, k) for j, k in pose.stiffness.items())
    damping = tuple((servos[j], d) for j, d in pose.damping.items())
    torques = tuple((servos[j].spring._constraint, t) for j, t in pose.max_torque.items())
    held = tuple(pose.frames.items())

    def write(frames, owner) -> None:
        for joint, spring, angle in targets:
            SET_TARGET(spring, angle)
            if frames.held:
                frames.forget(joint)
        for spring, k in stiffness:
            SET_STIFFNESS(spring, k)
        for servo, d in damping:
            servo.damping = d
        for spring, t in torques:
            SET_MAX_FORCE(spring, t)
        for joint, target in held:
            frames.hold(joint, target, owner)
    return write
