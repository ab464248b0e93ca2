"""What is wrong with an input event, or None: the one check of an event's shape and
values, for a log's lines (``puppet.timeline.log``) and for what live sources post
(``puppet.input.live``), beside the events it checks (``events.py``).

Every number must be finite and inside its range (``puppet.data.ranges``), every name a
bounded string, every key one a file may bind: a malformed event is refused where it
enters, never raised inside the frame loop or the physics.
"""

from __future__ import annotations

import re
from typing import Any

from puppet.data import ranges
from puppet.data.keys import GAMEPAD_BUTTONS, GAMEPAD_STICKS, GAMEPAD_TRIGGERS, key_problem
from puppet.interface.app_keys import SIM_ACTIONS

GAMEPAD_NAMES = frozenset(GAMEPAD_STICKS + GAMEPAD_TRIGGERS + GAMEPAD_BUTTONS)

EVENT_FIELDS = {  # event type -> required fields (besides "type")
    "mouse": ("x", "y"),
    "key": ("key", "down"),
    "action": ("name",),
    "drag": ("phase",),
    "push": ("link", "impulse"),  # a shove: an impulse at a point of a link
    "mouse_button": ("button", "down"),  # interface inputs (puppet/interface/events.py)
    "gamepad": ("name", "value"),
    "channel": ("name", "value"),
    "channels": ("values",),  # many named channels at one step (a mocap frame)
    "reload": ("text",),  # a hot reload: the interface's whole new text
    "gesture": ("key", "path"),  # bind a recorded mouse path to a key
}

MAX_NAME = 200  # characters in a key, link, action, device or channel name
MAX_PATH = 4096  # characters in a file name in a header or a reload event
MAX_GESTURE_POINTS = 200_000
MAX_CHANNELS = 4096  # named values in one channels event (a mocap frame has a few hundred)
MAX_STEP = 10 ** 12  # a rewind's step when no log bounds it (a live source)


def is_number(v) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def _is_name(v) -> bool:
    return isinstance(v, str) and 0 < len(v) <= MAX_NAME


def _number_problem(what: str, v, range_name: str) -> str | None:
    message = ranges.problem(range_name, v)
    return None if message is None else f"{what} {message}, got {short(v)}"


def short(v) -> str:
    text = repr(v)
    return text if len(text) <= 40 else text[:37] + "..."


def _point_problem(what: str, v, range_name: str) -> str | None:
    if not (isinstance(v, list) and len(v) == 2):
        return f"{what} must be [x, y], got {short(v)}"
    return (_number_problem(what + " x", v[0], range_name)
            or _number_problem(what + " y", v[1], range_name))


def _check_mouse(e):
    return _number_problem("mouse event: 'x'", e["x"], "mouse") \
        or _number_problem("mouse event: 'y'", e["y"], "mouse")


def _check_key(e):
    if not (_is_name(e["key"]) and isinstance(e["down"], bool)):
        return (f"key event: 'key' must be a name of 1..{MAX_NAME} characters and 'down' "
                "true or false")
    problem = key_problem(e["key"])  # the names a file may bind (a device sends no other)
    return None if problem is None else f"key event: {problem}"


def _check_action(e, last_step):
    name = e["name"]
    if name == "rewind":
        to = e.get("to_step")
        if not (isinstance(to, int) and not isinstance(to, bool) and 0 <= to <= last_step):
            return f"rewind action needs a whole-number 'to_step', 0..{last_step}"
        return None
    if name == "take":  # an abandoned future taken up again (a kept branch)
        branch = e.get("branch")
        if not (isinstance(branch, int) and not isinstance(branch, bool) and branch >= 0):
            return "take action needs a whole-number 'branch' >= 0"
        return None
    if name not in SIM_ACTIONS:
        return (f"action event: unknown action {short(name)}; expected one of: "
                f"{', '.join(sorted(SIM_ACTIONS | {'rewind', 'take'}))}")
    return None


