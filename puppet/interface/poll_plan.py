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
(``poll_states``: armed by ``poll_fill``, handed back after the call).

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
the same ticks run in Python, to the same bits. A state's transitions are read as
rows by ``poll_table`` and written into the table by ``poll_fill``.
"""

from __future__ import annotations

from puppet.interface.controllers.tracking import OFF
from puppet.interface.ownership import BLEND, SEQUENCE
from puppet.interface.poll_feed import feed, runs
from puppet.interface.poll_fill import MAX_CONDITIONS, NEVER, fill, held_again
from puppet.interface.poll_machines import joint_table, quiet_now, since_back, since_into
from puppet.interface.poll_reach import fill_grasps, fill_reaches
from puppet.interface.poll_states import States
from puppet.interface.poll_table import sequence_until, state_table
from puppet.interface.poll_track import SAMPLE, may_track, track_part
from puppet.interface.poses import made_frame_target
from puppet.interface.track_poll import TrackPoll, run_stop
from puppet.physics import kernel as _kernel

NAN = float("nan")  # a device input not set (the plan's in_val)


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
        self._held: list = []  # the plan's transitions with a `for` (poll_fill)
        self._travelling: dict = {}  # joint -> its travel's index, a frame target's (poll_fill)
        self._com = False  # the plan reads the centre of mass (the fall time: gravity)
        self._velocity = 0  # the plan's polls read VELOCITY: 1 a machine, 2 an until
        self._inputs = False  # the plan reads device inputs (in_val, at each ready)
        self._live = False  # the state's table reads no input but those (LIVE)
        self.resume = -1  # where the next call may go on, its tick the kernel's (see run)
        self.seat = None  # and the space it ran on then (a re-seat lists no contacts)
        self._root = self._space_cd = self._space_void = self._feeding = None  # (run)
        self._states = States(self)  # transitions the loop takes (poll_states)
        self._armed = False  # (the plan's states table armed by the last fill)
        self._angles = None  # (poll_track.AngleTrack: a tracker's angles, made once)

    def pointer(self, cdata):
        """``kernel.pointer``, remembered (``physics.kernel.remembered``)."""
        return _kernel.remembered(self.kernel, self._pointers, cdata)

    def prime(self) -> None:
        """Every state's table and every sequence step's ``until``, made when the
        runtime is (a state's first entry in a replay would make them between its
        steps, as cold as the rest of the entry)."""
        for machine in self.runtime._machine_list:
            for state in machine.spec.states:
                state_table(self, machine, state)
        for name, steps in self.runtime.sequences.specs.items():
            for index in range(len(steps)):
                sequence_until(self, name, index)
        self._states.prime(self.runtime)  # (the loop's states tables: poll_states)

    def _state_table(self):
        """The current state's table (looked up once per state and binding)."""
        rt, machine = self.runtime, self.machine
        if self._many:
            return joint_table(self)  # (its device-only machines: Python's; _live False)
        if machine.current is not self._state or rt.roles.binding is not self._binding:
            self._state, self._binding = machine.current, rt.roles.binding
            self._current = table = state_table(self, machine)
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
            feeding = feedback.compiled()  # (Feedback.tick's own compiled call; None:
            if (feeding is None and not runs(feedback)) \
                    or feedback.every != machine.every:  # poll_feed's, armed)
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
        # (an armed plan no longer usable - a press kept for a state, a reach, sensor
        # maps, begun by an event since the fill - is filled again and so disarmed)
        key = (machine.entered, machine.quiet and not self._live, sim.seats, every, seq,
               tuple(moving.items()), self._armed and self._states.stale(rt))
        if table is not self._filled or sim.space is not self._space or key != self._key \
                or self._offline:
            self._filled, self._space, self._key = table, sim.space, key
            self._frames_ids, self._frames_kept = frames_ids, frames_now
            self._offline = not machine.quiet and any(  # (a quiet state polls nothing)
                kind is None for _, cs, *_ in table if cs for kind, *_ in cs)
            self._until = fill(self, table, machine, every, seq)
        elif frames_ids != self._frames_ids:  # only held again (a frame map, each event)
            self._frames_ids, self._frames_kept = frames_ids, frames_now
            if not held_again(self, held):
                self._until = fill(self, table, machine, every, seq)
        if self._armed and self._states.fb_on:  # (feedback's rows follow the states)
            feeding = feed(feedback, sim.space)
        elif feeding is None:
            return None
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
        p.ev_at_stop = until < end and until < last  # (the events there, then the tick)
        rt = self.runtime
        root = rt.character.bodies[frame[1]]._body
        if root is not self._root:  # (held: the same object is the same body)
            self._root, p.root = root, self.pointer(root)
        if space_ptr is not self._space_cd:
            self._space_cd, self._space_void = space_ptr, self.pointer(space_ptr)
        machine = self.machine
        quiet = machine.quiet
        s = self.poll(self._space_void, dt, now, stop, p, tick_first)
        if p.ev_done and p.ch_n or p.c_n and p.track:  # (samples applied, contacts
            self._angles.handed_back()  # swung: the tracker's part, poll_track)
        handed = self._armed and p.states.n_log  # (states entered, targets arrived)
        entered = handed and self._states.handed_back(rt, machine)
        if entered:
            self._state_table()  # (the plan holds its rows, as poll_fill writes them)
        if self._live and machine.device_only:
            self._quieted(p, quiet and not entered, now, s, tick_first)
        if handed:  # what ready's key finds now: the plan as the loop left it (a state
            self._filled, sim = self._current, rt.sim  # entered: no `for`s)
            self._held = self._states.held_rows() if entered else self._held
            self._key = (machine.entered, machine.quiet and not self._live, sim.seats,
                         machine.every, None, tuple(rt.blends.moving.items()), False)
            # (ready's last part: the table armed still the one to use - a press kept
            # since, other work begun: True there, so filled again)
        if self._armed and self._states.fb_on:  # (each state's rows: poll_feed)
            self._states.fed_back(rt, s)
        elif p.fb_ticks:  # the sensors' readings handed back (base and last: the kernel's)
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
        wake, full = None, handed
        for controller in () if handed else rt._active:
            at = controller.next_wakeup(s)
            if at is None:  # (done: feedback's additions taken back, poll_feed)
                full = True
                break
            if wake is None or at < wake:
                wake = at
        if full:  # (the controllers with work may be others: the full one)
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
        k = p.ev_done - 1 if p.n_ev else -1
        while k >= 0 and p.ev_kind[k] == SAMPLE:  # (a sample stirs no machine)
            k -= 1
        if k >= 0:
            start, quiet = p.ev_step[k], False
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
