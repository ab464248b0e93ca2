"""Sensor conditions written as data, compiled to fast tests on a Character.

Conditions drive state-machine transitions ("when the lean passes 20 deg, swap
legs"). Each reads one named sensor (the names ``puppet check`` accepts, listed in
``puppet.data.interface_refs``) and compares it with thresholds converted to SI once,
up front. A reader and its test are separate so that a state polling several
conditions on one sensor reads it once per poll.
"""

from __future__ import annotations

import math
from collections.abc import Callable

from pymunk._chipmunk_cffi import lib as _cp

from puppet.data.actions import ConditionSpec
from puppet.physics.character import Character
from puppet.physics.kernel import remainder as _remainder

Reader = Callable[[], float]
Test = Callable[[float], bool]
_TURN = 2.0 * math.pi  # world angles are read within one turn: -180..180 deg


def _lean(c: Character) -> Reader:
    def lean() -> float:
        x, y = c.com()
        rx, ry = c.bodies[c.spec.root].position
        return math.atan2(x - rx, y - ry)
    return lean


def _fall_time(c: Character) -> Reader:
    """The seconds until the centre of mass, flying freely from where it is under the
    space's gravity (read live: a meta key may change it), comes down to the scene's
    y = 0 (the floor of flat): (vy + sqrt(vy^2 + 2 g y)) / g; 0 at or under y = 0,
    infinite without gravity pulling down. With the angle and the spin it says when to
    open a flip (the time left to turn in)."""
    sqrt, inf = math.sqrt, math.inf

    def fall_time() -> float:
        y = c.com()[1]
        if y <= 0.0:
            return 0.0
        g = -c.bodies[c.spec.root].space.gravity[1]
        if g <= 0.0:
            return inf
        vy = c.com_velocity()[1]
        return (vy + sqrt(vy * vy + 2.0 * g * y)) / g
    return fall_time


# Readers run at every poll of a state machine (each control step): they make pymunk's
# own C calls (what Body.angle and Body.angular_velocity return), without the property.
# ``c.bodies`` is looked up on every read: a restore re-binds the bodies.
_get_angle, _get_spin = _cp.cpBodyGetAngle, _cp.cpBodyGetAngularVelocity


def _angle(c: Character, link: str) -> Reader:
    """A link's world angle within one turn (NaN for a blown-up, infinite angle, as the
    kernel's libm ``remainder`` answers, where Python's raises: both paths then recover
    at the session's frame check)."""
    return lambda: _remainder(_get_angle(c.bodies[link]._body), _TURN)


def _spin(c: Character, link: str) -> Reader:
    """A link's angular velocity (rad/s, counter-clockwise)."""
    return lambda: _get_spin(c.bodies[link]._body)


def _com_dx(c: Character, name: str) -> Reader:
    """The centre of mass's horizontal offset (m, + ahead in +x) from a link's centre of
    mass, or (``support``) from the middle of the support polygon: the segment between
    the outermost ground contacts (0 when nothing touches)."""
    if name == "support":
        def from_support() -> float:
            extent = c.support_extent()
            return 0.0 if extent is None else c.com()[0] - 0.5 * (extent[0] + extent[1])
        return from_support
    return lambda: c.com()[0] - c.link_position(name)[0]


def _lead(c: Character, link: str, other: str) -> Reader:
    """How far (m, + ahead in +x) a link's centre of mass is from another's: the swing
    foot's lead over the stance foot (``lead.swing_foot.stance_foot``)."""
    where = c.link_position
    return lambda: where(link)[0] - where(other)[0]


def _joint(c: Character, name: str) -> Reader:
    joint = c.spec.joint(name)

    child, parent = joint.child, joint.parent

    def angle() -> float:  # c.bodies looked up on every read: a restore re-binds them
        bodies = c.bodies
        return _get_angle(bodies[child]._body) - _get_angle(bodies[parent]._body)
    return angle


_rest_angle, _stiffness, _damping, _max_force = (
    _cp.cpDampedRotarySpringGetRestAngle, _cp.cpDampedRotarySpringGetStiffness,
    _cp.cpDampedRotarySpringGetDamping, _cp.cpConstraintGetMaxForce)


def _torque(c: Character, name: str) -> Reader:
    """The torque (N*m, + counter-clockwise on the child) the joint's servo puts on its
    child as its gains say now: stiffness * (target - angle) - damping * relative spin,
    within its cap; the child's parent gets the opposite. Worked out from the state (a
    restored run reads the same), so that another joint can take it over: SIMBICON's
    stance hip takes the swing hip's reaction on the pelvis (guide 9.8)."""
    joint = c.spec.joint(name)
    child, parent = joint.child, joint.parent

    def torque() -> float:
        bodies, servo = c.bodies, c.servos[name]
        a, b = bodies[child]._body, bodies[parent]._body
        spring = servo.spring._constraint
        t = (_stiffness(spring) * (_rest_angle(spring) - (_get_angle(a) - _get_angle(b)))
             - servo.damping * (_get_spin(a) - _get_spin(b)))
        cap = _max_force(spring)
        return cap if t > cap else -cap if t < -cap else t
    return torque


