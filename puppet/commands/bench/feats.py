"""The control layer's cost on what users run: every shipped feat log, replayed.

Each log is played twice, in turns: **with control** - a Session fed the log's
events as the window and the replays feed them (``LogFeeder``: the interface
runtime, its controllers, the timeline's keyframes) - and **bare** - the same
Simulation stepped by Chipmunk's step in long runs, with, at each step where the
controlled run changed anything, the very values it wrote: servo targets and gains,
bodies' velocities (a push, KD tracking's pulls), grasps made or let go, gravity and
friction, and the re-seat of a checkpoint. Those are recorded once, step by step,
from a controlled run (``record``); the bare run must end in the log's own state
(the hashes are compared), so both do the same physics work to the bit, and
``control overhead = CPU time with control / CPU time bare - 1``.

The bare run is the cheapest honest way to make that physics happen, so that the
figure is the control layer's and not the bench's own bookkeeping: the trace holds
only the values that changed (a servo's target, stiffness, Chipmunk damping or
torque limit, a body's velocity or spin, each on its own), each as the Chipmunk
setter pymunk's property calls (``cpDampedRotarySpringSetRestAngle``,
``cpBodySetVelocity``, ...) with its value, and the bare run calls those setters on
handles it looks up once per seat, and steps with ``cpSpaceStep`` itself between
them (pymunk's own step only while its queues hold something, as ``step_space``).
A re-seat is the checkpoint's rebuild without pickling the snapshot; grasps are
made and let go in the order the controlled run did (the order is in the bits).
``tests/test_bench_feats.py`` fails if the bare run writes a value that did not
change.

The two runs of a round go in chunks of half a simulated second, the order
rotating, so that a shared machine's drifting speed slows both alike; the overhead
is the median of the rounds' ratios, with their range, and is the control layer's
work alone.
"""

from __future__ import annotations

import itertools
import statistics
from dataclasses import dataclass, field
from pathlib import Path

from pymunk._chipmunk_cffi import lib as _cp

from puppet.commands.bench.config import in_turns
from puppet.commands.bench.speed import grasp_changes
from puppet.physics.simulation import queued, step_space

CHUNK_STEPS = 240  # half a simulated second at 1/480 s: the runs' turns
_GETV, _GETW = _cp.cpBodyGetVelocity, _cp.cpBodyGetAngularVelocity
_GETP, _GETA = _cp.cpBodyGetPosition, _cp.cpBodyGetAngle
# a servo's four values as Chipmunk holds them (the damping is the one handed to
# Chipmunk), read and written by the C calls pymunk's properties make
SERVO_GET = (_cp.cpDampedRotarySpringGetRestAngle, _cp.cpDampedRotarySpringGetStiffness,
             _cp.cpDampedRotarySpringGetDamping, _cp.cpConstraintGetMaxForce)
SERVO_SET = (_cp.cpDampedRotarySpringSetRestAngle, _cp.cpDampedRotarySpringSetStiffness,
             _cp.cpDampedRotarySpringSetDamping, _cp.cpConstraintSetMaxForce)
SET_VELOCITY, SET_SPIN = _cp.cpBodySetVelocity, _cp.cpBodySetAngularVelocity


@dataclass
class Trace:
    """What a controlled run wrote into the physics, step by step: ``ops`` are
    ``(step, reseat, writes, grasp changes, world or None)``, each acting before the
    space steps from ``step``; ``writes`` are ``(setter, handle index, value)``, one
    per value that changed (``handles``: the servos' constraints, then the bodies)."""

    ops: list = field(default_factory=list)
    steps: int = 0
    end_hash: str = ""

    @property
    def writes(self) -> int:
        """How many values the bare run writes (each one that changed)."""
        return sum(len(op[2]) for op in self.ops)


def _bodies(sim) -> list:
    out = list(sim.character.bodies.items())
    out += [("prop " + n, p.body) for n, p in sim.props.items()
            if p.body.body_type == 0]  # dynamic props (a rope's links)
    return out


def _motion(sim) -> dict:
    res = {}
    for name, body in _bodies(sim):
        cb = body._body
        v, p = _GETV(cb), _GETP(cb)
        res[name] = (v.x, v.y, _GETW(cb), p.x, p.y, _GETA(cb))
    return res


def _servos(sim) -> list:
    return [tuple(get(s.spring._constraint) for get in SERVO_GET)
            for s in sim.character.servos.values()]


def handles(sim) -> list:
    """The C handles a trace's writes index: each servo's constraint, then each body
    of ``_bodies`` (looked up again after a re-seat, which may make new objects)."""
    return ([s.spring._constraint for s in sim.character.servos.values()]
            + [body._body for _, body in _bodies(sim)])


