"""The simulation: one character in one scene, stepped at a fixed time step.

Fixed step, no wall clock: the same inputs at the same step indices give the same
bits. pymunk does not keep the solver's warm-start state across a copy or a pickle
(constraints' accumulated impulses, the spatial index's pair cache), so a restored
copy drifts from the original; two restores of one snapshot agree exactly. Callers
that need "restored == never restored" (checkpoints) re-seat the live run on a
restored copy at the moment they snapshot: see ``checkpoint()``. Sessions do so at
step 0, so every run's bits depend on exactly how ``restore`` builds the space.

Snapshots are not pickled pymunk objects: pymunk's generic pickle support made a cat
checkpoint cost 2-3 ms. ``snapshot`` records plain values instead - per object its
class, constructor arguments and settable state, plus the cached contacts and
counters pymunk's pickle keeps - and ``restore`` builds a fresh space from them with
the calls, order and values that unpickling would use, so it is bit-identical to the
pickle format it replaced (tests/test_checkpoint_format.py checks that). Not carried,
as nothing here uses them: collision handlers, custom body velocity/position
functions, constraint solve callbacks, extra attributes on pymunk objects.
"""

from __future__ import annotations

import hashlib
import math
import pickle
import struct
from operator import attrgetter

import pymunk
from pymunk._chipmunk_cffi import lib as _cp  # the C calls pymunk's own pickle uses

from puppet.data.characters import CharacterSpec
from puppet.data.scenes import SceneSpec
from puppet.physics.character import Character
from puppet.physics.scene import build_ground

DEFAULT_DT = 1.0 / 480.0  # s; small enough for stiff hopping servos on light links
SOLVER_ITERATIONS = 20
COLLISION_SLOP = 0.0005  # m; pymunk's default (0.1) assumes pixel units
DRAG_STIFFNESS_PER_KG = 200.0  # N/m per kg of character, for Ctrl+drag
MAX_SPEED = 200.0  # m/s; beyond this the state has blown up