# sensor name -> (reader factory, reads an angle?)
FIXED: dict[str, tuple[Callable[[Character], Reader], bool]] = {
    "root.angle": (lambda c: _angle(c, c.spec.root), True),
    "lean": (_lean, True),
    "com.x": (lambda c: lambda: c.com()[0], False),
    "com.y": (lambda c: lambda: c.com()[1], False),
    "com.vx": (lambda c: lambda: c.com_velocity()[0], False),
    "com.vy": (lambda c: lambda: c.com_velocity()[1], False),
    "com.fall_time": (_fall_time, False),
    "com.spin": (lambda c: c.com_spin, True),
}
# "<kind>.<joint or link name>" -> (reader factory, reads an angle?)
NAMED: dict[str, tuple[Callable[[Character, str], Reader], bool]] = {
    "joint": (_joint, True),
    "torque": (_torque, False),
    "angle": (_angle, True),
    "height": (lambda c, n: lambda: c.link_position(n)[1], False),
    "contact": (lambda c, n: lambda: 1.0 if c.in_contact(n) else 0.0, False),
    "spin": (_spin, True),
    "com.dx": (_com_dx, False),
}


LEAD = "lead."  # lead.LINK.OTHER: two links' names


def _lookup(sensor: str) -> tuple[Callable, bool, tuple]:
    if sensor in FIXED:
        make, is_angle = FIXED[sensor]
        return make, is_angle, ()
    if sensor.startswith("com.dx."):
        make, is_angle = NAMED["com.dx"]
        return make, is_angle, (sensor[len("com.dx."):],)
    if sensor.startswith(LEAD):
        link, dot, other = sensor[len(LEAD):].partition(".")
        if link and dot and other and "." not in other:
            return _lead, False, (link, other)
    kind, _, name = sensor.partition(".")
    if kind in NAMED and name:
        make, is_angle = NAMED[kind]
        return make, is_angle, (name,)
    raise ValueError(f"unknown sensor '{sensor}'")


_NAN = float("nan")
INPUT = "input."  # a device input as a sensor: input.mouse.x, input.gamepad.left_x


HELD = "held."  # held.CHAIN: the height of what the chain holds (a script rule's sensor)


def reader(sensor: str, character: Character, channels: dict | None = None,
           inputs: dict | None = None,
           grasp_point: Callable[[str], tuple | None] | None = None) -> Reader:
    """A zero-argument reader of the sensor's current value (SI units). ``channel.NAME``
    reads the input channel from ``channels`` (the runtime's), in the plugin's own
    units; ``input.NAME`` a device input (``input.mouse.x``: 0 .. 1) from ``inputs``
    (the runtime's); either is NaN - no condition holds - until its first value comes.
    ``held.CHAIN`` is the height (m) of the point the chain holds, NaN while it holds
    nothing, from ``grasp_point`` (the simulation's: chain -> world point or None)."""
    if sensor.startswith(HELD):
        if grasp_point is None:
            raise ValueError(f"'{sensor}': held.CHAIN is read by a script's rules only")
        name = sensor[len(HELD):]

        def held() -> float:
            point = grasp_point(name)
            return _NAN if point is None else point[1]
        return held
    if sensor.startswith("channel."):
        name, values = sensor[len("channel."):], channels if channels is not None else {}
        return lambda: values.get(name, _NAN)
    if sensor.startswith(INPUT):
        name, values = sensor[len(INPUT):], inputs if inputs is not None else {}
        return lambda: values.get(name, _NAN)
    make, _, args = _lookup(sensor)
    return make(character, *args)


def map_reader(sensor: str, character: Character) -> Reader:
    """A reader in the units files use (degrees, and degrees per second, for angles),
    for maps whose input is ``sensor.<sensor>``."""
    read = reader(sensor, character)
    if _lookup(sensor)[1]:
        k = 180.0 / math.pi
        return lambda: read() * k
    return read


def compile_bounds(spec: ConditionSpec) -> tuple[float, float] | None:
    """(lo, hi) such that the condition holds when lo < value < hi (``compile_test``'s
    test, for a state machine to compare without a call); None for an ``is`` test."""
    if spec.is_ is not None:
        return None
    angle = not spec.sensor.startswith(("channel.", INPUT, HELD)) and _lookup(spec.sensor)[1]
    conv = math.radians if angle else float
    lo = conv(spec.above) if spec.above is not None else -math.inf
    hi = conv(spec.below) if spec.below is not None else math.inf
    return lo, hi


def compile_test(spec: ConditionSpec) -> Test:
    """The condition as a test on its sensor's value."""
    if spec.is_ is not None:
        want = spec.is_
        return lambda value: (value > 0.5) == want
    lo, hi = compile_bounds(spec)
    return lambda value: lo < value < hi
