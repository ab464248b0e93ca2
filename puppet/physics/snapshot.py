"""The snapshot format: a pymunk space as plain values, and back, exactly.

pymunk does not keep the solver's warm-start state across a copy or a pickle, and its
generic pickle support made a cat checkpoint cost 2-3 ms. ``capture`` records plain
values instead - per object its class, constructor arguments and settable state, plus
the cached contacts and counters pymunk's pickle keeps - and ``rebuild`` builds a fresh
space from them with the calls, order and values that unpickling would use, so it is
bit-identical to the pickle format it replaced (tests/test_checkpoint_format.py checks
that). Not carried, as nothing here uses them: collision handlers, custom body
velocity/position functions, constraint solve callbacks, extra attributes on pymunk
objects.

The owner of the space (``Simulation``) names the objects it must find again after a
rebuild (the character's bodies, the ground, grasp joints...): ``capture`` keeps them
as indices, ``rebuild`` hands back the new objects under the same names.
"""

from __future__ import annotations

import ctypes
import weakref
from operator import attrgetter

import pymunk
from pymunk._chipmunk_cffi import ffi as _ffi
from pymunk._chipmunk_cffi import lib as _cp  # the C calls pymunk's own pickle uses

from puppet.physics import reseat

_libc_free = ctypes.CDLL(None).free  # Chipmunk allocates with the process's calloc
_libc_free.argtypes, _libc_free.restype = [ctypes.c_void_p], None


def capture(space: pymunk.Space, named: dict[str, list]) -> tuple:
    """Plain values (tuples, numbers, pymunk classes) from which ``rebuild`` makes the
    space pymunk's own unpickling would make; objects are referred to by their index in
    bodies + static body + shapes + constraints. ``named``: lists of objects of the
    space to find again (their indices are kept)."""
    static = space._static_body  # made on first use; pickle leaves out a None
    bodies, shapes, constraints = list(space.bodies), space.shapes, space.constraints
    objects = [*bodies, *(() if static is None else (static,)), *shapes, *constraints]
    index = {o: i for i, o in enumerate(objects)}
    cp_space = space._space
    return (_plain(_SPACE_GET(space)), [_body_record(b) for b in bodies],
            None if static is None else _body_record(static),
            [_shape_record(s, index) for s in shapes],
            [_constraint_record(c, index) for c in constraints],
            (_cp.cpSpaceGetShapeIDCounter(cp_space), _cp.cpSpaceGetTimestamp(cp_space),
             _cp.cpSpaceGetCurrentTimeStep(cp_space)),
            # sorted: the contact cache's own order follows the shapes' addresses
            sorted(_arbiter_record(a, index) for a in space._get_arbiters()),
            {name: [index[o] for o in objs] for name, objs in named.items()})


def rebuild(state: tuple, into: pymunk.Space | None = None) -> tuple[pymunk.Space, dict[str, list]]:
    """A fresh space from ``capture``: the objects made, set up and added in the order
    (and with the values) that unpickling the space with pymunk would use; and the
    named objects' new copies. ``into``: a live space to re-seat in place instead when
    its objects match the snapshot's one for one (``reseat``: the same state, the same
    objects; the named objects are then the ones it held)."""
    (space_values, bodies, static, shapes, constraints, (ids, stamp, dt), arbiters,
     named) = state
    match = None if into is None else reseat.live_objects(into, state)
    if match is None:
        space, objects = _fresh(state)
        made = [_make_arbiter(r, objects) for r in arbiters]
        _seat_arbiters(space, made, (ids, stamp, dt))
    else:  # all that can raise first (reseat.prepare), then only C calls on its values
        space = into
        plan = reseat.prepare(space, state, match)
        objects = plan[0]
        counters = (_fit("cpHashValue", ids), _fit("cpTimestamp", stamp), float(dt))
        made = [_make_arbiter(r, objects) for r in arbiters]  # (they read shapes' bodies)
        held = reseat.hold_interrupt()
        try:
            reseat.commit(plan, _BODY_SET, _SHAPE_SET, _CONSTRAINT_SET)
            _seat_arbiters(space, made, counters)
        finally:
            reseat.release_interrupt(held)
    # the captured step's contacts, worked out when first asked (restored_contacts)
    space._puppet_contacts = [stamp, None, (made, arbiters, objects), None]
    return space, {name: [objects[i] for i in idx] for name, idx in named.items()}


