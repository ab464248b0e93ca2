"""The window's pointer as a player meets it: Ctrl+drag does not drive the mouse maps
nor move the camera; after a reset the mouse holds the start pose until it moves.
SDL's dummy video driver, with pygame's event queue, pointer and modifiers scripted."""

import pygame
import pytest

from puppet.app import window
from puppet.data.catalog import load_setup
from puppet.timeline.log import read_log


def _key(kind, key):
    return pygame.event.Event(kind, key=key, mod=0, unicode="", scancode=0)


@pytest.fixture
def desk(monkeypatch):
    """A scripted desk: ``plan["at"][frame]`` is a function run at that frame (move the
    pointer, hold Ctrl, queue events); the pointer and modifiers are pygame's, faked."""
    plan = {"frame": 0, "at": {}, "pos": (640, 360), "mods": 0, "queue": [], "warps": [],
            "frames": {}}
    real_get = pygame.event.get

    def fake_get(*args, **kw):
        real_get()
        plan["frame"] += 1
        if plan["frame"] in plan["at"]:
            plan["at"][plan["frame"]](plan)
        out, plan["queue"] = plan["queue"], []
        return out

    def set_pos(pos):
        plan["warps"].append(tuple(pos))
        plan["pos"] = tuple(pos)

    monkeypatch.setattr(pygame.event, "get", fake_get)
    monkeypatch.setattr(pygame.mouse, "get_focused", lambda: True)
    monkeypatch.setattr(pygame.mouse, "get_pos", lambda: plan["pos"])
    monkeypatch.setattr(pygame.mouse, "set_pos", set_pos)
    monkeypatch.setattr(pygame.key, "get_mods", lambda: plan["mods"])
    return plan


def _mouse_steps(log):
    return [e.step for e in log.events if e.event["type"] == "mouse"]


def test_after_a_reset_the_mouse_holds_the_start_pose_until_it_moves(tmp_path, desk):
    def throw(p):  # the pointer far from the start pose: the lamp is thrown
        p["pos"] = (1200, 50)

    def reset(p):
        p["queue"] += [_key(pygame.KEYDOWN, pygame.K_r), _key(pygame.KEYUP, pygame.K_r)]

    def move(p):
        x, y = p["pos"]
        p["pos"] = (x + 3, y)

    desk["at"] = {5: throw, 40: reset, 80: move,
                  100: lambda p: p["queue"].append(pygame.event.Event(pygame.QUIT))}
    path = tmp_path / "reset.jsonl"
    assert window.run_window(load_setup("luxo-mouse"), record=str(path)) == 0
    log = read_log(path)
    reset_step = next(e.step for e in log.events if e.event.get("key") == "r")
    assert len(desk["warps"]) == 2  # at the start and at the reset
    after = [s for s in _mouse_steps(log) if s > reset_step]
    # nothing until the user moved, then it follows the mouse again
    assert after and all(s > reset_step + 10 for s in after)
    assert min(_mouse_steps(log)) < reset_step  # it did drive the lamp before
    # the first move after the reset starts from where the mouse holds the start pose
    # (the pointer was put back there), not from where it threw the lamp
    first = next(e.event for e in log.events
                 if e.event["type"] == "mouse" and e.step > reset_step)
    wx, wy = desk["warps"][1]
    rest = (wx / 1279, 1 - wy / 719)
    assert abs(first["x"] - rest[0]) < 0.01 and abs(first["y"] - rest[1]) < 0.01
    assert abs(first["x"] - 1200 / 1279) > 0.1 or abs(first["y"] - (1 - 50 / 719)) > 0.1
    # and between the reset and that move, the joints aim at the start pose
    from puppet.timeline.replay import replay

    session = replay(path, until_step=reset_step + 5).session
    start = session.character.start_joint_angles()
    for name, servo in session.character.servos.items():
        assert servo.target == pytest.approx(start.get(name, 0.0), abs=0.05), name


def test_ctrl_held_neither_drives_the_maps_nor_moves_the_camera(tmp_path, desk, monkeypatch):
    import puppet.app.camera as camera_mod

    follows = []

    class SpyCamera(camera_mod.Camera):
        def follow(self, subject, wall_dt):
            follows.append(desk["frame"])
            super().follow(subject, wall_dt)

    monkeypatch.setattr(camera_mod, "Camera", SpyCamera)

    def ctrl(p):
        p["mods"] = pygame.KMOD_LCTRL

    def move(p):
        x, y = p["pos"]
        p["pos"] = (x - 5, y + 4)

    def release(p):
        p["mods"] = 0

    desk["at"] = {10: ctrl, **{f: move for f in range(12, 40, 3)}, 45: release,
                  60: lambda p: p["queue"].append(pygame.event.Event(pygame.QUIT))}
    path = tmp_path / "ctrl.jsonl"
    assert window.run_window(load_setup("luxo-mouse"), record=str(path)) == 0
    log = read_log(path)
    mouse = [e for e in log.events if e.event["type"] == "mouse"]
    assert len(mouse) == 1  # the move after Ctrl was released, none while it was held
    assert not [f for f in follows if 10 <= f < 45]  # the camera held still
    assert [f for f in follows if f >= 45]


def test_the_window_draws_its_frames_as_headless_runs_do(tmp_path, desk, monkeypatch):
    """One drawing path: every window frame goes through ``frame.FrameRenderer`` into the
    screen, the renderer that screenshots, video export and the bench use."""
    import puppet.app.frame as frame_mod

    drawn = []
    real = frame_mod.FrameRenderer.render

    def spy(self, session, *args, **kw):
        drawn.append((self.surface is pygame.display.get_surface(), session.steps))
        return real(self, session, *args, **kw)

    monkeypatch.setattr(frame_mod.FrameRenderer, "render", spy)
    desk["at"] = {20: lambda p: p["queue"].append(pygame.event.Event(pygame.QUIT))}
    assert window.run_window(load_setup("luxo-mouse"), record=str(tmp_path / "f.jsonl")) == 0
    assert len(drawn) >= 19 and all(on_screen for on_screen, _ in drawn)
    assert drawn[-1][1] > drawn[0][1]  # the frames followed the simulation
