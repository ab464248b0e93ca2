"""Live takes without a window: a real-time frame loop that drains live sources into a
Session and records the take, so it replays headless with no network.

The loop runs at ``FRAME_HZ`` like the window: each frame it drains every source
(``OscSource.drain``) into ``Session.handle`` (the events are recorded at the step
they act), then advances the steps the wall clock says are due (times the slowdown).
"""

from __future__ import annotations

import contextlib
import time
from collections.abc import Callable

from puppet.data.catalog import Setup
from puppet.physics.upright_watch import UprightWatch
from puppet.session import Session

FRAME_HZ = 60.0


def run_live(setup: Setup, sources, seconds: float, record=None, slowdown: float | None = None,
             description: str | None = None, on_frame: Callable[[Session], None] | None = None,
             clock: Callable[[], float] = time.perf_counter,
             sleep: Callable[[float], None] = time.sleep) -> Session:
    """Play ``seconds`` of simulated time paced by the wall clock (``slowdown`` wall
    seconds per simulated second; default the interface's), fed by ``sources``."""
    session = Session(setup)
    watch = session.upright_watch = UprightWatch()  # the end line's upright= (each frame)
    dt = session.sim.dt
    slowdown = slowdown or setup.interface.slowdown
    until = round(seconds / dt)
    recording = contextlib.nullcontext()
    if record:
        from puppet.timeline.log import Recorder

        recording = Recorder(session, record, slowdown=slowdown, description=description)
    with recording:
        start = clock()
        frame = 0
        while session.steps < until:
            frame += 1
            wait = start + frame / FRAME_HZ - clock()
            if wait > 0:
                sleep(wait)
            for source in sources:
                for event in source.drain(session.time):
                    session.handle(event)
            due = min(until, int((clock() - start) / (dt * slowdown)))
            session.advance(due - session.steps)
            watch(session)
            if on_frame is not None:
                on_frame(session)
    return session