def _fit(ctype: str, value):
    return _ffi.new(ctype + " *", value)[0]


def _seat_arbiters(space: pymunk.Space, made: list, counters: tuple) -> None:
    """The space's counters and the cached arbiters ``made``, as pymunk's unpickling
    leaves them (and the earlier seat's arbiters freed, ``_own_arbiters``)."""
    ids, stamp, dt = counters
    cp_space = space._space
    _cp.cpSpaceSetShapeIDCounter(cp_space, ids)
    _cp.cpSpaceSetTimestamp(cp_space, stamp)
    _cp.cpSpaceSetCurrentTimeStep(cp_space, dt)
    for arb in made:
        _cp.cpSpaceAddCachedArbiter(cp_space, arb)
    _own_arbiters(space, made)


def _fresh(state: tuple) -> tuple[pymunk.Space, list]:
    """A new space and new objects (pymunk's unpickling order), without the arbiters."""
    space_values, bodies, static, shapes, constraints = state[:5]
    objects = [_make_body(r) for r in bodies]
    static_body = None if static is None else _make_body(static)
    if static_body is not None:
        objects.append(static_body)
    first_shape = len(objects)
    objects += [_make_shape(r, objects) for r in shapes]
    first_constraint = len(objects)
    objects += [_make_constraint(r, objects) for r in constraints]
    space = pymunk.Space()
    for setter, value in zip(_SPACE_SET, space_values):
        setter(space, value)
    space.add(*objects[:len(bodies)])
    if static_body is not None:
        space._static_body = static_body
        space._setup_static_body(static_body)
    space.add(*objects[first_shape:first_constraint])
    space.add(*objects[first_constraint:])
    return space, objects


def _own_arbiters(space: pymunk.Space, made: list) -> None:
    """Free the arbiters ``rebuild`` made once nothing can reach them: the ones of an
    earlier seat of a space re-seated in place now (``cpSpaceDestroy`` has dropped the
    space's lists of them and every body was re-initialised), the new ones with the
    space (``_free_with_space``)."""
    held = getattr(space, "_puppet_made", None)
    addresses = [int(_ffi.cast("uintptr_t", arb)) for arb in made]
    if held is not None:
        old = getattr(space, "_puppet_contacts", None)
        if old is not None and old[2] is not None:  # never worked out: now it cannot be
            old[1], old[2], old[3] = {}, None, {}
        freed, held[:] = held[:], addresses  # listed first: never freed twice
        for address in freed:
            _libc_free(address)
    elif made:
        _free_with_space(space, addresses)


def _free_with_space(space: pymunk.Space, addresses: list) -> None:
    """Free the arbiters ``rebuild`` made (``cpArbiterNew``: Chipmunk's calloc, about
    0.2 kB each; ``addresses``, a list kept as ``space._puppet_made``) right after
    Chipmunk frees their space, as pymunk's own unpickling never does (it leaked them:
    115-220 bytes per contact per restore, issue 32).

    Chipmunk never frees an arbiter itself: the ones it makes live in blocks the space
    frees whole, and one it is handed stays in its cache, its list of the step's
    arbiters or its pool (reused for any later pair) until the space goes. Their
    contacts are copied into the space's own buffers at once (pymunk's
    ``cpSpaceAddCachedArbiter`` frees the array it is given), so the arbiter itself is
    all that is left. Freeing it any earlier corrupts the heap: pymunk's destructor
    (``Space.__init__``'s ``spacefree``) removes every shape first, which unthreads
    each cached arbiter from its bodies, writing into it; so does freeing what
    ``arb.contacts`` points to by then (the space's buffer). So the space's handle is
    wrapped: when the Space goes, the wrapper lets go of pymunk's own handle (its
    destructor runs then, the space is freed) and then frees the arbiters listed then
    (a re-seat in place frees its earlier ones itself: ``_own_arbiters``). Were that
    handle still held elsewhere (its destructor not run), they are left, as before."""
    original = space._space
    holder = [original]
    space._puppet_made = addresses

    def release(_ptr) -> None:
        handle = holder.pop()
        gone = weakref.ref(handle)
        del handle  # the last reference: pymunk's spacefree runs here
        if gone() is None:
            for address in addresses:
                _libc_free(address)

    space._space = _ffi.gc(_ffi.cast("cpSpace *", original), release)


