"""Hot reload of the interface file: the "reload" event, its validation, replay and
rewind across it, and the window's file poller (no display needed)."""

import math
import os
import textwrap

import pytest
from helpers import session_of, tap

from puppet.app.reloader import Reloader
from puppet.data.catalog import load_setup, parse_interface_text
from puppet.data.errors import DataError
from puppet.interface import events as ev
from puppet.session import Session
from puppet.timeline.log import Recorder
from puppet.timeline.replay import replay

BASE = """name: t
description: test interface
character: luxo
# a designer's comment
maps:
  - {input: mouse.x, joint: ankle, from: [0, 1], to: [80, -80]}
  - {input: mouse.y, joint: knee, to: [160, -20]}
poses:
  crouch: {joints: {ankle: -70, knee: 130}}
  tall: {joints: {ankle: 0, knee: 0}}
sequences:
  hop: [{pose: crouch, hold: 0.2}, {pose: tall, hold: 0.3}]
keys:
  - {key: h, sequence: hop}
"""
NARROW = BASE.replace("to: [80, -80]", "to: [40, -40]")


def deg(session, joint):
    return round(math.degrees(session.character.servos[joint].target), 6)


def session_for(tmp_path, text=BASE, **kw) -> Session:
    path = tmp_path / "iface.yaml"
    path.write_text(text)
    return Session(load_setup(str(path)), **kw)


def test_reload_changes_the_mapping_without_moving_the_character(tmp_path):
    s = session_for(tmp_path)
    ref = session_for(tmp_path)
    for x in (s, ref):
        x.handle(ev.mouse(1.0, 0.5))
        x.advance(200)
    assert deg(s, "ankle") == -80
    s.handle(ev.reload(NARROW, str(tmp_path / "iface.yaml")))
    assert deg(s, "ankle") == -80  # nothing moves until an input changes
    assert s.interface.maps[0].to == (40, -40) and s.setup.interface is s.interface
    s.advance(300)
    ref.advance(300)
    assert s.sim.state_hash() == ref.sim.state_hash()  # physics untouched
    s.handle(ev.mouse(1.0, 0.5))
    assert deg(s, "ankle") == -40
    assert s.runtime.inputs["mouse.y"] == 0.5  # input state carried over


def test_reload_carries_a_running_sequence_and_held_keys(tmp_path):
    s = session_for(tmp_path)
    s.handle(ev.key("h", True))  # held
    s.advance(10)
    s.handle(ev.reload(NARROW))
    assert s.runtime.sequence is not None and "h" in s.runtime.held
    s.advance(100)
    assert deg(s, "ankle") == 0  # the sequence went on to its second pose


def test_invalid_text_is_refused_with_file_line_and_the_old_runtime_stays(tmp_path):
    s = session_for(tmp_path)
    old = s.runtime
    bad = BASE.replace("joint: knee", "joint: kneee")
    with pytest.raises(DataError) as err:
        s.handle(ev.reload(bad, "interfaces/t.yaml"))
    assert str(err.value).startswith("interfaces/t.yaml:7:")
    assert "kneee" in str(err.value) and "did you mean 'knee'" in str(err.value)
    assert s.runtime is old and s.version == 0
    with pytest.raises(DataError, match=r"x.yaml:3:\d+: .*cannot change the character"):
        parse_interface_text(BASE.replace("character: luxo", "character: cat"), "x.yaml",
                             s.setup.character, s.setup.character_path)
    with pytest.raises(DataError, match=r"x.yaml:6:\d+: YAML syntax error"):
        parse_interface_text(BASE.replace("{input: mouse.x", "{input: [mouse.x"), "x.yaml")


def test_a_log_with_a_reload_replays_to_the_same_bits_without_the_file(tmp_path):
    s = session_for(tmp_path)
    log = tmp_path / "run.jsonl"
    with Recorder(s, log):
        s.handle(ev.mouse(0.2, 0.3))
        s.advance(300)
        s.handle(ev.reload(NARROW, str(tmp_path / "iface.yaml")))
        s.advance(50)
        s.handle(ev.mouse(0.9, 0.8))
        s.advance(400)
        s.handle(ev.key("h", True))
        s.advance(400)
    live = s.sim.state_hash()
    (tmp_path / "iface.yaml").write_text(BASE.replace("to: [80, -80]", "to: [0, 0]"))
    result = replay(log, as_recorded=True)
    assert result.final_hash == live and result.ok, result.summary
    assert result.warnings == []  # the interface came from the log's header
    today = replay(log)  # by default, against today's file: it changed, and says so
    assert today.final_hash != live and any("differs from the one recorded" in w
                                            for w in today.warnings)
    assert any("hot-reloaded its interface (first at step 300)" in w for w in today.warnings)
    (tmp_path / "iface.yaml").unlink()  # gone: the recorded copy stands in
    gone = replay(log)
    assert gone.final_hash == live and "is not found" in gone.warnings[0]


