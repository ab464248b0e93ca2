"""A fall's get-up under KD control (Oshita 2006's stand-up, through the recovery poses of
Laszlo et al. 2000: hands and knees, crouch, stand): what the tracker follows while the
figure gets up, and what keeps it honest.

The get-up is a list of poses (``tracking.reaction.get_up.steps``): joint angles of the
interface's poses and the root link's angle in the world. It starts from where the body
lies - its own joint angles, its root's place and angle - and blends into each pose in
turn over that step's ``hold``; the tracker's pulls place each pose where the figure is,
its lowest point on the ground. No levitation: while neither a foot nor a hand touches
the ground no pull may lift a link (``supported``), so the pelvis rises only while hands
or feet push on the ground. After the last pose the tracker blends back to the
performer.
"""

from __future__ import annotations

import math


def joint_degrees(character, joints: dict[str, str]) -> dict[str, float]:
    """channel -> the figure's joint angle now (deg), for the tracked joints."""
    out = {}
    for joint, channel in joints.items():
        spec = character.spec.joint(joint)
        a = character.bodies[spec.child].angle - character.bodies[spec.parent].angle
        out[channel] = math.degrees(math.remainder(a, 2 * math.pi))
    return out


class GetUp:
    """The channels of a get-up over time. ``came``: the figure's own (the first pose
    blends from it); ``targets``: each step's channels; ``at``: the step the get-up
    began."""

    def __init__(self, spec, poses: dict[str, dict[str, float]], came: dict[str, float],
                 root_names, x: float, at: int, dt: float):
        self.spec = spec
        self.came = came
        self.at = at
        self.dt = dt
        rx, ry, ra, rc = root_names
        self.targets = []
        for step in spec.steps:
            values = dict(poses[step.pose])
            values.update({rx: x, ry: came.get(ry, 0.0), ra: step.angle, rc: 0.0})
            self.targets.append(values)
        if ra in came:  # the root's angle, by whole turns nearest the first pose's
            first = spec.steps[0].angle
            came[ra] = first + math.remainder(came[ra] - first, 360.0)
        self.ends = []  # the step each pose is reached at
        end = at
        for step in spec.steps:
            end += max(1, round(step.hold / dt))
            self.ends.append(end)

    @property
    def done_at(self) -> int:
        return self.ends[-1]

    def index(self, step: int) -> int:
        for i, end in enumerate(self.ends):
            if step < end:
                return i
        return len(self.ends) - 1

    def view(self, step: int) -> dict[str, float]:
        """The channels to follow at ``step``: part way from the last pose (the
        figure's own, first) to this step's."""
        i = self.index(step)
        start = self.at if i == 0 else self.ends[i - 1]
        a = self.came if i == 0 else self.targets[i - 1]
        b = self.targets[i]
        w = min(1.0, max(0.0, (step - start) / max(1, self.ends[i] - start)))
        return {n: a.get(n, v) + (v - a.get(n, v)) * w for n, v in b.items()}

    def pose_name(self, step: int) -> str:
        return self.spec.steps[self.index(step)].pose

    def state(self) -> list:
        return [dict(self.came), self.at]


def supported(character, feet, hands) -> bool:
    """A foot or a hand on the ground: the body may push itself up."""
    return any(character.in_contact(link) for link in (*feet, *hands))
