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
``rebuild``, and so does a space whose bodies may sleep (``cpSpaceDestroy`` can miss
some of two or more sleeping components), a body with its own velocity or position
function or a constraint with a pre- or post-solve callback (the ``Init`` would reset
them while pymunk still reports them), and any pymunk but the ones whose Chipmunk
(Munk2D) sources this was checked against (``VERIFIED``). tests/test_reseat.py checks
both ways agree bit for bit.

**Nothing that can raise once the space is torn down.** ``prepare`` does everything
that can fail - reads every handle, unpacks and checks every record, makes the
polygons' vertex arrays and a constraint missing (pymunk's constructor only allocates
and inits it: it reads no body and joins no space, so it can be made first), turns
every value into the exact type its setter takes (a float, a pair of floats, an
integer that fits) - and only then does ``commit`` run: C calls on those values,
which cannot fail. A record that does not unpack raises from ``prepare`` and leaves
the space as it was. A Ctrl+C during ``commit`` is held back (``hold_interrupt``) and
raised once the space is whole again.
"""

from __future__ import annotations

import math
import signal
import threading

import pymunk
from pymunk._chipmunk_cffi import ffi as _ffi
from pymunk._chipmunk_cffi import lib as _cp

# pymunk versions whose Chipmunk (Munk2D) the Init/Destroy sequence above was read
# against; add one only after re-reading its cpSpace/cpBody/cpShape/cpConstraint Init
# and Destroy, cpSpaceAddBody/Shape/Constraint and cpArbiterInit
VERIFIED = {"7.3.1"}
ENABLED = pymunk.version in VERIFIED

_DYNAMIC, _KINEMATIC, _STATIC = pymunk.Body.DYNAMIC, pymunk.Body.KINEMATIC, pymunk.Body.STATIC
_BODY_TYPES = (_DYNAMIC, _KINEMATIC, _STATIC)
_IDENTITY = _ffi.new("cpTransform *", (1.0, 0.0, 0.0, 1.0, 0.0, 0.0))  # a Poly's default
_ZERO = (0.0, 0.0)
_cast = _ffi.cast
_MAIN = threading.main_thread()
# Chipmunk's setters behind pymunk's Space properties (snapshot.SPACE_ATTRS, in order:
# each property is the bare C call), and the C types of their values
_SPACE_SET = (_cp.cpSpaceSetIterations, _cp.cpSpaceSetGravity, _cp.cpSpaceSetDamping,
              _cp.cpSpaceSetIdleSpeedThreshold, _cp.cpSpaceSetSleepTimeThreshold,
              _cp.cpSpaceSetCollisionSlop, _cp.cpSpaceSetCollisionBias,
              _cp.cpSpaceSetCollisionPersistence)
_SPACE_TYPES = ("int", "cpVect", "cpFloat", "cpFloat", "cpFloat", "cpFloat", "cpFloat",
                "cpTimestamp")


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


def _vec(v) -> tuple[float, float]:
    x, y = v
    return (float(x), float(y))


def _fits(ctype: str, value):
    """``value`` as the C type ``ctype`` gives it back (raises if it does not fit)."""
    return _ffi.new(ctype + " *", value)[0]


_INTEGERS: dict = {}  # (collision type, filter) -> the two in their C types


def _integers(collision_type, shape_filter) -> tuple:
    """A shape's collision type and filter, checked and in the types their setters
    take (integers alone: equal keys are the same values; a few per scene)."""
    got = _INTEGERS.get((collision_type, shape_filter))
    if got is None:
        got = (_fits("cpCollisionType", collision_type),
               _ffi.new("cpShapeFilter *", shape_filter))
        if len(_INTEGERS) > 256:
            _INTEGERS.clear()
        _INTEGERS[(collision_type, shape_filter)] = got
    return got


# A shape's init arguments (snapshot's records: pymunk's constructor arguments) in the
# types ``...Init`` takes, and the Init: (kind, typed handle cast, arguments)
def _circle(args):
    radius, (x, y) = args
    return 0, _CIRCLE, (float(radius), (float(x), float(y)))


def _segment(args):
    (ax, ay), (bx, by), radius = args
    return 1, _SEGMENT, ((float(ax), float(ay)), (float(bx), float(by)), float(radius))


def _poly(args):
    verts, transform, radius = args  # pymunk's pickle passes no transform (identity)
    if transform is not None or len(verts) < 1:
        raise ValueError(f"polygon record {args!r}: a transform, or no corners")
    return 2, _POLY, (len(verts), _ffi.new("cpVect[]", [_vec(v) for v in verts]),
                                float(radius))


_CIRCLE, _SEGMENT, _POLY = (_ffi.typeof(t) for t in (
    "cpCircleShape *", "cpSegmentShape *", "cpPolyShape *"))
_SHAPE_ARGS = {pymunk.Circle: _circle, pymunk.Segment: _segment, pymunk.Poly: _poly}
_SHAPE_INIT = (_cp.cpCircleShapeInit, _cp.cpSegmentShapeInit, _cp.cpPolyShapeInit)

_T = {t: _ffi.typeof(t) for t in ("cpPivotJoint *", "cpRotaryLimitJoint *",
                                  "cpDampedRotarySpring *", "cpGearJoint *",
                                  "cpDampedSpring *")}
# A constraint's: (Init, typed handle cast, its arguments in the types the Init takes)
_CONSTRAINT_ARGS = {
    pymunk.PivotJoint: (_cp.cpPivotJointInit, _T["cpPivotJoint *"],
                        lambda x: ((float(x[0][0]), float(x[0][1])),
                                   (float(x[1][0]), float(x[1][1])))),
    pymunk.RotaryLimitJoint: (_cp.cpRotaryLimitJointInit, _T["cpRotaryLimitJoint *"],
                              lambda x: (float(x[0]), float(x[1]))),
    pymunk.DampedRotarySpring: (_cp.cpDampedRotarySpringInit, _T["cpDampedRotarySpring *"],
                                lambda x: (float(x[0]), float(x[1]), float(x[2]))),
    pymunk.GearJoint: (_cp.cpGearJointInit, _T["cpGearJoint *"],
                       lambda x: (float(x[0]), float(x[1]))),
    pymunk.DampedSpring: (_cp.cpDampedSpringInit, _T["cpDampedSpring *"],
                          lambda x: (_vec(x[0]), _vec(x[1]), float(x[2]), float(x[3]),
                                     float(x[4]))),
}


def live_objects(space: pymunk.Space, state: tuple) -> tuple[list, list] | None:
    """The space's objects in the snapshot's index order (bodies, static body, shapes,
    constraints) if its bodies and shapes match ``state``'s records one for one (else
    None); a constraint the snapshot has and the space has not (a grasp let go since)
    is None there, and the space's constraints the snapshot has not (a grasp made
    since) are listed apart: ``(objects, left over)``, left over None when the
    constraints matched one for one in order. None too for what only ``rebuild``
    handles (the module docstring)."""
    if (not ENABLED or space.threaded or space._handlers or space._locked
            or space._add_later or space._remove_later or space._post_step_callbacks
            or math.isfinite(_cp.cpSpaceGetSleepTimeThreshold(space._space))):
        return None
    _values, bodies, static, shapes, constraints = state[:5]
    static_body = space._static_body
    if (static is None) != (static_body is None):
        return None
    live_shapes = space._shapes
    if len(space._bodies) != len(bodies) or len(live_shapes) != len(shapes):
        return None
    objects = [*space._bodies, *(() if static_body is None else (static_body,))]
    for body in objects:
        if body._velocity_func is not None or body._position_func is not None:
            return None
    for shape, record in zip(live_shapes, shapes):
        if type(shape) is not record[0] or record[0] not in _SHAPE_ARGS \
                or shape._body() is not objects[record[1]]:
            return None
    objects += live_shapes
    live = space._constraints
    for c in live:
        if c._pre_solve_func is not None or c._post_solve_func is not None:
            return None
    if len(live) == len(constraints) and all(
            type(c) is r[0] and c._a is objects[r[1]] and c._b is objects[r[2]]
            for c, r in zip(live, constraints)):
        if not all(r[0] in _CONSTRAINT_ARGS for r in constraints):
            return None
        return objects + list(live), None
    free: dict = {}  # (class, body a, body b) -> the space's constraints, in its order
    for c in live:
        free.setdefault((type(c), c._a, c._b), []).append(c)
    for cls, a, b, _args, _values in constraints:
        if cls not in _CONSTRAINT_ARGS:
            return None
        same = free.get((cls, objects[a], objects[b]))
        objects.append(same.pop(0) if same else None)
    return objects, [c for left in free.values() for c in left]


def prepare(space: pymunk.Space, state: tuple, match: tuple[list, list]) -> tuple:
    """Everything the re-seat of ``space`` into ``state`` (``live_objects``' ``match``)
    needs, read, checked and converted while the space is untouched; raises on a record
    that does not unpack. ``commit`` then does the re-seat; the re-seated objects, in
    the snapshot's order, are the plan's first item."""
    objects, left_over = match
    space_values, bodies, static, shapes, constraints = state[:5]
    n_bodies = len(bodies) + (static is not None)
    body_records = [*bodies, static] if static is not None else bodies
    cp_space = space._space
    values = tuple([_fits(t, v) if t in ("int", "cpTimestamp") else
                    _vec(v) if t == "cpVect" else float(v)
                    for t, v in zip(_SPACE_TYPES, space_values, strict=True)])
    body_rows = []
    for body, (body_type, mass, moment, v) in zip(objects[:n_bodies], body_records,
                                                  strict=True):
        if body_type not in _BODY_TYPES:
            raise ValueError(f"body type {body_type!r}")
        (fx, fy), angle, (px, py), (cx, cy), (vx, vy), spin, torque = v  # (inline: a
        body_rows.append((body._body, body_type, float(mass), float(moment),  # call
                          body._data_handle, (float(fx), float(fy)), float(angle),  # per
                          (float(px), float(py)), (float(cx), float(cy)),  # value costs)
                          (float(vx), float(vy)), float(spin), float(torque)))
    first_constraint = n_bodies + len(shapes)
    shape_rows = []
    for shape, (cls, body, args, v, mass, density) in zip(
            objects[n_bodies:first_constraint], shapes, strict=True):
        kind, typed, init_args = _SHAPE_ARGS[cls](args)
        sensor, collision_type, shape_filter, e, u, (sx, sy), _hash_id = v
        if (bool(sensor), collision_type, shape_filter) == _SHAPE_DEFAULTS:
            own = None  # what the Init writes
        else:
            own = (bool(sensor), *_integers(collision_type, shape_filter))
        h = shape._shape
        shape_rows.append((kind, h, _cast(typed, h), objects[body]._body, init_args,
                           shape._h, own, float(e), float(u), (float(sx), float(sy)),
                           float(mass), float(density)))
    constraint_rows = []
    for i, (cls, a, b, args, v) in enumerate(constraints, first_constraint):
        init, typed, convert = _CONSTRAINT_ARGS[cls]
        init_args = convert(args)
        constraint = objects[i]
        if constraint is None:  # pymunk's constructor: the ...New that runs this Init
            constraint = objects[i] = cls(objects[a], objects[b], *init_args)
            init = None
        own = None if v == _CONSTRAINT_DEFAULTS else (  # else the Init writes these
            float(v[0]), float(v[1]), float(v[2]), bool(v[3]))
        h = constraint._constraint
        constraint_rows.append((init, h, _cast(typed, h), objects[a]._body,
                                objects[b]._body, init_args, own))
    # the handles the C calls take, checked (a pointer of the right type, user data
    # a pointer): converting them again cannot fail
    _ffi.new("cpBody *[]", [r[0] for r in body_rows])
    _ffi.new("cpShape *[]", [r[1] for r in shape_rows])
    _ffi.new("cpConstraint *[]", [r[1] for r in constraint_rows])
    _ffi.new("cpDataPointer[]", [r[4] for r in body_rows] + [r[5] for r in shape_rows])
    left = [c._constraint for c in left_over or ()]
    _ffi.new("cpConstraint *[]", left)
    order = None if left_over is None else dict.fromkeys(objects[first_constraint:])
    seat = space.__dict__.get("_puppet_seat", 0)
    space._puppet_seat = seat + 1  # before the seat: one counted too many only re-reads
    return (objects, cp_space, values, body_rows, shape_rows, constraint_rows, left,
            space._removed_shapes, space._constraints, order)


def commit(plan: tuple, body_setters, shape_setters, constraint_setters) -> None:
    """Put the space in the state ``rebuild`` gives a fresh space, object by object,
    from ``prepare``'s plan: C calls on converted values only (nothing here raises);
    the cached arbiters are left to the caller, as in ``rebuild``."""
    (_objects, cp_space, space_values, body_rows, shape_rows, constraint_rows, left,
     removed_shapes, live_constraints, order) = plan
    # a body re-initialised must read as dynamic (cpBodySetMass asserts it): turned so
    # while the space still holds it (moving it between the space's lists, soon freed)
    set_type, get_type = _cp.cpBodySetType, _cp.cpBodyGetType
    for row in body_rows:
        if get_type(row[0]) != _DYNAMIC:
            set_type(row[0], _DYNAMIC)
    set_type(_cp.cpSpaceGetStaticBody(cp_space), _DYNAMIC)  # cpSpaceInit re-inits it
    for h in left:  # out of the space (and of pymunk's list, below)
        _cp.cpSpaceRemoveConstraint(cp_space, h)
    _cp.cpSpaceDestroy(cp_space)  # frees its arrays, indexes, contact cache, arbiters
    _cp.cpSpaceInit(cp_space)

    # the setters unrolled (a loop over them costs about as much as the calls)
    body_init, set_data = _cp.cpBodyInit, _cp.cpBodySetUserData
    set_cog, set_angle = _cp.cpBodySetCenterOfGravity, _cp.cpBodySetAngle
    b0, b1, b2, b3, b4, b5, b6 = body_setters
    for h, body_type, mass, moment, data, f, angle, p, c, v, spin, torque in body_rows:
        if body_type == _DYNAMIC:  # cpBodyNew(mass, moment)
            body_init(h, mass, moment)
        else:  # cpBodyNewKinematic / cpBodyNewStatic: cpBodyNew(0, 0), then the type
            body_init(h, 0.0, 0.0)
            set_type(h, body_type)
        set_cog(h, _ZERO)  # calloc's zero, and the transform made with it
        set_angle(h, 0.0)
        set_data(h, data)  # pymunk's handle, as its constructor sets it
        b0(h, f)
        b1(h, angle)
        b2(h, p)
        b3(h, c)
        b4(h, v)
        b5(h, spin)
        b6(h, torque)

    shape_set, set_mass, set_density = (_cp.cpShapeSetUserData, _cp.cpShapeSetMass,
                                        _cp.cpShapeSetDensity)
    circle_init, segment_init, poly_init = _SHAPE_INIT
    # the hash id (the last setter) is left out: cpSpaceAddShape overwrites it; and
    # sensor, collision type and filter when they are what the Init just wrote
    s0, s1, s2, s3, s4, s5 = shape_setters[:6]
    for kind, h, typed, body, a, data, own, e, u, surface, mass, density in shape_rows:
        if kind == 0:
            circle_init(typed, body, a[0], a[1])
        elif kind == 1:
            segment_init(typed, body, a[0], a[1], a[2])
        else:
            _cp.cpShapeDestroy(h)  # frees the planes of more than 6 corners (Init makes them)
            poly_init(typed, body, a[0], a[1], _IDENTITY[0], a[2])
        shape_set(h, data)
        if own is not None:
            s0(h, own[0])
            s1(h, own[1])
            s2(h, own[2][0])
        s3(h, e)
        s4(h, u)
        s5(h, surface)
        if mass > 0:  # as snapshot._make_shape: the mass before the density
            set_mass(h, mass)
        if density > 0:
            set_density(h, density)

    c0, c1, c2, c3 = constraint_setters
    for init, h, typed, a, b, args, own in constraint_rows:
        if init is not None:  # (a constraint made anew in ``prepare`` is inited)
            init(typed, a, b, *args)
        if own is not None:
            c0(h, own[0])
            c1(h, own[1])
            c2(h, own[2])
            c3(h, own[3])

    for setter, value in zip(_SPACE_SET, space_values):
        setter(cp_space, value)
    add_body, add_shape, add_constraint = (_cp.cpSpaceAddBody, _cp.cpSpaceAddShape,
                                           _cp.cpSpaceAddConstraint)
    for row in body_rows:  # the static body last, as rebuild adds it
        add_body(cp_space, row[0])
    for row in shape_rows:
        add_shape(cp_space, row[1])
    for row in constraint_rows:
        add_constraint(cp_space, row[1])
    removed_shapes.clear()
    if order is not None:  # pymunk's list in the snapshot's order, as a new space's
        live_constraints.clear()  # (the same dict: ``space.constraints`` views stay)
        live_constraints.update(order)


def hold_interrupt():
    """Hold back a Ctrl+C (SIGINT) until ``release_interrupt(held)``, which raises it
    then: a Python signal handler runs between two bytecodes of the main thread, so
    a KeyboardInterrupt could otherwise come between two of ``commit``'s C calls.
    (Blocking the signal with ``pthread_sigmask`` costs less but holds it only from
    the calling thread: the kernel may hand it to another, whose C handler still has
    the main thread run the Python one at once.) Nothing to hold outside the main
    thread (handlers never run there) or when no Python handler is set."""
    if threading.current_thread() is not _MAIN:
        return None
    handler = signal.getsignal(signal.SIGINT)
    if not callable(handler):  # ignored, the default (the process ends), or set in C
        return None
    caught: list = []
    signal.signal(signal.SIGINT, lambda *_: caught.append(True))
    return handler, caught


def release_interrupt(held) -> None:
    if held is not None:
        handler, caught = held
        signal.signal(signal.SIGINT, handler)
        if caught:
            signal.raise_signal(signal.SIGINT)  # the handler held back runs now
