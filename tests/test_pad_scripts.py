"""The gamepad without a gamepad: stick, trigger and button events in scripts (so a
stick map acts in a scripted, recorded and replayed proof), the virtual pad of the
window (the mouse and keys), and the pointer input a map reads from the mouse or a
stick alike."""

from __future__ import annotations

import math
import os

import pytest

from puppet.data.catalog import ROOT, load_setup
from puppet.data.errors import DataError
from puppet.data.validate import located_data
from puppet.interface import events as ev
from puppet.session import Session
from puppet.session.playback import play
from puppet.timeline.script import compile_script, load_script, parse_script

DT = 1 / 480


def script(*events, seconds=2.0):
    return parse_script(located_data({"seconds": seconds, "events": list(events)}, "s.yaml"))


def test_gamepad_entries_glide_sticks_press_buttons_and_go_back_to_rest():
    spec = script({"t": 0.5, "gamepad": {"left_x": 0.8, "right_trigger": 1.0, "a": 1},
                   "over": 0.1, "hold": 0.2},
                  {"t": 1.0, "key": "gamepad.b", "hold": 0.3})
    events = compile_script(spec, DT)
    pads = [(step, e["name"], e["value"]) for step, e in events if e["type"] == "gamepad"]
    assert (240, "a", 1.0) in pads  # a button jumps at t
    glide = [(s, v) for s, n, v in pads if n == "left_x" and v > 0]
    assert len(glide) == 24 and glide[-1] == (288, 0.8)  # 240 positions a second, 0.1 s
    assert all(a[1] < b[1] for a, b in zip(glide, glide[1:]))
    assert {(n, v) for s, n, v in pads if s == 288 + 96} == {("left_x", 0.0), (
        "right_trigger", 0.0), ("a", 0.0)}  # held 0.2 s, then at rest
    assert (480, "b", 1.0) in pads and (624, "b", 0.0) in pads  # a pad key as a button
    assert not any(e["type"] == "key" for _, e in events)


@pytest.mark.parametrize("entry, says", [
    ({"t": 0, "gamepad": {"left_z": 1}}, "unknown gamepad input 'left_z'"),
    ({"t": 0, "gamepad": {"left_x": 1.5}}, "gamepad 'left_x' reads -1..1, got 1.5"),
    ({"t": 0, "gamepad": {"left_trigger": -0.5}}, "reads 0..1, got -0.5"),
    ({"t": 0, "gamepad": {"a": 0.5}}, "gamepad button 'a' is 0 (up) or 1 (pressed)"),
    ({"t": 0, "gamepad": {}}, "'gamepad' names no input"),
])
def test_a_bad_gamepad_entry_is_one_line_at_its_place(entry, says):
    with pytest.raises(DataError) as err:
        script(entry)
    assert says in err.value.message


def test_a_stick_map_acts_in_the_scripted_recorded_and_replayed_proof(tmp_path):
    """luxo-gamepad's stick maps hop the lamp from a script; recorded, the log replays
    to the same bits; the shipped proof (assets/logs/luxo-gamepad-hop) passes."""
    from puppet.testing import replay_log
    from puppet.timeline.log import Recorder
    from puppet.timeline.replay import replay

    spec = load_script(ROOT / "assets" / "scripts" / "luxo-gamepad-hop.yaml")
    session = Session(load_setup("luxo-gamepad"))
    ankle = session.character.servos["ankle"]
    before = ankle.target
    path = tmp_path / "hop.jsonl"
    with Recorder(session, path):
        play(session, compile_script(spec, DT), round(1.2 / DT))
    assert abs(math.degrees(ankle.target - before)) > 5  # the stick moved the joint
    assert replay(path).final_hash == session.sim.state_hash()
    result = replay_log(ROOT / "assets" / "logs" / "luxo-gamepad-hop.jsonl")
    assert result.ok, result


POINTER_LUXO = (ROOT / "interfaces" / "luxo-mouse.yaml").read_text(encoding="utf-8") \
    .replace("input: mouse.x", "input: pointer.x").replace("input: mouse.y", "input: pointer.y")