def _check_drag(e):
    phase = e["phase"]
    if phase not in ("start", "move", "end"):
        return f"drag event: unknown phase {short(phase)}; expected start, move or end"
    if phase == "start":
        if not _is_name(e.get("link")):
            return f"drag start: 'link' must be a link name of 1..{MAX_NAME} characters"
        return (_point_problem("drag start: 'point'", e.get("point"), "model_xy")
                or _point_problem("drag start: 'target'", e.get("target"), "world_xy"))
    if phase == "move":
        return _point_problem("drag move: 'target'", e.get("target"), "world_xy")
    return None


def _check_button(e):
    if e["button"] not in ("left", "middle", "right") or not isinstance(e["down"], bool):
        return "mouse_button event: 'button' must be left, middle or right and 'down' " \
               "true or false"
    return None


def _check_device(e):
    kind = e["type"]
    name = e["name"]
    if kind == "gamepad":
        if not (isinstance(name, str) and (re.fullmatch(r"(axis|button)\d{1,3}", name)
                                           or name in GAMEPAD_NAMES)):
            return (f"gamepad event: 'name' must be a standard name (left_x, a, ...), axisN "
                    f"or buttonN, got {short(name)}")
    elif not (_is_name(name) and re.fullmatch(r"[A-Za-z_][A-Za-z0-9_.-]*", name)):
        return f"channel event: 'name' must be a channel name, got {short(name)}"
    return _number_problem(f"{kind} event: 'value'", e["value"], "input")


def _check_reload(e):
    if not (isinstance(e["text"], str) and isinstance(e.get("path", ""), str)
            and len(e.get("path", "")) <= MAX_PATH):
        return "reload event: 'text' (and 'path') must be strings"
    return None


def _check_gesture(e):
    path = e["path"]
    if not (_is_name(e["key"]) and isinstance(path, list)
            and 0 < len(path) <= MAX_GESTURE_POINTS
            and isinstance(e.get("description", ""), str)):
        return "gesture event: 'key' must be a string and 'path' a list of [t, x, y]"
    problem = key_problem(e["key"])
    if problem is not None:
        return f"gesture event: {problem}"
    for p in path:
        if not (isinstance(p, list) and len(p) == 3):
            return "gesture event: 'path' must be a list of [t, x, y]"
        for v in p:
            problem = _number_problem("gesture event: a path value", v, "input")
            if problem:
                return problem
    return None


def _check_channels(e):
    values = e["values"]
    if not isinstance(values, dict) or len(values) > MAX_CHANNELS:
        return f"channels event: 'values' must map at most {MAX_CHANNELS} channel names to numbers"
    for name, value in values.items():
        if not (_is_name(name) and re.fullmatch(r"[A-Za-z_][A-Za-z0-9_.-]*", name)):
            return f"channels event: {short(name)} is not a channel name"
        problem = _number_problem(f"channels event: '{name}'", value, "input")
        if problem:
            return problem
    return None


def _check_push(e):
    if not _is_name(e["link"]):
        return f"push event: 'link' must be a link name of 1..{MAX_NAME} characters"
    return (_point_problem("push event: 'impulse'", e["impulse"], "shove")
            or ("point" in e and _point_problem("push event: 'point'", e["point"], "model_xy"))
            or None)


EVENT_CHECKS = {  # event type -> what is wrong with it, or None (required fields present)
    "mouse": _check_mouse,
    "key": _check_key,
    "action": _check_action,
    "drag": _check_drag,
    "mouse_button": _check_button,
    "gamepad": _check_device,
    "channel": _check_device,
    "reload": _check_reload,
    "gesture": _check_gesture,
    "channels": _check_channels,
    "push": _check_push,
}


def event_problem(event: Any, last_step: int | None = None) -> str | None:
    """What is wrong with an input event (from a log line or a live source), or None.
    ``last_step``: the last step a rewind may name (None: any)."""
    if not isinstance(event, dict):
        return "'event' must be an object"
    kind = event.get("type")
    if not isinstance(kind, str) or kind not in EVENT_FIELDS:
        return f"unknown event type {short(kind)}; expected one of: {', '.join(EVENT_FIELDS)}"
    missing = [f for f in EVENT_FIELDS[kind] if f not in event]
    if missing:
        return f"{kind} event without {', '.join(repr(m) for m in missing)}"
    check = EVENT_CHECKS[kind]
    if kind == "action":
        return check(event, MAX_STEP if last_step is None else last_step)
    return check(event)
