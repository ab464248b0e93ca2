"""KD tracking's control steps between a performer's samples, in the compiled kernel.

A stream's samples come at 60 Hz or so, the tracker's control steps at 120 Hz
(``Tracker.tick``); a control step with no sample since the last one does the same
work as the last, on the figure as it is now: the same channels' joint targets
(``pk_targets``), the same performed pose and velocities (``pk_track_pose`` again
would give the same targets, the performed velocities kept as the same sample's), and
the pulls (``pk_track_pull``) on the bodies of now. When that is all a tick leaves to
do, ``TrackPoll.ready`` says so, and ``run`` hands the steps to ``pk_poll``
(``kernel_poll``) with the tracker's part of its table filled: it steps the space and
does those ticks between the steps, until the step the stream is lost at, a history
boundary or the call's end; the runtime is then rescheduled as though it had ticked in
between. A replay's samples are events of the run (``session.event_runs``'
samples-only runs, ``pk_sample``), when the view is the performer's, a get-up's, a mix
back to the performer or a library's window: the first tick after one is a sample's
(``pk_fresh``: the performed velocities and the lift; walking in place, the step
read from the performed feet, ``pk_walk_step``), as ``ready``'s ``resume`` path makes
it; else the run stops at a sample and ``ready`` fills the tick there.

It holds when the tracker follows the performer's channels plainly - KD with the
pulls, not lost, no blend into tracking, no reaction, push, step or get-up under way,
no motion library's window, no walking in place, no intentional contacts - the
tracker is the only busy controller and there is no state machine; anything else
stays on Python's path. Without the kernel there is no plan (``PUPPET_KERNEL=
python``): the same ticks run in Python, to the same bits (tests/test_track_poll.py).
"""

from __future__ import annotations

from puppet.interface.controllers.tracking import KD, PRESS, TRACK
from puppet.interface.controllers.tracking_pull import velocity_sample
from puppet.interface.poll_table import NEVER
from puppet.interface.track_poll_walk import walk_from, walk_table, walked_back


def run_stop(now: int, until: int, end: int, health: int, every: int) -> tuple[int, int]:
    """Where a kernel run from ``now`` stops: at ``until``, ``end`` or the next history
    boundary (a multiple of ``health`` that ends a frame of ``every`` steps), whichever
    comes first; and that boundary (``PollPlan.run``, ``TrackPoll.run``)."""
    last = now - now % health + health
    while last % every:
        last += health
    stop = until if until < end else end
    return (stop if stop < last else last), last


