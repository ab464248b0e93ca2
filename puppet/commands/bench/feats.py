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

The two runs of a round go in chunks of half a simulated second, the order
rotating, so that a shared machine's drifting speed slows both alike; the overhead
is the median of the rounds' ratios, with their range. The bare run steps with
``step_space`` (Chipmunk's step without pymunk's per-call Python, as the Session
does), so the overhead is the control layer's work alone.
"""

from __future__ import annotations

import statistics
from dataclasses import dataclass, field
from pathlib import Path

from pymunk._chipmunk_cffi import lib as _cp

from puppet.commands.bench.config import in_turns
from puppet.commands.bench.speed import grasp_changes

CHUNK_STEPS = 240  # half a simulated second at 1/480 s: the runs' turns
_GETV, _GETW = _cp.cpBodyGetVelocity, _cp.cpBodyGetAngularVelocity
_GETP, _GETA = _cp.cpBodyGetPosition, _cp.cpBodyGetAngle


@dataclass
class Trace:
    """What a controlled run wrote into the physics, step by step: ``ops`` are
    ``(step, reseat, servo changes, body changes, grasp changes, world or None)``,
    each acting before the space steps from ``step``."""

    ops: list = field(default_factory=list)
    steps: int = 0
    end_hash: str = ""


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
    return [(s.target, s.stiffness, s.damping, s.max_torque)
            for s in sim.character.servos.values()]


def _world(sim) -> tuple:
    return (tuple(sim.space.gravity), tuple(s.friction for s in sim.ground))


def _seat(sim) -> tuple:
    """Which seat of which space ``sim`` runs on: it changes at every checkpoint or
    restore (a re-seat in place keeps the space, and counts in ``seats``)."""
    return (id(sim.space), sim.seats)


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
    pending_reseat = False
    while True:
        seat = _seat(sim)
        while (move := next_move(session.steps, events[i][0] if i < len(events) else None,
                                 until, end)) == 0:
            session.handle(events[i][1])
            i += 1
        if move is None:
            if pending_reseat:  # a keyframe at the last step: the end state is re-seated
                trace.ops.append((session.steps, True, [], [], [], None))
            break
        sim, runtime = session.sim, session.runtime
        if runtime._pending:
            runtime.flush()  # as advance does first
        wake = runtime.next_wakeup
        if wake is not None and wake <= session.steps:
            runtime.tick(session.steps)  # so advance(1) below does not tick again
        reseat = pending_reseat or _seat(sim) != seat
        if _seat(sim) != seat:
            held = {n: j for n, (j, _) in sim.grasps.items()}
        now_servos, now_motion, now_world = _servos(sim), _motion(sim), _world(sim)
        servo_ch = [(k, p) for k, (p, q) in enumerate(zip(now_servos, servos)) if p != q]
        motion_ch = [(n, m[:3]) for n, m in now_motion.items() if m != motion.get(n)]
        grasps = grasp_changes(sim, held)
        world_ch = now_world if now_world != world else None
        if reseat or servo_ch or motion_ch or grasps or world_ch:
            trace.ops.append((session.steps, reseat, servo_ch, motion_ch, grasps, world_ch))
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


def bare_run(log, setup, trace: Trace):
    """The same start, stepped by Chipmunk in long runs with ``trace``'s changes
    written at their steps; yields the Simulation."""
    from puppet.physics.simulation import step_space
    from puppet.timeline.replay import new_session

    sim = new_session(log, setup).sim  # the same start (re-seated at step 0)
    dt, now, ops = sim.dt, 0, iter(trace.ops)
    op = next(ops, None)
    k = yield sim
    while True:
        stop = min(trace.steps, now + k)
        while op is not None and (op[0] < stop or op[0] == stop == trace.steps):
            at, reseat, servo_ch, motion_ch, grasps, world_ch = op
            if at > now:
                step_space(sim.space, dt, at - now)
                now = at
            if reseat:
                sim.checkpoint()
            if servo_ch:
                servos = list(sim.character.servos.values())
                for i, (angle, stiffness, damping, torque) in servo_ch:
                    servo = servos[i]
                    servo.target = angle
                    servo.stiffness = stiffness
                    servo.damping = damping
                    servo.max_torque = torque
            for name, g in grasps:
                if g is None:
                    sim.detach(name)
                else:
                    sim.attach(name, *g)
            if motion_ch:
                bodies = dict(_bodies(sim))
                for name, (vx, vy, w) in motion_ch:
                    body = bodies[name]
                    body.velocity = (vx, vy)
                    body.angular_velocity = w
            if world_ch is not None:
                sim.space.gravity = world_ch[0]
                for segment, friction in zip(sim.ground, world_ch[1]):
                    segment.friction = friction
            op = next(ops, None)
        if stop > now:
            step_space(sim.space, dt, stop - now)
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
            "writes": len(trace.ops),
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
