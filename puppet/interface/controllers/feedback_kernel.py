"""Feedback's add maps with their sensors as one compiled call (``pk_feedback_tick``).

A walker's control step read three or four sensors (the centre of mass, its offset
from the stance foot, a thigh's angle) through Python readers and added four to eight
maps' values to their joints' targets: about 9 us of Python a control step against a
few of C. At load (``plan``), each add map becomes a row (its sensor's index, its
range's numbers, its gain, its joint's slot) and each sensor a kind with its links;
the kernel reads the sensors, sums the rows in file order and writes the targets with
the arithmetic of ``Feedback.tick``, ``conditions.map_reader`` and
``maps.compile_contribution`` (tests/test_kernel.py compares the paths bit for bit).

What ``Feedback`` keeps of the joints it adds to (``base``, ``last``: a joint's target
before the additions, and as written) is held in the kernel's arrays, one slot per
servo, while the compiled call runs; ``pull`` makes the dicts again, in the order the
Python path's dicts would have (``seq``: when a joint entered them), and ``push`` puts
them back. A sensor the kernel does not read (the lean, a contact...), and the support
polygon right after a restore, are read in Python and handed over; a map with a
response curve or a device or channel input, or a sensor map that sets targets, keeps
the whole tick on the Python path. The kernel's stepping loop (``pk_poll``,
``interface.poll_plan``) runs the same struct between Python's ticks
(``Feedback.compiled``, ``for_loop``) when no sensor is read in Python.
"""

from __future__ import annotations

from puppet.physics.snapshot import restored_touching

# the kernel's sensor kinds (kernel_control: PK_S_*; a contact is the stepping loop's
# conditions' alone, interface.poll_plan)
(GIVEN, COM_X, COM_Y, COM_VX, COM_VY, COM_DX, ANGLE, SPIN, JOINT, HEIGHT, LEAD, SUPPORT,
 FALL_TIME, CONTACT, COM_SPIN) = range(15)
COM = {"com.x": COM_X, "com.y": COM_Y, "com.vx": COM_VX, "com.vy": COM_VY,
       "com.fall_time": FALL_TIME, "com.spin": COM_SPIN}
USES_COM = {COM_X, COM_Y, COM_VX, COM_VY, COM_DX, SUPPORT, FALL_TIME, COM_SPIN}  # (PK_S_COM)
_NAMED = {"angle": ANGLE, "spin": SPIN, "height": HEIGHT}


def sensor_kind(sensor: str, character) -> tuple[int, str | None, str | None]:
    """(kind, link, other link) of a map's sensor (its name after ``sensor.``, roles
    resolved); GIVEN for one the kernel does not read."""
    if sensor in COM:
        return COM[sensor], None, None
    if sensor == "root.angle":
        return ANGLE, character.spec.root, None
    links = character.bodies
    if sensor.startswith("com.dx."):
        name = sensor[len("com.dx."):]
        if name == "support":
            return SUPPORT, None, None
        return (COM_DX, name, None) if name in links else (GIVEN, None, None)
    if sensor.startswith("lead."):
        link, dot, other = sensor[len("lead."):].partition(".")
        if link in links and dot and other in links:
            return LEAD, link, other
        return GIVEN, None, None
    kind, _, name = sensor.partition(".")
    if kind in _NAMED and name in links:
        return _NAMED[kind], name, None
    if kind == "joint" and name:
        joint = character.spec.joint(name)
        return JOINT, joint.child, joint.parent
    return GIVEN, None, None