class Simulation:
    def __init__(self, character: CharacterSpec, scene: SceneSpec, dt: float = DEFAULT_DT):
        self.character_spec = character
        self.scene_spec = scene
        self.dt = dt
        self.steps = 0
        self.space = pymunk.Space()
        self.space.gravity = scene.gravity
        self.space.iterations = SOLVER_ITERATIONS
        self.space.collision_slop = COLLISION_SLOP
        self.ground = build_ground(scene, self.space)
        self.character = Character(character)
        self.character.add_to(self.space)
        self._place_at_start()
        self.drag_body = pymunk.Body(body_type=pymunk.Body.KINEMATIC)
        self.drag_spring: pymunk.DampedSpring | None = None
        self.space.add(self.drag_body)

    def _place_at_start(self) -> None:
        c, start = self.character, self.scene_spec.start
        angle = math.radians(self.character_spec.start.angle)
        c.place(start.x, 0.0, angle, c.start_joint_angles())
        ground = self.scene_spec.ground_height(start.x)
        floor = start.y if ground is None else max(ground, start.y)
        lift = floor + self.character_spec.start.lift + 0.002 - c.lowest_point()
        c.place(start.x, lift, angle, c.start_joint_angles())

    # -- time --------------------------------------------------------------------
    @property
    def time(self) -> float:
        return self.steps * self.dt

    def step(self, n: int = 1) -> None:
        space_step, dt = self.space.step, self.dt
        for _ in range(n):
            space_step(dt)
        self.steps += n

    # -- Ctrl+drag: a spring from a point on a body to a target (the viewer convention)
    def start_drag(self, link: str, local_point: tuple[float, float],
                   target: tuple[float, float]) -> None:
        self.end_drag()
        body = self.character.bodies[link]
        k = DRAG_STIFFNESS_PER_KG * self.character.mass
        damping = 2.0 * math.sqrt(k * self.character.mass) * 0.3
        self.drag_body.position = target
        self.drag_spring = pymunk.DampedSpring(self.drag_body, body, (0, 0), local_point,
                                               0.0, k, damping)
        self.space.add(self.drag_spring)

    def move_drag(self, target: tuple[float, float]) -> None:
        self.drag_body.position = target

    def end_drag(self) -> None:
        if self.drag_spring is not None:
            self.space.remove(self.drag_spring)
            self.drag_spring = None

    # -- physical parameters ---------------------------------------------------------
    @property
    def gravity(self) -> tuple[float, float]:
        return tuple(self.space.gravity)

    @gravity.setter
    def gravity(self, value: tuple[float, float]) -> None:
        self.space.gravity = value

    # -- state -------------------------------------------------------------------
    def snapshot(self) -> bytes:
        """The whole physical state as self-contained bytes (restore with ``restore``)."""
        return pickle.dumps(self._state(), protocol=pickle.HIGHEST_PROTOCOL)

    def restore(self, data: bytes) -> None:
        """Back to a ``snapshot``, on a fresh space (the objects callers held are replaced)."""
        self._rebuild(pickle.loads(data))

    def checkpoint(self) -> bytes:
        """Snapshot, and continue from a restored copy so that any later restore of
        this snapshot replays bit-identically to the run that never restored."""
        state = self._state()
        data = pickle.dumps(state, protocol=pickle.HIGHEST_PROTOCOL)
        self._rebuild(state)  # plain values: the same as ``pickle.loads(data)``
        return data

    def _state(self) -> tuple:
        """Plain values (tuples, numbers, pymunk classes) from which ``_rebuild`` makes
        the space pymunk's own unpickling would make; objects are referred to by their
        index in bodies + static body + shapes + constraints."""
        space = self.space
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
                ([index[o] for o in self.character.state_objects()],
                 [index[g] for g in self.ground], index[self.drag_body],
                 None if self.drag_spring is None else index[self.drag_spring]),
                self.steps)

    def _rebuild(self, state: tuple) -> None:
        """A fresh space from ``_state``: the objects made, set up and added in the order
        (and with the values) that unpickling the space with pymunk would use."""
        (space_values, bodies, static, shapes, constraints, (ids, stamp, dt), arbiters,
         (character, ground, drag_body, drag_spring), steps) = state
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
        cp_space = space._space
        _cp.cpSpaceSetShapeIDCounter(cp_space, ids)
        _cp.cpSpaceSetTimestamp(cp_space, stamp)
        _cp.cpSpaceSetCurrentTimeStep(cp_space, dt)
        made = [_make_arbiter(r, objects) for r in arbiters]
        for arb in made:
            _cp.cpSpaceAddCachedArbiter(cp_space, arb)
        if made:  # freed after the space itself (pymunk's unpickling leaks them)
            space._puppet_arbiters = _CachedArbiters(made)
        self.space = space
        self.character.bind([objects[i] for i in character])
        self.ground = [objects[i] for i in ground]
        self.drag_body = objects[drag_body]
        self.drag_spring = None if drag_spring is None else objects[drag_spring]
        self.steps = steps

    def state_vector(self) -> list[float]:
        """Position, angle, velocity and angular velocity of every body, in link order."""
        out: list[float] = []
        for name in self.character.link_order:
            b = self.character.bodies[name]
            out += (b.position.x, b.position.y, b.angle, b.velocity.x, b.velocity.y,
                    b.angular_velocity)
        return out

    def state_hash(self) -> str:
        vec = self.state_vector()
        return hashlib.sha256(struct.pack(f"<{len(vec)}d", *vec)).hexdigest()[:16]

    def blown_up(self) -> bool:
        """NaN or runaway velocity anywhere (the state can no longer be trusted)."""
        for b in self.character.bodies.values():
            vx, vy = b.velocity
            w = b.angular_velocity
            x, y = b.position
            if not all(math.isfinite(v) for v in (vx, vy, w, x, y, b.angle)):
                return True
            if vx * vx + vy * vy > MAX_SPEED ** 2 or abs(w) > 50 * MAX_SPEED:
                return True
        return False


# -- the snapshot format ------------------------------------------------------------------
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
_BODY_GET, _BODY_SET = attrgetter(*BODY_ATTRS), _setters(pymunk.Body, BODY_ATTRS)
_SHAPE_GET, _SHAPE_SET = attrgetter(*SHAPE_ATTRS), _setters(pymunk.Shape, SHAPE_ATTRS)
_CONSTRAINT_GET = attrgetter(*CONSTRAINT_ATTRS)
_CONSTRAINT_SET = _setters(pymunk.Constraint, CONSTRAINT_ATTRS)
_SET_MASS, _SET_DENSITY = pymunk.Shape.mass.fset, pymunk.Shape.density.fset
_init_getters: dict[type, object] = {}