def test_a_mouse_layout_reads_the_stick_through_the_pointer_input(tmp_path):
    """luxo-mouse with its two inputs renamed pointer.x / pointer.y: the mouse plays it
    to the very bits of luxo-mouse, and the left stick drives the same targets."""
    assert POINTER_LUXO.count("pointer.") == 2
    path = tmp_path / "luxo-pointer.yaml"
    path.write_text(POINTER_LUXO, encoding="utf-8")
    events = compile_script(load_script(ROOT / "assets" / "scripts" / "luxo-hop.yaml"), DT)
    mouse, pointer = Session(load_setup("luxo-mouse")), Session(load_setup(str(path)))
    for s in (mouse, pointer):
        play(s, events, round(4.5 / DT))
    assert pointer.sim.state_hash() == mouse.sim.state_hash()
    stick = Session(load_setup(str(path)))
    servos = stick.character.servos
    for x, y in ((0.5, 0.5), (1.0, 0.159), (0.123, 0.378)):
        stick.handle(ev.gamepad("left_x", 2 * x - 1))
        stick.handle(ev.gamepad("left_y", 2 * y - 1))
        table = Session(load_setup("luxo-mouse"))
        table.handle(ev.mouse(x, y))
        for joint in ("ankle", "knee"):
            assert servos[joint].target == pytest.approx(
                table.character.servos[joint].target, abs=1e-9)


def test_the_pointer_stick_is_chosen_and_the_hud_names_either_device(tmp_path):
    from puppet.app.describe import input_words

    path = tmp_path / "luxo-right.yaml"
    path.write_text(POINTER_LUXO.replace("slowdown: 1\n", "slowdown: 1\ngamepad: {pointer: "
                                         "right}\n", 1), encoding="utf-8")
    session = Session(load_setup(str(path)))
    knee = session.character.servos["knee"]
    start = knee.target
    session.handle(ev.gamepad("left_y", 1.0))  # not the pointer stick: nothing
    assert knee.target == start
    session.handle(ev.gamepad("right_y", 1.0))  # the top: straight (to: [160, -20])
    assert math.degrees(knee.target) == pytest.approx(-20)
    assert input_words("pointer.x")[0] == "mouse or stick left-right"


def test_the_virtual_pad_sends_gamepad_events_that_replay(tmp_path, monkeypatch):
    """--virtual-pad in the window (SDL dummy driver): the mouse is the left stick, k the
    a button; the log is a gamepad session and replays to its end."""
    os.environ.setdefault("SDL_VIDEODRIVER", "dummy")
    import pygame

    from puppet.app import window
    from puppet.timeline.log import read_log
    from puppet.timeline.replay import replay

    E = pygame.event.Event
    plan = {20: [E(pygame.KEYDOWN, key=pygame.K_k, mod=0, unicode="k", scancode=0)],
            24: [E(pygame.KEYUP, key=pygame.K_k, mod=0, unicode="k", scancode=0)],
            40: [E(pygame.QUIT)]}
    frame = {"n": 0}
    real_get = pygame.event.get

    def fake_get(*a, **k):
        real_get()
        frame["n"] += 1
        return plan.get(frame["n"], [])

    monkeypatch.setattr(pygame.event, "get", fake_get)
    monkeypatch.setattr(pygame.mouse, "get_focused", lambda: True)
    monkeypatch.setattr(pygame.mouse, "get_pos",
                        lambda: (640 + 20 * min(frame["n"], 10), 360))  # right of the middle
    path = tmp_path / "pad.jsonl"
    assert window.run_window(load_setup("luxo-gamepad"), record=str(path),
                             virtual_pad=True) == 0
    log = read_log(path)
    kinds = {e.event["type"] for e in log.events}
    assert "mouse" not in kinds and "key" not in kinds
    pads = [(e.event["name"], e.event["value"]) for e in log.events if e.event["type"] == "gamepad"]
    xs = [v for n, v in pads if n == "left_x"]
    assert xs and xs[-1] == pytest.approx(2 * (840 / 1279) - 1, abs=1e-5)
    assert ("a", 1.0) in pads and ("a", 0.0) in pads
    assert replay(path).final_hash == log.end_hash


def test_virtual_pad_is_for_the_window(capsys):
    from puppet.commands import main

    assert main(["play", "luxo-gamepad", "--headless", "--virtual-pad"]) == 2
    assert "--virtual-pad is for the window" in capsys.readouterr().err
