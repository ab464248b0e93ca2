"""Heads-up display: time, slowdown (requested and measured), fps, scene, bindings."""

from __future__ import annotations

from dataclasses import dataclass

import pygame

from puppet.app.keymap import draw_keymap
from puppet.interface.describe import app_lines, interface_lines, where_line
from puppet.session import Session

TEXT = (40, 44, 52)
DIM = (110, 116, 128)
PANEL = (255, 255, 255, 200)


MESSAGE_SECONDS = 5.0  # how long a session message stays on screen


@dataclass
class HudInfo:
    slowdown: float = 1.0
    measured: float | None = None
    fps: float | None = None
    paused: bool = False
    show_help: bool = False
    message: str = ""
    scrubbing: bool = False  # the rewind key is held
    replaying: str = ""  # the log a window replay plays (its events, not the devices)
    _seen_serial: int = 0
    _message_until: float = 0.0

    def follow_messages(self, session: Session, now: float) -> None:
        """Show the session's newest message (e.g. a recovered blow-up) for
        MESSAGE_SECONDS of the caller's clock (wall time in the window, video time in
        an export), then clear it."""
        if session.message_serial != self._seen_serial:
            self._seen_serial, self._message_until = session.message_serial, now + MESSAGE_SECONDS
            self.message = session.message
        elif self.message and now > self._message_until:
            self.message = ""


def _panel(surface, rect) -> None:
    panel = pygame.Surface(rect.size, pygame.SRCALPHA)
    panel.fill(PANEL)
    surface.blit(panel, rect.topleft)


def _fmt_rate(x: float | None) -> str:
    if x is None:
        return "-"
    return f"{x:.2f}x" if x < 1 else f"{x:.1f}x" if x < 10 else f"{x:.0f}x"


def draw_hud(surface: pygame.Surface, session: Session, info: HudInfo,
             font: pygame.font.Font, small: pygame.font.Font) -> None:
    setup = session.setup
    lines = [
        f"{setup.interface.name}  -  {setup.character.name} on {setup.scene.name}",
        f"sim time {session.time:7.2f} s   step {session.steps}",
        f"slowdown {_fmt_rate(info.slowdown)} (measured {_fmt_rate(info.measured)})",
        f"fps {info.fps:.0f}" if info.fps is not None else "fps -",
    ]
    if info.replaying:
        lines.append(f"REPLAY  {info.replaying}")
    if info.paused:
        lines.append("PAUSED  (step with the step key)")
    height = 8 + len(lines) * 22
    width = max(360, 16 + max(font.size(text)[0] for text in lines))  # never clipped
    _panel(surface, pygame.Rect(8, 8, width, height))
    for i, text in enumerate(lines):
        surface.blit(font.render(text, True, TEXT if i else (20, 60, 120)), (16, 12 + i * 22))

    runtime = session.runtime
    controls = interface_lines(setup.interface, runtime.state, runtime.mode)
    app = app_lines(setup.interface)
    where = where_line(setup.interface, runtime.state, runtime.mode)
    rows = [(f"controls  ({where})" if where else "controls", "")] + controls
    if info.show_help:
        rows += [("", ""), ("app keys", "")] + app
    else:
        help_key = session.app_keys["help"]
        rows += [("", ""), (help_key, "all keys")]
    # As wide as the longest line needs, up to half the window (then text is clipped).
    widest = max((110 + small.size(text)[0] for _, text in rows if text), default=0)
    width = int(min(max(330, widest + 16), surface.get_width() / 2))
    x0 = surface.get_width() - width - 8
    _panel(surface, pygame.Rect(x0, 8, width, 8 + len(rows) * 18))
    for i, (k, text) in enumerate(rows):
        y = 12 + i * 18
        if not text:
            surface.blit(small.render(k, True, (20, 60, 120)), (x0 + 8, y))
            continue
        surface.blit(small.render(k, True, TEXT), (x0 + 8, y))
        surface.blit(small.render(text, True, DIM), (x0 + 110, y))
    if info.show_help:  # pose keys as pictures, laid out like the keyboard
        draw_keymap(surface, setup.interface, setup.character, small, (8, 16 + height),
                    state=session.runtime.state)
    draw_timeline(surface, session, info, small)
    if info.message:
        msg = font.render(info.message, True, (160, 30, 30))
        rect = msg.get_rect(midbottom=(surface.get_width() / 2, surface.get_height() - 40))
        _panel(surface, rect.inflate(16, 8))
        surface.blit(msg, rect)


def draw_timeline(surface: pygame.Surface, session: Session, info: HudInfo,
                  small: pygame.font.Font) -> None:
    """A bar along the bottom: the rewindable span (blue), checkpoints (orange ticks),
    automatic checkpoints (grey ticks) and where the simulation is now (dark line)."""
    history = getattr(session, "history", None)
    if history is None:
        return
    dt = session.sim.dt
    span = history.span()
    marks = history.checkpoint_steps()
    last = max([session.steps] + ([span[1]] if span else []) + marks)
    end = max(last * dt, 1.0)
    w, h = surface.get_size()
    x0, x1, y = 90, w - 16, h - 18
    _panel(surface, pygame.Rect(8, y - 12, w - 16, 24))
    label = "REWIND" if info.scrubbing else f"{session.time:6.1f} s"
    surface.blit(small.render(label, True, (20, 60, 120) if info.scrubbing else TEXT),
                 (16, y - 7))

    def px(step: int) -> int:
        return round(x0 + (x1 - x0) * min(1.0, step * dt / end))

    pygame.draw.rect(surface, (215, 218, 224), pygame.Rect(x0, y - 3, x1 - x0, 6))
    if span is not None:
        a, b = px(span[0]), px(span[1])
        pygame.draw.rect(surface, (120, 160, 220), pygame.Rect(a, y - 3, max(2, b - a), 6))
    for snap in history.auto:
        pygame.draw.line(surface, (150, 150, 150), (px(snap.step), y + 3), (px(snap.step), y + 6))
    for step in marks:
        pygame.draw.line(surface, (230, 140, 30), (px(step), y - 8), (px(step), y + 8), 2)
    cur = px(session.steps)
    pygame.draw.line(surface, (20, 30, 50), (cur, y - 9), (cur, y + 9), 3)
