"""Runs of input events inside the kernel's stepping loop: a replay's mouse moves and
stick events applied by ``pk_poll`` at their steps (``physics.kernel_poll``'s
``pk_events``), between Chipmunk's steps, instead of stopping the loop for each.

On Luxo a physics step is 2-3 us and a mouse move or a stick comes every 2-5 steps;
each one stopping the kernel's loop (the stepping loop's head, the runtime's
``on_event``, the history, the kernel's call again) cost 3-4 us, as much as the steps
between two events (luxo-headstand and luxo-gamepad-hop: 21-30 % control overhead,
nearly all of it their events). The kernel takes a run of them when all an event
does is what ``InterfaceRuntime.on_event`` does on its hot path with the runtime as it
is now: store the input, and run the active maps reading it, each of them a plain map
(``maps._plain_run``'s rows: one joint, clamped, linear; written operation for
operation in C, so the targets have the same bits; a clamped linear map on several
joints gives a row a joint, ``maps._compile_linear``'s ``plain_run``) on a joint no
controller owns (the owners' table would take it back), one run of pose grids on the
mouse's x and y (the cat's legs: ``maps._grid_run``'s table, ``pk_grid_run`` after the
rows, on joints no row writes), or a frame map (``maps._compile_frame``'s: clamped,
linear, held under the frame owner) on a joint the poll plan's frame loop already
holds under it, in the same frame (the walkers' mouse: their swing and stance hips
held in the world), which the kernel holds at the map's new angle and solves at once
(``FrameTargets.holder``'s ``hold_at``), with nothing pending, no machine in a state
that polls device inputs alone (an event stirs it) and, when the state's table is the
kernel's, no input read by its conditions (decided when the plan was filled); the
idle loop (no plan, no frame targets) takes them when no frame target is held. After
the call the events it applied are recorded in the history, the inputs hold the last
values and the frame targets the last angles (new targets, as ``hold_at`` makes), as
after ``on_event`` one by one; the first event it cannot apply ends the call there,
for the stepping loop to apply as ever.

A performer's samples (``channels`` events) are the runs' too when the poll plan's
tracker takes them (``interface.poll_track``: an angles tracker beside a machine, its
intentional contacts' hands after its values; ``interface.track_poll``: a KD tracker
alone, runs of samples only, the clearance after its values): ``pk_sample`` stores
each one's values of the tracker's channels (``samples``: made once per window and
names; a value not a number within HUGE is Python's) and moves the tracker's last
sample and phase; ``applied`` stores them in the runtime's channels, as ``flush``
does, and the plan hands the tracker's state back. No active map may read a channel.
"""

from __future__ import annotations

from puppet.interface.ownership import FRAME
from puppet.interface.poll_track import SAMPLE  # (a performer's sample; -1: Python's)
from puppet.interface.poses import made_frame_target
from puppet.interface.track_poll import TrackPoll
from puppet.physics.kernel import remembered

MOUSE = 0  # an event's kind: a mouse move; 1, 2...: a gamepad event by its name
MOUSE_NAMES = ("mouse.x", "mouse.y")
NUMBERS = (float, int, bool)  # a mouse move's values the kernel takes (else Python's)
HUGE = 1e300  # and only within this (an int past a double's range stays Python's)
BOUND = 1 << 30  # steps the kernel's int holds
POINTER_NAMES = ("pointer.x", "pointer.y")


WINDOW = 512  # events a window of arrays holds (made when a run first reaches them)


