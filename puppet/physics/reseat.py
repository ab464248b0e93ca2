"""A snapshot re-seated into the live space: the space ``snapshot.rebuild`` would make,
made out of the objects already there.

``rebuild`` makes a fresh space - every body, shape and constraint made again through
pymunk's Python, added, and the old space freed: most of a checkpoint's time. A fresh
space is needed for the bits (it drops the solver's warm starts, the spatial index's
history and the contact graph), not fresh Python objects. So when the live space holds
bodies and shapes that match the snapshot one for one (the same classes, each shape on
the same body - always so at a checkpoint), this runs Chipmunk's own sequence of a
fresh build on them, in the same order and with the same values:

* the space: ``cpSpaceDestroy`` then ``cpSpaceInit`` on its own memory - new arrays,
  spatial indexes, contact cache and buffers, stamp 0, as ``cpSpaceNew`` makes them;
* each body, shape and constraint: its ``...Init`` again (what ``...New`` runs after
  ``calloc``), with the snapshot's constructor arguments, then the same setters as
  ``rebuild``, then the adds in the snapshot's order. The few fields an ``Init`` leaves
  to ``calloc``'s zeros are put back to zero (a body's centre of gravity, and the
  transform worked out from it); a shape's bounding box and hash id and a joint's
  solver terms are written by the add or the next step before anything reads them.
  pymunk's user data (the handle back to the Python object) is kept.

Constraints are matched by class and bodies: one the snapshot has and the space has
not (a grasp let go since) is made anew, as ``rebuild`` makes it; one the space has
and the snapshot has not (a grasp made since) is taken out first. What stays
different from ``rebuild`` is where things are in memory, which Chipmunk's results do
not depend on (a replay gives the same bits in any process). Anything else (another
class, other bodies or shapes, collision handlers, a threaded space) goes through
``rebuild``. tests/test_reseat.py checks both ways agree bit for bit.
"""

from __future__ import annotations

import pymunk
from pymunk._chipmunk_cffi import ffi as _ffi
from pymunk._chipmunk_cffi import lib as _cp

_DYNAMIC, _KINEMATIC, _STATIC = pymunk.Body.DYNAMIC, pymunk.Body.KINEMATIC, pymunk.Body.STATIC
_IDENTITY = (1.0, 0.0, 0.0, 1.0, 0.0, 0.0)  # pymunk's Transform.identity(), a Poly's default
_ZERO = (0.0, 0.0)
_cast = _ffi.cast


def _defaults() -> tuple[tuple, tuple]:
    """What ``cpShapeInit`` writes for a shape's sensor flag, collision type and filter,
    and ``cpConstraintInit`` for a constraint's max force, error bias, max bias and
    collide flag, as ``snapshot`` records them (read off new objects). A setter
    writing the same value changes nothing else (it wakes the bodies, awake already),
    so the re-seat skips it. Integers, infinities and a non-zero bias: equal values
    are equal bits."""
    a, b = pymunk.Body(1.0, 1.0), pymunk.Body(1.0, 1.0)
    h = pymunk.Circle(a, 1.0)._shape
    f = _cp.cpShapeGetFilter(h)
    c = pymunk.PivotJoint(a, b, (0.0, 0.0), (0.0, 0.0))._constraint
    bias = _cp.cpConstraintGetErrorBias(c)
    assert bias != 0.0
    return ((bool(_cp.cpShapeGetSensor(h)), _cp.cpShapeGetCollisionType(h),
             (f.group, f.categories, f.mask)),
            (_cp.cpConstraintGetMaxForce(c), bias, _cp.cpConstraintGetMaxBias(c),
             _cp.cpConstraintGetCollideBodies(c)))


_SHAPE_DEFAULTS, _CONSTRAINT_DEFAULTS = _defaults()


def _poly(h, body, args):
    verts, _transform, radius = args  # pymunk's pickle passes no transform (identity)
    _cp.cpShapeDestroy(h)  # frees the planes of more than 6 corners (Init allocates them)
    _cp.cpPolyShapeInit(_cast("cpPolyShape *", h), body, len(verts), verts, _IDENTITY, radius)