def _touching(made, records, objects, stamp) -> tuple[dict, dict]:
    """body -> the world points where it touched something at the captured step; and
    body -> (the other shape, point) of each of them.

    A rebuilt space holds the cached arbiters, but Chipmunk lists a body's contacts
    (``each_arbiter``) only once a step has found them again, so right after a restore
    - every checkpoint, a rewind - every link would read as touching nothing.
    ``restored_contacts`` answers from these until the space steps."""
    out: dict = {}
    shapes: dict = {}
    for arb, record in zip(made, records):
        if arb.stamp != stamp or arb.count <= 0:
            continue  # not touching at the captured step (kept for warm starts)
        pair = (objects[record[0]], objects[record[1]])
        for side, shape in enumerate(pair):
            body = shape.body
            if body is None or body.body_type != pymunk.Body.DYNAMIC:
                continue
            cx, cy = body.local_to_world(body.center_of_gravity)
            points = out.setdefault(body, [])
            others = shapes.setdefault(body, [])
            for i in range(arb.count):
                r = arb.contacts[i].r1 if side == 0 else arb.contacts[i].r2
                points.append((cx + r.x, cy + r.y))
                others.append((pair[1 - side], points[-1]))
    return out, shapes


def restored_contacts(body) -> list | None:
    """The world points where ``body`` touched something, as restored with its space,
    while that space has not stepped since (None once it has: ask the arbiters)."""
    restored = restored_touching(body._space())  # (body.space, without its assert)
    return None if restored is None else restored.get(body, [])


def restored_touching(space) -> dict | None:
    """body -> the world points where it touched something, as restored with ``space``,
    while it has not stepped since (None once it has)."""
    got = getattr(space, "_puppet_contacts", None)
    if got is None or _cp.cpSpaceGetTimestamp(space._space) != got[0]:
        return None
    return touching(got)


def touching(got: list) -> dict:
    """body -> points of a space's ``_puppet_contacts`` (worked out once)."""
    if got[1] is None:
        made, records, objects = got[2]
        (got[1], got[3]), got[2] = _touching(made, records, objects, got[0]), None
    return got[1]


def touching_shapes(got: list) -> dict:
    """body -> (the shape it touched, world point) of a space's ``_puppet_contacts``."""
    touching(got)
    return got[3]


# -- records ---------------------------------------------------------------------------
# Attributes in the order pymunk's pickle support sets them when it unpickles (its
# ``_pickle_attrs_general`` lists; the order matters: a body's position is set before its
# centre of gravity, a shape's mass before its density). tests/test_checkpoint_format.py
# checks them against pymunk's lists.
SPACE_ATTRS = ("iterations", "gravity", "damping", "idle_speed_threshold",
               "sleep_time_threshold", "collision_slop", "collision_bias",
               "collision_persistence")  # and "threads", a no-op on an unthreaded space
BODY_ATTRS = ("force", "angle", "position", "center_of_gravity", "velocity",
              "angular_velocity", "torque")
SHAPE_ATTRS = ("sensor", "collision_type", "filter", "elasticity", "friction",
               "surface_velocity", "_hashid")
CONSTRAINT_ATTRS = ("max_force", "error_bias", "max_bias", "collide_bodies")
_CONTACT_FIELDS = ("nMass", "tMass", "bounce", "jnAcc", "jtAcc", "jBias", "bias", "hash")


def _setters(cls, names):
    # the property setters themselves: assigning through a pymunk instance also runs
    # its attribute-typing hook, which costs more than the setter
    return tuple(getattr(cls, n).fset for n in names)


_SPACE_GET, _SPACE_SET = attrgetter(*SPACE_ATTRS), _setters(pymunk.Space, SPACE_ATTRS)
# Chipmunk's setters for the attributes above, in their order (tests check the names)
_BODY_SET = (_cp.cpBodySetForce, _cp.cpBodySetAngle, _cp.cpBodySetPosition,
             _cp.cpBodySetCenterOfGravity, _cp.cpBodySetVelocity,
             _cp.cpBodySetAngularVelocity, _cp.cpBodySetTorque)