class EventArrays:
    """A window of an events list ((step, event) pairs), ``events[lo:hi]``, as the
    kernel reads it: per event its step, its kind (-1: not the kernel's) and its two
    values, and where the run that starts at each must end (``brk``: the next event of
    no kind, one whose step goes back (a scrub's mouse), or the window's end)."""

    def __init__(self, ffi, events, lo: int = 0, hi: int | None = None,
                 names: list | None = None):
        hi = len(events) if hi is None else min(hi, len(events))
        self.events, self.lo, self.hi = events, lo, hi
        self.names: list[str] = [] if names is None else names  # kind k >= 1: a gamepad
        kinds = {name: k + 1 for k, name in enumerate(self.names)}  # event's name
        steps, kind, v = [], [], []
        add_step, add_kind, add_v = steps.append, kind.append, v.append
        names = self.names
        for at, event in events[lo:hi]:
            t = event["type"]
            if type(at) is int and -BOUND < at < BOUND:
                if t == "mouse":  # (the values on_event computes with: numbers)
                    x, y = event.get("x"), event.get("y")
                    if type(x) in NUMBERS and type(y) in NUMBERS \
                            and -HUGE < x < HUGE and -HUGE < y < HUGE:
                        add_step(at), add_kind(MOUSE), add_v(x), add_v(y)
                        continue
                elif t == "channels" and type(event.get("values")) is dict:
                    add_step(at), add_kind(SAMPLE), add_v(0.0), add_v(0.0)  # (its values:
                    continue  # samples, per tracker)
                elif t == "gamepad" and type(event.get("name")) is str:
                    try:  # (on_event's float())
                        x = float(event["value"])
                    except (KeyError, TypeError, ValueError, OverflowError):
                        pass  # (an int past a double's range: Python's, as it raises)
                    else:
                        name = event["name"]
                        k = kinds.get(name)
                        if k is None:
                            names.append(name)
                            k = kinds[name] = len(names)
                        add_step(at), add_kind(k), add_v(x), add_v(0.0)
                        continue
            add_step(at if type(at) is int and -BOUND < at < BOUND else 0)
            add_kind(-1), add_v(0.0), add_v(0.0)
        n = hi - lo
        brk = [hi] * (n + 1)
        for k in range(n - 2, -1, -1):
            m = k + 1
            brk[k] = lo + m if kind[m] == -1 or steps[m] < steps[k] else brk[m]
        self.brk = brk
        self._samples: dict = {}  # channel names -> their values per event (samples)
        self.step = ffi.new("int[]", steps + [0])
        self.kind = ffi.new("int[]", kind + [-1])
        self.v = ffi.new("double[]", v + [0.0, 0.0])


    def samples(self, ffi, names: tuple) -> tuple:
        """Per event of the window, ``names``' values in a sample (0.0 elsewhere) and
        whether it has each (2: a value Python's tick takes, not a number within HUGE,
        or NaN: the kernel's run stops there): ``pk_sample``'s rows, made once per
        window and names."""
        got = self._samples.get(names)
        if got is None:
            vals, has = [], []
            zeros, nones = [0.0] * len(names), bytes(len(names))
            for (_, event), kind in zip(self.events[self.lo:self.hi], self.kind):
                if kind == SAMPLE:
                    values = event["values"]
                    row = [values.get(n) for n in names]
                    for v in row:
                        if v is None:
                            vals.append(0.0)
                            has.append(b"\0")
                        elif type(v) in NUMBERS and -HUGE < v < HUGE:
                            vals.append(float(v))
                            has.append(b"\1")
                        else:
                            vals.append(0.0)
                            has.append(b"\2")
                else:
                    vals += zeros
                    has.append(nones)
            got = self._samples[names] = (ffi.new("double[]", vals or [0.0]),
                                          ffi.new("char[]", b"".join(has) or b"\0"))
        return got