# A shape's or constraint's ``Init`` from the constructor arguments ``snapshot`` records
# (the arguments pymunk's constructor passes to the ``...New`` that runs this ``Init``).
_SHAPE_INIT = {
    pymunk.Circle: lambda h, body, a: _cp.cpCircleShapeInit(
        _cast("cpCircleShape *", h), body, a[0], a[1]),
    pymunk.Segment: lambda h, body, a: _cp.cpSegmentShapeInit(
        _cast("cpSegmentShape *", h), body, a[0], a[1], a[2]),
    pymunk.Poly: _poly,
}
_CONSTRAINT_INIT = {
    pymunk.PivotJoint: lambda h, a, b, x: _cp.cpPivotJointInit(
        _cast("cpPivotJoint *", h), a, b, x[0], x[1]),
    pymunk.RotaryLimitJoint: lambda h, a, b, x: _cp.cpRotaryLimitJointInit(
        _cast("cpRotaryLimitJoint *", h), a, b, x[0], x[1]),
    pymunk.DampedRotarySpring: lambda h, a, b, x: _cp.cpDampedRotarySpringInit(
        _cast("cpDampedRotarySpring *", h), a, b, x[0], x[1], x[2]),
    pymunk.GearJoint: lambda h, a, b, x: _cp.cpGearJointInit(
        _cast("cpGearJoint *", h), a, b, x[0], x[1]),
    pymunk.DampedSpring: lambda h, a, b, x: _cp.cpDampedSpringInit(
        _cast("cpDampedSpring *", h), a, b, x[0], x[1], x[2], x[3], x[4]),
}


def live_objects(space: pymunk.Space, state: tuple) -> tuple[list, list] | None:
    """The space's objects in the snapshot's index order (bodies, static body, shapes,
    constraints) if its bodies and shapes match ``state``'s records one for one (else
    None); a constraint the snapshot has and the space has not (a grasp let go since)
    is None there, and the space's constraints the snapshot has not (a grasp made
    since) are listed apart: ``(objects, left over)``, left over None when the
    constraints matched one for one in order."""
    if (space.threaded or space._handlers or space._locked or space._add_later
            or space._remove_later or space._post_step_callbacks):
        return None
    _values, bodies, static, shapes, constraints = state[:5]
    static_body = space._static_body
    if (static is None) != (static_body is None):
        return None
    live_shapes = space._shapes
    if len(space._bodies) != len(bodies) or len(live_shapes) != len(shapes):
        return None
    objects = [*space._bodies, *(() if static_body is None else (static_body,))]
    for shape, record in zip(live_shapes, shapes):
        if type(shape) is not record[0] or record[0] not in _SHAPE_INIT \
                or shape._body() is not objects[record[1]]:
            return None
    objects += live_shapes
    live = space._constraints
    if len(live) == len(constraints) and all(
            type(c) is r[0] and c._a is objects[r[1]] and c._b is objects[r[2]]
            for c, r in zip(live, constraints)):
        if not all(r[0] in _CONSTRAINT_INIT for r in constraints):
            return None
        return objects + list(live), None
    free: dict = {}  # (class, body a, body b) -> the space's constraints, in its order
    for c in live:
        free.setdefault((type(c), c._a, c._b), []).append(c)
    for cls, a, b, _args, _values in constraints:
        if cls not in _CONSTRAINT_INIT:
            return None
        same = free.get((cls, objects[a], objects[b]))
        objects.append(same.pop(0) if same else None)
    return objects, [c for left in free.values() for c in left]


