"""One frame of what the window shows - the world under the HUD's panels, then the HUD -
drawn into a surface. The window draws into its screen with it and headless runs,
video export and the bench into an off-screen surface, so a screenshot is the window's
frame, not a copy of its drawing code."""

from __future__ import annotations

import os

from puppet.app.camera import camera_for, subject_of
from puppet.session import Session

DEFAULT_SIZE = (1280, 720)


def load_pygame():
    """pygame with its fonts, headless unless a display was asked for."""
    os.environ.setdefault("SDL_VIDEODRIVER", "dummy")
    os.environ.setdefault("PYGAME_HIDE_SUPPORT_PROMPT", "1")
    import pygame

    pygame.font.init()
    return pygame


class FrameRenderer:
    """Draws what the window would show (world and HUD) into ``surface`` (the window's
    screen), or into an off-screen surface of ``size``. ``info``: the HUD's figures
    (a ``HudInfo``; a fresh one at ``slowdown`` when not given)."""

    def __init__(self, session: Session, size=DEFAULT_SIZE, slowdown: float = 1.0,
                 overlay: bool = False, surface=None, info=None):
        from puppet.app.hud import HudInfo

        pygame = self.pygame = load_pygame()
        self.surface = surface if surface is not None else pygame.Surface(size)
        self.camera = camera_for(session.setup)
        self.camera.resize(*self.surface.get_size())
        self.font = pygame.font.Font(None, 24)
        self.small = pygame.font.Font(None, 20)
        self.info = info if info is not None else HudInfo(slowdown=slowdown,
                                                          measured=slowdown, overlay=overlay)

    def render(self, session: Session, hud: bool = True, wall_dt: float | None = None,
               ghost: Session | None = None, hold_camera: bool = False,
               world: bool = True):
        """``wall_dt``: wall seconds since the last frame, for the camera's easing (None
        snaps to the character). ``ghost``: a session drawn translucently beside the
        live one (see ``puppet.timeline.ghost``). ``hold_camera``: keep the view where it
        is (the window, while a link is dragged or ctrl held). ``world=False`` leaves the
        last world drawn (the window, while a blown-up step waits for its recovery)."""
        from puppet.app.hud import draw_hud, frame_under_panels
        from puppet.app.render import draw_world

        if world:
            if not hold_camera:
                frame_under_panels(self.surface, self.camera, session, self.info,
                                   self.font, self.small)
                self.camera.follow(subject_of(session), wall_dt)
            draw_world(self.surface, session, self.camera, self.small, ghost=ghost,
                       overlay=self.info.overlay)
        if hud:
            draw_hud(self.surface, session, self.info, self.font, self.small)
        return self.surface

    def save(self, session: Session, path, hud: bool = True,
             ghost: Session | None = None) -> None:
        from pathlib import Path

        Path(path).parent.mkdir(parents=True, exist_ok=True)
        self.pygame.image.save(self.render(session, hud, ghost=ghost), str(path))
