"""Run the app without a window: scripted input in, images of what the window shows out."""

from __future__ import annotations

import contextlib

import os
from pathlib import Path

from puppet.app.camera import camera_for, subject_of
from puppet.data.catalog import Setup
from puppet.interface.events import Event
from puppet.session import Session
from puppet.timeline.playback import play

DEFAULT_SIZE = (1280, 720)


def _pygame():
    os.environ.setdefault("SDL_VIDEODRIVER", "dummy")
    os.environ.setdefault("PYGAME_HIDE_SUPPORT_PROMPT", "1")
    import pygame

    pygame.font.init()
    return pygame


class FrameRenderer:
    """Draws what the window would show (world and HUD) into an off-screen surface."""

    def __init__(self, session: Session, size=DEFAULT_SIZE, slowdown: float = 1.0,
                 overlay: bool = False):
        pygame = _pygame()
        from puppet.app.hud import HudInfo

        self.pygame = pygame
        self.surface = pygame.Surface(size)
        self.camera = camera_for(session.setup)
        self.camera.resize(*size)
        self.font = pygame.font.Font(None, 24)
        self.small = pygame.font.Font(None, 20)
        self.info = HudInfo(slowdown=slowdown, measured=slowdown, overlay=overlay)

    def render(self, session: Session, hud: bool = True, wall_dt: float | None = None,
               ghost: Session | None = None):
        """``wall_dt``: wall seconds since the last frame, for the camera's easing as in
        the window (None snaps to the character). ``ghost``: a session drawn
        translucently beside the live one (see ``puppet.timeline.ghost``)."""
        from puppet.app.hud import draw_hud
        from puppet.app.render import draw_world

        self.camera.follow(subject_of(session), wall_dt)
        draw_world(self.surface, session, self.camera, self.small, ghost=ghost,
                   overlay=self.info.overlay)
        if hud:
            draw_hud(self.surface, session, self.info, self.font, self.small)
        return self.surface

    def save(self, session: Session, path: str | Path, hud: bool = True,
             ghost: Session | None = None) -> None:
        Path(path).parent.mkdir(parents=True, exist_ok=True)
        self.pygame.image.save(self.render(session, hud, ghost=ghost), str(path))


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
    to ``frames_dir``."""
    session = Session(setup)
    until = round(seconds / session.sim.dt)
    renderer = None
    if screenshot or frames_dir:
        renderer = FrameRenderer(session, size, slowdown or setup.interface.slowdown,
                                 overlay=overlay)
    every, on_tick = 0, None
    session.frames_written = 0  # how many frames went to frames_dir (the CLI says so)
    if frames_dir:
        every = max(1, round(1.0 / (fps * session.sim.dt)))

        def on_tick(s: Session) -> None:
            _follow(renderer, s)
            renderer.save(s, Path(frames_dir) / f"frame_{session.frames_written:05d}.png",
                          ghost=_synced(ghost, s))
            session.frames_written += 1

    recording = contextlib.nullcontext()
    if record:
        from puppet.timeline.log import Recorder

        recording = Recorder(session, record, slowdown=slowdown, description=description,
                             script=script if rules is not None else None)
    with recording:
        if rules is not None:
            from puppet.timeline.reactive import ScriptPlayer, Speed, play_script

            speed = Speed(slowdown or setup.interface.slowdown)
            player = ScriptPlayer(session, rules, until, speed, speed.apply, timed=events)
            play_script(session, player, every, on_tick)
        else:
            play(session, events, until, every, on_tick)
    if screenshot:
        _follow(renderer, session)
        renderer.save(session, screenshot, ghost=_synced(ghost, session))
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