class EventRuns:
    """A session's runs of events in the kernel: the events lists' arrays and the map
    rows of the runtime as it is (made again when its maps, binding or seat change)."""

    def __init__(self, kern):
        self.kernel, self.ffi = kern, kern.ffi
        self._arrays: dict[int, EventArrays] = {}
        self._entries: dict[tuple, _Rows] = {}  # the maps' ids -> their rows
        self._entry: _Rows | None = None  # the last used
        self._written: dict = {}  # a plan -> the entry whose rows it points at
        self._pointers: dict = {}
        # the frame maps' holds of the last run started: (kind, joint, its row in the
        # poll plan's frame targets, ref, hold_parent)
        self._holds: list = []
        self._maps_of, self._maps_read = None, False  # (_sampled: the active maps read a
        # channel)

    def arrays(self, events, i: int) -> EventArrays:
        """The window of ``events`` holding ``events[i]`` (made at ``i`` when none
        does; a gamepad name keeps its kind from window to window)."""
        got = self._arrays.get(id(events))
        if got is None or got.events is not events or not got.lo <= i < got.hi:
            if len(self._arrays) > 4:
                self._arrays.clear()
            names = got.names if got is not None and got.events is events else None
            got = self._arrays[id(events)] = EventArrays(self.ffi, events, i, i + WINDOW,
                                                         names)
        return got

    def _pointer(self, cdata):
        return remembered(self.kernel, self._pointers, cdata)

    def start(self, plan, runtime, events, i: int, cap: int, tail: int | None,
              poll=None) -> int | None:
        """Hand ``events[i:]`` (the first due at the stretch's end) to ``plan`` for its
        next ``pk_poll`` call: the step the stretch may run on to (at most ``cap``; once
        the events run out, ``tail``: where the replay runs on to, or the last event's
        step), or None when the first is not the kernel's to apply. ``poll``: the
        runtime's ``PollPlan`` when the call is its (None: the idle loop's)."""
        if runtime._pending or (poll is None and runtime.frames.held):
            return None  # (the idle loop holds no frame targets)
        if poll is not None:
            if type(poll) is TrackPoll:  # (a KD tracker's: samples alone)
                return self._samples_only(plan, runtime, events, i, cap, tail, poll)
            if poll._offline:  # (an input the plan's table decided when it was filled)
                return None
            live = poll._live  # (the plan's one machine polls its inputs in the kernel)
        else:
            live = False
        for machine in runtime._device_machines:
            if machine.device_only and not live:
                return None
        arrays = self.arrays(events, i)
        kinds = self._kinds(runtime, arrays)
        lo = arrays.lo
        first = arrays.kind[i - lo]
        names = None if poll is None else self._sampled(poll, runtime)
        if first == SAMPLE:
            if names is None:
                return None
        elif first < 0 or first >= len(kinds) or kinds[first] is None:
            return None
        table = runtime.owners.table
        entry = self._entry
        if table:  # a joint a controller owns: the map takes it back (Python's)
            k_first = entry.rows[0]
            for k, written in enumerate(entry.joints):
                if written is not None and any(j in table for j in written):
                    k_first[k] = -1
                    entry.off.append(k)
                    if k == first:
                        return None
        if entry.holds:
            if not self._held(entry, runtime, poll, first):
                return None
        else:
            self._holds = []
        j = arrays.brk[i - lo]
        reach = _reach(events, i, j, cap, tail)
        if reach is None:
            return None
        plan.n_ev = j - i
        plan.ev_step, plan.ev_kind, plan.ev_v = arrays.step + (i - lo), \
            arrays.kind + (i - lo), arrays.v + 2 * (i - lo)
        if names is None:
            if poll is not None:
                plan.ch_n = 0  # (a sample ends the run: Python's)
        else:
            vals, has = arrays.samples(self.ffi, names)
            n = plan.ch_n = len(names)
            plan.ch_v, plan.ch_has = vals + n * (i - lo), has + n * (i - lo)
        entry = self._entry
        if self._written.get(plan) is not entry:  # (the rows this plan points at)
            if len(self._written) > 8:  # (the plans of runtimes gone: a reload's)
                self._written.clear()
            self._written[plan] = entry
            rows = entry.rows
            plan.n_kind, plan.k_first, plan.k_last = len(kinds), rows[0], rows[1]
            plan.k_grid = self.ffi.NULL if entry.grids is None else entry.grids
            (plan.m_use, plan.m_x0, plan.m_inv, plan.m_lo, plan.m_span, plan.m_gain,
             plan.m_spring, plan.m_frame) = rows[2:]
        return reach

    def _samples_only(self, plan, runtime, events, i: int, cap: int, tail: int | None,
                      poll) -> int | None:
        """``start`` for a KD tracker's ``TrackPoll``: a run of samples alone (the
        first other event ends it: no map rows, ``n_kind`` 0), when its plan takes
        them (``TrackPoll.sampled``) and no active map reads a channel."""
        names = poll.sampled()
        if names is None or self._reads_channels(runtime):
            return None
        arrays = self.arrays(events, i)
        lo = arrays.lo
        if arrays.kind[i - lo] != SAMPLE:
            return None
        j = arrays.brk[i - lo]
        reach = _reach(events, i, j, cap, tail)
        if reach is None:
            return None
        plan.n_ev, plan.n_kind = j - i, 0
        plan.ev_step, plan.ev_kind, plan.ev_v = arrays.step + (i - lo), \
            arrays.kind + (i - lo), arrays.v + 2 * (i - lo)
        vals, has = arrays.samples(self.ffi, names)
        n = plan.ch_n = len(names)
        plan.ch_v, plan.ch_has = vals + n * (i - lo), has + n * (i - lo)
        return reach

    def _reads_channels(self, runtime) -> bool:
        """An active map reads a channel (``_on_channels`` runs it: Python's)."""
        maps = runtime.active_maps
        if maps is not self._maps_of:  # (per set of active maps: a state's)
            self._maps_of = maps
            self._maps_read = any(not m.feedback and any(
                i.startswith("channel.") for i in m.inputs) for m in maps)
        return self._maps_read

    def _sampled(self, poll, runtime) -> tuple | None:
        """The channel names a performer's sample stores for ``poll``'s angles tracker
        when the kernel may apply samples (``pk_sample``), else None: the tracker's
        part in the plan (``poll_track``: an angles tracker, not lost; its intentional
        contacts' hands after its angles) and no active map reading a channel
        (``_on_channels`` runs none then)."""
        track = poll._angles
        if track is None or not track._on or not track.key:
            return None
        return None if self._reads_channels(runtime) else track.key

    def _held(self, entry: _Rows, runtime, poll, first: int) -> bool:
        """The frame maps' rows pointed at the poll plan's frame targets they hold: a
        kind whose frame map holds a joint the plan does not hold in the same frame
        under the frame owner (or travelling in a blend, or with no plan: the idle
        loop's) turned off (Python's: its hold changes what the plan holds). False
        when that is the first event's kind."""
        rows = None if poll is None else poll._frame_rows
        at = {} if rows is None else {row[0]: n for n, row in enumerate(rows)}
        travelling = {} if poll is None else poll._travelling
        held, owners = runtime.frames.held, runtime.owners.table
        m_frame, k_first = entry.rows[-1], entry.rows[0]
        self._holds = holds = []
        for k, kind_holds in enumerate(entry.holds):
            if not kind_holds or k_first[k] < 0:
                continue
            for r, joint, ref, hold_parent in kind_holds:
                n = at.get(joint)
                if n is None or rows[n][1] != ref or rows[n][2] != hold_parent \
                        or joint in travelling or owners.get(joint) != FRAME \
                        or held.get(joint, (None, None))[1] != FRAME:
                    k_first[k] = -1
                    entry.off.append(k)
                    if k == first:
                        return False
                    break
                m_frame[r] = n
                holds.append((k, joint, n, ref, hold_parent))
        return True

    def _kinds(self, runtime, arrays) -> list:
        """Per kind, its rows' (first, last) in the kernel's arrays (None: Python's),
        for the maps its event runs now; the rows made once per set of maps (a state
        entered changes the mode's), their springs written again after a re-seat."""
        sim = runtime.sim
        entry = self._entry
        if not arrays.names and entry is not None and len(entry.objects) == 2 \
                and entry.objects[0] is runtime and entry.objects[1] is runtime._mouse_maps \
                and entry.sim is sim and entry.seats == sim.seats:  # (the mouse's, as
            entry.restore()  # last time: the commonest call)
            return entry.spans
        binding = runtime.roles.binding
        sticks = []
        for ename in arrays.names:
            name = runtime._stick_names[ename]
            compiled = None
            if name is not None and not (runtime._pointer and runtime._pointer_axes.get(name)):
                compiled = runtime._input_maps.get((binding, (name,)))
            sticks.append((name, compiled))
        objects = (runtime, runtime._mouse_maps, *[c for _, c in sticks])
        key = tuple(map(id, objects))
        entry = self._entries.get(key)
        if entry is None or any(a is not b for a, b in zip(entry.objects, objects)):
            if len(self._entries) > 32:
                self._entries.clear()
                self._written.clear()
            entry = self._entries[key] = self._made(runtime, sticks, objects)
        self._entry = entry  # (the plan's arrays: this entry's)
        entry.restore()
        if sim is not entry.sim or sim.seats != entry.seats:  # a re-seat: new springs
            entry.sim, entry.seats = sim, sim.seats
            spring, pointer = entry.rows[-2], self._pointer
            for r, servo in enumerate(entry.servos):
                if servo is not None:  # (a frame map's row: the plan's spring)
                    spring[r] = pointer(servo.spring._constraint)
            for bind in entry.binds:  # (the pose grids' tables: their own springs)
                bind()
        return entry.spans

    def _made(self, runtime, sticks, objects) -> _Rows:
        mouse_names = MOUSE_NAMES + (POINTER_NAMES if runtime._pointer else ())
        frames = runtime.frames
        grids: list = [None]  # per kind: its pose grids' (table, bind, joints), or None
        per_kind = [_plain_rows(runtime._mouse_maps, mouse_names, frames, grids)]
        for name, compiled in sticks:
            grids.append(None)
            per_kind.append(None if compiled is None else
                            _plain_rows(compiled, (name,), frames, grids))
        rows, spans, joints, holds = [], [], [], []
        for got, grid in zip(per_kind, grids):
            if got is None:
                spans.append(None)
                joints.append(None)
                holds.append(None)
                continue
            spans.append((len(rows), len(rows) + len(got)))
            joints.append(tuple(r[7] for r in got if r[8] is None) + (grid[2] if grid else ()))
            holds.append([(len(rows) + n, r[7], *r[8]) for n, r in enumerate(got)
                          if r[8] is not None])
            rows.extend(got)
        ffi, nk, nr = self.ffi, len(spans), max(1, len(rows))
        k_first, k_last = ffi.new("int[]", nk), ffi.new("int[]", nk)
        arrays_ = [ffi.new("int[]", nr)] + [ffi.new("double[]", nr) for _ in range(5)] + \
            [ffi.new("void *[]", nr), ffi.new("int[]", nr)]
        use, x0, inv, lo, span, gain, _, m_frame = arrays_
        for k, s in enumerate(spans):
            k_first[k], k_last[k] = (-1, -1) if s is None else s
        for r, (u, a, b, c, d, g, _, _, frame) in enumerate(rows):
            use[r], x0[r], inv[r], lo[r], span[r], gain[r] = u, a, b, c, d, g
            m_frame[r] = -1 if frame is None else 0  # (a frame row's: set at each start)
        got = _Rows(objects, spans, joints, (k_first, k_last, *arrays_), [r[6] for r in rows],
                    holds if any(holds) else None)
        if any(g is not None for g, s in zip(grids, spans) if s is not None):
            got.grids = ffi.new("pk_grid_table *[]", nk)
            for k, (g, s) in enumerate(zip(grids, spans)):
                if g is not None and s is not None:
                    got.grids[k] = g[0]
                    got.binds.append(g[1])
        return got

    def applied(self, session, plan, events, i: int, on_event, rebuilding: bool) -> int:
        """The events ``plan``'s call applied, recorded and stored as ``feed`` does one
        by one (``recorded``, the runtime's inputs, the frame maps' holds at their last
        angles); the next event's index."""
        done = plan.ev_done
        plan.n_ev = 0
        if not done:
            return i
        runtime, history = session.runtime, session.history
        inputs = runtime.inputs
        j = i + done
        run = events[i:j]
        if on_event is not None:
            for k in range(i, j):
                on_event(k, events[k][1])
        if not rebuilding:  # (recorded, each: the listener is None in a run)
            if run[0][0] < history.head:
                history.branch(run[0][0])
            seq = history.next_seq
            history.events.extend([(seq + k, at, event) for k, (at, event) in enumerate(run)])
            history.next_seq = seq + done
        mouse = None
        sticks, channels = runtime._stick_names, runtime.channels
        for _, event in run:
            kind = event["type"]
            if kind == "mouse":
                mouse = event
            elif kind == "channels":  # (flush's: the tracker's last_sample and phase are
                channels.update(event["values"])  # handed back by poll_track)
            else:
                inputs[sticks[event["name"]]] = float(event["value"])
        if mouse is not None:
            inputs["mouse.x"] = mouse["x"]
            inputs["mouse.y"] = mouse["y"]
            if runtime._pointer:
                inputs["pointer.x"], inputs["pointer.y"] = mouse["x"], mouse["y"]
        if self._holds:  # each joint a frame map held: a new target at its last angle
            kinds = set(self.ffi.unpack(plan.ev_kind, done))
            held, angle = runtime.frames.held, plan.f_angle
            for k, joint, n, ref, hold_parent in self._holds:
                if k in kinds:
                    held[joint] = (made_frame_target(ref, angle[n], hold_parent), FRAME)
        return j