_SHAPE_SET = (_cp.cpShapeSetSensor, _cp.cpShapeSetCollisionType, _cp.cpShapeSetFilter,
              _cp.cpShapeSetElasticity, _cp.cpShapeSetFriction, _cp.cpShapeSetSurfaceVelocity,
              _cp.cpShapeSetHashID)
_CONSTRAINT_SET = (_cp.cpConstraintSetMaxForce, _cp.cpConstraintSetErrorBias,
                   _cp.cpConstraintSetMaxBias, _cp.cpConstraintSetCollideBodies)
_init_getters: dict[type, object] = {}


def _xy(v) -> tuple:
    return (v.x, v.y)


# The constructor arguments of the classes a character and its props are made of, read
# through Chipmunk (the getters behind the properties pymunk's pickle reads); any other
# class goes through its properties (``_init_args``).
_FAST_INIT = {
    pymunk.Circle: lambda h: (_cp.cpCircleShapeGetRadius(h), _xy(_cp.cpCircleShapeGetOffset(h))),
    pymunk.Segment: lambda h: (_xy(_cp.cpSegmentShapeGetA(h)), _xy(_cp.cpSegmentShapeGetB(h)),
                               _cp.cpSegmentShapeGetRadius(h)),
    pymunk.PivotJoint: lambda h: (_xy(_cp.cpPivotJointGetAnchorA(h)),
                                  _xy(_cp.cpPivotJointGetAnchorB(h))),
    pymunk.RotaryLimitJoint: lambda h: (_cp.cpRotaryLimitJointGetMin(h),
                                        _cp.cpRotaryLimitJointGetMax(h)),
    pymunk.DampedRotarySpring: lambda h: (_cp.cpDampedRotarySpringGetRestAngle(h),
                                          _cp.cpDampedRotarySpringGetStiffness(h),
                                          _cp.cpDampedRotarySpringGetDamping(h)),
    pymunk.GearJoint: lambda h: (_cp.cpGearJointGetPhase(h), _cp.cpGearJointGetRatio(h)),
    pymunk.Poly: lambda h: (tuple([_xy(_cp.cpPolyShapeGetVert(h, i))
                                   for i in range(_cp.cpPolyShapeGetCount(h))]),
                            None, _cp.cpPolyShapeGetRadius(h)),
}


def _init_args(obj, skip: int) -> tuple:
    """The constructor arguments pymunk's pickle would pass (its ``_pickle_attrs_init``,
    after the ``skip`` body arguments)."""
    cls = type(obj)
    fast = _FAST_INIT.get(cls)
    if fast is not None:
        return fast(obj._shape if skip == 1 else obj._constraint)
    get = _init_getters.get(cls)
    if get is None:
        names = cls._pickle_attrs_init[skip:]
        one = attrgetter(*names)
        get = _init_getters[cls] = one if len(names) > 1 else (lambda o: (one(o),))
    return _plain(get(obj))


def _plain(values) -> tuple:
    """pymunk's Vec2d and ShapeFilter are named tuples, slow to pickle: plain tuples."""
    return tuple([(*v,) if isinstance(v, tuple) else v for v in values])


# The records read and write through Chipmunk's own getters and setters (the calls
# pymunk's properties make, in the order of the attribute lists below): a property adds a
# Python call and a Vec2d per value, a third of a biped checkpoint's time.
_B_TYPE, _B_MASS, _B_MOMENT = _cp.cpBodyGetType, _cp.cpBodyGetMass, _cp.cpBodyGetMoment
_B_FORCE, _B_ANGLE, _B_POS = _cp.cpBodyGetForce, _cp.cpBodyGetAngle, _cp.cpBodyGetPosition
_B_COG, _B_VEL = _cp.cpBodyGetCenterOfGravity, _cp.cpBodyGetVelocity
_B_SPIN, _B_TORQUE = _cp.cpBodyGetAngularVelocity, _cp.cpBodyGetTorque


def _body_record(b: pymunk.Body) -> tuple:
    h = b._body
    f, p, c, v = _B_FORCE(h), _B_POS(h), _B_COG(h), _B_VEL(h)
    return (_B_TYPE(h), _B_MASS(h), _B_MOMENT(h),
            ((f.x, f.y), _B_ANGLE(h), (p.x, p.y), (c.x, c.y), (v.x, v.y), _B_SPIN(h),
             _B_TORQUE(h)))


