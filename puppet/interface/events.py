"""Input events: what devices say, in the form the log records and replay feeds back.

Events are plain dicts (JSON-ready). Kinds:
  {"type": "mouse", "x": 0..1, "y": 0..1}            normalised to the window, y up
  {"type": "key", "key": "ctrl+a", "down": true}      a key chord pressed / released
  {"type": "drag", "phase": "start", "link": name, "point": [lx, ly], "target": [x, y]}
  {"type": "drag", "phase": "move", "target": [x, y]}
  {"type": "drag", "phase": "end"}
  {"type": "action", "name": "reset"}                 an app action that changes the sim
"""

from __future__ import annotations

from typing import Any

Event = dict[str, Any]


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
