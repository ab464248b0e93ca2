"""Gamepads: SDL's game-controller API gives standard names (gamepad.left_x, a, ...),
sticks -1..1 with y up, triggers 0..1, dead zones from the interface file; other
joysticks fall back to raw axisN / buttonN. Tested through the real device code path
with SDL's own virtual joystick (reached with ctypes in the SDL library pygame-ce
ships) and with injected pygame events."""

import ctypes
import glob
import math
import os

import pygame
import pytest
from helpers import session_of

from puppet.app.devices import Gamepads, controller_value, dead_zone, device_events
from puppet.data.catalog import load_setup
from puppet.data.interfaces import GamepadSpec
from puppet.interface import events as ev
from puppet.session import Session

SETTINGS = GamepadSpec(dead_zone=0.1, trigger_dead_zone=0.05)


@pytest.fixture
def gamepads():
    pygame.display.init()
    pygame.joystick.init()
    return Gamepads(pygame)


def _values(out):
    return [(e["name"], round(e["value"], 4)) for e in out]


def test_dead_zones_read_zero_inside_and_stretch_the_rest():
    assert dead_zone(0.05, 0.1) == 0.0 and dead_zone(-0.1, 0.1) == 0.0
    assert dead_zone(0.55, 0.1) == pytest.approx(0.5) and dead_zone(-1.0, 0.1) == -1.0
    assert controller_value("left_y", -32767, SETTINGS) == 1.0  # pushed up reads +1
    assert controller_value("left_trigger", 0, SETTINGS) == 0.0
    assert controller_value("right_trigger", 32767, SETTINGS) == 1.0


def test_injected_controller_events_have_standard_names(gamepads):
    E = pygame.event.Event
    out = []
    for event in (E(pygame.CONTROLLERAXISMOTION, instance_id=7, axis=pygame.CONTROLLER_AXIS_LEFTX,
                    value=32767),
                  E(pygame.CONTROLLERAXISMOTION, instance_id=7, axis=pygame.CONTROLLER_AXIS_RIGHTY,
                    value=-16384),
                  E(pygame.CONTROLLERAXISMOTION, instance_id=7,
                    axis=pygame.CONTROLLER_AXIS_TRIGGERRIGHT, value=32767),
                  E(pygame.CONTROLLERAXISMOTION, instance_id=7, axis=pygame.CONTROLLER_AXIS_LEFTX,
                    value=1000),  # inside the dead zone: 0
                  E(pygame.CONTROLLERAXISMOTION, instance_id=7, axis=pygame.CONTROLLER_AXIS_LEFTX,
                    value=-1500),  # still 0: not sent again
                  E(pygame.CONTROLLERBUTTONDOWN, instance_id=7, button=pygame.CONTROLLER_BUTTON_A),
                  E(pygame.CONTROLLERBUTTONUP, instance_id=7, button=pygame.CONTROLLER_BUTTON_A),
                  E(pygame.JOYAXISMOTION, instance_id=9, joy=9, axis=3, value=0.5),  # raw
                  E(pygame.JOYBUTTONDOWN, instance_id=9, joy=9, button=4)):
        out += device_events(pygame, event, gamepads, SETTINGS)
    assert _values(out) == [("left_x", 1.0), ("right_y", round((16384 / 32767 - 0.1) / 0.9, 4)),
                            ("right_trigger", 1.0), ("left_x", 0.0), ("a", 1.0), ("a", 0.0),
                            ("axis3", round((0.5 - 0.1) / 0.9, 4)), ("button4", 1.0)]


def _sdl():
    """SDL2 as loaded by pygame-ce (the same library instance), or None."""
    base = os.path.dirname(pygame.__file__)
    found = glob.glob(os.path.join(base, "..", "pygame_ce.libs", "libSDL2-2*"))
    if not found:
        return None
    sdl = ctypes.CDLL(found[0])
    if not hasattr(sdl, "SDL_JoystickAttachVirtual"):
        return None
    sdl.SDL_JoystickOpen.restype = ctypes.c_void_p
    sdl.SDL_JoystickSetVirtualAxis.argtypes = [ctypes.c_void_p, ctypes.c_int, ctypes.c_int16]
    sdl.SDL_JoystickSetVirtualButton.argtypes = [ctypes.c_void_p, ctypes.c_int, ctypes.c_uint8]
    sdl.SDL_JoystickClose.argtypes = [ctypes.c_void_p]
    return sdl


