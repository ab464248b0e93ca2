"""The key and input vocabulary that data files are checked against: pure data, no pygame.

What an interface or a script may name as a key (``key_problem``), in canonical form
(``normalize_key``): pygame's key names (``pygame.key.name``), lower case, with optional
``ctrl+``/``shift+``/``alt+`` prefixes; the mouse buttons; the gamepad's inputs by SDL's
standard names. Also the app's own keys (``APP_KEYS``), listed once: an interface that
binds one of them for itself without moving the app's action (``app_keys:``) is refused
at load time. The app's runtime vocabulary over these (``AppAction``, ``SetSlowdown``)
is in ``puppet.interface.app_keys``.

``PYGAME_KEY_NAMES`` is a literal copy of what ``pygame.key.name`` reports for every
``pygame.K_*`` constant, so validation needs no pygame; ``tests/test_keys.py`` fails when
an upgraded pygame names its keys otherwise (then regenerate the table as that test says).
"""

from __future__ import annotations

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

MODIFIERS = ("ctrl", "shift", "alt")
BUTTON_KEYS = ("mouse.left", "mouse.middle", "mouse.right")  # bindable like keys

# A game controller's inputs by SDL's standard names (the layout of an Xbox pad: a is
# the bottom face button). Sticks read -1..1 with y up, triggers 0..1, buttons 0/1.
GAMEPAD_STICKS = ("left_x", "left_y", "right_x", "right_y")
GAMEPAD_TRIGGERS = ("left_trigger", "right_trigger")
POINTER = ("pointer.x", "pointer.y")  # the mouse, or a stick: one input for either


def pointer_value(stick: float) -> float:
    """A stick's -1..1 as the pointer's 0..1 (centred: the middle of the window)."""
    return (stick + 1.0) / 2.0


GAMEPAD_BUTTONS = ("a", "b", "x", "y", "back", "guide", "start", "left_stick",
                   "right_stick", "left_shoulder", "right_shoulder", "dpad_up",
                   "dpad_down", "dpad_left", "dpad_right")

# pygame.key.name(pygame.K_*).lower() for every K_* constant, without pygame.init()
# (generated with pygame-ce 2.5.8; checked against the installed pygame by the tests).
PYGAME_KEY_NAMES: frozenset[str] = frozenset({
    '!', '"', '#', '$', '%', '&', "'", '(', ')', '*', '+', ',', '-', '.', '/', '0', '1', '2', '3',
    '4', '5', '6', '7', '8', '9', ':', ';', '<', '=', '>', '?', '@', '[', '[*]', '[+]', '[-]',
    '[.]', '[/]', '[0]', '[1]', '[2]', '[3]', '[4]', '[5]', '[6]', '[7]', '[8]', '[9]', '\\', ']',
    '^', '_', '`', 'a', 'ac back', 'alt gr', 'b', 'backspace', 'break', 'c', 'caps lock', 'clear',
    'currencysubunit', 'd', 'delete', 'down', 'e', 'end', 'enter', 'equals', 'escape', 'euro', 'f',
    'f1', 'f10', 'f11', 'f12', 'f13', 'f14', 'f15', 'f2', 'f3', 'f4', 'f5', 'f6', 'f7', 'f8', 'f9',
    'g', 'h', 'help', 'home', 'i', 'insert', 'j', 'k', 'l', 'left', 'left alt', 'left ctrl',
    'left meta', 'left shift', 'm', 'menu', 'n', 'numlock', 'o', 'p', 'page down', 'page up',
    'power', 'print screen', 'q', 'r', 'return', 'right', 'right alt', 'right ctrl', 'right meta',
    'right shift', 's', 'scroll lock', 'space', 'sys req', 't', 'tab', 'u', 'up', 'v', 'w', 'x',
    'y', 'z',
})


def normalize_key(text: str) -> str:
    """Canonical form of a key chord: modifiers sorted, lower case ('Ctrl+A' -> 'ctrl+a')."""
    parts = [p.strip().lower() for p in text.split("+")] if text != "+" else ["+"]
    if text.endswith("++"):  # "ctrl++" means ctrl and the plus key
        parts = [p.strip().lower() for p in text[:-2].split("+")] + ["+"]
    mods = sorted(p for p in parts[:-1] if p in MODIFIERS)
    return "+".join(mods + [parts[-1]])


def key_problem(text: str) -> str | None:
    """Why ``text`` is not a key chord a device can send, or None if it is one."""
    parts = [p.strip().lower() for p in text.split("+")] if text != "+" else ["+"]
    if text.endswith("++"):
        parts = [p.strip().lower() for p in text[:-2].split("+")] + ["+"]
    for mod in parts[:-1]:
        if mod not in MODIFIERS:
            return f"unknown modifier '{mod}' in key '{text}'; expected {', '.join(MODIFIERS)}"
    name = parts[-1]
    if name in PYGAME_KEY_NAMES or name in BUTTON_KEYS or \
            (name.startswith("gamepad.button") and name[len("gamepad.button"):].isdigit()):
        return None
    if name.startswith("gamepad.") and name[len("gamepad."):] in GAMEPAD_BUTTONS:
        return None
    import difflib  # (only for a mistake: process start)

    names = [*sorted(PYGAME_KEY_NAMES), *BUTTON_KEYS, *(f"gamepad.{b}" for b in GAMEPAD_BUTTONS)]
    close = difflib.get_close_matches(name, [n for n in names if len(n) > 1], n=1, cutoff=0.7)
    hint = f"; did you mean '{close[0]}'?" if close else ";"
    return (f"unknown key name '{name}'{hint} expected a pygame key name such as a, 1, space, "
            f"return, backspace, tab, left, f1, [, =, or mouse.left / gamepad.a / gamepad.button0")


def key_chord(name: str, mods: tuple[str, ...] | list[str] = ()) -> str:
    """Chord string for a key name and held modifiers."""
    return "+".join(sorted(set(m for m in mods if m in MODIFIERS)) + [name.lower()])