def _writes(servos: list, now_servos: list, motion: dict, now_motion: dict) -> list:
    """One ``(setter, handle index, value)`` per value that changed."""
    out = [(SERVO_SET[f], k, v) for k, (now, was) in enumerate(zip(now_servos, servos))
           if now != was for f, (v, w) in enumerate(zip(now, was)) if v != w]
    first = len(now_servos)
    for j, name in enumerate(now_motion):
        m, was = now_motion[name], motion.get(name)
        if m == was:
            continue
        if was is None or m[:2] != was[:2]:
            out.append((SET_VELOCITY, first + j, m[:2]))
        if was is None or m[2] != was[2]:
            out.append((SET_SPIN, first + j, m[2]))
    return out


def _world(sim) -> tuple:
    return (tuple(sim.space.gravity), tuple(s.friction for s in sim.ground))


def _seat(sim) -> tuple:
    """Which seat of which space ``sim`` runs on: it changes at every checkpoint or
    restore (a re-seat in place keeps the space, and counts in ``seats``)."""
    return (id(sim.space), sim.seats)


def _watch_grasps(sim, order: dict, clock) -> None:
    """Note in ``order`` (name -> a tick of ``clock``) when ``sim`` last made or let go of
    each grasp: taking a joint out of the space moves its last constraint into its
    place, so the order of the releases and grasps is part of the bits."""
    if "detach" in vars(sim):
        return
    detach, attach = sim.detach, sim.attach

    def noted_detach(name, *args):
        order[name] = next(clock)
        return detach(name, *args)

    def noted_attach(name, *args, **kwargs):
        attach(name, *args, **kwargs)
        order[name] = next(clock)

    sim.detach, sim.attach = noted_detach, noted_attach


def record(log, setup, until: int | None = None) -> Trace:
    """Play ``log`` one step at a time (its events, the runtime's ticks, then a step,
    as ``Session.advance`` orders them) and note what changed in the physics before
    each step."""
    from puppet.session.playback import next_move
    from puppet.timeline.replay import new_session

    session = new_session(log, setup)
    sim = session.sim
    events, i = log.pairs(), 0
    end = log.last_step if until is None else until
    trace = Trace()
    servos, motion, world = _servos(sim), _motion(sim), _world(sim)
    held = {n: j for n, (j, _) in sim.grasps.items()}
    pending_reseat, order, clock = False, {}, itertools.count(1)
    while True:
        _watch_grasps(session.sim, order, clock)
        seat = _seat(sim)
        while (move := next_move(session.steps, events[i][0] if i < len(events) else None,
                                 until, end)) == 0:
            session.handle(events[i][1])
            i += 1
        if move is None:
            if pending_reseat:  # a keyframe at the last step: the end state is re-seated
                trace.ops.append((session.steps, True, (), [], None))
            break
        sim, runtime = session.sim, session.runtime
        _watch_grasps(sim, order, clock)  # (an event may have restored another)
        if runtime._pending:
            runtime.flush()  # as advance does first
        wake = runtime.next_wakeup
        if wake is not None and wake <= session.steps:
            runtime.tick(session.steps)  # so advance(1) below does not tick again
        reseat = pending_reseat or _seat(sim) != seat
        if _seat(sim) != seat:
            held = {n: j for n, (j, _) in sim.grasps.items()}
        now_servos, now_motion, now_world = _servos(sim), _motion(sim), _world(sim)
        writes = _writes(servos, now_servos, motion, now_motion)
        grasps = sorted(grasp_changes(sim, held), key=lambda g: order.get(g[0], 0))
        world_ch = now_world if now_world != world else None
        if reseat or writes or grasps or world_ch:
            trace.ops.append((session.steps, reseat, tuple(writes), grasps, world_ch))
        seat = _seat(sim)
        session.advance(1)
        sim = session.sim
        pending_reseat = _seat(sim) != seat  # a keyframe re-seated it after the step
        if pending_reseat:
            held = {n: j for n, (j, _) in sim.grasps.items()}
        servos, motion, world = _servos(sim), _motion(sim), _world(sim)
    trace.steps = session.steps
    trace.end_hash = session.sim.state_hash()
    return trace


def control_run(log, setup):
    """A Session fed the log (``send(k)`` plays its next k steps); yields the Session."""
    from puppet.timeline.replay import LogFeeder, new_session

    session = new_session(log, setup)
    feeder = LogFeeder(session, log)
    k = yield session
    while True:
        feeder.advance(k)
        k = yield session


def _queued(space) -> bool:
    """Whether ``step_space`` has Python work to do: pymunk's queues, or shapes it
    lets go of after a step."""
    return queued(space) or bool(space._removed_shapes)


