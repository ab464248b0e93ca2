"""Build a character's pymunk bodies, shapes, hinges and PD servos from its spec.

Every body's local frame is the character's model frame placed at the body's pose,
so shapes and anchors are written once, in model coordinates, and forward kinematics
is ``world = R(body.angle) * model + body.position``.
"""

from __future__ import annotations

import math

import pymunk
from pymunk._chipmunk_cffi import ffi as _ffi
from pymunk._chipmunk_cffi import lib as _cp

from puppet.data.characters import CharacterSpec, LinkSpec
from puppet.physics import kernel as _kernel
from puppet.physics.body_state import BodyReader
from puppet.physics.servo import PDServo
from puppet.physics.snapshot import restored_contacts, restored_touching

# Scratch shared by the callbacks below: module globals, so single-threaded (the
# physics and its sensors run on one thread).
_TOUCHING = [0]  # set by _count_arbiter: the body has an arbiter (it touches something)


def _count_arbiter(body, arbiter, data) -> None:
    """Chipmunk's arbiter iterator, made once: a third of the cost of pymunk's
    ``each_arbiter`` (which wraps every arbiter in an object) for a contact sensor read
    at every control step."""
    _TOUCHING[0] = 1


_XS: list[float] = []  # filled by _contact_xs: the contact points' x (support_extent)
_point_set = _cp.cpArbiterGetContactPointSet  # what arbiter.contact_point_set reads


def _contact_xs(body, arbiter, data) -> None:
    """Each contact point's point_a.x, as pymunk's ``each_arbiter`` would hand them
    (Chipmunk orders the arbiter for the body during the call, as for pymunk's)."""
    got = _point_set(arbiter)
    for i in range(got.count):
        _XS.append(got.points[i].pointA.x)


def _arbiter_callbacks(make=_ffi.callback):
    """The two iterators as C callbacks, or None where they cannot be made: an old-style
    cffi callback needs write+execute memory, which some systems forbid (macOS arm64
    hardened runtime, SELinux deny_execmem: MemoryError "Cannot allocate write+execute
    memory"). Then the sensors go through pymunk's ``each_arbiter`` (its callbacks are
    compiled ones): the same arbiters in the same order, the same readings."""
    try:
        kind = make("cpBodyArbiterIteratorFunc")
        return kind(_count_arbiter), kind(_contact_xs)
    except (MemoryError, SystemError, RuntimeError, _ffi.error):
        return None


_COUNT, _COLLECT = _arbiter_callbacks() or (None, None)


def _touched(arbiter) -> None:  # (without C callbacks: for each_arbiter)
    _TOUCHING[0] = 1


def _arbiter_xs(arbiter) -> None:  # (without C callbacks: for each_arbiter)
    for point in arbiter.contact_point_set.points:
        _XS.append(point.point_a.x)


def _rot(p, angle):
    c, s = math.cos(angle), math.sin(angle)
    return (c * p[0] - s * p[1], s * p[0] + c * p[1])


def _make_shapes(body: pymunk.Body, link: LinkSpec) -> list[pymunk.Shape]:
    shapes: list[pymunk.Shape] = []
    for s in link.shapes:
        if s.type == "box":
            w, h = s.size
            a = math.radians(s.angle)
            corners = [_rot(p, a) for p in ((-w / 2, -h / 2), (w / 2, -h / 2),
                                             (w / 2, h / 2), (-w / 2, h / 2))]
            verts = [(x + s.center[0], y + s.center[1]) for x, y in corners]
            shapes.append(pymunk.Poly(body, verts, radius=s.radius))
        elif s.type == "circle":
            shapes.append(pymunk.Circle(body, s.radius, s.center))
        elif s.type == "segment":
            shapes.append(pymunk.Segment(body, s.a, s.b, s.radius))
        else:
            shapes.append(pymunk.Poly(body, [tuple(p) for p in s.points], radius=s.radius))
    areas = [max(_area(sh), 1e-9) for sh in shapes]
    total = sum(areas)
    for shape, area in zip(shapes, areas):
        if link.inertia is None:  # else the body carries the link's mass properties
            shape.mass = link.mass * area / total  # spread the link's mass by area
        shape.friction = link.friction
        shape.elasticity = link.elasticity
    return shapes


