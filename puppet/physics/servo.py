"""PD servo: a joint that tracks a target angle with stiffness, damping and a torque limit.

It is a pymunk ``DampedRotarySpring`` (child, parent): the spring term
``stiffness * (target - angle)`` is applied explicitly each step, the damping term
``-damping * relative angular velocity`` is applied implicitly by the solver (so it is
stable for any damping at any step), and ``max_force`` caps the total torque, which is
what a torque limit is. It all runs in C; Python only touches it when a target or a
gain changes.
"""

from __future__ import annotations

import pymunk
from pymunk._chipmunk_cffi import lib as _cp

# The C call pymunk's own ``rest_angle`` setter makes, called directly: assigning through
# the instance also runs pymunk's attribute-typing hook and two Python layers, which
# triple the cost of the hot input-to-target path (maps write a target per joint per
# event). The value written is the same.
_SET_REST_ANGLE = _cp.cpDampedRotarySpringSetRestAngle
_GET_REST_ANGLE = _cp.cpDampedRotarySpringGetRestAngle  # (what spring.rest_angle returns)
# ``SET_TARGET(servo.spring._constraint, radians)`` is ``servo.target = radians`` without
# the property's call, for loops that write many servos (maps.fused)
SET_TARGET = _SET_REST_ANGLE
GET_TARGET = _GET_REST_ANGLE  # ``GET_TARGET(servo.spring._constraint)``: ``servo.target``


class PDServo:
    """Drives ``angle = child.angle - parent.angle`` (radians) toward ``target``."""

    __slots__ = ("name", "spring", "parent", "child", "default_gains")

    def __init__(self, name: str, parent: pymunk.Body, child: pymunk.Body, target: float,
                 stiffness: float, damping: float, max_torque: float):
        self.name = name
        self.parent = parent
        self.child = child
        self.spring = pymunk.DampedRotarySpring(child, parent, target, stiffness, damping)
        self.spring.max_force = max_torque
        self.default_gains = (stiffness, damping, max_torque)

    def bind(self, spring: pymunk.DampedRotarySpring) -> None:
        """Point at a restored copy of the spring (after a snapshot is restored)."""
        self.spring = spring
        self.child, self.parent = spring.a, spring.b

    @property
    def angle(self) -> float:
        return self.child.angle - self.parent.angle

    @property
    def velocity(self) -> float:
        return self.child.angular_velocity - self.parent.angular_velocity

    @property
    def target(self) -> float:
        return _GET_REST_ANGLE(self.spring._constraint)

    @target.setter
    def target(self, value: float) -> None:
        _SET_REST_ANGLE(self.spring._constraint, value)

    @property
    def stiffness(self) -> float:
        return self.spring.stiffness

    @stiffness.setter
    def stiffness(self, value: float) -> None:
        self.spring.stiffness = value

    @property
    def damping(self) -> float:
        return self.spring.damping

    @damping.setter
    def damping(self, value: float) -> None:
        self.spring.damping = value

    @property
    def max_torque(self) -> float:
        return self.spring.max_force

    @max_torque.setter
    def max_torque(self, value: float) -> None:
        self.spring.max_force = value

    def torque(self, dt: float) -> float:
        """Torque the servo applied on the child during the last step (N*m)."""
        return -self.spring.impulse / dt