def virtual_controller_run() -> dict:
    """Attach SDL's virtual game controller, move its left stick and press a, and
    translate what SDL sends through ``device_events``: run in a fresh process (SDL's
    controller events depend on what earlier windows in a process did to its state)."""
    import json

    sdl = _sdl()
    if sdl is None:
        print(json.dumps({"skip": True}))
        return {}
    pygame.display.init()
    pygame.joystick.init()
    gamepads = Gamepads(pygame)
    pygame.event.get()
    index = sdl.SDL_JoystickAttachVirtual(1, 6, 15, 0)  # SDL_JOYSTICK_TYPE_GAMECONTROLLER
    joy = sdl.SDL_JoystickOpen(index)

    def pump():
        sdl.SDL_JoystickUpdate()
        out = []
        for event in pygame.event.get():
            out += device_events(pygame, event, gamepads, SETTINGS)
        return out

    try:
        pump()  # JOYDEVICEADDED: opened through the game-controller API
        opened = (len(gamepads.controllers), len(gamepads.joysticks))
        sdl.SDL_JoystickSetVirtualAxis(joy, 0, 32767)  # SDL's axis 0: the left stick's x
        sdl.SDL_JoystickSetVirtualAxis(joy, 1, -32768)  # left stick pushed up
        sdl.SDL_JoystickSetVirtualButton(joy, 0, 1)  # button 0: a
        got = _values(pump())
    finally:
        sdl.SDL_JoystickClose(joy)
        sdl.SDL_JoystickDetachVirtual(index)
    result = {"opened": opened, "got": got}
    print(json.dumps(result))
    return result


def test_sdl_virtual_controller_through_the_real_device_path():
    import json
    import subprocess
    import sys

    env = dict(os.environ, SDL_VIDEODRIVER="dummy")
    proc = subprocess.run([sys.executable, "-c", "import test_gamepad as t; "
                                                 "t.virtual_controller_run()"],
                          cwd=os.path.dirname(__file__), env=env, capture_output=True,
                          text=True, timeout=60)
    assert proc.returncode == 0, proc.stderr
    result = json.loads(proc.stdout.strip().splitlines()[-1])
    if result.get("skip"):
        pytest.skip("SDL's virtual joystick is not reachable in this pygame-ce build")
    assert result["opened"] == [1, 0]  # a controller, not a raw joystick
    got = dict(result["got"])
    assert got == {"left_x": 1.0, "left_y": 1.0, "a": 1.0}  # standard names, y up, once


@pytest.mark.parametrize("name", ["luxo-gamepad", "cat-gamepad"])
def test_shipped_gamepad_interfaces_hold_the_start_pose_centred_and_follow_the_sticks(name):
    session = Session(load_setup(name))
    start = session.character.start_joint_angles()
    servos = session.character.servos
    for stick in ("left_x", "left_y", "right_x", "right_y"):
        session.handle(ev.gamepad(stick, 0.0))
    for joint, servo in servos.items():
        assert servo.target == pytest.approx(start.get(joint, 0.0), abs=0.11), joint
    before = {j: s.target for j, s in servos.items()}
    session.handle(ev.gamepad("left_x", 1.0))
    session.handle(ev.gamepad("left_y", -1.0))
    moved = [j for j, s in servos.items() if abs(s.target - before[j]) > 0.3]
    assert len(moved) >= 2
    session.handle(ev.gamepad("a", 1.0))  # a button strikes a pose
    session.advance(240)
    assert not session.sim.blown_up()