def _make_body(record) -> pymunk.Body:
    body_type, mass, moment, values = record
    body = pymunk.Body(mass, moment, body_type)
    h = body._body
    for setter, value in zip(_BODY_SET, values):
        setter(h, value)
    return body


_S_FILTER, _S_SURFACE, _S_SENSOR = (_cp.cpShapeGetFilter, _cp.cpShapeGetSurfaceVelocity,
                                    _cp.cpShapeGetSensor)
_S_TYPE, _S_E, _S_U, _S_ID = (_cp.cpShapeGetCollisionType, _cp.cpShapeGetElasticity,
                              _cp.cpShapeGetFriction, _cp.cpShapeGetHashID)
_S_MASS, _S_DENSITY = _cp.cpShapeGetMass, _cp.cpShapeGetDensity


def _shape_record(s: pymunk.Shape, index: dict) -> tuple:
    h = s._shape
    f, sv = _S_FILTER(h), _S_SURFACE(h)
    cls = type(s)
    fast = _FAST_INIT.get(cls)
    return (cls, index[s._body()], _init_args(s, 1) if fast is None else fast(h),
            (bool(_S_SENSOR(h)), _S_TYPE(h), (f.group, f.categories, f.mask), _S_E(h),
             _S_U(h), (sv.x, sv.y), _S_ID(h)),
            _S_MASS(h), _S_DENSITY(h))


def _make_shape(record, objects: list) -> pymunk.Shape:
    cls, body, args, values, mass, density = record
    shape = cls(objects[body], *args)
    h = shape._shape
    for setter, value in zip(_SHAPE_SET, values):
        setter(h, value)
    if mass > 0:  # the mass before the density, as pymunk's pickle
        _cp.cpShapeSetMass(h, mass)
    if density > 0:
        _cp.cpShapeSetDensity(h, density)
    return shape


_C_MAX_FORCE, _C_ERROR_BIAS = _cp.cpConstraintGetMaxForce, _cp.cpConstraintGetErrorBias
_C_MAX_BIAS, _C_COLLIDE = _cp.cpConstraintGetMaxBias, _cp.cpConstraintGetCollideBodies


def _constraint_record(c: pymunk.Constraint, index: dict) -> tuple:
    h = c._constraint
    cls = type(c)
    fast = _FAST_INIT.get(cls)
    return (cls, index[c._a], index[c._b], _init_args(c, 2) if fast is None else fast(h),
            (_C_MAX_FORCE(h), _C_ERROR_BIAS(h), _C_MAX_BIAS(h), _C_COLLIDE(h)))


def _make_constraint(record, objects: list) -> pymunk.Constraint:
    cls, a, b, args, values = record
    constraint = cls(objects[a], objects[b], *args)
    h = constraint._constraint
    for setter, value in zip(_CONSTRAINT_SET, values):
        setter(h, value)
    return constraint


def _arbiter_record(arb, index: dict) -> tuple:
    """A cached arbiter (its contacts' accumulated impulses), as pymunk's pickle keeps it."""
    shape = pymunk.Shape._from_cp_shape
    contacts = tuple((c.r1.x, c.r1.y, c.r2.x, c.r2.y, *(getattr(c, f) for f in _CONTACT_FIELDS))
                     for c in (arb.contacts[i] for i in range(arb.count)))
    return (index[shape(arb.a)], index[shape(arb.b)], arb.e, arb.u,
            (arb.surface_vr.x, arb.surface_vr.y), arb.count, contacts, (arb.n.x, arb.n.y),
            arb.swapped, arb.stamp, arb.state)


def _make_arbiter(record, objects: list):
    a, b, e, u, surface_vr, count, contacts, n, swapped, stamp, state = record
    arb = _cp.cpArbiterNew(objects[a]._shape, objects[b]._shape)
    arb.e, arb.u, arb.surface_vr, arb.count = e, u, surface_vr, count
    array = _cp.cpContactArrAlloc(len(contacts))
    for i, values in enumerate(contacts):
        c = array[i]
        c.r1.x, c.r1.y, c.r2.x, c.r2.y = values[:4]
        for field, value in zip(_CONTACT_FIELDS, values[4:]):
            setattr(c, field, value)
    arb.contacts, arb.n, arb.swapped, arb.stamp, arb.state = array, n, swapped, stamp, state
    return arb