def _reach(events, i: int, j: int, cap: int, tail: int | None) -> int | None:
    """The step a run of ``events[i:j]`` may go on to (``start``'s): the next event's
    (the last's when a step goes back), once they run out ``tail``, at most ``cap``;
    None when that is not past the first's step."""
    last = events[j - 1][0]
    if j >= len(events):  # (the events run out: the loop's target, as ever)
        reach = last if tail is None or tail < last else tail
    else:
        at = events[j][0]
        reach = last if at < last else at  # (a step that goes back: the last passed)
    reach = cap if reach > cap else reach
    return None if reach <= events[i][0] else reach  # (nothing to run on over)


class _Rows:
    """The kernel's rows for one set of maps (``EventRuns._kinds``)."""

    def __init__(self, objects, spans, joints, rows, servos, holds=None):
        self.objects = objects  # (the runtime, its mouse maps, each stick's maps)
        self.spans = spans  # per kind: its rows' (first, last), None: Python's
        self.joints = joints  # per kind: the joints its plain maps write
        self.rows = rows  # (kinds' first, last, the rows' arrays), kept alive
        self.servos = servos  # per row: its servo (its spring: the seat's; None: a
        # frame map's, whose spring is the plan's)
        self.holds = holds  # per kind: its frame maps' (row, joint, ref, hold_parent);
        # None: no frame maps
        self.sim = self.seats = None  # the seat the rows' springs are of
        self.off: list = []  # the kinds turned off for the owners' table (start)
        self.grids = None  # per kind: its pose grids' table (NULL: none; None: no kind's), and
        self.binds: list = []  # the calls that bind those tables to the seat's springs

    def restore(self) -> None:
        """The kinds ``start`` turned off, on again."""
        if self.off:
            k_first, spans = self.rows[0], self.spans
            for k in self.off:
                k_first[k] = spans[k][0]
            self.off = []