def _mass_shape(body: pymunk.Body, link: LinkSpec, group: int) -> pymunk.Circle:
    """The link's given mass properties (an anthropometric table's centre of mass and
    inertia) as a solid disc of the link's mass at its centre of mass, radius chosen
    so that its moment (m r^2 / 2) is the inertia. pymunk sums the body's mass,
    centre of gravity and moment from its shapes; the collision shapes are massless,
    and the disc collides with nothing (no category, no mask), so it never touches
    the ground, is never picked, and is never drawn. (Setting a body's
    centre_of_gravity directly would not survive a snapshot: pymunk's pickle order,
    which snapshots follow, sets it after the position and so moves the body.)"""
    disc = pymunk.Circle(body, math.sqrt(2.0 * link.inertia / link.mass), link.center_of_mass)
    disc.mass = link.mass
    disc.sensor = True
    disc.filter = pymunk.ShapeFilter(group=group, categories=0, mask=0)
    return disc


def _area(shape: pymunk.Shape) -> float:
    if isinstance(shape, pymunk.Circle):
        return math.pi * shape.radius ** 2
    if isinstance(shape, pymunk.Segment):
        r = shape.radius
        return 2 * r * (shape.b - shape.a).length + math.pi * r * r
    return shape.area


class Character:
    """A character in a space: bodies by link name, servos by joint name, and sensors."""

    def __init__(self, spec: CharacterSpec, group: int = 1):
        self.spec = spec
        self.root = spec.root  # the root link's name (read every frame)
        self.group = group
        self.bodies: dict[str, pymunk.Body] = {}
        self.shapes: dict[str, list[pymunk.Shape]] = {}
        self.hinges: list[pymunk.Constraint] = []
        self.servos: dict[str, PDServo] = {}
        # links with given mass properties: their mass disc (not a collision shape)
        self.mass_shapes: dict[str, pymunk.Circle] = {}
        no_self_collision = pymunk.ShapeFilter(group=group)
        for link in spec.links:
            body = pymunk.Body()
            shapes = _make_shapes(body, link)
            for shape in shapes:
                shape.filter = no_self_collision
            self.bodies[link.name] = body
            self.shapes[link.name] = shapes
            if link.inertia is not None:
                self.mass_shapes[link.name] = _mass_shape(body, link, group)
        start = {j.name: math.radians(v) for j, v in
                 ((spec.joint(n), v) for n, v in spec.start.joints.items())}
        for joint in spec.joints:
            parent, child = self.bodies[joint.parent], self.bodies[joint.child]
            self.hinges.append(pymunk.PivotJoint(parent, child, joint.anchor, joint.anchor))
            if joint.limits is not None:
                lo, hi = (math.radians(v) for v in joint.limits)
                self.hinges.append(pymunk.RotaryLimitJoint(parent, child, lo, hi))
            if joint.pd is not None:
                pd = joint.pd
                self.servos[joint.name] = PDServo(joint.name, parent, child,
                                                  start.get(joint.name, 0.0),
                                                  pd.stiffness, pd.damping, pd.max_torque)
        self.link_order = [link.name for link in spec.links]
        self.mass = sum(link.mass for link in spec.links)
        self._memo: dict | None = None  # whole-body sensors, while ``sample`` reads

    def add_to(self, space: pymunk.Space) -> None:
        for name in self.link_order:
            space.add(self.bodies[name], *self.shapes[name])
            if name in self.mass_shapes:
                space.add(self.mass_shapes[name])
        space.add(*self.hinges, *(s.spring for s in self.servos.values()))

    def set_step(self, dt: float) -> None:
        """The step (s) the space is stepped with: the servos' damping is meant as at
        1/480 s and handed to the engine for this one (puppet/physics/servo.py)."""
        for servo in self.servos.values():
            servo.set_step(dt)

    def place(self, x: float, y: float, angle: float, joint_angles: dict[str, float]) -> None:
        """Put the model origin at (x, y), root at ``angle``; joints at angles (radians)."""
        angles = {self.spec.root: angle}
        root = self.bodies[self.spec.root]
        root.position = (x, y)
        root.angle = angle
        done = {self.spec.root}
        pending = list(self.spec.joints)
        while pending:
            for joint in list(pending):
                if joint.parent not in done:
                    continue
                parent = self.bodies[joint.parent]
                child = self.bodies[joint.child]
                a = angles[joint.parent] + joint_angles.get(joint.name, 0.0)
                angles[joint.child] = a
                anchor_world = parent.local_to_world(joint.anchor)
                off = _rot(joint.anchor, a)
                child.angle = a
                child.position = (anchor_world[0] - off[0], anchor_world[1] - off[1])
                done.add(joint.child)
                pending.remove(joint)
        for body in self.bodies.values():
            body.velocity = (0.0, 0.0)
            body.angular_velocity = 0.0

    def start_joint_angles(self) -> dict[str, float]:
        return {n: math.radians(v) for n, v in self.spec.start.joints.items()}

    def lowest_point(self) -> float:
        """Lowest y of any shape (m), for placing the character on the ground."""
        return min(shape.cache_bb().bottom for shapes in self.shapes.values() for shape in shapes)

    # -- restoring from a snapshot ------------------------------------------------
    def state_objects(self) -> list:
        """Every pymunk object we hold, in a fixed order: a flat list, which a snapshot
        keeps as indices into its space (``bind`` takes the restored copies back)."""
        out: list = [self.bodies[n] for n in self.link_order]
        for n in self.link_order:
            out += self.shapes[n]
        out += self.mass_shapes.values()
        out += self.hinges
        out += [s.spring for s in self.servos.values()]
        return out

    def bind(self, objects: list) -> None:
        """Hold, and point the servos at, restored copies of ``state_objects()``."""
        it = iter(objects)
        self.bodies = {n: next(it) for n in self.link_order}
        self.shapes = {n: [next(it) for _ in self.shapes[n]] for n in self.link_order}
        self.mass_shapes = {n: next(it) for n in self.mass_shapes}
        self.hinges = [next(it) for _ in self.hinges]
        for servo in self.servos.values():
            servo.bind(next(it))

    # -- sensors (named after what they measure; also used by conditions and checks)
    def sample(self, readers, values: dict) -> None:
        """``values[name] = read()`` for each (name, read) of ``readers``, at one instant:
        the centre of mass and its velocity are worked out once for all of them (two
        maps reading the weight's offset from each foot sum the 13 links once)."""
        self._memo = {}
        try:
            for name, read in readers:
                values[name] = read()
        finally:
            self._memo = None

    def com(self) -> tuple[float, float]:
        """Centre of mass, world m."""
        return self._sampled("com", self._com)

    def com_velocity(self) -> tuple[float, float]:
        """The centre of mass's velocity, world m/s."""
        return self._sampled("com_velocity", self._com_velocity)

    def com_spin(self) -> float:
        """The whole body's spin about its centre of mass (rad/s, counter-clockwise):
        its angular momentum about the centre of mass over its moment of inertia there.
        Unlike one link's spin it does not change in the air: what the take-off gave."""
        return self._sampled("com_spin", self._com_spin)

    def _sampled(self, name: str, compute):
        """``compute()``, once per ``sample`` while one runs."""
        memo = self._memo
        if memo is None:
            return compute()
        got = memo.get(name)
        if got is None:
            got = memo[name] = compute()
        return got

    def _com(self) -> tuple[float, float]:
        """The mass-weighted mean of each link's centre of gravity in the world
        (``cpBodyLocalToWorld`` of it, worked out from the bulk reading)."""
        if _kernel.get() is not None:
            return self._com_kernel()[0]
        values, rows = self._read()
        sx = sy = 0.0
        cos, sin = _kernel.cos, _kernel.sin  # (C's answers on a blown-up state)
        for i, mass, gx, gy in rows:
            a = values[i + 2]
            c, s = cos(a), sin(a)
            sx += mass * (c * gx + -s * gy + values[i])
            sy += mass * (s * gx + c * gy + values[i + 1])
        return (sx / self.mass, sy / self.mass)

    def _com_velocity(self) -> tuple[float, float]:
        """... and of their velocities (a body's velocity at its centre of gravity is
        its velocity)."""
        if _kernel.get() is not None:
            return self._com_kernel()[1]
        values, rows = self._read()
        sx = sy = 0.0
        for i, mass, _, _ in rows:
            sx += mass * values[i + 3]
            sy += mass * values[i + 4]
        return (sx / self.mass, sy / self.mass)

    def _com_kernel(self) -> tuple[tuple[float, float], tuple[float, float]]:
        """``_com`` and ``_com_velocity`` by the compiled kernel (``physics.kernel``: the
        same sums, reading each body through Chipmunk's getters), both at once (once
        per ``sample``)."""
        return self._sampled("com_kernel", self._com_kernel_now)

    def _com_kernel_now(self) -> tuple[tuple[float, float], tuple[float, float]]:
        _, com, args, _ = self._com_bound()
        com(*args)
        out = args[-1]
        return ((out[0], out[1]), (out[2], out[3]))

    def _com_bound(self, kern=None) -> tuple:
        """(bodies, pk_com, its arguments, pk_com_spin), the arguments pointing at the
        bodies of now (a restore re-binds them); ``kern``: the kernel the caller holds
        (else the loaded one)."""
        bodies = self.bodies
        cached = self.__dict__.get("_com_rows")
        if cached is None or cached[0] is not bodies:
            k = kern or _kernel.get()
            ffi, values = k.ffi, list(bodies.values())
            args = (ffi.new("void *[]", [k.pointer(b._body) for b in values]),
                    ffi.new("double[]", [b.mass for b in values]),
                    ffi.new("double[]", [b.center_of_gravity[0] for b in values]),
                    ffi.new("double[]", [b.center_of_gravity[1] for b in values]),
                    len(values), self.mass, ffi.new("double[4]"))
            cached = self._com_rows = (bodies, k.lib.pk_com, args, k.lib.pk_com_spin)
        return cached

    def _com_spin(self) -> float:
        """Sum of m (r x v) + I w over the links, r and v relative to the centre of
        mass, divided by sum of I + m r^2 (both about the centre of mass); the compiled
        kernel's ``pk_com_spin`` does the same sums in C, from the same centre of mass."""
        if _kernel.get() is not None:
            _, _, args, com_spin = self._com_bound()
            return com_spin(*args)
        values, rows = self._read()
        cx, cy = self.com()
        vx, vy = self.com_velocity()
        cos, sin = _kernel.cos, _kernel.sin  # (no crash on a blown-up state, as _com)
        momentum = inertia = 0.0
        for (i, mass, gx, gy), body in zip(rows, self.bodies.values()):
            a = values[i + 2]
            c, s = cos(a), sin(a)
            rx = c * gx - s * gy + values[i] - cx
            ry = s * gx + c * gy + values[i + 1] - cy
            moment = body.moment
            momentum += mass * (rx * (values[i + 4] - vy) - ry * (values[i + 3] - vx)) + \
                moment * values[i + 5]
            inertia += moment + mass * (rx * rx + ry * ry)
        return momentum / inertia

    def _read(self) -> tuple[list[float], list]:
        """Every body's state in one call (``body_state``), once per ``sample``, and
        per link (where its values start, mass, centre of gravity), in link order."""
        memo = self._memo
        if memo is not None:
            got = memo.get("bodies")
            if got is not None:
                return got
        bodies = self.bodies
        cached = self.__dict__.get("_rows")
        root = bodies[self.root]
        space = root.space
        if cached is None or cached[0] is not bodies or cached[1] is not space:
            reader = self.__dict__.get("_reader") or BodyReader()
            self._reader = reader
            rows = [(reader.offset(space, b), b.mass, *b.center_of_gravity)
                    for b in bodies.values()]
            cached = self._rows = (bodies, space, rows)
        got = (self._reader.read(space), cached[2])
        if memo is not None:
            memo["bodies"] = got
        return got

    def root_angle(self) -> float:
        """Angle of the root link (radians, counter-clockwise, 0 = as in the model)."""
        return self.bodies[self.spec.root].angle

    def upright(self, tolerance_deg: float = 45.0) -> bool:
        """Root link within ``tolerance_deg`` of its model orientation (mod full turns)."""
        a = math.remainder(self.root_angle(), 2 * math.pi)
        return abs(math.degrees(a)) <= tolerance_deg

    def in_contact(self, name: str) -> bool:
        """True if the link touches anything outside the character (the ground)."""
        body = self.bodies[name]
        _TOUCHING[0] = 0
        if _COUNT is not None:
            _cp.cpBodyEachArbiter(body._body, _COUNT, _ffi.NULL)  # = body.each_arbiter
        else:
            body.each_arbiter(_touched)
        if _TOUCHING[0]:
            return True
        # none listed: also so right after a restore, until the space steps (its
        # arbiters are listed again only then): the snapshot's contacts
        restored = restored_contacts(body)
        return bool(restored)

    def support_extent(self) -> tuple[float, float] | None:
        """(leftmost, rightmost) x of the points where the character touches anything
        outside itself (the support polygon, in the plane a segment), or None."""
        bodies = self.bodies.values()
        restored = restored_touching(next(iter(bodies)).space)  # (one space for all)
        if restored is not None:  # right after a restore: the snapshot's contacts
            xs = [x for body in bodies for x, _ in restored.get(body, ())]
        elif _kernel.get() is not None:  # the loop below in C, min and max as Python's
            support, args = self._support_args()
            if support(*args):
                out = args[2]
                return (out[0], out[1])
            return None
        else:  # each body's arbiters, through one callback made once (= each_arbiter)
            xs = _XS
            xs.clear()
            each, collect, null = _cp.cpBodyEachArbiter, _COLLECT, _ffi.NULL
            if collect is None:  # (no C callbacks here)
                for body in bodies:
                    body.each_arbiter(_arbiter_xs)
            else:
                for body in bodies:
                    each(body._body, collect, null)
        return (min(xs), max(xs)) if xs else None

    def _support_args(self) -> tuple:
        """``pk_support`` and its arguments (the bodies' kernel pointers, an out array),
        made again when the bodies are re-bound."""
        bodies = self.bodies
        cached = self.__dict__.get("_support")
        if cached is None or cached[0] is not bodies:
            k = _kernel.get()
            values = list(bodies.values())
            args = (k.ffi.new("void *[]", [k.pointer(b._body) for b in values]), len(values),
                    k.ffi.new("double[2]"))
            cached = self._support = (bodies, k.lib.pk_support, args)
        return cached[1], cached[2]

    def joint_angle(self, name: str) -> float:
        return self.servos[name].angle

    def link_position(self, name: str) -> tuple[float, float]:
        """A link's centre of mass in the world (pymunk's ``local_to_world`` of its
        ``center_of_gravity``, through the same C calls: sensors read it each step)."""
        cb = self.bodies[name]._body
        p = _cp.cpBodyLocalToWorld(cb, _cp.cpBodyGetCenterOfGravity(cb))
        return (p.x, p.y)
