"""Named poses, compiled once to radians: what "set a pose" writes to the servos.

A pose may be partial (only some joints) and may carry gains for its joints; a
pose's gains apply together with its targets, so a "push" pose can also be stiffer.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from puppet.data.actions import PoseSpec


@dataclass(frozen=True)
class Pose:
    targets: dict[str, float]  # joint -> radians
    stiffness: dict[str, float] = field(default_factory=dict)
    damping: dict[str, float] = field(default_factory=dict)

    @property
    def joints(self) -> set[str]:
        return set(self.targets) | set(self.stiffness) | set(self.damping)


def compile_pose(spec: PoseSpec) -> Pose:
    return Pose({j: math.radians(v) for j, v in spec.joints.items()},
                dict(spec.stiffness), dict(spec.damping))


def compile_poses(specs: dict[str, PoseSpec]) -> dict[str, Pose]:
    return {name: compile_pose(spec) for name, spec in specs.items()}


def apply_pose(servos, pose: Pose, only: set[str] | None = None) -> None:
    """Write a pose's targets and gains to the servos (only the joints in ``only``)."""
    for joint, angle in pose.targets.items():
        if only is None or joint in only:
            servos[joint].target = angle
    for joint, k in pose.stiffness.items():
        if only is None or joint in only:
            servos[joint].stiffness = k
    for joint, d in pose.damping.items():
        if only is None or joint in only:
            servos[joint].damping = d
