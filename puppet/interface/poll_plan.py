"""Every-step polls in the compiled kernel: what a tick leaves to do, as its table.

After a tick (``InterfaceRuntime.tick``), ``PollPlan.ready`` says whether the work due
until something else happens is only what ``physics.kernel_poll``'s ``pk_poll`` does:
one state machine's polled transitions on sensors it reads (a link's contact, world
angle or spin, a joint's angle, a link's height; the centre of mass's place, velocity,
fall time and offset from a link, the body's spin; a device input or channel, which no
step changes, is read here once), a blend's plain targets travelling and the held
frame targets re-solved (``FrameTargets.tick``: a biped's world-held joints), at the
control period. Then
``Session.advance`` hands the steps to ``run``, which returns at the first step where
a transition holds (or the frame check fails, or a timer, a blend's arrival, a
history boundary or the call's end comes) with the runtime rescheduled as though it
had ticked at every step in between: the next tick runs exactly where it would have.
A run cut at its call's end (an input event) or at a history boundary goes on at the
next tick, the kernel's (``resume``), if ``ready`` finds the plan still holds what is
due there. With nothing else busy, a transition into a state whose entry is a plain
``set`` with ``over`` (or nothing), timers and the blend's arrivals are the loop's too
(``poll_states``: armed by ``_fill``, handed back after the call).

Feedback's add maps run there too, when every active one is the kernel's to run
with every sensor it reads (``Feedback.compiled``: the struct of ``Feedback.tick``'s
own compiled call, ``pk_feedback_tick``, whose arrays keep its base and last writes).
A condition on the mouse (``input.mouse.x``, ``.y``, the pointer's) reads the
plan's ``in_val``, written at each ``ready`` and by the replay's mouse moves the
kernel applies (``session.event_runs``): a state polling the mouse alone polls it at
each control step in the kernel, which finds what Python's stirred polls find, and
its machine is left quiet as Python's ticks leave it (``_quieted``).
Anything else keeps Python's path: a ``for`` on a device input, a state polling
other device inputs alone, another sensor (a lean, the support polygon, a lead), a frame
target taken back by a later write or travelling in a blend, any other busy
controller, a second machine, a tracker but an ``angles`` one with intentional
contacts (``poll_track``: its targets and the contacts' swing at its control steps,
``may_track`` asked first; the swing first, ``c_late``, where a machine reads a
velocity it moves). Without the kernel there is no plan (``PUPPET_KERNEL=python``):
the same ticks run in Python, to the same bits.
"""

from __future__ import annotations

from puppet.interface.conditions import INPUT, compile_bounds, reader
from puppet.interface.controllers import feedback_kernel as _fk
from puppet.interface.controllers.tracking import OFF
from puppet.interface.ownership import BLEND, SEQUENCE
from puppet.interface.poll_machines import joint_table, quiet_now, since_back, since_into
from puppet.interface.poll_reach import fill_grasps, fill_reaches
from puppet.interface.poll_states import States
from puppet.interface.poll_track import VELOCITY, may_track, track_part
from puppet.interface.poses import made_frame_target
from puppet.interface.track_poll import TrackPoll, run_stop
from puppet.physics import kernel as _kernel

# sensor kind -> the kernel's code (PK_S_*, kernel_control's pk_sensor): a link's
# contact, its angle within a turn, a joint's angle, a link's spin, its height; and
# the centre of mass's (COM: its place, velocity, fall time, the body's spin; com.dx
# from a link)
KINDS = {"contact": _fk.CONTACT, "angle": _fk.ANGLE, "joint": _fk.JOINT, "spin": _fk.SPIN,
         "height": _fk.HEIGHT}
COM = _fk.COM  # the centre of mass's (its position, velocity, fall time; the body's spin)
OFFLINE = ("channel.", INPUT)  # sensors no step changes: read once, when the plan is made
MAX_CONDITIONS = 32
# a device input a mouse move sets, read by pk_poll's conditions from the plan's in_val
# (PK_S_INPUT + its slot): written at each ``ready``, and by the kernel's event runs
LIVE_INPUT = 100
LIVE = {"mouse.x": 0, "mouse.y": 1, "pointer.x": 2, "pointer.y": 3}
NAN = float("nan")
NEVER = 1 << 62  # no timer, no arrival: the run ends at the call's end or a boundary


