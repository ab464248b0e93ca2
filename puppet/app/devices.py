"""Devices beyond keys and mouse motion, translated into input events: mouse buttons
and gamepads (pygame joysticks, hot-plugged: devices come and go while playing).

All gamepads report as one ``gamepad``: axes as ``gamepad.axisN`` (-1..1, as pygame
reports them: y down) and buttons as ``gamepad.buttonN`` (0/1).
"""

from __future__ import annotations

from puppet.interface import events as ev
from puppet.interface.events import Event

MOUSE_BUTTONS = {1: "left", 2: "middle", 3: "right"}


def device_events(pygame, event, joysticks: dict) -> list[Event]:
    """Input events for one pygame event; ``joysticks`` keeps opened devices by id."""
    t = event.type
    if t == pygame.JOYDEVICEADDED:
        try:
            js = pygame.joystick.Joystick(event.device_index)
            joysticks[js.get_instance_id()] = js
        except pygame.error:
            pass
        return []
    if t == pygame.JOYDEVICEREMOVED:
        joysticks.pop(event.instance_id, None)
        return []
    if t == pygame.JOYAXISMOTION:
        return [ev.gamepad(f"axis{event.axis}", event.value)]
    if t in (pygame.JOYBUTTONDOWN, pygame.JOYBUTTONUP):
        return [ev.gamepad(f"button{event.button}", 1.0 if t == pygame.JOYBUTTONDOWN else 0.0)]
    if t in (pygame.MOUSEBUTTONDOWN, pygame.MOUSEBUTTONUP) and event.button in MOUSE_BUTTONS:
        down = t == pygame.MOUSEBUTTONDOWN
        if down and pygame.key.get_mods() & pygame.KMOD_CTRL:
            return []  # ctrl+click is the drag, not a button input
        return [ev.mouse_button(MOUSE_BUTTONS[event.button], down)]
    return []
