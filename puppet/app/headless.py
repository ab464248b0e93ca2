"""Run the app without a window: scripted input in, images of what the window shows out
(``frame.FrameRenderer``, the window's own drawing)."""

from __future__ import annotations

import contextlib
import math
from pathlib import Path

from puppet.app.frame import DEFAULT_SIZE, FrameRenderer
from puppet.data.catalog import Setup
from puppet.interface.events import Event
from puppet.physics.upright_watch import UprightWatch
from puppet.session import Session
from puppet.session.playback import play


class Images:
    """The images of a headless run, drawn as the window draws them: every frame at
    ``fps`` into ``frames_dir`` (frame_00000.png, ...) and/or the last one into
    ``screenshot``. One path for ``puppet play --headless`` and ``puppet replay
    --headless``: ``every(dt)`` and ``frame`` go to ``playback.play`` as its ``every``
    and ``on_tick``, ``finish`` writes the screenshot. Drawing reads the session only:
    the run, its log and its state hash are those of a run without images."""

    def __init__(self, screenshot: str | Path | None = None, frames_dir: str | Path | None = None,
                 fps: float = 30.0, size=DEFAULT_SIZE, slowdown: float = 1.0,
                 overlay: bool = False, ghost=None):
        self.screenshot, self.frames_dir, self.fps = screenshot, frames_dir, fps
        self.size, self.slowdown, self.overlay, self.ghost = size, slowdown, overlay, ghost
        self.renderer: FrameRenderer | None = None
        self.written = 0  # frames written to frames_dir

    def every(self, dt: float) -> int:
        """Steps between two frames (0: no frames asked for)."""
        return max(1, round(1.0 / (self.fps * dt))) if self.frames_dir else 0

    def _draw(self, session: Session, path: Path | str) -> None:
        if self.renderer is None:  # made for the first session drawn (its scene's camera)
            self.renderer = FrameRenderer(session, self.size, self.slowdown,
                                          overlay=self.overlay)
        _follow(self.renderer, session)
        self.renderer.save(session, path, ghost=_synced(self.ghost, session))

    def frame(self, session: Session) -> None:
        """Write the next frame (``play``'s ``on_tick``)."""
        self._draw(session, Path(self.frames_dir) / f"frame_{self.written:05d}.png")
        self.written += 1

    def finish(self, session: Session) -> None:
        """Write the screenshot: the last frame, where the run ended."""
        if self.screenshot:
            self._draw(session, self.screenshot)


def run_headless(setup: Setup, events: list[tuple[int, Event]], seconds: float,
                 screenshot: str | None = None, frames_dir: str | None = None,
                 fps: float = 30.0, size=DEFAULT_SIZE, slowdown: float | None = None,
                 record: str | Path | None = None, description: str | None = None,
                 ghost=None, overlay: bool = False, rules=None,
                 script: tuple[str, str] | None = None) -> Session:
    """Play ``events`` for ``seconds``; write the final frame (``screenshot``) and/or
    every frame at ``fps`` (``frames_dir``); ``record``: also write the input log
    there (the images do not change the run: same log, same state hash).
    ``ghost``: a ``puppet.timeline.ghost.Ghost`` drawn beside the character;
    ``overlay``: draw the balance overlay (``render.draw_balance``). ``rules``: a
    script with rules (``ScriptSpec``), played with ``events`` by a reactive player
    (``puppet.timeline.reactive``); ``script``: its (name, text), kept in the log's
    header. The session returned has ``frames_written``: the number of frames written
    to ``frames_dir``, and ``upright_watch``: whether the root stayed upright over the
    last second."""
    session = Session(setup)
    until = round(seconds / session.sim.dt)
    images = Images(screenshot, frames_dir, fps, size, slowdown or setup.interface.slowdown,
                    overlay, ghost)
    recording = contextlib.nullcontext()
    if record:
        from puppet.timeline.log import Recorder

        recording = Recorder(session, record, slowdown=slowdown, description=description,
                             script=script if rules is not None else None)
    # the end line's upright=: over the last second, not the last step (UprightWatch)
    watch = session.upright_watch = UprightWatch()
    watch_every = UprightWatch.every(session.sim.dt)
    frame_every = images.every(session.sim.dt)
    every = math.gcd(frame_every, watch_every)  # (the steps do not depend on it)

    def on_tick(s: Session) -> None:
        if s.steps % watch_every == 0:
            watch(s)
        if frame_every and s.steps % frame_every == 0:
            images.frame(s)

    with recording:
        watch(session)
        if rules is not None:
            from puppet.timeline.reactive import ScriptPlayer, Speed, play_script

            speed = Speed(slowdown or setup.interface.slowdown)
            player = ScriptPlayer(session, rules, until, speed, speed.apply, timed=events)
            play_script(session, player, every, on_tick)
        else:
            play(session, events, until, every, on_tick)
    images.finish(session)
    session.frames_written = images.written  # how many frames went to frames_dir (the CLI says so)
    return session


def _follow(renderer: FrameRenderer, session: Session) -> None:
    """The session's messages on the frame, as the window shows them: each for
    ``hud.MESSAGE_SECONDS`` of the wall time the run would take at its slowdown."""
    renderer.info.follow_messages(session, session.time * renderer.info.slowdown)


def _synced(ghost, session: Session) -> Session | None:
    """The ghost's session, brought to ``session``'s time (None without a ghost)."""
    if ghost is None:
        return None
    ghost.sync(session)
    return ghost.session