def condition_kind(sensor: str, root: str) -> tuple[int, str] | None:
    """(pk_poll's code, the link or joint) for a sensor ``pk_poll`` reads, else None."""
    if sensor == "root.angle":
        return KINDS["angle"], root
    if sensor in COM:
        return COM[sensor], None
    if sensor.startswith("com.dx."):  # from a link (the support polygon: Python's)
        name = sensor[len("com.dx."):]
        return None if name == "support" or "." in name else (_fk.COM_DX, name)
    kind, _, name = sensor.partition(".")
    if kind in KINDS and name and "." not in name:
        return KINDS[kind], name
    return None


class PollPlan:
    """The table ``pk_poll`` reads, for one runtime (made when the kernel is there)."""

    def __init__(self, runtime, kern):
        self.runtime = runtime
        self.kernel = kern
        ffi = kern.ffi
        self.ffi, self.poll = ffi, kern.lib.pk_poll
        n = MAX_CONDITIONS
        self.plan = p = ffi.new("pk_poll_plan *")
        # the arrays live as long as the plan (cffi frees them with their owners)
        self._keep = [ffi.new("int[]", n) for _ in range(12)] + \
            [ffi.new("void *[]", n) for _ in range(7)] + [ffi.new("double[]", n) for _ in range(6)]
        (p.first, p.period, p.hold, p.since, p.cond0, p.n_cond, p.kind, p.want, p.b_first, p.b_last,
         p.f_hold_parent, p.f_blend, p.body_a, p.body_b, p.spring, p.f_parent, p.f_child,
         p.f_ref, p.f_spring, p.lo, p.hi, p.start, p.to, p.f_angle, p.b_value) = self._keep
        self._tables: dict = {}  # (machine, state, binding) -> transitions or None
        self._pointers: dict = {}  # a pymunk object -> the kernel's void * (see pointer)
        self._frame = None  # the session's frame check, as written into the plan
        self.machine = runtime._machine_list[0]  # (the first: several, poll_machines)
        self._many = len(runtime._machine_list) > 1
        self._joint_key = self._joint = None  # (poll_machines.joint_table)
        self._state = self._binding = self._current = None  # the state's table (ready)
        self._filled = self._space = self._key = self._until = None  # the plan (ready)
        self._frames_kept: tuple = ()  # the held frame targets the plan was filled with
        self._frames_ids: tuple = ()  # (their ids)
        self._frame_rows: list | None = None  # per frame row: (joint, ref, hold_parent)
        self._offline = False  # the plan's table reads an input: filled at each ready
        self._held: list = []  # the plan's transitions with a `for` (_fill)
        self._travelling: dict = {}  # joint -> its travel's index, a frame target's (_fill)
        self._com = False  # the plan reads the centre of mass (the fall time: gravity)
        self._velocity = 0  # the plan's polls read VELOCITY: 1 a machine, 2 an until
        self._inputs = False  # the plan reads device inputs (in_val, at each ready)
        self._live = False  # the state's table reads no input but those (LIVE)
        self.resume = -1  # where the next call may go on, its tick the kernel's (see run)
        self.seat = None  # and the space it ran on then (a re-seat lists no contacts)
        self._root = self._space_cd = self._space_void = self._feeding = None  # (run)
        self._states = States(self)  # transitions the loop takes (poll_states)
        self._armed = False  # (the plan's states table armed by the last _fill)
        self._angles = None  # (poll_track.AngleTrack: a tracker's angles, made once)

    def pointer(self, cdata):
        """``kernel.pointer``, remembered (``physics.kernel.remembered``)."""
        return _kernel.remembered(self.kernel, self._pointers, cdata)

    def _table(self, machine, current: str | None = None):
        """The current state's transitions as ``pk_poll`` can poll them, in ``due``'s
        order: ``(after, None, 0, index)`` a timer, ``(after, conditions, for, index)``
        a polled one (``for`` in steps, 0 without; ``index``: the machine's), each
        condition ``(code or None, name or reader, lo, hi, want)`` (``None``: a device
        input or channel, its reader); None when one cannot be polled there."""
        rt = self.runtime
        current = machine.current if current is None else current  # (prime: each state)
        key = (machine.name, current, rt.role_binding)
        if key in self._tables:
            return self._tables[key]
        rename = rt.roles.sensor
        spec, name = machine.spec, machine.name
        state = spec.states[current]
        shared = [t for t in spec.any_state.transitions
                  if rt.spec.resolve_goto(t.to, name) != (name, current)]
        table = []
        for index, t in enumerate([*state.transitions, *shared]):
            after = round((t.after or 0.0) / machine.dt)
            if not t.conditions:
                table.append((after, None, 0, index))
                continue
            hold = round((t.held or 0.0) / machine.dt)  # (StateMachine._hold_steps)
            if hold and any(rename(c.sensor).startswith(OFFLINE) for c in t.conditions):
                table = None  # (a `for` left out when an input rules it out: Python's)
                break
            conditions = self._conditions(t.conditions)
            if conditions is None:
                table = None
                break
            table.append((after, conditions, hold, index))
        self._tables[key] = table
        return table

    def _conditions(self, conditions) -> list | None:
        """A transition's or an ``until``'s conditions as ``pk_poll`` reads them:
        ``(code or None, name or reader, lo, hi, want)``; None if one cannot be."""
        rt = self.runtime
        rename, root = rt.roles.sensor, rt.character.spec.root
        out = []
        for c in conditions:
            sensor = rename(c.sensor)
            bounds = compile_bounds(c)
            lo, hi = bounds if bounds is not None else (0.0, 0.0)
            want = -1 if bounds is not None else int(bool(c.is_))
            if sensor.startswith(OFFLINE):
                slot = LIVE.get(sensor[len(INPUT):]) if sensor.startswith(INPUT) else None
                if slot is not None and (slot < 2 or rt._pointer):  # (pointer: the mouse's)
                    out.append((LIVE_INPUT + slot, None, lo, hi, want))
                    continue
                out.append((None, reader(sensor, rt.character, rt.channels, rt.inputs),
                            lo, hi, want))
                continue
            kind = condition_kind(sensor, root)
            if kind is None or (kind[0] == _fk.COM_DX and kind[1] not in rt.character.bodies):
                return None  # (a name no link has: Python's reader says so)
            out.append((*kind, lo, hi, want))
        return out

    def prime(self) -> None:
        """Every state's table and every sequence step's ``until``, made when the
        runtime is (a state's first entry in a replay would make them between its
        steps, as cold as the rest of the entry)."""
        for machine in self.runtime._machine_list:
            for state in machine.spec.states:
                self._table(machine, state)
        for name, steps in self.runtime.sequences.specs.items():
            for index in range(len(steps)):
                self._sequence_until(name, index)
        self._states.prime(self.runtime)  # (the loop's states tables: poll_states)

    def _sequence_until(self, name: str, index: int):
        """A sequence step's ``until`` (``compile_untils``): (after in steps, its
        conditions), None without one, False when ``pk_poll`` cannot read it."""
        key = ("sequence", name, index, self.runtime.roles.binding)
        if key not in self._tables:
            spec = self.runtime.sequences.specs[name][index]
            found = None
            if spec.until is not None:
                conditions = self._conditions(spec.conditions)
                found = False if conditions is None else \
                    (round((spec.after or 0.0) / self.runtime.dt), conditions)
            self._tables[key] = found
        return self._tables[key]

    def _state_table(self):
        """The current state's table (looked up once per state and binding)."""
        rt, machine = self.runtime, self.machine
        if self._many:
            return joint_table(self)  # (its device-only machines: Python's; _live False)
        if machine.current is not self._state or rt.roles.binding is not self._binding:
            self._state, self._binding = machine.current, rt.roles.binding
            self._current = table = self._table(machine)
            # (every input it reads one a mouse move sets: a device-only state's polls
            # are the kernel's at each control step, which find what a stirred poll
            # does; quiet, they find nothing until an event moves an input)
            self._live = table is not None and not any(
                kind is None for _, cs, *_ in table if cs for kind, *_ in cs)
        return self._current

    def waits(self) -> bool:
        """The one machine is quiet in a state polling the mouse alone (``LIVE``): a
        run of mouse events may be the kernel's, its polls finding what a stirred
        machine's do (``ready(step, idle=True)``)."""
        machine = self.machine
        return machine.device_only and machine.quiet and self._state_table() is not None \
            and self._live

    def ready(self, step: int, idle: bool = False) -> int | None:
        """After the tick at ``step`` (or where a run resumes: Session.advance's check
        of ``resume`` and ``seat``): the step up to which
        ``pk_poll`` may run (the first timer, blend arrival or other wake-up), the
        table filled; None when the work due is not all its to do. Runs at every tick
        of a one-machine interface, so it is kept lean: the state's table is looked up
        once per state, and the plan filled again only when what it holds changed.
        ``idle``: no tick is due at ``step`` (``waits``: events are coming)."""
        rt, machine = self.runtime, self.machine
        if step != self.resume:  # Python ticked before the step the last run went on to
            self.resume = -1
        tracking = rt.tracker.mode != OFF  # (poll_track: an angles tracker beside)
        if tracking and not may_track(rt.tracker):  # (asked first: its every tick)
            return None
        table = self._state_table()
        if table is None:
            return None
        feeding, feedback = self.ffi.NULL, rt.feedback
        if feedback.busy:  # sensor maps: all add maps it can run, at the same period
            feeding = feedback.compiled()  # (Feedback.tick's own compiled call)
            if feeding is None or feedback.every != machine.every:
                return None
        if (rt.next_wakeup is None and not idle) or rt._pending:
            return None
        blends, sequences = rt.blends, rt.sequences
        frames, reaching, grasping = rt.frames, rt.reaching, rt.grasping
        tracker = rt.tracker if tracking else None
        for controller in rt._active:
            if controller is not blends and controller is not sequences \
                    and controller is not feedback and controller is not frames \
                    and controller is not reaching and controller is not grasping \
                    and controller is not tracker:
                return None
        held = frames.held
        if held:  # frame targets: re-solved at the control steps, each by its owner
            if frames.every != machine.every or frames not in rt._active:
                return None  # (runtime.tick's reschedule: Python's)
            owners = rt.owners.table
            for joint, (_, owner) in held.items():
                if owners.get(joint) != owner:  # taken back: Python's tick lets it go
                    return None
        seq = sequences.running
        if seq is not None:
            if SEQUENCE not in rt.owners.table.values():  # (its tick ends it: Python's)
                return None
            seq = (seq.name, seq.index, seq.until, seq.began, rt.roles.binding)
        every = machine.every
        if blends.every != every:
            return None
        if machine.device_only and not self._live and not machine.quiet \
                and not quiet_now(machine, step):
            return None
        moving, owners = blends.moving, rt.owners.table
        travelling = False  # a frame target's angle travels (blend holds it each tick)
        for joint, m in moving.items():
            if owners.get(joint) != BLEND:  # taken back: Python's tick lets it go
                return None
            if m[4] is not None:
                if joint not in held:
                    return None
                travelling = True
        sim = rt.sim
        # what the plan holds: the table, when the state was entered, the polls, the
        # bodies (a re-seat makes new ones), the period, the travelling targets and the
        # held frame targets (each hold is a new pair: compared by identity, as 0.0 and
        # -0.0 are equal but need not solve alike; the pairs kept so their ids stay;
        # a travelling one's angle is the blend's, the loop's hand-back a new pair)
        frames_now = tuple(v for j, v in held.items() if j not in moving) if travelling \
            else tuple(held.values())
        frames_ids = tuple(map(id, frames_now))
        key = (machine.entered, machine.quiet and not self._live, sim.seats, every, seq,
               tuple(moving.items()))
        if table is not self._filled or sim.space is not self._space or key != self._key \
                or self._offline:
            self._filled, self._space, self._key = table, sim.space, key
            self._frames_ids, self._frames_kept = frames_ids, frames_now
            self._offline = not machine.quiet and any(  # (a quiet state polls nothing)
                kind is None for _, cs, *_ in table if cs for kind, *_ in cs)
            self._until = self._fill(table, machine, every, seq)
        elif frames_ids != self._frames_ids:  # only held again (a frame map, each event)
            self._frames_ids, self._frames_kept = frames_ids, frames_now
            if not self._held_again(held):
                self._until = self._fill(table, machine, every, seq)
        if feeding is not self._feeding:  # (the same struct: already in the plan)
            self._feeding = self.plan.feedback = feeding
        if self._com:
            self.plan.gravity = -sim.space.gravity[1]  # (conditions._fall_time's g)
        if self._inputs or self._armed:  # the inputs as they are now (an event may
            # have moved them; a state the loop enters may read them)
            get, in_val = rt.inputs.get, self.plan.in_val
            in_val[0], in_val[1] = get("mouse.x", NAN), get("mouse.y", NAN)
            in_val[2], in_val[3] = get("pointer.x", NAN), get("pointer.y", NAN)
        if self._held and self._many:
            since_into(self)
        elif self._held:  # the `for`s' starts, as the machine has them now
            p, since = self.plan, machine._since
            for k, index in self._held:
                p.since[k] = since.get(index, -1)
        until = self._until
        if until is None:
            return None
        ends = fill_reaches(self, rt, NEVER)  # (at every ready: the owners may change)
        if ends is None:
            return None
        until = ends if ends < until else until
        ends = fill_grasps(self, rt, NEVER)  # (and the grasps held)
        if ends is None:
            return None
        until = ends if ends < until else until
        ends = track_part(self, step, step == self.resume)  # (and a tracker's angles)
        if ends is None:
            return None
        until = ends if ends < until else until
        return until if until > step else None  # (due now: Python's)

    def _held_again(self, held: dict) -> bool:
        """The same joints held in the same frames, at new angles: written into the
        plan's rows (False: held otherwise, the plan must be filled again)."""
        rows = self._frame_rows
        if rows is None or len(rows) != len(held):
            return False
        angle = self.plan.f_angle
        for n, ((joint, (target, _)), (was, ref, hold_parent)) in enumerate(zip(held.items(),
                                                                                 rows)):
            if joint != was or target.ref != ref or target.hold_parent != hold_parent:
                return False
            angle[n] = target.angle
        return True

    def _fill(self, table, machine, every: int, seq, states: bool = True) -> int | None:
        """Write the plan: the state's polled transitions (those an input rules out
        left out), the blend's travelling targets; the step a timer or an arrival is
        due (NEVER: none), or None when there is nothing to do or it does not fit.
        ``states``: the loop may take transitions and arrivals (``poll_states``: the
        timers are rows then, the arrivals the loop's; armed if all else fits)."""
        rt = self.runtime
        p, until = self.plan, NEVER
        p.states, self._armed, rows = self.ffi.NULL, False, []
        states = states and seq is None and not self._many and not any(
            c[0] is None for _, cs, *_ in table if cs for c in cs) and States.usable(rt)
        character = rt.character
        bodies, joints = character.bodies, character.spec
        k = i = 0
        entered = machine.entered
        self._held = held = []  # (the plan's transition, the machine's) with a `for`
        self._frame_rows = None
        uses_com = self._inputs = False
        moves = 0
        if seq is not None:  # a running sequence: its step's end, its ``until``
            name, step_index, ends, began, _ = seq
            found = self._sequence_until(name, step_index)
            if found is False:
                return None
            until = ends  # (the next step's pose: Python's tick)
            if found is not None:
                self._offline = self._offline or any(c[0] is None for c in found[1])
                table = [((began or 0) + found[0] - entered, found[1], 0, -1, 1), *table]
        for after, conditions, hold, index, *period in table:
            first = entered + after
            if conditions is None and states and k < MAX_CONDITIONS:  # a timer: a row
                p.first[k], p.cond0[k], p.n_cond[k], p.hold[k], p.period[k] = first, i, 0, 0, 1
                rows.append(index)
                k += 1
                continue
            if conditions is None:  # a timer: Python's tick fires it
                until = first if first < until else until
                continue
            if machine.quiet and not self._live:  # (a device-only state between input
                continue  # events: no polls; the mouse's alone: the kernel's, see waits)
            c0 = i
            for kind, name, lo, hi, want in conditions:
                if kind is None:  # no step changes it: decided now
                    value = name()
                    if not (lo < value < hi if want < 0 else (value > 0.5) == bool(want)):
                        break
                    continue
                if i >= MAX_CONDITIONS:
                    return None
                if kind == _fk.JOINT:
                    joint = joints.joint(name)
                    p.body_a[i] = self.pointer(bodies[joint.child]._body)
                    p.body_b[i] = self.pointer(bodies[joint.parent]._body)
                elif name is not None:
                    p.body_a[i] = self.pointer(bodies[name]._body)
                uses_com = uses_com or kind in _fk.USES_COM
                if kind in VELOCITY:  # (1: a machine's, 2: a sequence's until's)
                    moves |= 2 if index == -1 else 1
                self._inputs = self._inputs or kind >= LIVE_INPUT
                p.kind[i], p.lo[i], p.hi[i], p.want[i] = kind, lo, hi, want
                i += 1
            else:
                if k >= MAX_CONDITIONS:
                    return None
                p.first[k], p.cond0[k], p.n_cond[k], p.hold[k] = first, c0, i - c0, hold
                p.period[k] = period[0] if period else every
                if hold:
                    held.append((k, index))
                if states:
                    rows.append(index if index >= 0 else None)
                k += 1
                continue
            i = c0  # an input condition that does not hold: the transition cannot fire
        p.n_trans = k
        n, servos, null = 0, character.servos, self.ffi.NULL
        self._travelling = travelling = {}  # joint -> its travel (a frame target's)
        for joint, (start, to, first, last, target) in rt.blends.moving.items():
            if n >= MAX_CONDITIONS:
                return None
            if target is None:
                p.spring[n] = self.pointer(servos[joint].spring._constraint)
            else:  # (its angle: the frame loop's)
                p.spring[n] = null
                travelling[joint] = n
            p.start[n], p.to[n], p.b_first[n], p.b_last[n] = start, to, first, last
            until = last if last < until and not states else until  # (the loop's, armed)
            n += 1
        p.n_blend, p.every = n, every
        n, frame_joints, frame_rows = 0, rt.frames.joints, []
        for joint, (target, _) in rt.frames.held.items():  # (FrameTargets.tick's order)
            if n >= MAX_CONDITIONS:
                return None
            spec, ref = frame_joints[joint], target.ref
            frame_rows.append((joint, ref, target.hold_parent))
            p.f_parent[n] = self.pointer(bodies[spec.parent]._body)
            p.f_child[n] = self.pointer(bodies[spec.child]._body)
            p.f_ref[n] = null if ref is None else self.pointer(bodies[ref]._body)
            p.f_spring[n] = self.pointer(servos[joint].spring._constraint)
            p.f_angle[n], p.f_hold_parent[n] = target.angle, target.hold_parent
            p.f_blend[n] = travelling.get(joint, -1)
            n += 1
        p.n_frame, self._frame_rows = n, frame_rows
        if states:
            if not self._states.arm(rt, machine, seq, rows):
                return self._fill(table, machine, every, seq, False)
            self._armed = True
            uses_com = uses_com or self._states.uses_com
        if uses_com:  # Character._com_kernel's arguments, for these bodies
            args = self._com_args = character._com_bound(self.kernel)[2]  # (kept alive)
            p.com_bodies, p.com_mass, p.com_gx, p.com_gy, p.com_n, p.com_total = args[:6]
        self._velocity = moves
        self._com = uses_com  # (nothing to do between the steps: the loop steps on, and
        return until  # goes on after an input event, which Python's would tick at)

    def run(self, space_ptr, dt: float, now: int, until: int, end: int, health: int,
            frame: tuple, tick_first: bool = False) -> int:
        """Step from ``now`` with ``pk_poll`` up to ``until`` (``ready``'s), ``end`` or
        the next history boundary (``health``, on a frame's end); the runtime is then
        rescheduled from the step it returns. ``frame``: the session's frame check
        (steps a frame, the root link, its box x0, x1, y0, y1, the speed squared);
        ``tick_first``: the tick at ``now`` is the kernel's too (``resume``)."""
        p = self.plan
        if frame is not self._frame:
            self._frame = frame
            p.frame_every, root, p.x0, p.x1, p.y0, p.y1, p.max_speed2 = frame
        stop, last = run_stop(now, until, end, health, frame[0])
        rt = self.runtime
        root = rt.character.bodies[frame[1]]._body
        if root is not self._root:  # (held: the same object is the same body)
            self._root, p.root = root, self.pointer(root)
        if space_ptr is not self._space_cd:
            self._space_cd, self._space_void = space_ptr, self.pointer(space_ptr)
        machine = self.machine
        quiet = machine.quiet
        s = self.poll(self._space_void, dt, now, stop, p, tick_first)
        handed = self._armed and p.states.n_log  # (states entered, targets arrived)
        entered = handed and self._states.handed_back(rt, machine)
        if entered:
            self._state_table()  # (the plan holds its rows, as _fill writes them)
        if self._live and machine.device_only:
            self._quieted(p, quiet and not entered, now, s, tick_first)
        if handed:  # what ready's key finds now: the plan as the loop left it (a state
            self._filled, sim = self._current, rt.sim  # entered: no `for`s)
            self._held = [] if entered else self._held
            self._key = (machine.entered, machine.quiet and not self._live, sim.seats,
                         machine.every, None, tuple(rt.blends.moving.items()))
        if p.fb_ticks:  # the sensors' readings handed back (base and last: the kernel's)
            rt.feedback.ran()
        if self._travelling and p.writes:  # the blend's holds at the last control step
            held, b_value = rt.frames.held, p.b_value  # (BlendController._write's)
            for joint, j in self._travelling.items():
                target = held[joint][0]
                held[joint] = (made_frame_target(target.ref, b_value[j], target.hold_parent),
                               BLEND)
        if self._held and self._many:
            since_back(self)
        elif self._held:  # the `for`s' starts handed back (a snapshot keeps them)
            since = p.since
            self.machine._since = {index: since[k] for k, index in self._held
                                   if since[k] >= 0}
        self.resume = -1
        # rt._reschedule(s), for what ``ready`` allows: the controllers with work are
        # those that had it (the run changed none of their schedules' inputs), and the
        # one machine
        wake = None
        for controller in () if handed else rt._active:
            at = controller.next_wakeup(s)
            if at is None:
                rt._reschedule(s)  # (never here: the full one)
                return s
            if wake is None or at < wake:
                wake = at
        if handed:  # (the controllers with work may be others: the full one)
            rt._reschedule(s)
            wake = rt.next_wakeup
        else:
            rt._controllers_wake = wake
            for machine in rt._machine_list:
                at = machine.next_wakeup(s)
                if at is not None and (wake is None or at < wake):
                    wake = at
            rt.next_wakeup = wake = wake if wake is None or wake > s else s
        # stopped at the call's end: the next call may go on at the next tick (the
        # session steps to it as the loop would; an input event comes first, and
        # ``ready`` says whether it changed anything), when nothing else is due there
        # and no history boundary comes before it; or stopped at a history boundary
        # (``last``): the session's health check there changes nothing the run holds
        # (a keyframe re-seats, a recovery restores: ``seat``, ``set_state``), so its
        # next tick may go on likewise, before the boundary after it
        if wake is not None and wake < until and ((s == last and wake < s + health)
                                                  or (s == end and wake < last)):
            sim = rt.sim
            self.resume, self.seat = wake, (sim.space, sim.seats)
        return s


    def _quieted(self, p, quiet: bool, now: int, s: int, tick_first: bool) -> None:
        """A device-only machine whose polls the run made: quiet as Python's ticks
        leave it (``StateMachine.due``): after an input event (the last the run applied,
        at its step, before its tick) it polls at its next control step, and a poll
        that finds nothing quiets it until the next event."""
        machine = self.machine
        if p.n_ev and p.ev_done:
            start, quiet = p.ev_step[p.ev_done - 1], False
        else:
            start = now if tick_first else now + 1
        if not quiet:
            every = machine.every
            first = machine.entered + machine._polled
            first = first if first > start else start
            if -(-first // every) * every < s:  # (a poll before ``s``: nothing held)
                quiet = True
        machine.quiet = quiet


def plan_for(runtime) -> PollPlan | TrackPoll | None:
    """The runtime's plan, with the kernel and its state machines, or with a KD
    tracker and none (``track_poll``); None on Python's path."""
    kern = _kernel.get()
    if kern is None or runtime.sim is None:
        return None
    if not runtime._machine_list:
        tracker = runtime.tracker
        if tracker._kern is None:
            return None
        spec = tracker.spec  # (intentional contacts: Python's; a walk in place that
        walk = spec.walk_in_place  # blends the clearance in, too)
        if spec.contacts is None and (walk is None or tracker.walk_cycle is None
                                      or spec.root.clearance not in walk.joints):
            return TrackPoll(runtime, kern, tracker._kern)
        return None
    return PollPlan(runtime, kern)
