"""Recording mouse gestures in the window (pure: no pygame, testable).

The record key starts recording the mouse path as the mouse events go to the
session ([sim time since the start, x, y]); pressing it again stops; the next key
pressed binds the path to that key, as a "gesture" event for ``Session.handle`` (so
the log has it and a replay binds the very same gesture). Escape cancels. The save
key writes the interface's gestures into its file (``puppet.data.gesture_file``),
and the hot reload then runs the saved file.
"""

from __future__ import annotations

from puppet.data.interfaces import InterfaceSpec, with_gesture
from puppet.data.keys import normalize_key
from puppet.interface import events as ev

IDLE, RECORDING, BINDING = "idle", "recording", "binding"
DIGITS = 4  # decimals kept of times (s) and positions


class GestureRecorder:
    def __init__(self):
        self.state = IDLE
        self.path: list[list[float]] = []
        self.t0 = 0.0
        self.unsaved: dict[str, dict] = {}  # key -> gesture event bound since the last save

    @property
    def binding(self) -> bool:
        return self.state == BINDING

    def toggle(self, time: float, mouse: tuple[float, float] | None, key: str) -> str:
        """The record key: start (from the mouse's position now) or stop. A prompt."""
        if self.state == RECORDING:
            if len(self.path) < 2:
                self.state = IDLE
                return "gesture: nothing recorded (move the mouse while recording)"
            self.state = BINDING
            return (f"gesture of {self.path[-1][0]:.2f} s recorded: press the key to bind "
                    "it to (Esc cancels)")
        self.state, self.path, self.t0 = RECORDING, [], time
        if mouse is not None:
            self.add(time, *mouse)
        return f"recording a gesture: move the mouse, {key} to stop"

    def add(self, time: float, x: float, y: float) -> None:
        """A mouse position sent to the session at sim ``time``."""
        if self.state != RECORDING:
            return
        point = [round(time - self.t0, DIGITS), round(x, DIGITS), round(y, DIGITS)]
        if self.path and point[0] <= self.path[-1][0]:  # same step (or paused): latest wins
            self.path[-1][1:] = point[1:]
        else:
            self.path.append(point)

    def bind(self, chord: str, spec: InterfaceSpec,
             save_key: str = "f3") -> tuple[dict | None, str]:
        """The key pressed after recording: (the "gesture" event or None, a message).
        A key that is taken keeps waiting for another."""
        if chord == "escape":
            self.state, self.path = IDLE, []
            return None, "gesture discarded"
        description = f"gesture {self.path[-1][0]:.1f} s"
        try:
            with_gesture(spec, chord, self.path, description)
        except ValueError as exc:
            return None, f"{exc}; press another key (Esc cancels)"
        event = ev.gesture(chord, self.path, description)
        self.unsaved[event["key"]] = event
        self.state, self.path = IDLE, []
        return event, f"gesture bound to {chord}; {save_key} saves it into the interface file"

    def rebind_after_reload(self, spec: InterfaceSpec) -> list[dict]:
        """Gesture events to send again after a reload of a file without them (bound
        but not saved yet), so a reload does not lose them."""
        have = {normalize_key(g.key) for g in spec.gestures}
        out = []
        for key, event in list(self.unsaved.items()):
            if key in have:
                continue
            try:
                spec = with_gesture(spec, key, event["path"], event.get("description", ""))
            except ValueError:
                del self.unsaved[key]  # the key is taken now: drop it
                continue
            out.append(event)
        return out
