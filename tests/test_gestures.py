"""Recorded gestures: mouse paths bound to keys, played back through the mouse maps in
sim time; preemption; validation; saving them into the file; recording and binding
through Session events, replayed from a log."""

import math

import pytest

from puppet.app.gestures import GestureRecorder
from puppet.commands.check import check_file
from puppet.data.catalog import load_setup, parse_interface_text
from puppet.data.errors import DataError
from puppet.data.gesture_file import replace_gestures
from puppet.interface import events as ev
from puppet.session import Session
from puppet.timeline.log import Recorder
from puppet.timeline.replay import replay

BASE = """name: t
description: test interface
character: luxo
maps:
  - {input: mouse.x, joint: ankle, from: [0, 1], to: [80, -80]}
  - {input: mouse.y, joint: knee, to: [160, -20]}
poses:
  crouch: {joints: {ankle: -70, knee: 130}}
  fold: {joints: {knee: 100}}
sequences:
  sit: [{pose: crouch, hold: 0.5}]
keys:
  - {key: s, sequence: sit}
  - {key: f, pose: fold}
"""
GESTURES = """gestures:
  - key: k
    description: sweep right
    path: [[0, 0, 0.5], [0.1, 0.5, 0.5], [0.2, 1, 1]]
  - {key: l, path: [[0, 1, 0], [0.1, 0.5, 0]]}
"""


def deg(s, joint):
    return round(math.degrees(s.character.servos[joint].target), 6)


def session_for(tmp_path, text=BASE + GESTURES, **kw) -> Session:
    path = tmp_path / "iface.yaml"
    path.write_text(text)
    return Session(load_setup(str(path)), **kw)


def press(s, key):
    s.handle(ev.key(key, True))
    s.handle(ev.key(key, False))


def test_a_gesture_plays_its_path_through_the_mouse_maps_in_sim_time(tmp_path):
    s = session_for(tmp_path)
    s.handle(ev.mouse(0.5, 0.5))
    press(s, "k")
    assert (deg(s, "ankle"), deg(s, "knee")) == (80, 70)  # the first point at once
    s.advance(48)  # 0.1 s: the next point acts at step 48, before stepping from it
    assert deg(s, "ankle") == 80
    s.advance(1)
    assert deg(s, "ankle") == 0
    s.advance(48)
    assert (deg(s, "ankle"), deg(s, "knee")) == (-80, -20)
    assert s.runtime.gesture is None and s.runtime.next_wakeup is None  # done, idle
    assert s.runtime.inputs["mouse.x"] == 0.5  # the real mouse is where it was
    s.handle(ev.mouse(0.5, 0.5))
    assert deg(s, "ankle") == 0


def test_preemption_by_sequences_poses_gestures_and_the_mouse(tmp_path):
    s = session_for(tmp_path)
    press(s, "k")
    s.advance(20)
    press(s, "f")  # a pose takes the knee; the gesture keeps the ankle
    s.advance(40)
    assert (deg(s, "ankle"), deg(s, "knee")) == (0, 100)
    press(s, "l")  # a new gesture replaces the running one
    assert s.runtime.gesture[0] == "l" and (deg(s, "ankle"), deg(s, "knee")) == (-80, 160)
    press(s, "s")  # a sequence takes all the gesture's joints: it ends
    s.advance(60)
    assert s.runtime.gesture is None and (deg(s, "ankle"), deg(s, "knee")) == (-70, 130)
    press(s, "k")
    s.handle(ev.mouse(0.25, 1.0))  # moving the mouse takes the joints back
    s.advance(100)
    assert s.runtime.gesture is None and (deg(s, "ankle"), deg(s, "knee")) == (40, -20)


