"""A channels stream (a mocap frame of many values) into a Session, against the very
targets it produced written directly: what the input path costs."""

from __future__ import annotations

import math
import statistics

from puppet.commands.bench.config import FRAME_HZ, in_turns, target
from puppet.commands.bench.speed import CHUNK_FRAMES, fed

CHANNEL_HZ = 120.0
CHANNEL_COUNT = 40
CHANNEL_TARGET_PCT = 10.0
# The figure a stream drives (the human, with the mocap plugin) carries the target; the
# cat, whose physics is the cheapest per frame here, is shown as the worst case.
CHANNEL_SUBJECTS = (("biped", "biped-track", True), ("cat", "cat-flat", False))


def channel_interface_text(character, scene: str, count: int = CHANNEL_COUNT) -> str:
    """An interface mapping the first of ``count`` channels c0, c1... one to each
    actuated joint (+-20 deg around the start pose); the rest are read by nothing."""
    lines = ["name: bench-channels", "description: channels onto every joint (bench)",
             f"character: {character.name}", f"scene: {scene}", "maps:"]
    start = {j.name: character.start.joints.get(j.name, 0.0) for j in character.actuated}
    for i, joint in enumerate(start):
        if i >= count:
            break
        lo, hi = start[joint] - 20.0, start[joint] + 20.0
        if character.joint(joint).limits is not None:
            lim = character.joint(joint).limits
            lo, hi = max(lo, lim[0]), min(hi, lim[1])
        lines.append(f"  - {{input: channel.c{i}, joint: {joint}, from: [-1, 1], "
                     f"to: [{lo:g}, {hi:g}]}}")
    return "\n".join(lines) + "\n"


def channel_frames(frames: int, count: int = CHANNEL_COUNT) -> list[list[dict]]:
    """Per 1/60 s frame, the ``channels`` events of a 120 Hz stream of ``count``
    slow sinusoids (the window drains a live source's events once a frame)."""
    from puppet.interface import events as ev

    per_frame = max(1, round(CHANNEL_HZ / FRAME_HZ))
    out = []
    for f in range(frames):
        batch = []
        for k in range(per_frame):
            t = (f * per_frame + k) / CHANNEL_HZ
            batch.append(ev.channels({f"c{i}": 0.8 * math.sin(2 * math.pi * (0.3 + 0.05 * i)
                                                              * t + i)
                                      for i in range(count)}))
        out.append(batch)
    return out


def measure_channels(seconds: float, repeats: int, character_name: str = "cat",
                     scene: str = "cat-flat", targeted: bool = True) -> dict:
    """A Session fed a 120 Hz x 40-value ``channels`` stream against the same Session
    given the very targets the stream produced, written through the servo setters at
    the same steps (identical physics: the state hashes are compared)."""
    from puppet.data.catalog import load_character_named, setup_from_text
    from puppet.physics.simulation import step_of
    from puppet.session import Session

    character, _ = load_character_named(character_name)
    setup = setup_from_text(channel_interface_text(character, scene), "bench-channels.yaml")
    dt = step_of(character)  # the step its sessions run on
    n = max(1, round(1.0 / (FRAME_HZ * dt)))
    frames = max(1, round(seconds * FRAME_HZ))
    inputs = channel_frames(frames)
    probe = Session(setup, keyframes=False)
    servos = list(probe.character.servos)
    targets = []
    for batch in inputs:
        for event in batch:
            probe.handle(event)
        probe.runtime.flush()  # as advance would, so that the targets can be read
        targets.append([probe.character.servos[j].target for j in servos])
        probe.advance(n)

    def streamed():
        return fed(Session(setup, keyframes=False), inputs, n)

    def written():
        session = Session(setup, keyframes=False)
        objs = [session.character.servos[j] for j in servos]
        it = iter(targets)
        k = yield session
        while True:
            for _ in range(k):
                for servo, value in zip(objs, next(it)):
                    servo.target = value
                session.advance(n)
            k = yield session

    ratios, walls = [], []
    identical = True
    for _ in range(repeats):
        wall, last = in_turns({"streamed": streamed(), "written": written()}, frames,
                              CHUNK_FRAMES)
        ratios.append(wall["streamed"] / wall["written"])
        walls.append(wall["streamed"])
        identical = identical and last["streamed"].sim.state_hash() == \
            last["written"].sim.state_hash() == probe.sim.state_hash()
    sim_seconds = frames * n * dt
    return {"character": character_name, "channels": CHANNEL_COUNT, "hz": CHANNEL_HZ,
            "sim_seconds": sim_seconds, "repeats": repeats,
            "overhead_pct": (statistics.median(ratios) - 1.0) * 100.0,
            "overhead_range_pct": [(min(ratios) - 1.0) * 100.0, (max(ratios) - 1.0) * 100.0],
            "speed_x": sim_seconds / statistics.median(walls),
            "state_identical": identical,
            "target": target(f"channels stream overhead ({character_name})",
                              (statistics.median(ratios) - 1.0) * 100.0, "<=",
                              CHANNEL_TARGET_PCT, "%") if targeted else None}