def test_rewind_across_a_reload_restores_the_interface_of_that_time(tmp_path):
    """Keyframes (every 240 steps here) carry the interface version; a rewind that
    re-simulates across the reload event replays it; a log of it all replays exactly."""
    def run(until, reload_at=300, session=None):
        s = session or session_for(tmp_path, checkpoint_interval=0.5)
        s.handle(ev.mouse(0.8, 0.4))
        s.advance(reload_at)
        s.handle(ev.reload(NARROW))
        s.advance(100)
        s.handle(ev.mouse(0.1, 0.9))
        s.advance(until - s.steps)
        return s

    s = session_for(tmp_path, checkpoint_interval=0.5)
    log = tmp_path / "rewinds.jsonl"
    rec = Recorder(s, log)
    run(1500, session=s)
    for step, version in ((480, 1), (240, 0), (360, 1), (720, 1)):
        s.handle({"type": "action", "name": "rewind", "to_step": step})
        assert s.steps == step and s.version == version, step
        if step % 240 == 0:  # exactly a keyframe: the very bits of a straight run
            if step > 300:
                straight = run(step)
            else:
                straight = session_for(tmp_path)
                straight.handle(ev.mouse(0.8, 0.4))
                straight.advance(step)
            assert s.sim.state_hash() == straight.sim.state_hash(), step
    s.handle({"type": "action", "name": "rewind", "to_step": 240})
    assert s.interface.maps[0].to == (80, -80)
    s.handle(ev.mouse(1.0, 0.5))  # branches the history: the old interface goes on
    assert deg(s, "ankle") == -80
    s.advance(200)
    rec.close()
    assert replay(log).final_hash == s.sim.state_hash()


def test_restoring_a_checkpoint_keeps_the_reloaded_interface(tmp_path):
    s = session_for(tmp_path)
    s.handle(ev.action("checkpoint"))
    s.advance(100)
    s.handle(ev.reload(NARROW))
    s.advance(100)
    s.handle(ev.action("restore"))
    assert s.steps == 0 and s.interface.maps[0].to == (40, -40)
    s.handle(ev.mouse(1.0, 0.5))
    assert deg(s, "ankle") == -40


def test_the_poller_notices_a_save_and_checks_it(tmp_path):
    path = tmp_path / "iface.yaml"
    path.write_text(BASE)
    setup = load_setup(str(path))

    def check(text):
        parse_interface_text(text, str(path), setup.character, setup.character_path)

    r = Reloader(path, check, interval=0.5, now=0.0)
    assert r.poll(0.1) is None and r.poll(0.6) is None  # nothing saved
    path.write_text(NARROW)
    os.utime(path, ns=(1, 10**18))
    assert r.poll(0.7) is None  # not yet time to look
    change = r.poll(1.2)
    assert change is not None and change.ok and change.text == NARROW
    assert r.poll(1.8) is None  # seen
    path.write_text(BASE.replace("key: h", "key: r"))  # the app's reset key
    os.utime(path, ns=(1, 2 * 10**18))
    change = r.poll(2.4)
    assert not change.ok and change.error.startswith(f"{path}:14:11: key 'r'")