class Plan:
    """One set of active add maps as the kernel's rows: ``given`` (name, reader, index)
    are read in Python; ``names`` (name, index) are stored in the inputs afterwards."""

    def __init__(self, fk, readers, rows):
        ffi, character = fk.ffi, fk.character
        found = [sensor_kind(name[len("sensor."):], character) for name, _ in readers]
        self.links = [(a, b) for _, a, b in found]
        kinds = [kind for kind, _, _ in found]
        self.given = [(name, read, i) for i, ((name, read), kind) in
                      enumerate(zip(readers, kinds)) if kind == GIVEN]
        self.given_readers = [(name, read) for name, read, _ in self.given]
        self.scratch: dict = {}
        # the support sensors: read in Python right after a restore (the snapshot's
        # contacts, until the space steps: Character.support_extent)
        self.support = [(name, read, i) for i, ((name, read), kind) in
                        enumerate(zip(readers, kinds)) if kind == SUPPORT]
        self.support_readers = [(name, read) for name, read, _ in self.support]
        self.falls = FALL_TIME in kinds  # (the kernel is handed the gravity)
        self.names = [(name, i) for i, (name, _) in enumerate(readers)]
        n = max(1, len(readers))
        self.kind = ffi.new("int[]", kinds or [0])
        self.a, self.b = ffi.new("void *[]", n), ffi.new("void *[]", n)
        self.values = ffi.new("double[]", n)
        self.count = len(readers)
        columns = list(zip(*rows))
        self.n_rows = len(rows)
        self.sensor, self.clamp, self.slot = (ffi.new("int[]", list(c)) for c in columns[:3])
        self.x0, self.inv, self.lo, self.span, self.gain = (ffi.new("double[]", list(c))
                                                            for c in columns[3:])
        self.bound = None  # the bodies a and b point into


