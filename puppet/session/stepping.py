"""The session's one stepping loop: input events applied at their steps and the
physics stepped between them, in one call (``feed``).

Every path that moves a session on comes here: ``Session.advance`` (the window's live
play: no events, its input goes through ``Session.handle`` first), the replays'
``playback.play`` and ``LogFeeder`` (the window's replay, the export, the ghost, the
benchmark). Why one call for a run of events: on Luxo a physics step is 2.3 us, and a
mouse event comes every 2-5 steps, so re-entering ``advance`` once per event (its
locals, the space's queue check, the history's bookkeeping: about 3 us) cost more than
the steps. Here they are set up once per call, and a mouse event is recorded and
applied in place (``Session.handle``'s frequent branch, the same statements); any
other event goes through ``Session.handle`` and the loop then takes everything up
again from the session (a reset, a restore, a reload or a rewind may have changed
it). The steps between two events are exactly one ``advance`` of them, so where a
run stops, what it checks and which ticks are the kernel's do not depend on the
caller (``tests/test_feed.py`` compares a replay with the event-by-event one).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING

from pymunk._chipmunk_cffi import lib as _cp

from puppet.interface.app_keys import SIM_ACTIONS
from puppet.physics import kernel
from puppet.physics.simulation import MAX_SPEED, step_space
from puppet.session.event_runs import EventRuns

if TYPE_CHECKING:
    from puppet.session.session import Session

MAX_SPEED2 = MAX_SPEED ** 2
# the root's position and velocity each frame: pymunk's own C calls, without its Vec2d
_position, _velocity = _cp.cpBodyGetPosition, _cp.cpBodyGetVelocity
_space_step = _cp.cpSpaceStep
NO_BUDGET = 1 << 62  # step on until the events' rule says stop
MOVES = ("mouse", "gamepad")  # the events a run of them in the kernel may start with
SAMPLED = MOVES + ("channels",)  # (a poll plan's run: a performer's samples, poll_track)


def clean(space) -> bool:
    """``step_space`` would only call Chipmunk's step: nothing queued in pymunk's space,
    nothing to let go of after a step (then the loop calls the C step itself)."""
    return not (space._bodies_to_check or space._add_later or space._remove_later
                or space._post_step_callbacks or space.threaded or space._removed_shapes)
    # (``physics.simulation.queued``, inlined: it runs at every call)


def recorded(session: Session, history, step: int, event: dict) -> None:
    """A frequent event (mouse, gamepad, channels) at ``step`` into the history, as
    ``Session.handle`` records it (not while re-simulating): logged, the future
    rewritten after a rewind, then kept."""
    listener = session.listener
    if listener is not None:
        listener(step, event)  # logged
    if step < history.head:
        history.branch(step)  # new input: the future is rewritten
    seq = history.next_seq  # history.record(step, event), inlined
    history.events.append((seq, step, event))
    history.next_seq = seq + 1


def _cap(stop_at: int, budget: int, every: int, until: int | None) -> int:
    """How far a stretch ending at ``stop_at`` may run on over the events coming there
    (the budget, ``play``'s next tick, ``until``: where the loop would stop anyway)."""
    cap = stop_at + budget
    if every:
        tick = stop_at - stop_at % every
        cap = stop_at if tick == stop_at else min(cap, tick + every)
    return until if until is not None and until < cap else cap


def feed(session: Session, events: Sequence, i: int, until: int | None, end: int | None,
         budget: int = NO_BUDGET, every: int = 0,
         on_event: Callable[[int, dict], None] | None = None,
         on_action: Callable[[int, object], object] | None = None,
         on_raise: Callable[[int], None] | None = None) -> tuple[int, bool]:
    """Apply ``events[i:]`` ((step, event) pairs, in order) at their steps, stepping
    the physics between them, by ``playback.next_move``'s rule (``until``: the
    replay's until step, ``end``: where it runs on to once the events run out), for
    at most ``budget`` steps; the events due at the step reached act too (a replay's
    frame: ``LogFeeder.advance``). ``every``: return as soon as a stretch of steps ends
    on a multiple of it (``play``'s ticks, before that step's events). ``on_event``:
    called with each event's index first; ``on_action``: with the next event's index
    and each app action an event asks for. Returns (the next event's index, whether it
    stopped at a tick). ``on_raise``: called with the next event's index when the call
    ends by an exception (an event's, a callback's, the physics'), before it propagates:
    the events before that index were taken, the raising one too (``LogFeeder`` keeps
    its index right so; the ``try`` costs nothing until something raises)."""
    n = len(events)
    sim, history = session.sim, session.history
    runtime = session.runtime
    rebuilding = session._rebuilding
    # a frame check at each ``frame`` steps (the full one at ``health``): the root
    # link (by name) must stay in the box x0..x1, y0..y1
    frame, root, x0, x1, y0, y1 = session._advance_constants
    checks = session._frame  # (the kernel's loop checks it)
    health = history.health_every
    dt, space = sim.dt, sim.space
    is_clean = clean(space)  # (a tick that adds to the space is checked again)
    ptr = space._space
    idle = session._idle  # the kernel's loop with nothing to poll (None: Python's)
    runs = None  # the kernel's runs of events (event_runs), in a replay
    if idle is not None:
        idle_poll, idle_plan, idle_space, seated = idle.poll, idle.plan, None, None
        checked = math.lcm(health, frame)  # (the health checks the frame loop reaches)
        if n:
            runs = idle.runs
    tail = end if until is None else until  # (where the loop runs on to, events done)
    try:
        while True:
            now = sim.steps
            # playback.next_move, inlined: the next event acts now (at or before ``now``;
            # once ``until`` is reached, only one logged at it), else step to it, to
            # ``until`` or, once the events run out, to ``end``
            if i < n:
                at, event = events[i]
                due = at <= now and (until is None or now < until or at == now)
                target = at if until is None or at < until else until
            else:
                due, target = False, end if until is None else until
            if due:
                if on_event is not None:
                    on_event(i, event)
                i += 1
                kind = event["type"]
                if kind == "mouse" or kind == "gamepad" or kind == "channels":
                    # the frequent events: Session.handle's branch for them, in place
                    if not rebuilding:
                        recorded(session, history, now, event)
                    if kind == "mouse":
                        runtime.on_event(event)  # its maps: servo targets only (None)
                        continue
                    if kind == "channels":  # a stream's frame (mocap)
                        runtime._on_channels(event["values"])
                        is_clean = clean(space)  # (a tracker coming back may take joints)
                        continue
                    action = runtime.on_event(event)  # a button may ask for an action,
                    if action is None:  # or grasp (a stick: maps only)
                        is_clean = clean(space)
                        continue
                    if action in SIM_ACTIONS:
                        session.perform(action)
                        action = None
                else:
                    action = session.handle(event)
                if action is not None and on_action is not None:
                    on_action(i, action)
                # anything may have changed: the runtime (a reload), the space (a reset, a
                # restore, a grasp), the steps (a rewind)
                runtime, rebuilding = session.runtime, session._rebuilding
                space = sim.space
                is_clean = clean(space)
                ptr, seated = space._space, None
                continue
            if target is None or target <= now or budget <= 0:
                return i, False
            move = target - now
            k = budget if budget < move else move
            if every:
                left = every - now % every
                k = left if left < k else k
            budget -= k
            # -- ``Session.advance(k)``: step the physics, taking the history's snapshots
            # at their step boundaries (and recovering from a blow-up there)
            if runtime._pending:
                runtime.flush()  # the last channels frame's maps, before stepping
            if now < history.head and not rebuilding:
                history.branch(now)  # playing on from a rewound point
            stop_at = now + k
            if session.halted:  # time goes on, the physics stands still
                sim.steps = stop_at
                if stop_at > history.head and not rebuilding:
                    history.head = stop_at
                if every and stop_at % every == 0:
                    return i, True
                continue
            while now < stop_at:
                # Time-driven interface work (sequences, reaches, timers...) runs at the
                # steps the runtime asks for; when idle (next_wakeup None) the physics
                # steps in one tight loop up to the next history boundary.
                wake = runtime.next_wakeup
                until_poll = None
                if wake is not None and wake <= now:
                    # what is due next all the kernel's to do: its loop (interface.poll_plan;
                    # the same steps, ticks and bits), from this tick on where the last
                    # call's loop stopped at its end, else after Python's tick
                    poll = runtime.poll
                    resume = poll is not None and poll.resume == now and is_clean \
                        and poll.seat == (sim.space, sim.seats)
                    # (the last run stopped at ``now``, its call's end, on the space there is
                    # now, not re-seated since: Chipmunk lists a re-seated space's contacts
                    # only once it steps; then the tick at ``now`` may be the kernel's)
                    if resume:
                        until_poll = poll.ready(now)
                    if until_poll is None:
                        resume = False
                        runtime.tick(now)
                        wake = runtime.next_wakeup
                        space = sim.space
                        is_clean = clean(space)
                        ptr, seated = space._space, None
                        poll = runtime.poll
                        until_poll = poll.ready(now) if poll is not None and is_clean else None
                if until_poll is None and runs is not None and i < n and events[i][0] == stop_at \
                        and is_clean and events[i][1]["type"] in MOVES \
                        and (wake is None or wake >= stop_at) and session.listener is None:
                    # nothing due before the next event (also after a tick here), which stirs
                    # a state polling the mouse alone: the kernel's loop polls it from the
                    # next step, over the events
                    poll = runtime.poll
                    if poll is not None and poll.waits():
                        resume = False
                        until_poll = poll.ready(now, idle=True)
                if until_poll is not None:
                    # the input events coming while the kernel's loop runs, when all they do
                    # is plain maps (event_runs): it applies them at their steps and runs on
                    over = runs is not None and i < n and events[i][0] == stop_at \
                        and events[i][1]["type"] in SAMPLED \
                        and session.listener is None
                    if over:
                        reach = runs.start(poll.plan, runtime, events, i,
                                           _cap(stop_at, budget, every, until), tail, poll)
                        over = reach is not None and reach > stop_at
                        if over:
                            budget -= reach - stop_at
                            stop_at = reach
                    sim.steps = now = poll.run(ptr, dt, now, until_poll, stop_at, health, checks,
                                               resume)
                    if over:
                        i = runs.applied(session, poll.plan, events, i, on_event, rebuilding)
                        if i < n and events[i][0] < stop_at:  # stopped before the next
                            budget += stop_at - events[i][0]  # event: the stretch ends there
                            stop_at = events[i][0]  # (at ``now``: its events act before the
                            # tick there)
                    wake = runtime.next_wakeup
                    boundary = now if now % frame == 0 else -1
                else:
                    stop = stop_at if wake is None or wake >= stop_at else wake
                    over = runs is not None and is_clean and stop == stop_at and i < n \
                        and events[i][0] == stop_at and events[i][1]["type"] in MOVES \
                        and session.listener is None
                    if over:  # the events coming: the kernel's to apply (event_runs)
                        reach = runs.start(idle_plan, runtime, events, i,
                                           _cap(stop_at, budget, every, until), tail)
                        over = reach is not None and reach > stop_at
                        if over:
                            budget -= reach - stop_at
                            stop_at = reach
                            stop = stop_at if wake is None or wake >= stop_at else wake
                    if idle is not None and is_clean and (over or stop > now + 1):
                        # (one step alone, with no events to run on over: Python's)
                        # nothing due before ``stop``: the kernel steps on to it (or to the
                        # next health check) with the frame check between the steps, and
                        # returns at the first frame that fails it (checked below again)
                        if seated is None:  # (the space or the bodies may be new)
                            seated = sim.character.bodies[root]._body
                            if seated is not idle.body or ptr is not idle.space:
                                idle.seat(ptr, seated)
                            idle_space = idle.space_ptr
                        last = now - now % checked + checked
                        sim.steps = now = idle_poll(idle_space, dt, now,
                                                    stop if stop < last else last, idle_plan, 0)
                        if over:
                            i = runs.applied(session, idle_plan, events, i, on_event, rebuilding)
                            if i < n and events[i][0] < stop_at:  # (as the kernel's run above)
                                budget += stop_at - events[i][0]
                                stop_at = events[i][0]
                        boundary = now if now % frame == 0 else -1
                    else:
                        boundary = now - now % frame + frame
                        if boundary < stop:
                            stop = boundary
                        if is_clean:  # Simulation.step, inlined: step_space's C steps
                            for _ in range(stop - now):
                                _space_step(ptr, dt)
                        else:
                            step_space(space, dt, stop - now)
                            is_clean = clean(space)
                        sim.steps = now = stop
                if now == boundary:
                    if now % health == 0:
                        session._at_boundary()  # a recovery restores the state, not the step
                        runtime = session.runtime  # count, and may switch interface versions
                        space = sim.space  # (a keyframe re-seats it)
                        is_clean = clean(space)
                        ptr, seated = space._space, None
                    else:  # the root alone, each frame: NaN fails every comparison
                        body = sim.character.bodies[root]._body
                        while True:
                            p = _position(body)
                            x, y = p.x, p.y
                            ok = x0 < x < x1 and y0 < y < y1
                            if ok:
                                v = _velocity(body)
                                vx, vy = v.x, v.y
                                ok = vx * vx + vy * vy < MAX_SPEED2
                            # passed, and the next frame whole, with nothing due in it and
                            # no health check at its end: it is stepped and checked here
                            # (what the outer loop would do, at more cost; the kernel's
                            # loop does it there, when there is one)
                            nxt = now + frame
                            if not (ok and idle is None and is_clean and nxt <= stop_at
                                    and nxt % health and (wake is None or wake >= nxt)):
                                break
                            for _ in range(frame):
                                _space_step(ptr, dt)
                            sim.steps = now = nxt
                        if ok:
                            continue  # (not halted: only a recovery halts)
                        session._recover()
                        runtime = session.runtime
                        space = sim.space
                        is_clean = clean(space)
                        ptr, seated = space._space, None
                    if session.halted:
                        sim.steps = stop_at  # the rest of the call: time only
                        break
            now = sim.steps
            if now > history.head and not rebuilding:
                history.head = now
            if every and now % every == 0:
                return i, True
    except BaseException:
        if on_raise is not None:  # the events up to ``i`` were taken (the one raising
            on_raise(i)  # too, whatever it did): a caller keeping the index goes on there
        raise


class Idle:
    """``pk_poll`` with an empty table (``kernel_poll``): Chipmunk's steps and the
    session's frame check between them, in C, for the steps where nothing of the
    interface is due (Python's loop costs about 0.3 us a step there, 13 % of a Luxo
    step). It stops where ``pk_poll`` stops: at ``stop``, or at the first frame whose
    check fails, which the loop then checks again and recovers from, as without it."""

    def __init__(self, kern, frame: tuple):
        self.kernel, self.poll = kern, kern.lib.pk_poll
        self.plan = p = kern.ffi.new("pk_poll_plan *")  # (zeroed: no transitions, no
        p.every = 1  # blends, no feedback; a tick at every step finds nothing to do)
        p.frame_every, _, p.x0, p.x1, p.y0, p.y1, p.max_speed2 = frame
        self.body = self.space = self.space_ptr = None
        self.runs = EventRuns(kern)  # (a replay's runs of events: the session's)

    def seat(self, space_ptr, body) -> None:
        """The space and the root link's body to run on (a re-seat makes new ones)."""
        self.space, self.space_ptr = space_ptr, self.kernel.pointer(space_ptr)
        self.body = body
        self.plan.root = self.kernel.pointer(body)


def idle_for(frame: tuple) -> Idle | None:
    """The session's ``Idle`` loop with the kernel; None on the pure-Python path."""
    kern = kernel.get()
    return None if kern is None else Idle(kern, frame)
