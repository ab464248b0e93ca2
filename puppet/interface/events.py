"""Input events: what devices say, in the form the log records and replay feeds back.

Events are plain dicts (JSON-ready). Kinds:
  {"type": "mouse", "x": 0..1, "y": 0..1}            normalised to the window, y up
  {"type": "key", "key": "ctrl+a", "down": true}      a key chord pressed / released
  {"type": "drag", "phase": "start", "link": name, "point": [lx, ly], "target": [x, y]}
  {"type": "drag", "phase": "move", "target": [x, y]}
  {"type": "drag", "phase": "end"}
  {"type": "push", "link": name, "impulse": [jx, jy], "point": [lx, ly]}  a shove (N*s)
  {"type": "action", "name": "reset"}                 an app action that changes the sim
  {"type": "mouse_button", "button": "left", "down": true}   input mouse.left = 1 / 0
  {"type": "gamepad", "name": "left_x", "value": -0.3}       input gamepad.left_x
                                 (standard names, see puppet.data.keys.GAMEPAD_*; axisN / buttonN for a
                                 joystick SDL has no controller mapping for)
  {"type": "channel", "name": "lean", "value": 0.2}          input channel.lean (plugins)
  {"type": "channels", "values": {"hip": 0.3, "knee": -0.1}}  many channels at one step
                                                    (a mocap frame): one log line
  {"type": "reload", "text": "...", "path": "interfaces/x.yaml"}  run this interface text
                                                    from now on (hot reload of the file)
  {"type": "gesture", "key": "h", "path": [[t, x, y], ...], "description": ""}
                                                    bind a recorded mouse path to a key
"""

from __future__ import annotations

from typing import Any

from puppet.data.keys import GAMEPAD_STICKS, GAMEPAD_TRIGGERS

Event = dict[str, Any]


def is_analog(name: str) -> bool:
    """An input that is a position, not a button: mouse x/y, gamepad sticks, triggers
    and raw axes, plugin channels."""
    device, _, part = name.partition(".")
    if device == "gamepad":
        return part in GAMEPAD_STICKS or part in GAMEPAD_TRIGGERS or part.startswith("axis")
    return device == "channel" or name in ("mouse.x", "mouse.y")


class AnalogNames(dict):
    """A gamepad event's name -> ``gamepad.NAME`` when that input is analog (a stick, a
    trigger, an axis: ``is_analog``; maps only, no press), else None; worked out once
    per name (the runtime's fast path for sticks)."""

    def __missing__(self, part: str) -> str | None:
        name = f"gamepad.{part}"
        self[part] = name if is_analog(name) else None
        return self[part]


def mouse(x: float, y: float) -> Event:
    return {"type": "mouse", "x": float(x), "y": float(y)}


def key(chord: str, down: bool = True) -> Event:
    return {"type": "key", "key": chord, "down": bool(down)}


def action(name: str) -> Event:
    return {"type": "action", "name": name}


def drag_start(link: str, point, target) -> Event:
    return {"type": "drag", "phase": "start", "link": link,
            "point": [float(point[0]), float(point[1])],
            "target": [float(target[0]), float(target[1])]}


def drag_move(target) -> Event:
    return {"type": "drag", "phase": "move", "target": [float(target[0]), float(target[1])]}


def drag_end() -> Event:
    return {"type": "drag", "phase": "end"}


def push(link: str, impulse, point=None) -> Event:
    """A shove: ``impulse`` (N*s, world) at ``point`` of ``link`` (model frame, m;
    default its centre of mass). An input like a drag, so a log replays it."""
    event: Event = {"type": "push", "link": link,
                    "impulse": [float(impulse[0]), float(impulse[1])]}
    if point is not None:
        event["point"] = [float(point[0]), float(point[1])]
    return event


def mouse_button(button: str, down: bool = True) -> Event:
    """A mouse button ("left", "middle", "right"): input mouse.<button> = 1 or 0."""
    return {"type": "mouse_button", "button": button, "down": bool(down)}


def gamepad(name: str, value: float) -> Event:
    """A gamepad input: a stick ("left_x", -1..1), a trigger ("left_trigger", 0..1), a
    button ("a", 0/1), or a raw joystick's axis ("axis0") or button ("button1")."""
    return {"type": "gamepad", "name": name, "value": float(value)}


def channel(name: str, value: float) -> Event:
    """A named plugin channel (e.g. a mocap feature): input channel.<name>."""
    return {"type": "channel", "name": name, "value": float(value)}


def channels(values) -> Event:
    """Many named channels at one step (a frame of a motion-capture stream): inputs
    channel.<name> for each. Logged as one line; the runtime's fast path applies it."""
    return {"type": "channels", "values": {str(n): float(v) for n, v in values.items()}}


def reload(text: str, path: str | None = None) -> Event:
    """Run the interface in ``text`` from now on (the file was saved). The log keeps the
    whole text, so a replay rebuilds the same interface without reading the file."""
    event: Event = {"type": "reload", "text": str(text)}
    if path is not None:
        event["path"] = str(path)
    return event


def gesture(key: str, path, description: str = "") -> Event:
    """Bind a recorded mouse path ([t s since the start, x, y] points) to a key."""
    event: Event = {"type": "gesture", "key": str(key),
                    "path": [[float(t), float(x), float(y)] for t, x, y in path]}
    if description:
        event["description"] = str(description)
    return event
