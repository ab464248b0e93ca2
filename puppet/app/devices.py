"""Devices beyond keys and mouse motion, translated into input events: mouse buttons
and gamepads, hot-plugged (devices come and go while playing).

A gamepad SDL knows (it has a controller mapping, as most do: SDL ships a database of
them) is opened through SDL's game-controller API (pygame-ce's
``pygame._sdl2.controller``), so its inputs have standard names whatever the make:
``gamepad.left_x`` .. ``gamepad.right_y`` (sticks, -1..1, y up), ``gamepad.left_trigger``
/ ``right_trigger`` (0..1) and buttons ``gamepad.a`` ... ``gamepad.dpad_up`` (0/1); see
``puppet.data.keys.GAMEPAD_*``. Any other joystick is the fallback: raw
``gamepad.axisN`` (-1..1, as the device reports) and ``gamepad.buttonN``. All gamepads
report as one ``gamepad``. Dead zones (the interface's ``gamepad:`` settings) are applied
here, so the log records what the interface read, and an input that did not change
after its dead zone is not sent again.
"""

from __future__ import annotations

from puppet.interface import events as ev
from puppet.interface.events import Event

MOUSE_BUTTONS = {1: "left", 2: "middle", 3: "right"}
AXIS_MAX = 32767.0  # SDL's controller axes are 16-bit integers


def _names(pygame) -> tuple[dict, dict]:
    """SDL's controller axis and button numbers -> puppet's standard names."""
    axes = {pygame.CONTROLLER_AXIS_LEFTX: "left_x", pygame.CONTROLLER_AXIS_LEFTY: "left_y",
            pygame.CONTROLLER_AXIS_RIGHTX: "right_x",
            pygame.CONTROLLER_AXIS_RIGHTY: "right_y",
            pygame.CONTROLLER_AXIS_TRIGGERLEFT: "left_trigger",
            pygame.CONTROLLER_AXIS_TRIGGERRIGHT: "right_trigger"}
    buttons = {getattr(pygame, f"CONTROLLER_BUTTON_{sdl}"): name for sdl, name in (
        ("A", "a"), ("B", "b"), ("X", "x"), ("Y", "y"), ("BACK", "back"),
        ("GUIDE", "guide"), ("START", "start"), ("LEFTSTICK", "left_stick"),
        ("RIGHTSTICK", "right_stick"), ("LEFTSHOULDER", "left_shoulder"),
        ("RIGHTSHOULDER", "right_shoulder"), ("DPAD_UP", "dpad_up"),
        ("DPAD_DOWN", "dpad_down"), ("DPAD_LEFT", "dpad_left"),
        ("DPAD_RIGHT", "dpad_right"))}
    return axes, buttons


def dead_zone(value: float, zone: float) -> float:
    """0 inside ``zone`` (a fraction of the travel); beyond it the rest of the travel
    stretched back to the full range (no jump at the edge). Keeps the sign."""
    magnitude = abs(value)
    if magnitude <= zone:
        return 0.0
    out = min(1.0, (magnitude - zone) / (1.0 - zone))
    return out if value > 0 else -out


def controller_value(name: str, raw: int, settings) -> float:
    """A controller axis event's value in puppet's terms: sticks -1..1 with y up,
    triggers 0..1, each through its dead zone (``settings``: a ``GamepadSpec``)."""
    value = max(-1.0, min(1.0, raw / AXIS_MAX))
    if name.endswith("_trigger"):
        return dead_zone(max(0.0, value), settings.trigger_dead_zone)
    if name.endswith("_y"):
        value = -value  # SDL's y is down; puppet's inputs are y up (as the mouse)
    return dead_zone(value, settings.dead_zone)


class Gamepads:
    """Open gamepads and the last value of each input (by instance id), translating
    their pygame events into input events."""

    def __init__(self, pygame):
        self.pygame = pygame
        try:
            from pygame._sdl2 import controller
            controller.init()
        except (ImportError, pygame.error):  # no game-controller API: raw joysticks only
            controller = None
        self.controller = controller
        self.axes, self.buttons = _names(pygame) if controller is not None else ({}, {})
        self.controllers: dict[int, object] = {}  # instance id -> Controller
        self.joysticks: dict[int, object] = {}  # instance id -> Joystick (the fallback)
        self.last: dict[str, float] = {}  # input name -> last value sent

    def _send(self, name: str, value: float) -> list[Event]:
        if self.last.get(name) == value:
            return []  # noise inside a dead zone, or a repeat
        self.last[name] = value
        return [ev.gamepad(name, value)]

    def _added(self, index: int) -> None:
        pygame = self.pygame
        try:
            if self.controller is not None and self.controller.is_controller(index):
                pad = self.controller.Controller(index)
                self.controllers[pad.as_joystick().get_instance_id()] = pad
            else:
                js = pygame.joystick.Joystick(index)
                if js.get_instance_id() not in self.controllers:
                    self.joysticks[js.get_instance_id()] = js
        except pygame.error:
            pass

    def events(self, event, settings) -> list[Event]:
        """Input events for one pygame event (none if it is not a gamepad's)."""
        pygame, t = self.pygame, event.type
        if t == pygame.JOYDEVICEADDED:
            self._added(event.device_index)
            return []
        if t in (pygame.JOYDEVICEREMOVED, getattr(pygame, "CONTROLLERDEVICEREMOVED", -1)):
            self.controllers.pop(event.instance_id, None)
            self.joysticks.pop(event.instance_id, None)
            return []
        if t == getattr(pygame, "CONTROLLERAXISMOTION", -1):
            name = self.axes.get(event.axis)
            return self._send(name, controller_value(name, event.value, settings)) \
                if name else []
        if t in (getattr(pygame, "CONTROLLERBUTTONDOWN", -1),
                 getattr(pygame, "CONTROLLERBUTTONUP", -1)):
            name = self.buttons.get(event.button)
            down = t == pygame.CONTROLLERBUTTONDOWN
            return self._send(name, 1.0 if down else 0.0) if name else []
        # A controller also reports as a raw joystick: only the fallback devices do.
        raw = getattr(event, "instance_id", None) not in self.controllers
        if t == pygame.JOYAXISMOTION and raw:
            return self._send(f"axis{event.axis}", dead_zone(event.value, settings.dead_zone))
        if t in (pygame.JOYBUTTONDOWN, pygame.JOYBUTTONUP) and raw:
            return self._send(f"button{event.button}",
                              1.0 if t == pygame.JOYBUTTONDOWN else 0.0)
        return []


def device_events(pygame, event, gamepads: Gamepads, settings) -> list[Event]:
    """Input events for one pygame event: mouse buttons and gamepads (``settings``:
    the live interface's ``GamepadSpec``, for the dead zones)."""
    t = event.type
    if t in (pygame.MOUSEBUTTONDOWN, pygame.MOUSEBUTTONUP) and event.button in MOUSE_BUTTONS:
        down = t == pygame.MOUSEBUTTONDOWN
        if down and pygame.key.get_mods() & pygame.KMOD_CTRL:
            return []  # ctrl+click is the drag, not a button input
        return [ev.mouse_button(MOUSE_BUTTONS[event.button], down)]
    return gamepads.events(event, settings)
