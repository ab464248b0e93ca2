"""A gamepad made of the mouse and a few keys (``puppet play NAME --virtual-pad``), to try
a pad layout with no pad: what it sends are gamepad events, as a real pad's, so the
session, its log and its replay are a gamepad session.

- the mouse's place in the window is the left stick (the middle is the stick at rest,
  the edges full travel, y up); while the right mouse button is held it moves the
  right stick instead, and the left stick stays where it was;
- the left mouse button is the right trigger, the middle button the left trigger;
- the face buttons are a diamond on the keys ``i`` (y, top), ``j`` (x, left), ``l``
  (b, right) and ``k`` (a, bottom), as they sit on a pad; the arrows are the d-pad,
  ``u`` and ``o`` the left and right shoulder, ``return`` start and ``tab`` back.
"""

from __future__ import annotations

from puppet.interface import events as ev
from puppet.interface.events import Event

BUTTON_KEYS = {"k": "a", "l": "b", "j": "x", "i": "y", "up": "dpad_up", "down": "dpad_down",
               "left": "dpad_left", "right": "dpad_right", "u": "left_shoulder",
               "o": "right_shoulder", "return": "start", "tab": "back"}
TRIGGERS = {"left": "right_trigger", "middle": "left_trigger"}  # mouse button -> trigger
HELP = ("virtual pad: the mouse is the left stick (hold the right button: the right "
        "stick), left button the right trigger, i j k l the face buttons y x a b, "
        "arrows the d-pad, u o the shoulders, return start")


class VirtualPad:
    def __init__(self):
        self.last: dict[str, float] = {}  # input -> the value last sent
        self.right = False  # the right mouse button is held: the mouse is the right stick

    def _send(self, name: str, value: float) -> list[Event]:
        if self.last.get(name) == value:
            return []
        self.last[name] = value
        return [ev.gamepad(name, value)]

    def mouse(self, x: float, y: float) -> list[Event]:
        """The pointer at (x, y) of the window (0..1, y up) as a stick's position."""
        stick = "right" if self.right else "left"
        return (self._send(f"{stick}_x", round(2.0 * x - 1.0, 6))
                + self._send(f"{stick}_y", round(2.0 * y - 1.0, 6)))

    def button(self, button: str, down: bool) -> list[Event]:
        """A mouse button: the right one switches sticks, the others are triggers."""
        if button == "right":
            self.right = down
            return []
        trigger = TRIGGERS.get(button)
        return self._send(trigger, 1.0 if down else 0.0) if trigger else []

    def key(self, name: str, down: bool) -> list[Event] | None:
        """A key of the pad (a button's events), or None if the key is not one."""
        button = BUTTON_KEYS.get(name)
        if button is None:
            return None
        return self._send(button, 1.0 if down else 0.0)

    @staticmethod
    def clashes(interface) -> list[str]:
        """The interface's own keys that the pad takes (they do not reach it)."""
        bound = {k.key for k in interface.keys}
        for state in interface.states.values():
            bound |= {k.key for k in state.keys}
        for machine in interface.machines.values():
            for state in machine.states.values():
                bound |= {k.key for k in state.keys}
        return sorted(k for k in bound if k in BUTTON_KEYS)


def pad_events(pygame, pad: VirtualPad, event,
               translated: list[Event]) -> tuple[list[Event], bool]:
    """(what the window sends, whether the event was the pad's alone) for one pygame
    event with the virtual pad: a mouse button's input becomes a trigger (or switches
    sticks), a pad key's press a button's; other events as they were."""
    if event.type in (pygame.MOUSEBUTTONDOWN, pygame.MOUSEBUTTONUP):
        out = []
        for e in translated:
            out += pad.button(e["button"], e["down"]) if e["type"] == "mouse_button" else [e]
        return out, False
    if event.type in (pygame.KEYDOWN, pygame.KEYUP) and not pygame.key.get_mods() & (
            pygame.KMOD_CTRL | pygame.KMOD_ALT | pygame.KMOD_SHIFT):
        sent = pad.key(pygame.key.name(event.key), event.type == pygame.KEYDOWN)
        if sent is not None:
            return sent, True
    return translated, False
