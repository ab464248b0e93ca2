"""Heads-up display: time, slowdown (requested and measured), fps, scene, bindings."""

from __future__ import annotations

from dataclasses import dataclass

import pygame

from puppet.interface.describe import app_lines, interface_lines
from puppet.session import Session

TEXT = (40, 44, 52)
DIM = (110, 116, 128)
PANEL = (255, 255, 255, 200)


@dataclass
class HudInfo:
    slowdown: float = 1.0
    measured: float | None = None
    fps: float | None = None
    paused: bool = False
    show_help: bool = False
    message: str = ""


def _panel(surface, rect) -> None:
    panel = pygame.Surface(rect.size, pygame.SRCALPHA)
    panel.fill(PANEL)
    surface.blit(panel, rect.topleft)


def _fmt_rate(x: float | None) -> str:
    if x is None:
        return "-"
    return f"{x:.1f}x" if x < 10 else f"{x:.0f}x"


def draw_hud(surface: pygame.Surface, session: Session, info: HudInfo,
             font: pygame.font.Font, small: pygame.font.Font) -> None:
    setup = session.setup
    lines = [
        f"{setup.interface.name}  -  {setup.character.name} on {setup.scene.name}",
        f"sim time {session.time:7.2f} s   step {session.steps}",
        f"slowdown {_fmt_rate(info.slowdown)} (measured {_fmt_rate(info.measured)})",
        f"fps {info.fps:.0f}" if info.fps is not None else "fps -",
    ]
    if info.paused:
        lines.append("PAUSED  (step with the step key)")
    height = 8 + len(lines) * 22
    _panel(surface, pygame.Rect(8, 8, 360, height))
    for i, text in enumerate(lines):
        surface.blit(font.render(text, True, TEXT if i else (20, 60, 120)), (16, 12 + i * 22))

    controls = interface_lines(setup.interface)
    app = app_lines(setup.interface)
    rows = [("controls", "")] + controls
    if info.show_help:
        rows += [("", ""), ("app keys", "")] + app
    else:
        help_key = setup.interface.app_key_table()["help"]
        rows += [("", ""), (help_key, "all keys")]
    width = 330
    x0 = surface.get_width() - width - 8
    _panel(surface, pygame.Rect(x0, 8, width, 8 + len(rows) * 18))
    for i, (k, text) in enumerate(rows):
        y = 12 + i * 18
        if not text:
            surface.blit(small.render(k, True, (20, 60, 120)), (x0 + 8, y))
            continue
        surface.blit(small.render(k, True, TEXT), (x0 + 8, y))
        surface.blit(small.render(text, True, DIM), (x0 + 110, y))
    if info.message:
        msg = font.render(info.message, True, (160, 30, 30))
        rect = msg.get_rect(midbottom=(surface.get_width() / 2, surface.get_height() - 12))
        _panel(surface, rect.inflate(16, 8))
        surface.blit(msg, rect)