def _init_args(obj, skip: int) -> tuple:
    """The constructor arguments pymunk's pickle would pass (its ``_pickle_attrs_init``,
    after the ``skip`` body arguments)."""
    cls = type(obj)
    if cls is pymunk.Poly:
        return (tuple(map(tuple, obj.get_vertices())), None, obj.radius)
    get = _init_getters.get(cls)
    if get is None:
        names = cls._pickle_attrs_init[skip:]
        one = attrgetter(*names)
        get = _init_getters[cls] = one if len(names) > 1 else (lambda o: (one(o),))
    return _plain(get(obj))


def _plain(values) -> tuple:
    """pymunk's Vec2d and ShapeFilter are named tuples, slow to pickle: plain tuples."""
    return tuple([(*v,) if isinstance(v, tuple) else v for v in values])


def _body_record(b: pymunk.Body) -> tuple:
    return (b.body_type, b.mass, b.moment, _plain(_BODY_GET(b)))


def _make_body(record) -> pymunk.Body:
    body_type, mass, moment, values = record
    body = pymunk.Body(mass, moment, body_type)
    for setter, value in zip(_BODY_SET, values):
        setter(body, value)
    return body


def _shape_record(s: pymunk.Shape, index: dict) -> tuple:
    return (type(s), index[s.body], _init_args(s, 1), _plain(_SHAPE_GET(s)), s.mass, s.density)


def _make_shape(record, objects: list) -> pymunk.Shape:
    cls, body, args, values, mass, density = record
    shape = cls(objects[body], *args)
    for setter, value in zip(_SHAPE_SET, values):
        setter(shape, value)
    if mass > 0:
        _SET_MASS(shape, mass)
    if density > 0:
        _SET_DENSITY(shape, density)
    return shape


def _constraint_record(c: pymunk.Constraint, index: dict) -> tuple:
    return (type(c), index[c.a], index[c.b], _init_args(c, 2), _CONSTRAINT_GET(c))


def _make_constraint(record, objects: list) -> pymunk.Constraint:
    cls, a, b, args, values = record
    constraint = cls(objects[a], objects[b], *args)
    for setter, value in zip(_CONSTRAINT_SET, values):
        setter(constraint, value)
    return constraint


def _arbiter_record(arb, index: dict) -> tuple:
    """A cached arbiter (its contacts' accumulated impulses), as pymunk's pickle keeps it."""
    shape = pymunk.Shape._from_cp_shape
    contacts = tuple((c.r1.x, c.r1.y, c.r2.x, c.r2.y, *(getattr(c, f) for f in _CONTACT_FIELDS))
                     for c in (arb.contacts[i] for i in range(arb.count)))
    return (index[shape(arb.a)], index[shape(arb.b)], arb.e, arb.u,
            (arb.surface_vr.x, arb.surface_vr.y), arb.count, contacts, (arb.n.x, arb.n.y),
            arb.swapped, arb.stamp, arb.state)


class _CachedArbiters:
    """Frees the arbiters that ``_rebuild`` allocates with ``cpArbiterNew`` (as pymunk's
    unpickling does): Chipmunk never frees them (they end in the space's arbiter pool;
    their contact arrays it frees itself), so each restore leaked about 0.2 kB per
    cached arbiter. They must outlive the C space: this object is set on the pymunk
    Space after its ``_space`` (an object's attributes are released in the order they
    were set), so it goes only after ``cpSpaceFree`` has run."""

    __slots__ = ("pointers",)

    def __init__(self, arbiters):
        self.pointers = list(arbiters)

    def __del__(self):
        free = _libc_free()
        for arb in self.pointers:
            free(arb)
        self.pointers = []


def _libc_free():
    global _FREE
    if _FREE is None:
        import cffi

        ffi = cffi.FFI()
        ffi.cdef("void free(void *);")
        c_free = ffi.dlopen(None).free
        _FREE = lambda ptr: c_free(ffi.cast("void *", int(pymunk.ffi.cast("uintptr_t", ptr))))
    return _FREE


_FREE = None


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