def test_the_window_records_standard_gamepad_names_and_the_log_replays(tmp_path, monkeypatch):
    from puppet.app import window
    from puppet.timeline.log import read_log
    from puppet.timeline.replay import replay

    E = pygame.event.Event
    plan = {5: [E(pygame.CONTROLLERAXISMOTION, instance_id=0, axis=pygame.CONTROLLER_AXIS_LEFTX,
                  value=20000)],
            20: [E(pygame.CONTROLLERBUTTONDOWN, instance_id=0, button=pygame.CONTROLLER_BUTTON_A)],
            40: [E(pygame.QUIT)]}
    frame = {"n": 0}
    real_get = pygame.event.get

    def fake_get(*a, **k):
        real_get()
        frame["n"] += 1
        return plan.get(frame["n"], [])

    monkeypatch.setattr(pygame.event, "get", fake_get)
    monkeypatch.setattr(pygame.mouse, "get_focused", lambda: False)
    path = tmp_path / "pad.jsonl"
    assert window.run_window(load_setup("luxo-gamepad"), record=str(path)) == 0
    log = read_log(path)
    pads = [(e.event["name"], e.event["value"]) for e in log.events if e.event["type"] == "gamepad"]
    assert pads[0][0] == "left_x" and pads[0][1] == pytest.approx((20000 / 32767 - 0.12) / 0.88)
    assert ("a", 1.0) in pads
    assert replay(path).final_hash == log.end_hash


def deg(s) -> dict[str, float]:
    return {n: round(math.degrees(sv.target), 6) for n, sv in s.character.servos.items()}


def test_a_gamepad_button_is_down_above_half_way(tmp_path):
    s = session_of(tmp_path, """
    name: t
    description: a gamepad button as a key
    character: luxo
    poses:
      fold: {joints: {knee: 100}}
      open: {joints: {knee: 10}}
    keys:
      - {key: gamepad.a, pose: fold}
      - {key: o, pose: open}
    """)
    start = deg(s)["knee"]
    steps = [("a", 0.5, start), ("a", 0.6, 100), ("o", None, 10), ("a", 0.55, 10),
             ("a", 0.5, 10), ("a", 0.51, 100)]  # a press each time it passes 0.5 upward
    for what, value, knee in steps:
        if value is None:
            s.handle(ev.key(what, True))
            s.handle(ev.key(what, False))
        else:
            s.handle(ev.gamepad(what, value))
        s.advance(1)
        assert deg(s)["knee"] == pytest.approx(knee), (what, value)


def test_a_stick_event_leaves_the_wake_ups_as_a_reschedule_would(tmp_path):
    """A stick runs its maps only (as the mouse does): the runtime's wake-ups and the
    controllers it ticks stay what re-scheduling at that step would give."""
    session = session_of(tmp_path, """
    name: t
    description: a stick on the knee, a button blending the ankle, polling states
    character: luxo
    control_rate: 120
    modes:
      pad:
        - {input: gamepad.left_x, joint: knee, from: [-1, 1], to: [100, 10]}
    mode: pad
    keys:
      - {key: gamepad.a, set: {ankle: 40}, over: 0.2}
    initial: level
    states:
      level:
        transitions:
          - {to: tipped, when: {sensor: root.angle, above: 60}}
          - {to: pushed, when: {sensor: input.gamepad.left_x, above: 0.5}}
      pushed:
        transitions:
          - {to: level, when: {sensor: input.gamepad.left_x, below: -0.5}}
      tipped:
        transitions:
          - {to: level, after: 0.5}
    """)
    runtime = session.runtime
    session.handle(ev.gamepad("a", 1.0))  # the ankle's blend runs, the state polls
    assert runtime.next_wakeup is not None and runtime._active
    seen = [runtime.machine.current]
    for k in range(60):
        session.handle(ev.gamepad("left_x", (k % 7) / 3.5 - 1.0))
        kept = (runtime.next_wakeup, list(runtime._active), runtime._controllers_wake)
        runtime._reschedule(session.steps)
        assert (runtime.next_wakeup, list(runtime._active), runtime._controllers_wake) \
            == kept, k
        session.advance(1 + k % 4)
        if runtime.machine.current != seen[-1]:
            seen.append(runtime.machine.current)
    # a state polling the stick alone (quiet between events) polls again at each event
    assert seen.count("pushed") >= 3 and seen.count("level") >= 3, seen