class TrackPoll:
    """The ``PollPlan`` of a runtime with a tracker and no state machine."""

    # Input events are not this plan's to apply in the kernel (``event_runs``: a
    # performer's frames and presses stay Python's), and it has no states to compile.
    _offline = True

    def prime(self) -> None:
        """Nothing to compile ahead (``PollPlan.prime``: its states' tables)."""

    def waits(self) -> bool:
        """No machine waits on the mouse (``PollPlan.waits``)."""
        return False

    def __init__(self, runtime, kern, tracker_kernel):
        self.runtime = runtime
        self.kernel = kern
        ffi = self.ffi = kern.ffi
        self.poll = kern.lib.pk_poll
        self.tk = tracker_kernel
        self.plan = p = ffi.new("pk_poll_plan *")  # (zeroed: no transitions, blends,
        p.every = 1  # frame targets or feedback)
        p.t_ticks = 0
        n = max(1, len(tracker_kernel.names))
        self._vals = ffi.new("double[]", n)
        self._has = ffi.new("char[]", n)
        self._own = ffi.new("char[]", max(1, len(tracker_kernel.target_joints)))
        self._rows = ffi.new("char[]", max(1, len(tracker_kernel.row_joints)))
        self._offline = False  # (stepping.inert: the plan reads no input)
        self._go_on = False  # a run ended last (resume), not a restore or a refusal
        self.seat = None  # (the space and seats of the last run: Session.advance's check)
        self._frame = self._root = self._space_cd = self._space_void = None
        self._ready_at = None  # the step ready last said yes at (run's check)
        self._tick_first = False  # ... and whether the tick there is the kernel's
        self._moving = False  # ... and whether its ticks change the tracker's state
        self.kernel_ticks = 0  # control steps the kernel ran (tests read it)
        self._seen = None  # (the owners, the joints the tracker gave gains): ready's
        tr = runtime.tracker
        root = tr.spec.root
        self._root_names = (root.x, root.y, root.angle)
        p.track, p.t_vals, p.t_period, p.t_weight = tracker_kernel.t, self._vals, tr.period, 1.0
        self._walk = None if tr.spec.walk_in_place is None or tr.walk_cycle is None \
            else walk_table(self, tr, n)
        self._ground_of = None  # (the scene whose ground the spans are)
        self._g_of = self._feel_of = None  # (the get-up and the bodies its rows are of)
        self._l_of = None  # (the library and the window the plan's frames are of)
        self._came, self._came_has = ffi.new("double[]", n), ffi.new("char[]", n)
        self._view, self._view_has = ffi.new("double[]", n), ffi.new("char[]", n)
        p.t_view, p.t_view_has, p.t_n = self._view, self._view_has, len(tracker_kernel.names)
        p.t_came = self._came
        p.t_soles = bool(tr.soles) and tr.ground_at is not None
        # a sample in a run of events (event_runs, pk_sample): the tracker's values,
        # then the clearance (c_xy[0]: pk_fresh's lift), when the view is the plain
        # performer's (``_sampling``, worked out at each ready)
        self.key = (*tracker_kernel.names, root.clearance)
        p.ch_t, p.t_dt, p.t_cl_sample = len(tracker_kernel.names), tr.dt, 1
        self._sampling = False

    def ready(self, step: int) -> int | None:
        """After Python's tick at ``step``, or in its place (``step`` is ``resume``:
        the tick there is the kernel's, a sample's pose with it): the step up to which
        ``pk_poll`` may run (the first control step the stream would be lost at, or a
        fall's get-up would begin), the table filled; None when the work due is not
        all its to do. Runs at every sample, so it is kept lean."""
        self._ready_at = None
        rt = self.runtime
        resume = step == self.resume and rt.now != step  # (no Python tick there: the
        self._go_on = False  # session's check of the seat sent it to Python's)
        tr = rt.tracker
        if tr.mode != KD or not tr.kinematic or tr.due or rt._pending \
                or tr.impact_at is not None \
                or tr.blend_at is not None \
                or (step - tr.phase) % tr.every:  # (a tick that was not the tracker's)
            return None
        active = rt._active
        if len(active) != 1 or active[0] is not tr:
            return None
        hold, back, walk = tr.hold, tr.back, self._walk
        lost = tr.lost
        if lost and hold is None:
            return None
        mixing = hold is not None or back is not None  # (kd_pull.mix: Tracker._view's)
        getup = tr.getup  # (the get-up's poses, before either)
        library = tr.lib is not None or tr.search_at is not None  # (a window, or a
        if library and (getup is not None or hold is not None  # search to come)
                        or (tr.lib is not None and back is not None)):
            return None
        moving = mixing or getup is not None or tr.lib is not None  # (a view the kernel
        # works out at each tick)
        if moving and (walk is not None or not self._ground_ok(tr)):
            return None
        ch, tk = tr.channels, self.tk
        view = ch if hold is None else hold[1]  # (the values the view mixes toward)
        x, y, a = self._root_names
        p = self.plan
        # without the root's place in the view _pull returns before the pulls: the
        # targets alone (the walk's view has them: the performer's)
        nopull = view.get(x) is None or view.get(y) is None or view.get(a) is None
        if (nopull and walk is not None) or (not nopull and tr.x0 is None):
            return None
        if resume:  # Tracker.tick's lost check, before anything else
            if not lost and step - tr.last_sample > tr.lost_steps:
                return None
        else:
            got = tr._kernel_tick  # the values this tick's targets and pulls read
            if got is None or got[0] != step or (not nopull and (
                    not tk.t.has_prev or tr.prev_step != tr.last_sample)) \
                    or (not moving and got[1] is not (
                        ch if walk is None else (tr._walk_out or (None, None))[1])):
                return None
        p.t_nopull = nopull
        p.l_on, p.t_weight = 0, 1.0  # (_weight * _blend: 1.0 * 1.0 but for the below)
        if getup is not None:  # (its end: Python's, back to the performer)
            p.st_on = 0
            until = None if tr.step is not None else self._getting_up(tr, tk, getup, step)
        elif library:  # (the search, the window's end: Python's)
            p.g_on = p.st_on = p.rx_on = 0
            until = None if nopull or tr.step is not None else self._library(tr, tk, step)
        else:
            p.g_on = 0
            until = self._react(tr, step)  # (a reaction's weight: the kernel's, to until)
        if until is None:
            return None
        if not self._owners(rt, tr, tk, p):
            return None
        p.t_x0 = 0.0 if tr.x0 is None else tr.x0
        if resume:  # the tick's values and its pose (Python's tick would bind the
            rt.now = step  # kernel to new bodies first: _kernel_values)
            tr._kernel_tick = None
            if walk is None:
                vals, has = tr._kernel_values(tk, step, view, fresh=True)
                if not nopull:
                    self._lift(tr, vals[0], view)
            else:  # (Tracker._view's _performer: the walk advanced, its view the kernel's)
                out = tr._walk_out
                if out is None or out[0] != step:
                    tr._walk_advance(step)
                tr._walk_out = None
            c = tr.character
            if tk.bodies_of is not c.bodies:
                tk.bind(tr._link_plan(tr._figure.rows()), c.servos)
                tk.bodies_of = c.bodies
            if nopull:
                p.t_pose = 0
            else:
                self._velocities(tr, tk)
        else:
            p.t_pose = 0
            if walk is None:
                vals, has = got[2], got[3]
        p.t_mix = mixing
        if walk is not None:  # (the view walks on at each tick: the kernel's)
            if tr.walk[8] != step or not walk_from(self, tr, walk, ch):
                return None
        elif tr.lib is not None:  # (the window's channels at each tick: the kernel's)
            self._values(ch)
        elif mixing:  # (mix(came, view, w) at each tick: the kernel's)
            self._mix_from(tr, view, hold or back)
        else:
            self._vals[0:len(vals)] = vals
            if has is None:
                p.t_has = self.ffi.NULL
            else:
                self._has[0:len(has)] = has
                p.t_has = self._has
        phase, every = tr.phase, tr.every
        p.t_phase, p.t_every = phase, every
        # the first control step whose tick finds the stream lost is Python's: pk_tick
        # stops there (samples a run applies move it on: pk_sample)
        p.t_lost, p.t_sample = 0 if lost else tr.lost_steps, tr.last_sample
        p.t_fresh, p.t_prev = 0, tr.prev_step
        # (the performer's view; a get-up's poses, which read no sample: pk_fresh's
        # velocities, its lift the get-up's; a mix back to the performer, a library
        # window: the view's values and clearance, t_cl[1], the sample's)
        self._sampling = not lost and not nopull and self._ground_ok(tr) \
            and (walk is None or self._walk_samples)
        if self._sampling:
            p.c_xy[0] = ch.get(tr.spec.root.clearance, 0.0)
        if until <= step:
            return None
        self._ready_at = step
        self._tick_first = resume
        self._moving = walk is not None or moving or tr.reaction is not None
        return until

    def _owners(self, rt, tr, tk, p) -> bool:
        """The joints and links the tracker holds (bytes for the kernel), worked out
        again when the owners changed; False when Python's tick would give gains back
        or find nothing to do."""
        table = rt.owners.table
        seen = self._seen  # (the owners as the plan last had them: the same bytes)
        if seen is not None and seen[0] == table and seen[1] == list(tr.scaled):
            return True
        scaled = list(map(table.get, tr.scaled))
        if scaled.count(TRACK) != len(scaled) or not rt.owners.holds_any(TRACK):
            return False
        own = tr._owned(table, tk.target_joints, "_every_target")
        if own is None:
            p.t_own = self.ffi.NULL
        else:
            self._own[0:len(own)] = own
            p.t_own = self._own
        rows = tr._owned(table, tk.row_joints, "_every_row")
        if rows is None:
            p.t_rows = self.ffi.NULL
        else:
            self._rows[0:len(rows)] = rows
            p.t_rows = self._rows
        self._seen = (dict(table), list(tr.scaled))
        return True

    def _getting_up(self, tr, tk, getup, step: int) -> int | None:
        """A fall's get-up (``GetUp.view``, the pulls whole, no lifting unless a foot
        or a hand touches) into the plan; the step it ends at (Python's), None when it
        cannot run (it ends now, or the fall's hold is not over: ``_weight``'s)."""
        p, reaction = self.plan, tr.reaction
        if reaction is None or reaction[0] != "fall" or step >= getup.done_at \
                or (step - reaction[1]) * tr.dt < tr.spec.reaction.fall.hold \
                or tr.hold is not None or tr.back is not None:
            return None
        p.rx_on, p.t_weight = 0, 1.0  # (_weight: the pulls whole while getting up)
        if self._g_of is not getup:  # its rows: came, then each pose's values
            self._g_of = getup
            rows = [getup.came, *getup.targets]
            names, n = tk.names, len(tk.names)
            vals, has = [], []
            for row in rows:
                got = list(map(row.get, names))
                has += [v is not None for v in got]
                vals += [0.0 if v is None else v for v in got]
            cl = tr.spec.root.clearance
            ffi = self.ffi
            self._g_keep = keep = [
                ffi.new("int[]", getup.ends), ffi.new("double[]", vals),
                ffi.new("char[]", bytes(has)),
                ffi.new("double[]", [row.get(cl, 0.0) for row in rows]),
                ffi.new("int[]", [cl in row for row in rows])]
            p.g_ends, p.g_vals, p.g_has, p.g_cl, p.g_cl_has = keep
            p.g_n, p.g_at = len(getup.ends), getup.at
            assert len(vals) == n * len(rows)
        c = tr.character
        if self._feel_of is not c.bodies:  # supported(): the feet and the hands
            self._feel_of = c.bodies
            links = [*tr.soles, *tr.spec.reaction.get_up.hands]
            self._feel = self.ffi.new("void *[]", [self.kernel.pointer(c.bodies[name]._body)
                                                  for name in links] or 1)
            p.g_feel, p.g_n_feel = self._feel, len(links)
        p.g_rise = tr.spec.reaction.get_up.rise
        p.g_on = 1
        return getup.done_at

    def _library(self, tr, tk, step: int) -> int | None:
        """A motion library's reaction into the plan: before its search the pulls at
        the case's weight (the view the performer's), then the window's channels
        (``_library_view``) at ``_library_weight``; the step Python's tick must run
        at (the search, the window's end), None when the kernel cannot."""
        p, reaction, lib = self.plan, tr.reaction, tr.library
        if reaction is None:
            return None
        low = getattr(tr.spec.reaction, reaction[0]).weight
        if tr.lib is None:
            if step >= tr.search_at:
                return None
            p.t_weight = low  # (_library_weight with no window yet)
            return tr.search_at
        index, start, offset = tr.lib
        dt, every, duration = tr.dt, tr.every, lib.duration
        if (step - start) * dt >= duration:
            return None
        key = (lib, index)
        if self._l_of != key:  # the window's clip, its columns for the values
            window = lib.windows[index]
            frames = lib.clips[window.clip][1]
            names = lib.channels
            if window.mirrored:
                names = tuple(lib.swap.get(n, n) for n in names)
            column = {name: j for j, name in enumerate(names)}  # (the last of a name)
            cols = [column.get(name, -1) for name in tk.names]
            if min(cols[:3]) < 0:  # (the window lacks the root's place: Python's)
                return None
            keep = self._l_keep = [self.ffi.new("double[]", [v for f in frames for v in f]),
                                   self.ffi.new("int[]", cols)]
            p.l_frames, p.l_col = keep
            p.l_first, p.l_len, p.l_width = window.start, len(frames), len(names)
            p.l_cl = column.get(tr.spec.root.clearance, -1)
            self._l_of = key
        p.l_start, p.l_span, p.l_rate, p.l_duration = start, lib.frames, lib.rate, duration
        p.l_offset, p.l_low = offset, low
        spec = tr.spec.reaction.library
        p.l_blend, p.l_weight = spec.blend, spec.weight
        p.rx_dt = dt
        p.l_on = 1
        c = step + every  # the window's end: the first control step at its duration
        guess = start + int(duration / dt) - 2 * every
        if guess > c:
            c += (guess - c) // every * every
        while (c - start) * dt < duration:
            c += every
        return c

    def _into(self, values: dict, vals, has):
        """``values`` in the tracker's joint order into ``vals`` (0.0 where one is
        missing); returns ``has`` marking which are there, or NULL when all are."""
        got = list(map(values.get, self.tk.names))
        n = len(got)
        if None not in got:
            vals[0:n] = got
            return self.ffi.NULL
        has[0:n] = bytes(v is not None for v in got)
        vals[0:n] = [0.0 if v is None else v for v in got]
        return has

    def _values(self, ch: dict) -> None:
        """The performer's values (and clearance) into the plan, the view's base."""
        p = self.plan
        p.t_has = self._into(ch, self._vals, self._has)
        cl = self.runtime.tracker.spec.root.clearance
        p.t_cl_has[1], p.t_cl[1] = cl in ch, ch.get(cl, 0.0)

    def _react(self, tr, step: int) -> int | None:
        """A reaction's weight (``Tracker._weight``) into the plan; the step from which
        Python's tick must run (a fall's get-up begins: ``_pull``), NEVER without one;
        None when it begins now."""
        p, reaction = self.plan, tr.reaction
        if reaction is None:
            p.rx_on = p.st_on = 0
            return None if tr.step is not None else NEVER
        case, start = reaction
        spec = getattr(tr.spec.reaction, case)
        p.rx_on, p.rx_start, p.rx_dt = 1, start, tr.dt
        p.rx_weight, p.rx_hold, p.rx_recover = spec.weight, spec.hold, spec.recover
        step_ = tr.step  # a large push's protective step (Tracker._stepped)
        p.st_on = step_ is not None
        if step_ is not None:
            r = tr.spec.reaction
            foot, p.st_start, p.st_x0, p.st_y0, p.st_x1, p.st_y1 = step_
            p.st_row = self.tk.row_of[foot]
            p.st_time, p.st_lift, p.st_low = r.step_time, r.step_lift, r.large.weight
        if case != "fall" or tr.spec.reaction.get_up is None:
            return NEVER
        dt, every = tr.dt, tr.every
        if (step - start) * dt >= spec.hold:
            return None
        c = step + every  # (each control step's own test, from a step a little before)
        guess = start + int(spec.hold / dt) - 2 * every
        if guess > c:
            c += (guess - c) // every * every
        while (c - start) * dt < spec.hold:
            c += every
        return c

    def _mix_from(self, tr, view: dict, blend) -> None:
        """``kd_pull.mix(came, view, _fraction(s, at))`` of a stand (``hold``) or of
        the way back from it (``back``), into the plan."""
        p = self.plan
        came, at = blend[0], blend[-1]
        p.t_has = self._into(view, self._vals, self._has)
        p.t_came_has = self._into(came, self._came, self._came_has)
        p.t_mix_at, p.t_mix_steps = at, tr.blend_steps
        cl = tr.spec.root.clearance
        p.t_cl_has[0], p.t_cl_has[1] = cl in came, cl in view
        p.t_cl[0], p.t_cl[1] = came.get(cl, 0.0), view.get(cl, 0.0)

    def _ground_ok(self, tr) -> bool:
        """The ground's spans in the plan (the lift of a view that moves), when the
        tracker's ground is the simulation's."""
        sim = self.runtime.sim
        if tr.ground_at is not None and sim.scene_spec is not self._ground_of:
            if tr.ground_at != sim.ground_surface:
                return False
            self._ground_of = sim.scene_spec
            self._fill_ground(sim.scene_spec)
        return True

    def _fill_ground(self, scene) -> None:
        """``Simulation.ground_surface``'s spans, as it makes them."""
        spans = [(min(x0, x1), max(x0, x1), x0, y0, x1, y1, ground.thickness / 2)
                 for ground in scene.ground
                 for (x0, y0), (x1, y1) in zip(ground.points, ground.points[1:])
                 if x1 != x0]
        self._spans = self.ffi.new("double[]", [v for span in spans for v in span] or [0.0])
        self.plan.spans, self.plan.n_spans = self._spans, len(spans)
        if self._walk is not None:
            self._walk.spans, self._walk.n_spans = self._spans, len(spans)

    def _lift(self, tr, x: float, view) -> None:
        """``Tracker._pull_kernel``'s lift on the ground under the figure, for
        ``pk_track_pose``, into the plan."""
        p = self.plan
        lift, ground, extra = 0, 0.0, 0.0
        if tr.soles and tr.ground_at is not None:
            ground = tr.ground_at(tr.x0 + x)
            if ground is None:
                ground = 0.0
            else:
                lift = 1
                clearance = view.get(tr.spec.root.clearance, 0.0)
                extra = clearance if clearance > 0.0 else -PRESS
        p.t_lift, p.t_ground, p.t_extra = lift, ground, extra

    def _velocities(self, tr, tk) -> None:
        """... and the performed velocities' sample (a sample's tick: the pose)."""
        p = self.plan
        vel, h = velocity_sample(tr, tk.t)
        p.t_pose, p.t_vel, p.t_h = 1, vel, h

    def run(self, space_ptr, dt: float, now: int, until: int, end: int, health: int,
            frame: tuple, tick_first: bool = False) -> int:
        """``PollPlan.run``: step from ``now`` (Python ticked there) with ``pk_poll``
        up to ``until``, ``end`` or the next history boundary; the runtime is then
        rescheduled from the step it returns."""
        assert self._ready_at == now and tick_first == self._tick_first
        self._ready_at = None
        p = self.plan
        if frame is not self._frame:
            self._frame, self._root = frame, None
            p.frame_every, _, p.x0, p.x1, p.y0, p.y1, p.max_speed2 = frame
        stop, _ = run_stop(now, until, end, health, frame[0])
        rt = self.runtime
        bodies = rt.character.bodies
        if bodies is not self._root:  # (a re-seat makes new bodies)
            self._root, p.root = bodies, self.kernel.pointer(bodies[frame[1]]._body)
        if space_ptr is not self._space_cd:
            self._space_cd, self._space_void = space_ptr, self.kernel.pointer(space_ptr)
        s = self.poll(self._space_void, dt, now, stop, p, 1 if tick_first else 0)
        ticks = p.t_ticks
        self.kernel_ticks += ticks
        tr = rt.tracker
        if p.ev_done and p.ch_n:  # samples applied (pk_sample): Tracker.sampled's
            tr.last_sample, tr.phase = p.t_sample, p.t_phase  # (the values: event_runs)
        tr.prev_step = p.t_prev  # (velocity_sample's, at the samples' ticks: pk_fresh)
        if ticks:
            tr._kernel_tick = None  # (Tracker.tick's: the channels may change next)
            if self._moving:
                self._handed_back(tr, p, ticks > tick_first)
        # rt._reschedule(s), for what ``ready`` allows: the tracker alone
        phase, every = tr.phase, tr.every
        wake = phase - (-(s - phase) // every) * every  # (Tracker.next_wakeup)
        rt._controllers_wake = wake
        rt.next_wakeup = wake = wake if wake > s else s
        # the next tick may be the kernel's (``resume``; ``ready`` says, after what
        # comes first: an event, a sample mostly, a history boundary), on this seat
        sim = rt.sim
        self._go_on, self.seat = True, (sim.space, sim.seats)
        return s

    def _handed_back(self, tr, p, walked: bool) -> None:
        """What the kernel's ticks changed of the tracker's state, into it."""
        if p.walk != self.ffi.NULL:
            if walked:
                walked_back(self, tr)
            p.walk = self.ffi.NULL
        back = tr.back  # (Tracker._view: back at the performer's, the blend done)
        if back is not None and (tr.blend_steps <= 0 or p.t_last - back[1] >= tr.blend_steps):
            tr.back = None
        if p.rx_on and p.rx_done >= 0:  # (Tracker._weight: the reaction over)
            tr.reaction = tr.step = None
        if p.g_on:  # (the HUD's pose: the step last followed)
            tr.getup_step = p.t_last

    def sampled(self) -> tuple | None:
        """The channel names a sample stores for the kernel (``event_runs``: the
        tracker's values, then the clearance) when its next run may apply samples."""
        return self.key if self._sampling else None

    @property
    def resume(self) -> int:
        """The step whose tick the kernel may run, before Python's (Session.advance
        asks ``ready`` there first): the next wake-up after a run of its own (an event
        in between - a sample that moved the control steps to itself too - is judged
        by ``ready``), else -1 (a restored state ticks in Python first)."""
        wake = self.runtime.next_wakeup
        return wake if self._go_on and wake is not None else -1

    @resume.setter
    def resume(self, step: int) -> None:
        self._go_on = self._go_on and step >= 0  # (-1: a restore's)
