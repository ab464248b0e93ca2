"""Speed and the control layer's overhead: a Session fed as the window feeds it against
the same Simulation stepped by pymunk in a plain loop, through the same motion (the
servo changes the control run made, written straight onto the springs: the state
hashes are compared).

Each run is a generator: ``send(k)`` plays its next k frames. The variants of one
measurement are played in turns, a chunk of frames each, so that a machine whose
speed drifts (a shared VM) slows them alike; their order rotates every chunk.
"""

from __future__ import annotations

import statistics

from puppet.commands.bench.config import in_turns
from puppet.commands.bench.subjects import Subject, gesture

CHUNK_FRAMES = 30


def control_run(subject: Subject, inputs: list[list[dict]], keyframes: bool = False,
                obj=None):
    """A controlled run (one input batch then one frame of steps, as the window does):
    the control layer alone, or (``keyframes``) with the timeline's automatic keyframes.
    Plays on ``obj`` if given, else a fresh Session (or, without an interface, a
    Simulation); yields it."""
    obj = subject.session(keyframes) if obj is None else obj
    n = subject.steps_per_frame
    frames = iter(inputs)
    k = yield obj
    if subject.setup is None:  # no interface: nothing to control, just the Simulation
        step = obj.step
        while True:
            for _ in range(k):
                next(frames)
                step(n)
            k = yield obj
    feed = fed(obj, frames, n)
    next(feed)
    while True:
        k = yield feed.send(k)


def fed(session, frames, steps_per_frame: int):
    """A run of ``session``: ``send(k)`` plays the next k frames of ``frames`` (each a
    batch of events handed to the session, then a frame of steps); yields the session."""
    frames = iter(frames)
    handle, advance = session.handle, session.advance
    k = yield session
    while True:
        for _ in range(k):
            for event in next(frames):
                handle(event)
            advance(steps_per_frame)
        k = yield session


def _servo_params(spring) -> tuple[float, float, float, float]:
    return (spring.rest_angle, spring.stiffness, spring.damping, spring.max_force)


def target_trace(subject: Subject, inputs: list[list[dict]]) -> list[list[tuple]]:
    """Per frame, the servo changes the control layer made, at the step they acted:
    ``[(step in frame, [(spring index, (target, stiffness, damping, max torque)), ...])]``.
    Key sequences change targets between frames' events, so this goes step by step."""
    if subject.setup is None:
        return [[] for _ in inputs]
    session = subject.session(keyframes=False)
    runtime = session.runtime
    springs = lambda: [s.spring for s in session.character.servos.values()]  # noqa: E731
    last = [_servo_params(sp) for sp in springs()]
    held = {}
    trace = []
    for batch in inputs:
        for event in batch:
            session.handle(event)
        frame = []
        for k in range(subject.steps_per_frame):
            wake = runtime.next_wakeup  # tick here, as advance would, before reading
            if wake is not None and wake <= session.steps:
                runtime.tick(session.steps)
            now = [_servo_params(sp) for sp in springs()]
            changed = [(i, p) for i, (p, q) in enumerate(zip(now, last)) if p != q]
            grasps = grasp_changes(session.sim, held)
            if changed or grasps:
                frame.append((k, changed, grasps))
            last = now
            session.advance(1)
        trace.append(frame)
    return trace


def grasp_changes(sim, held: dict) -> list[tuple]:
    """The grasps made or let go since ``held`` (updated): ``(name, None)`` for a
    release, ``(name, (link, local point, world point, prop))`` for a grasp, to make
    again on a bare Simulation (``Simulation.attach``): a figure holding a bar or a
    rope swings on its constraints in the baseline too."""
    if not held and not sim.grasps:
        return []
    link_of = {id(b): n for n, b in sim.character.bodies.items()}
    out = [(name, None) for name in held if name not in sim.grasps]
    for name, (joint, prop) in sim.grasps.items():
        if held.get(name) is not joint:  # a new pin (each grasp makes its own)
            gear = sim.rigid.get(name)  # a rigid grasp: its angle hold too
            out.append((name, (link_of[id(joint.a)], tuple(joint.anchor_a),
                               sim.grasp_point(name), prop, gear is not None,
                               None if gear is None or gear.max_force == float("inf")
                               else gear.max_force)))
    held.clear()
    held.update({name: joint for name, (joint, _) in sim.grasps.items()})
    return out


