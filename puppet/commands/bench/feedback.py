"""Feedback maps (sensor inputs, ``add`` maps): a Session with them against the same
Session without them, fed the same input."""

from __future__ import annotations

import statistics

from puppet.commands.bench.config import FRAME_HZ, in_turns, target
from puppet.commands.bench.speed import CHUNK_FRAMES, fed
from puppet.commands.bench.subjects import gesture

FEEDBACK_TARGET_PCT = 10.0
FEEDBACK_INTERFACES = ("biped-balance", "biped-step")


def _without_feedback(spec):
    """The interface with its feedback maps (sensor inputs, ``add``) taken out, everywhere."""
    def keep(maps):
        return [m for m in maps if not m.feedback]
    states = {n: st.model_copy(update={"maps": keep(st.maps)}) for n, st in spec.states.items()}
    return spec.model_copy(update={"maps": keep(spec.maps), "states": states,
                                   "modes": {n: keep(ms) for n, ms in spec.modes.items()}})


def measure_feedback(name: str, seconds: float, repeats: int) -> dict:
    """A Session of ``name`` against the same Session with its feedback maps taken out,
    fed the same input (the window's mouse and key taps), played in turns. The two
    runs' motions differ a little (no feedback corrections), so this is the cost of
    the feedback maps with the physics they cause, not a hash-compared pair."""
    import dataclasses

    from puppet.data.catalog import load_setup
    from puppet.physics.simulation import step_of
    from puppet.session import Session

    setup = load_setup(name)
    bare = dataclasses.replace(setup, interface=_without_feedback(setup.interface))
    dt = step_of(setup.character)  # the step its sessions run on
    n = max(1, round(1.0 / (FRAME_HZ * dt)))
    frames = max(1, round(seconds * FRAME_HZ))
    inputs = gesture(frames, setup.interface)

    ratios = []
    for _ in range(repeats):
        wall, _ = in_turns({"with": fed(Session(setup, keyframes=False), inputs, n),
                            "without": fed(Session(bare, keyframes=False), inputs, n)},
                           frames, CHUNK_FRAMES)
        ratios.append(wall["with"] / wall["without"])
    pct = (statistics.median(ratios) - 1.0) * 100.0
    return {"interface": name, "overhead_pct": pct,
            "overhead_range_pct": [(min(ratios) - 1.0) * 100.0, (max(ratios) - 1.0) * 100.0],
            "target": target(f"feedback maps cost: {name}", pct, "<=", FEEDBACK_TARGET_PCT, "%")}