def test_window_records_binds_saves_and_reloads(tmp_path, monkeypatch):
    """The real window loop (SDL dummy driver): F2 records the mouse, F2 stops, h binds,
    F3 saves into the file, the poller reloads it; a bad edit is refused, a good one
    runs; the log replays to the recorded end."""
    import pygame

    from puppet.app import window
    from puppet.timeline.log import read_log

    path = tmp_path / "iface.yaml"
    path.write_text(BASE)
    frame = {"n": 0}

    def key(kind, k):
        return pygame.event.Event(kind, key=k, mod=0, unicode="", scancode=0)

    plan = {6: [key(pygame.KEYDOWN, pygame.K_F2), key(pygame.KEYUP, pygame.K_F2)],
            30: [key(pygame.KEYDOWN, pygame.K_F2), key(pygame.KEYUP, pygame.K_F2)],
            32: [key(pygame.KEYDOWN, pygame.K_j), key(pygame.KEYUP, pygame.K_j)],
            34: [key(pygame.KEYDOWN, pygame.K_F3), key(pygame.KEYUP, pygame.K_F3)]}
    edits = {75: lambda t: t.replace("key: h", "key: r"),  # the app's reset key: refused
             115: lambda t: t.replace("key: r", "key: h").replace("to: [80, -80]",
                                                                   "to: [40, -40]")}
    real_get = pygame.event.get

    def fake_get(*args, **kw):
        frame["n"] += 1
        n = frame["n"]
        if n in edits:
            path.write_text(edits[n](path.read_text()))
        real_get()
        return plan.get(n, []) + ([pygame.event.Event(pygame.QUIT)] if n >= 155 else [])

    monkeypatch.setattr(pygame.event, "get", fake_get)
    monkeypatch.setattr(pygame.mouse, "get_focused", lambda: True)
    monkeypatch.setattr(pygame.mouse, "get_pos",
                        lambda: (200 + 25 * min(frame["n"], 40), 300 + 5 * frame["n"] % 200))
    log_path = tmp_path / "win.jsonl"
    assert window.run_window(load_setup(str(path)), record=str(log_path)) == 0
    log = read_log(log_path)
    kinds = [e.event["type"] for e in log.events]
    assert kinds.count("gesture") == 1 and kinds.count("reload") == 2, kinds
    bound = next(e.event for e in log.events if e.event["type"] == "gesture")
    assert bound["key"] == "j" and len(bound["path"]) > 10
    text = path.read_text()
    assert text.startswith(BASE.replace("to: [80, -80]", "to: [40, -40]")) and "gestures:" in text
    reloads = [e.event["text"] for e in log.events if e.event["type"] == "reload"]
    assert 'key: "j"' in reloads[0] and "to: [40, -40]" in reloads[1]
    assert "interface_text" in log.header
    path.write_text("broken: [")  # replaying as recorded does not read the file
    assert replay(log_path, as_recorded=True).final_hash == log.end_hash


def test_a_logged_reload_with_a_bad_text_names_the_log_line(tmp_path):
    s = session_for(tmp_path)
    log = tmp_path / "bad.jsonl"
    with Recorder(s, log):
        s.advance(10)
    lines = log.read_text().splitlines()
    bad = '{"step":5,"event":{"type":"reload","text":"name: t\\ncharacter: luxo\\n"}}'
    log.write_text("\n".join(lines[:1] + [bad] + lines[1:]) + "\n")
    with pytest.raises(DataError, match=r"bad.jsonl:2: cannot apply this event: .*"
                                        r"missing required key 'description'"):
        replay(log)


LUXO = """
name: t
description: reaches and grasps in the pendulum scene
character: luxo
scene: pendulum
gains:
  ankle: {stiffness: 60, damping: 0.6, max_torque: 40}
  knee: {stiffness: 40, damping: 0.4, max_torque: 30}
chains:
  shade: {joints: [ankle, knee], end: [0.0, 0.43]}
keys:
  - key: s
    reach: {chain: shade, steer: {x: channel.hx, y: channel.hy, x_to: [-0.04, 0.06],
            y_to: [0.32, 0.40]}, duration: 0.3}
  - {key: g, reach: {chain: shade, point: {prop: rail}, duration: 0.4, hold: 0.4,
                     grasp: true, tolerance: 0.03}}
  - {key: u, release: all}
"""


HOP = """
name: t
description: a pose sequence to reload under
character: luxo
poses:
  crouch: {joints: {ankle: -70, knee: 130}}
  tall: {joints: {ankle: 0, knee: 0}}
sequences:
  hop: [{pose: crouch, hold: 0.2}, {pose: tall, hold: 0.3}]
keys:
  - {key: h, sequence: hop}
"""


def test_a_grasp_held_over_a_hot_reload_stays_held_unless_its_chain_changed(tmp_path):
    s = session_of(tmp_path, LUXO)
    s.advance(120)
    tap(s, "g")
    s.advance(600)
    assert "shade" in s.runtime.grasped
    held = s.runtime.grasped["shade"]
    s.reload(textwrap.dedent(LUXO).replace("description: reaches", "description: Reaches"),
             str(tmp_path / "iface.yaml"))
    s.advance(60)
    assert s.runtime.grasped.get("shade") == held  # the same chain: it holds on
    s.reload(textwrap.dedent(LUXO).replace("end: [0.0, 0.43]", "end: [0.0, 0.42]"),
             str(tmp_path / "iface.yaml"))
    s.advance(2)
    assert "shade" not in s.runtime.grasped  # the chain changed: it let go


def test_a_reload_that_changes_the_running_sequence_ends_it(tmp_path):
    s = session_of(tmp_path, HOP)
    s.handle(ev.key("h", True))
    s.advance(10)
    assert s.runtime.sequence is not None
    s.reload(textwrap.dedent(HOP).replace("hold: 0.2", "hold: 0.25"), str(tmp_path / "t.yaml"))
    assert s.runtime.sequence is None  # another sequence now: it does not carry on
    s.advance(200)
    assert round(math.degrees(s.character.servos["ankle"].target)) == -70  # left there