def reseat(space: pymunk.Space, state: tuple, match: tuple[list, list], space_setters,
           body_setters, shape_setters, constraint_setters) -> list:
    """Put ``space`` (whose objects ``live_objects`` matched to ``state``) in the state
    ``rebuild(state)`` gives a fresh space, object by object, and return its objects in
    the snapshot's order (a constraint missing made anew, one left over taken out);
    the cached arbiters are left to the caller, as in ``rebuild``."""
    objects, left_over = match
    space_values, bodies, static, shapes, constraints = state[:5]
    n_bodies = len(bodies) + (static is not None)
    body_records = [*bodies, static] if static is not None else bodies
    cp_space = space._space
    # a body re-initialised must read as dynamic (cpBodySetMass asserts it): turned so
    # while the space still holds it (moving it between the space's lists, soon freed)
    set_type = _cp.cpBodySetType
    for body in objects[:n_bodies]:
        if _cp.cpBodyGetType(body._body) != _DYNAMIC:
            set_type(body._body, _DYNAMIC)
    set_type(_cp.cpSpaceGetStaticBody(cp_space), _DYNAMIC)  # cpSpaceInit re-inits it
    for constraint in left_over or ():  # out of the space (and of pymunk's list, below)
        _cp.cpSpaceRemoveConstraint(cp_space, constraint._constraint)
    _cp.cpSpaceDestroy(cp_space)  # frees its arrays, indexes, contact cache, arbiters
    _cp.cpSpaceInit(cp_space)

    # the setters unrolled (a loop over them costs about as much as the calls)
    body_init, set_data = _cp.cpBodyInit, _cp.cpBodySetUserData
    set_cog, set_angle = _cp.cpBodySetCenterOfGravity, _cp.cpBodySetAngle
    b0, b1, b2, b3, b4, b5, b6 = body_setters
    for body, (body_type, mass, moment, v) in zip(objects, body_records):
        h = body._body
        if body_type == _DYNAMIC:  # cpBodyNew(mass, moment)
            body_init(h, mass, moment)
        else:  # cpBodyNewKinematic / cpBodyNewStatic: cpBodyNew(0, 0), then the type
            body_init(h, 0.0, 0.0)
            set_type(h, body_type)
        set_cog(h, _ZERO)  # calloc's zero, and the transform made with it
        set_angle(h, 0.0)
        set_data(h, body._data_handle)  # pymunk's handle, as its constructor sets it
        b0(h, v[0])
        b1(h, v[1])
        b2(h, v[2])
        b3(h, v[3])
        b4(h, v[4])
        b5(h, v[5])
        b6(h, v[6])

    shape_set, set_mass, set_density = (_cp.cpShapeSetUserData, _cp.cpShapeSetMass,
                                        _cp.cpShapeSetDensity)
    # the hash id (the last setter) is left out: cpSpaceAddShape overwrites it; and
    # sensor, collision type and filter when they are what the Init just wrote
    s0, s1, s2, s3, s4, s5 = shape_setters[:6]
    for shape, (cls, body, args, v, mass, density) in zip(objects[n_bodies:], shapes):
        h = shape._shape
        _SHAPE_INIT[cls](h, objects[body]._body, args)
        shape_set(h, shape._h)
        if v[:3] != _SHAPE_DEFAULTS:
            s0(h, v[0])
            s1(h, v[1])
            s2(h, v[2])
        s3(h, v[3])
        s4(h, v[4])
        s5(h, v[5])
        if mass > 0:  # as snapshot._make_shape: the mass before the density
            set_mass(h, mass)
        if density > 0:
            set_density(h, density)

    first_constraint = n_bodies + len(shapes)
    c0, c1, c2, c3 = constraint_setters
    for i, (cls, a, b, args, v) in enumerate(constraints, first_constraint):
        constraint = objects[i]
        if constraint is None:  # pymunk's constructor: the ...New that runs this Init
            constraint = objects[i] = cls(objects[a], objects[b], *args)
            h = constraint._constraint
        else:
            h = constraint._constraint
            _CONSTRAINT_INIT[cls](h, objects[a]._body, objects[b]._body, args)
        if v != _CONSTRAINT_DEFAULTS:  # else the Init wrote these very values
            c0(h, v[0])
            c1(h, v[1])
            c2(h, v[2])
            c3(h, v[3])

    for setter, value in zip(space_setters, space_values):
        setter(space, value)
    add_body, add_shape, add_constraint = (_cp.cpSpaceAddBody, _cp.cpSpaceAddShape,
                                           _cp.cpSpaceAddConstraint)
    for body in objects[:n_bodies]:  # the static body last, as rebuild adds it
        add_body(cp_space, body._body)
    for shape in objects[n_bodies:first_constraint]:
        add_shape(cp_space, shape._shape)
    for constraint in objects[first_constraint:]:
        add_constraint(cp_space, constraint._constraint)
    space._removed_shapes.clear()
    if left_over is not None:  # pymunk's list in the snapshot's order, as a new space's
        space._constraints = dict.fromkeys(objects[first_constraint:])
    return objects
