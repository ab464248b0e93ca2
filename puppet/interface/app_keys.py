"""The app's own keys, listed once. An interface may rebind them (``app_keys:``).

Keys are pygame key names (``pygame.key.name``), lower case, with optional
``ctrl+``/``shift+``/``alt+`` prefixes. An interface that binds one of these keys
for itself without rebinding the app's action is refused at load time.
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import Enum

# action -> (default key, what it does). Order is the order shown in the HUD.
APP_KEYS: dict[str, tuple[str, str]] = {
    "quit": ("escape", "quit"),
    "reset": ("r", "reset to the start pose"),
    "pause": ("p", "pause / resume"),
    "step": (".", "single step while paused"),
    "slower": ("-", "more slowdown"),
    "faster": ("=", "less slowdown"),
    "help": ("f1", "show / hide the key map"),
    "checkpoint": ("c", "set a checkpoint"),
    "restore": ("backspace", "back to the last checkpoint"),
    "rewind": ("b", "hold to rewind (release to play on from there)"),
    "forward": ("shift+b", "hold to scrub forward again after rewinding"),
    "record_gesture": ("f2", "record a mouse gesture / stop; then press its key"),
    "save_gestures": ("f3", "save the bound gestures into the interface file"),
    "balance": ("f4", "show / hide the balance overlay: centre of mass, support, xcom"),
    "branches": ("f9", "list the abandoned futures near now (branches); again: the next"),
    "take_branch": ("f10", "take up the selected branch again"),
    "export_branch": ("f11", "export the selected branch as a log of its own"),
}


class _Named(str, Enum):
    def __str__(self) -> str:
        return self.value

    __format__ = str.__format__


# The app's actions as a typed vocabulary, one member per entry of APP_KEYS (a ``str``
# so that it prints, logs and compares as its name): what a key asks of the app, or an
# interface's ``app:``. AppAction.PAUSE == "pause".
AppAction = _Named("AppAction", {name.upper(): name for name in APP_KEYS})


@dataclass(frozen=True)
class SetSlowdown:
    """Set the slowdown to ``value`` (an interface key's ``slowdown:``)."""

    value: float


# Actions that change the simulation (and so are handled by the Session, replayed
# from logs); the others only change how the window presents it.
SIM_ACTIONS = frozenset({AppAction.RESET, AppAction.CHECKPOINT, AppAction.RESTORE})

MODIFIERS = ("ctrl", "shift", "alt")


def normalize_key(text: str) -> str:
    """Canonical form of a key chord: modifiers sorted, lower case ('Ctrl+A' -> 'ctrl+a')."""
    parts = [p.strip().lower() for p in text.split("+")] if text != "+" else ["+"]
    if text.endswith("++"):  # "ctrl++" means ctrl and the plus key
        parts = [p.strip().lower() for p in text[:-2].split("+")] + ["+"]
    mods = sorted(p for p in parts[:-1] if p in MODIFIERS)
    return "+".join(mods + [parts[-1]])


_KEY_NAMES: frozenset[str] | None = None
BUTTON_KEYS = ("mouse.left", "mouse.middle", "mouse.right")  # bindable like keys


def _key_names() -> frozenset[str]:
    """pygame's key names (what ``pygame.key.name`` reports for a pressed key)."""
    global _KEY_NAMES
    if _KEY_NAMES is None:
        import os
        import warnings

        os.environ.setdefault("PYGAME_HIDE_SUPPORT_PROMPT", "1")
        import pygame

        with warnings.catch_warnings():  # names need no display, so no pygame.init()
            warnings.simplefilter("ignore")
            _KEY_NAMES = frozenset(
                pygame.key.name(getattr(pygame, c)).lower() for c in dir(pygame)
                if c.startswith("K_")) - {""}
    return _KEY_NAMES


def key_problem(text: str) -> str | None:
    """Why ``text`` is not a key chord a device can send, or None if it is one."""
    parts = [p.strip().lower() for p in text.split("+")] if text != "+" else ["+"]
    if text.endswith("++"):
        parts = [p.strip().lower() for p in text[:-2].split("+")] + ["+"]
    for mod in parts[:-1]:
        if mod not in MODIFIERS:
            return f"unknown modifier '{mod}' in key '{text}'; expected {', '.join(MODIFIERS)}"
    name = parts[-1]
    if name in _key_names() or name in BUTTON_KEYS or \
            (name.startswith("gamepad.button") and name[len("gamepad.button"):].isdigit()):
        return None
    from puppet.interface.events import GAMEPAD_BUTTONS

    if name.startswith("gamepad.") and name[len("gamepad."):] in GAMEPAD_BUTTONS:
        return None
    return (f"unknown key name '{name}'; expected a pygame key name such as a, 1, space, "
            f"return, backspace, tab, left, f1, [, =, or mouse.left / gamepad.a / gamepad.button0")


def key_chord(name: str, mods: tuple[str, ...] | list[str] = ()) -> str:
    """Chord string for a key name and held modifiers."""
    return "+".join(sorted(set(m for m in mods if m in MODIFIERS)) + [name.lower()])