def _plain_rows(appliers, names: tuple, frames=None, grids: list | None = None) -> list | None:
    """The rows of ``appliers`` when every one is plain on ``names`` (the values the
    event sets), or a frame map on them holding its joints under the frame owner in
    ``frames``: (which value, x0, inv, lo, span, gain, servo, joint, frame), ``frame``
    None (a plain map's) or (ref, hold_parent) (a frame map's, whose servo is None);
    else None. A joint a frame map holds is written by no other row. One run of pose
    grids on the event's two values (x then y: ``maps._grid_run``'s, in the kernel)
    may come among them, on joints no row writes: ``grids[-1]`` is set to its
    (table, bind, joints)."""
    rows, grid = [], None
    for apply in appliers:
        run = getattr(apply, "plain_run", None)
        if run is None:
            plain = getattr(apply, "plain", None)
            if plain is None and grids is not None and hasattr(apply, "grid_run"):
                table, bind, x_name, y_name, joints = apply.grid_run
                if grid is not None or x_name not in names or y_name not in names \
                        or names.index(x_name) % 2 != 0 or names.index(y_name) % 2 != 1:
                    return None
                grid = (table, bind, joints)
                continue
            if plain is None:
                held = getattr(apply, "frame_run", None)
                if held is None:
                    return None
                name, x0, inv, lo, span, where, joints = held
                if name not in names or where is not frames:
                    return None
                for g, joint, ref, hold_parent, owner in joints:
                    if owner is not None and owner != FRAME:
                        return None
                    rows.append((names.index(name) % 2, x0, inv, lo, span, g, None, joint,
                                 (ref, bool(hold_parent))))
                continue
            run = (plain[0], (plain[1],))
        source, params = run
        if source is not None:
            return None
        for name, x0, inv, lo, span, gain, servo, joint in params:
            if name not in names:
                return None
            rows.append((names.index(name) % 2, x0, inv, lo, span, gain, servo, joint, None))
    holding = [r[7] for r in rows if r[8] is not None]
    if holding and len({r[7] for r in rows}) < len(rows):
        return None  # (a joint held and written again: its owner changes, Python's)
    if grid is not None:
        if set(grid[2]) & {r[7] for r in rows} or len(set(grid[2])) < len(grid[2]):
            return None  # (a joint written twice: the order matters, Python's)
        grids[-1] = grid
    return rows
