"""A frame of the window with the HUD and the key map (F1) open, on the biped's scenes.

Each subject is a shipped log replayed as the window replays it (``LogFeeder``, a
frame's steps at a time) and drawn, HUD and F1's key map and help panels included,
into an off-screen surface of the window's default size (``FrameRenderer``, the
window's own drawing code): per frame the time to step it and to draw it, on the
bench's clock. The target is the 99th percentile of the whole frame.
"""

from __future__ import annotations

import gc

from puppet.commands.bench.config import clock

# (log, what it shows): the biped's scenes, each with its interface's panels
SUBJECTS = (("biped-walk", "biped-track"), ("biped-ladder-climb", "ladder"),
            ("biped-monkey-bars", "monkey bars"), ("biped-mocap-walk", "mocap, KD"))
SIZE = (1280, 720)


def _pct(values: list[float], p: float) -> float:
    values = sorted(values)
    return values[min(len(values) - 1, int(p * len(values)))] * 1e3


def measure_frames(frames: int) -> list[dict]:
    """Per subject: frame, physics and drawing times (ms: median, 99th percentile,
    worst) over its first ``frames`` frames (after ten to warm the caches)."""
    from puppet.app.frame import FrameRenderer
    from puppet.data.catalog import folder
    from puppet.timeline.log import read_log
    from puppet.timeline.replay import LogFeeder, new_session, setup_for_log

    out = []
    for name, scene in SUBJECTS:
        path = folder("log") / f"{name}.jsonl"
        if not path.is_file():
            continue
        log = read_log(path)
        setup, _ = setup_for_log(log)
        session = new_session(log, setup)
        feeder = LogFeeder(session, log)
        renderer = FrameRenderer(session, size=SIZE)
        renderer.info.show_help = True  # F1: the key map and the help panels
        steps = max(1, round(1.0 / (60.0 * session.sim.dt)))
        whole, physics, drawing = [], [], []
        gc.collect()
        for k in range(frames + 10):
            t0 = clock()
            feeder.advance(steps)
            t1 = clock()
            renderer.render(session, hud=True, wall_dt=1.0 / 60.0)
            t2 = clock()
            if k >= 10:
                whole.append(t2 - t0)
                physics.append(t1 - t0)
                drawing.append(t2 - t1)
        out.append({"log": name, "scene": scene, "frames": len(whole),
                    "p50_ms": _pct(whole, 0.5), "p99_ms": _pct(whole, 0.99),
                    "max_ms": _pct(whole, 1.0),
                    "physics_p50_ms": _pct(physics, 0.5), "physics_p99_ms": _pct(physics, 0.99),
                    "draw_p50_ms": _pct(drawing, 0.5), "draw_p99_ms": _pct(drawing, 0.99)})
    return out
