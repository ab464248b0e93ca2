"""PD servo: a joint that tracks a target angle with stiffness, damping and a torque limit.

It is a pymunk ``DampedRotarySpring`` (child, parent): the spring term
``stiffness * (target - angle)`` is applied explicitly each step, the damping term
``-damping * relative angular velocity`` is applied implicitly by the solver (so it is
stable for any damping at any step), and ``max_force`` caps the total torque, which is
what a torque limit is. It all runs in C; Python only touches it when a target or a
gain changes.

**Damping is the same at any step.** Chipmunk gives the spring's impulse first and then
damps the joint's relative speed by ``e^-lam`` each step, ``lam = damping * dt * (1/I_a
+ 1/I_b)`` (the two links' own moments, not the joint's). On light links ``lam`` is 1-4
at 1/480 s: the damping eats most of the step's own spring impulse, and the joint
follows its target as if damped by ``damping * (e^lam - 1) / lam`` (docs/characters.md,
section 8), which grows exponentially with the step: Luxo's ankle at the mouse gains is
damped 3.1x its number at 1/480 s and 12.8x at 1/240 s, and every Luxo and cat log fell
when replayed at 1/240 s. So a damping here means what it does at ``REFERENCE_STEP``
(1/480 s, the step every log was recorded on): on another step Chipmunk is handed the
damping whose ``(e^lam - 1) / (dt * (1/I_a + 1/I_b))`` is the same
(``chipmunk_damping``). At ``REFERENCE_STEP`` that is the number itself, bit for bit.
"""

from __future__ import annotations

import math

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
# likewise the gains' setters (a pose writes several at each state a gait enters)
_SET_STIFFNESS, _SET_DAMPING = (_cp.cpDampedRotarySpringSetStiffness,
                                _cp.cpDampedRotarySpringSetDamping)
_SET_MAX_FORCE = _cp.cpConstraintSetMaxForce
GET_TARGET = _GET_REST_ANGLE  # ``GET_TARGET(servo.spring._constraint)``: ``servo.target``
SET_STIFFNESS, SET_MAX_FORCE = _SET_STIFFNESS, _SET_MAX_FORCE  # (poses.pose_writer's)

REFERENCE_STEP = 1.0 / 480.0  # s; gains mean what they do on this step (the docstring)


def chipmunk_damping(damping: float, inverse_moments: float, dt: float) -> float:
    """The damping to hand Chipmunk on a step of ``dt`` s for a servo that acts as
    ``damping`` does at ``REFERENCE_STEP`` (``inverse_moments``: 1/I_a + 1/I_b of its
    two links): the one with the same ``(e^lam - 1) / (dt * inverse_moments)``."""
    if dt == REFERENCE_STEP or damping <= 0.0 or inverse_moments <= 0.0:
        return damping
    effective = math.expm1(damping * REFERENCE_STEP * inverse_moments) / REFERENCE_STEP
    return math.log1p(effective * dt) / (dt * inverse_moments)


def nominal_damping(chipmunk: float, inverse_moments: float, dt: float) -> float:
    """``chipmunk_damping``'s inverse: the damping a servo means, from Chipmunk's."""
    if dt == REFERENCE_STEP or chipmunk <= 0.0 or inverse_moments <= 0.0:
        return chipmunk
    effective = math.expm1(chipmunk * dt * inverse_moments) / dt
    return math.log1p(effective * REFERENCE_STEP) / (REFERENCE_STEP * inverse_moments)


class PDServo:
    """Drives ``angle = child.angle - parent.angle`` (radians) toward ``target``."""

    __slots__ = ("name", "spring", "parent", "child", "default_gains", "_damping", "_step",
                 "_inverse_moments")

    def __init__(self, name: str, parent: pymunk.Body, child: pymunk.Body, target: float,
                 stiffness: float, damping: float, max_torque: float):
        self.name = name
        self.parent = parent
        self.child = child
        self.spring = pymunk.DampedRotarySpring(child, parent, target, stiffness, damping)
        self.spring.max_force = max_torque
        self.default_gains = (stiffness, damping, max_torque)
        self._damping = damping  # what the servo means (at REFERENCE_STEP)
        self._step = REFERENCE_STEP  # until the simulation says (``set_step``)
        self._inverse_moments = 0.0

    def set_step(self, dt: float) -> None:
        """Step the servo's space is stepped with (s): its damping is handed to
        Chipmunk for it (``chipmunk_damping``). Call once its links carry their mass."""
        self._step = dt
        self._inverse_moments = 1.0 / self.child.moment + 1.0 / self.parent.moment
        self.damping = self._damping

    def bind(self, spring: pymunk.DampedRotarySpring) -> None:
        """Point at a restored copy of the spring (after a snapshot is restored)."""
        self.spring = spring
        self.child, self.parent = spring.a, spring.b
        held = spring.damping
        if held != chipmunk_damping(self._damping, self._inverse_moments, self._step):
            self._damping = nominal_damping(held, self._inverse_moments, self._step)

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
        _SET_STIFFNESS(self.spring._constraint, value)  # (pymunk's setter's own call)

    @property
    def damping(self) -> float:
        """N*m*s/rad, as it acts at ``REFERENCE_STEP`` (the docstring)."""
        return self._damping

    @damping.setter
    def damping(self, value: float) -> None:
        self._damping = value
        step = self._step  # (at REFERENCE_STEP chipmunk_damping is the number: not called)
        _SET_DAMPING(self.spring._constraint, value if step == REFERENCE_STEP else
                     chipmunk_damping(value, self._inverse_moments, step))

    @property
    def max_torque(self) -> float:
        return self.spring.max_force

    @max_torque.setter
    def max_torque(self, value: float) -> None:
        _SET_MAX_FORCE(self.spring._constraint, value)

    def torque(self, dt: float) -> float:
        """Torque the servo applied on the child during the last step (N*m)."""
        return -self.spring.impulse / dt