def bare_run(log, setup, trace: Trace):
    """The same start, stepped by Chipmunk in long runs with ``trace``'s changes
    written at their steps; yields the Simulation. Between the rare Python-side ops
    (a re-seat, a grasp, the world) it is Chipmunk's setters and ``cpSpaceStep``."""
    from puppet.timeline.replay import new_session

    sim = new_session(log, setup).sim  # the same start (re-seated at step 0)
    dt, now, ops, end = sim.dt, 0, iter(trace.ops), trace.steps
    step, space = _cp.cpSpaceStep, sim.space
    ptr, h, queued = space._space, handles(sim), _queued(space)
    op = next(ops, None)
    k = yield sim
    while True:
        stop = min(end, now + k)
        while op is not None and (op[0] < stop or op[0] == stop == end):
            at, reseat, writes, grasps, world_ch = op
            if at > now:
                if queued:
                    step_space(space, dt, at - now)
                    queued = _queued(space)
                elif at - now == 1:
                    step(ptr, dt)
                else:
                    for _ in range(at - now):
                        step(ptr, dt)
                now = at
            if reseat or grasps or world_ch is not None:
                if reseat:  # a checkpoint's re-seat, without pickling the snapshot
                    sim._rebuild(sim._state())  # (what ``checkpoint`` does besides)
                for name, g in grasps:
                    if g is None:
                        sim.detach(name)
                    else:
                        sim.attach(name, *g)
                if world_ch is not None:
                    sim.space.gravity = world_ch[0]
                    for segment, friction in zip(sim.ground, world_ch[1]):
                        segment.friction = friction
                space = sim.space
                ptr, h, queued = space._space, handles(sim), _queued(space)
            for set_, i, value in writes:
                set_(h[i], value)
            op = next(ops, None)
        if stop > now:
            step_space(space, dt, stop - now)
            queued = _queued(space)
            now = stop
        sim.steps = now
        k = yield sim


def measure_feat(path, rounds: int, seconds: float | None = None) -> dict:
    """One log: the rounds' overheads (median, range), time per step with control
    and bare, and whether the bare run ended in the controlled run's state (and the
    log's recorded one, when played whole)."""
    from puppet.timeline.log import read_log
    from puppet.timeline.replay import setup_for_log

    log = read_log(path)
    setup, _ = setup_for_log(log)
    until = None if seconds is None else min(log.last_step,
                                             round(seconds / float(log.header["dt"])))
    trace = record(log, setup, until)
    ratios, same = [], True
    control_s = bare_s = 0.0
    for _ in range(rounds):
        spent, last = in_turns({"control": control_run(log, setup),
                                "bare": bare_run(log, setup, trace)}, trace.steps,
                               CHUNK_STEPS)
        ratios.append(spent["control"] / spent["bare"])
        control_s += spent["control"]
        bare_s += spent["bare"]
        same = same and last["bare"].state_hash() == last["control"].sim.state_hash() \
            == trace.end_hash
    dt = float(log.header["dt"])
    return {"log": Path(log.path).stem,
            "character": setup.character.name, "steps": trace.steps,
            "sim_seconds": trace.steps * dt, "rounds": rounds,
            "writes": len(trace.ops), "values_written": trace.writes,
            "overhead_pct": (statistics.median(ratios) - 1.0) * 100.0,
            "overhead_range_pct": [(min(ratios) - 1.0) * 100.0, (max(ratios) - 1.0) * 100.0],
            "control_us_per_step": control_s / rounds / trace.steps * 1e6,
            "bare_us_per_step": bare_s / rounds / trace.steps * 1e6,
            "same_motion": same,
            "recorded_end": None if until is not None else trace.end_hash == log.end_hash}


def measure_feats(rounds: int, seconds: float | None = None,
                  only: list[str] | None = None, logs: list[str] | None = None) -> dict:
    """Every shipped log (``assets/logs/*.jsonl``), or those of the characters in
    ``only``, or the shipped logs named in ``logs`` (a name like ``luxo-hop``)."""
    from puppet.data.catalog import folder
    from puppet.data.errors import UsageError
    from puppet.timeline.log import read_log

    shipped = sorted(folder("log").glob("*.jsonl"))
    if logs:
        names = {p.stem: p for p in shipped}
        # a name given two ways (a/luxo-hop, luxo-hop.jsonl, luxo-hop) is one log
        wanted = [n.rsplit("/", 1)[-1] for n in logs]
        wanted = [n[:-len(".jsonl")] if n.endswith(".jsonl") else n for n in wanted]
        unknown = [n for n in wanted if n not in names]
        if unknown:
            raise UsageError(f"no shipped log named {', '.join(unknown)}; known: "
                             f"{', '.join(names)}")
        shipped = [names[n] for n in dict.fromkeys(wanted)]
        if only:
            of = {p.stem: read_log(p).header.get("character") for p in shipped}
            if not any(c in only for c in of.values()):
                raise UsageError(f"the characters named ({', '.join(only)}) leave out every "
                                 "log named: " + ", ".join(f"{n} is {c}'s"
                                                           for n, c in of.items()))
    items = []
    for path in shipped:
        try:
            if only and read_log(path).header.get("character") not in only:
                continue
            items.append(measure_feat(str(path), rounds, seconds))
        except Exception as exc:  # noqa: BLE001 - a report, not a test
            items.append({"log": path.stem, "error": f"{type(exc).__name__}: {exc}"})
    overheads = [i["overhead_pct"] for i in items if "overhead_pct" in i]
    return {"items": items, "rounds": rounds, "seconds": seconds,
            "median_overhead_pct": statistics.median(overheads) if overheads else None}