class FeedbackKernel:
    """The compiled feedback of one runtime: its slots (every servo) and its plans."""

    def __init__(self, kern, character, servos):
        self.ffi, self.lib, self.pointer = kern.ffi, kern.lib, kern.pointer
        self.character = character
        self.joints = list(servos)
        self.slots = {j: i for i, j in enumerate(self.joints)}
        self.servos = servos
        ffi, n = kern.ffi, len(self.joints)
        self.f = f = ffi.new("pk_feedback *")
        self._keep = [ffi.new("void *[]", n), ffi.new("double[]", n), ffi.new("int[]", n),
                      ffi.new("int[]", n), ffi.new("double[]", n), ffi.new("double[]", n),
                      ffi.new("int[]", n), ffi.new("long long[]", n)]
        (f.spring, f.acc, f.added, f.order, f.base, f.last, f.has, f.seq) = self._keep
        f.n_slots = n
        self._bodies = None  # the character's bodies the pointers were taken from
        self._com: list = []
        self._plans: dict = {}
        self._plan = None
        self._space = None

    def plan(self, readers, adders) -> Plan | None:
        """The add maps (``maps.compile_contribution``'s, with their ``row``) and their
        sensors as a Plan; None if one of them is not the kernel's to run."""
        key = (tuple(map(id, readers)), tuple(map(id, adders)))
        got = self._plans.get(key)
        if got is not None:  # (each kept with what its key names: their ids stay theirs)
            return got[0]
        got = self._plans[key] = (self._made(readers, adders), tuple(readers), tuple(adders))
        return got[0]

    def _made(self, readers, adders) -> Plan | None:
        index = {name: i for i, (name, _) in enumerate(readers)}
        rows = []
        for contribution in adders:
            row = getattr(contribution, "row", None)
            if row is None:
                break
            constant, name, x0, inv, lo, span, clamp, gains = row
            if constant:
                rows += [(-1, 0, self.slots[j], 0.0, 0.0, 0.0, 0.0, v) for j, v in gains]
                continue
            if name not in index:
                break
            rows += [(index[name], int(bool(clamp)), self.slots[j], x0, inv, lo, span, g)
                     for j, g in gains]
        else:
            return Plan(self, readers, rows) if rows else None
        return None

    def _bind(self, plan: Plan) -> None:
        """Point the kernel at the bodies and springs of now (a restore re-binds them)
        and at ``plan``'s rows."""
        c, f, pointer = self.character, self.f, self.pointer
        bodies = c.bodies
        if self._bodies is not bodies:
            values = list(bodies.values())
            ffi = self.ffi
            self._com = [ffi.new("void *[]", [pointer(b._body) for b in values]),
                         ffi.new("double[]", [b.mass for b in values]),
                         ffi.new("double[]", [b.center_of_gravity[0] for b in values]),
                         ffi.new("double[]", [b.center_of_gravity[1] for b in values])]
            f.bodies, f.mass, f.gx, f.gy = self._com
            f.n_bodies, f.total = len(values), c.mass
            for i, joint in enumerate(self.joints):
                f.spring[i] = pointer(self.servos[joint].spring._constraint)
            self._bodies = bodies
            self._space = values[0].space  # (one space for all; a new one re-binds them)
        if plan.bound is not bodies:
            null = self.ffi.NULL
            for i, (a, b) in enumerate(plan.links):
                plan.a[i] = null if a is None else pointer(bodies[a]._body)
                plan.b[i] = null if b is None else pointer(bodies[b]._body)
            plan.bound = bodies
        if self._plan is not plan:
            f.n_sensors, f.kind, f.a, f.b, f.values = (plan.count, plan.kind, plan.a, plan.b,
                                                       plan.values)
            f.n_rows, f.sensor, f.clamp, f.slot = plan.n_rows, plan.sensor, plan.clamp, plan.slot
            f.x0, f.inv, f.lo, f.span, f.gain = plan.x0, plan.inv, plan.lo, plan.span, plan.gain
            self._plan = plan

    def prepare(self, plan: Plan) -> None:
        """The struct ``f`` ready to run ``plan`` (bound to the bodies of now, the
        gravity handed over): by ``tick``, or by the stepping loop (``pk_poll``)."""
        bodies = self.character.bodies
        if plan.bound is not bodies or self._plan is not plan or self._bodies is not bodies:
            self._bind(plan)
        if plan.falls:  # (conditions._fall_time's g, read live)
            self.f.gravity = -self._space.gravity[1]

    def tick(self, plan: Plan, values: dict, sample) -> None:
        """One control step of ``plan``: its sensors into ``values`` (the runtime's
        inputs) and its joints' targets written."""
        self.prepare(plan)
        out = plan.values
        if plan.given:  # (read into their own dict: the inputs get every value in order)
            given = plan.scratch
            sample(plan.given_readers, given)
            for name, _, i in plan.given:
                out[i] = given[name]
        if plan.support:
            restored = restored_touching(self._space) is not None
            self.f.support_given = restored
            if restored:
                given = plan.scratch
                sample(plan.support_readers, given)
                for name, _, i in plan.support:
                    out[i] = given[name]
        self.lib.pk_feedback_tick(self.f)
        self.hand_back(plan, values)

    def for_loop(self, plan: Plan):
        """``f`` for the stepping loop to run ``plan``'s ticks with, or None when one of
        its sensors is read in Python (a kind the kernel does not read, the support
        polygon right after a restore)."""
        if plan.given:
            return None
        self.prepare(plan)
        if plan.support:
            if restored_touching(self._space) is not None:
                return None
            self.f.support_given = 0
        return self.f

    @staticmethod
    def hand_back(plan: Plan, values: dict) -> None:
        """The sensors' last readings into ``values`` (the runtime's inputs)."""
        out = plan.values
        for name, i in plan.names:
            values[name] = out[i]

    def pull(self) -> tuple[dict, dict]:
        """(base, last) as ``Feedback`` keeps them, in the order its dicts would have."""
        f, joints = self.f, self.joints
        held = sorted((f.seq[s], s) for s in range(len(joints)) if f.has[s])
        return ({joints[s]: f.base[s] for _, s in held}, {joints[s]: f.last[s] for _, s in held})

    def push(self, base: dict, last: dict) -> None:
        """``Feedback``'s (base, last) into the kernel's arrays."""
        f = self.f
        for s in range(len(self.joints)):
            f.has[s] = 0
        for i, (joint, value) in enumerate(last.items(), 1):
            s = self.slots[joint]
            f.has[s], f.seq[s], f.last[s], f.base[s] = 1, i, value, base[joint]
        f.counter = len(last)

