"""Sensor conditions written as data, compiled to fast predicates on a Character.

Conditions drive state-machine transitions ("when the lean passes 20 deg, swap
legs"). Each reads one named sensor - the same names the Character's sensor
methods have - and compares it with thresholds converted to SI once, up front.
"""

from __future__ import annotations

import math
from collections.abc import Callable

from puppet.data.actions import ConditionSpec
from puppet.physics.character import Character

Predicate = Callable[[Character], bool]
_TURN = 2.0 * math.pi  # world angles are read within one turn: -180..180 deg


def _reader(sensor: str, character: Character) -> tuple[Callable[[], float], bool]:
    """A zero-argument reader of the sensor and whether its unit is an angle."""
    c = character
    kind, _, name = sensor.partition(".")
    if sensor == "root.angle":
        return (lambda: math.remainder(c.root_angle(), _TURN)), True
    if sensor == "lean":
        def lean() -> float:
            x, y = c.com()
            rx, ry = c.bodies[c.spec.root].position
            return math.atan2(x - rx, y - ry)
        return lean, True
    if kind == "com":
        index = {"x": 0, "y": 1}.get(name)
        if index is not None:
            return (lambda: c.com()[index]), False
        index = {"vx": 0, "vy": 1}[name]
        return (lambda: c.com_velocity()[index]), False
    if kind == "joint":
        joint = c.spec.joint(name)

        def angle() -> float:
            return c.bodies[joint.child].angle - c.bodies[joint.parent].angle
        return angle, True
    if kind == "angle":
        return (lambda: math.remainder(c.bodies[name].angle, _TURN)), True
    if kind == "height":
        return (lambda: c.link_position(name)[1]), False
    if kind == "contact":
        return (lambda: 1.0 if c.in_contact(name) else 0.0), False
    raise ValueError(f"unknown sensor '{sensor}'")


def compile_condition(spec: ConditionSpec, character: Character) -> Predicate:
    read, is_angle = _reader(spec.sensor, character)
    if spec.is_ is not None:
        want = spec.is_
        return lambda _c: (read() > 0.5) == want
    conv = math.radians if is_angle else float
    lo = conv(spec.above) if spec.above is not None else -math.inf
    hi = conv(spec.below) if spec.below is not None else math.inf
    return lambda _c: lo < read() < hi