def bare_run(subject: Subject, trace: list[list[tuple]], with_targets: bool):
    """A plain pymunk loop, ``space.step(dt)``, over the same frames: with the servo
    changes of ``trace`` written onto the servos through the setters the Session uses
    (so the baseline pays what the control run pays for a write), or (not
    ``with_targets``) none. Yields the Simulation. (The Session steps through
    ``step_space``, Chipmunk's step without pymunk's per-call Python, 1-2 us a step
    less: part of what the control layer costs is won back there, and the overhead
    figure counts it, as it is measured against what a plain pymunk program does.)"""
    sim = subject.sim_of(subject.session())  # the same Simulation, interface gains applied
    servos = list(sim.character.servos.values())
    step, dt, n = sim.space.step, sim.dt, subject.steps_per_frame
    frames = iter(trace)
    k = yield sim
    while True:
        for _ in range(k):
            frame = next(frames) if with_targets else ()
            done = 0
            for at, changed, grasps in frame:
                for _ in range(at - done):
                    step(dt)
                done = at
                for name, g in grasps:
                    if g is None:
                        sim.detach(name)
                    else:
                        sim.attach(name, *g)
                for i, (angle, stiffness, damping, torque) in changed:
                    servo = servos[i]
                    servo.target = angle
                    servo.stiffness = stiffness
                    servo.spring.damping = damping  # read off the spring: the engine's
                    servo.max_torque = torque
            for _ in range(n - done):
                step(dt)
        sim.steps += k * n
        k = yield sim


def measure_speed(subject: Subject, seconds: float, repeats: int) -> dict:
    frames = subject.frames(seconds)
    sim_seconds = frames * subject.steps_per_frame * subject.dt
    inputs = gesture(frames, subject.interface_spec)
    trace = target_trace(subject, inputs)
    in_turns({"warm-up": control_run(subject, inputs)}, max(1, frames // 10), CHUNK_FRAMES)
    samples: dict[str, list[float]] = {"control": [], "with_keyframes": [],
                                       "bare_same_motion": [], "bare_at_rest": []}
    ratios, ratios_keyframes = [], []
    identical = True
    for _ in range(repeats):
        wall, last = in_turns({
            "control": control_run(subject, inputs),
            "with_keyframes": control_run(subject, inputs, keyframes=True),
            "bare_same_motion": bare_run(subject, trace, with_targets=True),
            "bare_at_rest": bare_run(subject, trace, with_targets=False)}, frames, CHUNK_FRAMES)
        for name, value in wall.items():
            samples[name].append(value)
        ratios.append(wall["control"] / wall["bare_same_motion"])
        ratios_keyframes.append(wall["with_keyframes"] / wall["bare_same_motion"])
        identical = identical and (last["bare_same_motion"].state_hash()
                                   == subject.sim_of(last["control"]).state_hash())
    c, h, s, r = (statistics.median(samples[name]) for name in samples)
    return {
        "sim_seconds": sim_seconds, "repeats": repeats, "frames": frames,
        "steps_per_frame": subject.steps_per_frame, "chunk_frames": CHUNK_FRAMES,
        "control_speed_x": sim_seconds / c,
        "bare_same_motion_speed_x": sim_seconds / s,
        "bare_at_rest_speed_x": sim_seconds / r,
        # medians of the per-repeat ratios of runs played in turns
        "control_overhead_pct": (statistics.median(ratios) - 1.0) * 100.0,
        "control_overhead_range_pct": [(min(ratios) - 1.0) * 100.0,
                                       (max(ratios) - 1.0) * 100.0],
        "with_keyframes_speed_x": sim_seconds / h,
        "with_keyframes_overhead_pct": (statistics.median(ratios_keyframes) - 1.0) * 100.0,
        "overhead_vs_rest_pct": (c / r - 1.0) * 100.0,
        "same_motion_state_identical": identical,
        "control_us_per_frame": c / frames * 1e6,
        "bare_us_per_frame": s / frames * 1e6,
        "wall_samples_s": samples,
    }