@pytest.mark.parametrize("gestures, where, message", [
    ("  - {key: k, path: [[0, 0, 0], [0, 1, 1]]}\n", ":5:", "must be after the previous"),
    ("  - {key: k, path: [[0, 0, 0], [0.1, 1.5, 1]]}\n", ":5:", "x = 1.5 is outside 0..1"),
    ("  - {key: k, path: [[-1, 0, 0]]}\n", ":5:", "must be 0 or more"),
    ("  - {key: r, path: [[0, 0, 0]]}\n", ":5:", "the app's 'reset' key"),
    ("  - {key: f2, path: [[0, 0, 0]]}\n", ":5:", "the app's 'record_gesture' key"),
    ("  - {key: k, path: [[0, 0, 0]]}\n  - {key: k, path: [[0, 1, 1]]}\n", ":6:",
     "the key of gestures[0]"),
    ("  - {key: k, path: []}\n", ":5:", "at least 1 item"),
])
def test_gesture_validation_names_file_and_line(gestures, where, message):
    text = "name: t\ndescription: x\ncharacter: luxo\ngestures:\n" + gestures
    with pytest.raises(DataError) as err:
        parse_interface_text(text, "g.yaml")
    assert str(err.value).startswith("g.yaml" + where) and message in str(err.value), err.value


def test_saving_replaces_the_block_and_keeps_every_other_byte(tmp_path):
    head = BASE.replace("keys:", "# designer's note: keys below\nkeys:  # trailing comment")
    tail = "# a comment about what follows\nperturbation: {impulse: 0.001}\n"
    s = session_for(tmp_path, head + GESTURES + tail)
    s.handle(ev.gesture("m", [[0, 0.2, 0.3], [0.05, 0.25, 0.35], [0.125, 1, 0]], "new one"))
    text = replace_gestures(head + GESTURES + tail, s.interface.gestures)
    assert text.startswith(head) and text.endswith(tail)
    path = tmp_path / "saved.yaml"
    path.write_text(text)
    assert check_file(path) == "interface"
    saved = load_setup(str(path)).interface
    assert saved.gestures == s.interface.gestures
    # no block yet: appended; an indentless block is replaced whole
    assert replace_gestures(BASE, saved.gestures) == BASE + replace_gestures("", saved.gestures)
    indentless = BASE + "gestures:\n- {key: k, path: [[0, 0, 0]]}\n" + tail
    assert replace_gestures(indentless, saved.gestures) == text.replace(head, BASE)
    assert replace_gestures(indentless, []) == BASE + tail


def test_recording_and_binding_through_session_events_replays_exactly(tmp_path):
    s = session_for(tmp_path, BASE, checkpoint_interval=0.5)
    log = tmp_path / "g.jsonl"
    rec = Recorder(s, log)
    g = GestureRecorder()
    s.handle(ev.mouse(0.5, 0.5))
    g.toggle(s.time, (0.5, 0.5), "f2")
    for i in range(30):  # the window: a mouse event per frame, recorded as it is sent
        x, y = 0.5 + 0.4 * math.sin(i / 5), 0.5 - 0.3 * math.cos(i / 7)
        s.handle(ev.mouse(x, y))
        g.add(s.time, x, y)
        s.advance(8)
    assert "press the key" in g.toggle(s.time, None, "f2")
    event, message = g.bind("s", s.interface)  # taken: waits for another key
    assert event is None and "keys[0]" in message
    event, message = g.bind("h", s.interface)
    s.handle(event)
    assert [x.key for x in s.interface.gestures] == ["h"] and s.version == 1
    s.advance(100)
    press(s, "h")
    s.advance(300)
    assert s.runtime.gesture is None
    s.handle({"type": "action", "name": "rewind", "to_step": 240})  # before the binding
    assert s.interface.gestures == [] and not s.runtime.handles_key("h")
    s.handle({"type": "action", "name": "rewind", "to_step": 480})
    assert s.runtime.handles_key("h")
    press(s, "h")
    s.advance(200)
    rec.close()
    result = replay(log)
    assert result.final_hash == s.sim.state_hash() and result.ok, result.summary
    assert result.session.interface.gestures == s.interface.gestures
    # after a reload of a file without it, the window binds it again (not saved yet)
    assert g.rebind_after_reload(load_setup(str(tmp_path / "iface.yaml")).interface) == [event]
