"""The walk and the march (assets/logs/biped-walk, biped-march): the human figure on
interfaces/biped-walk.yaml goes 10 m and more, on the mouse and the swap key, and with
the mouse parked on the swap key alone. Their expectations must fail when the physics
under them breaks (that they hold is tests/test_logs.py's: every shipped log)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from helpers import with_weak_hips
from test_luxo_feats import _failed, _weakened

from puppet.data.catalog import ROOT

LOGS = ROOT / "assets" / "logs"


def _events(name: str) -> list[dict]:
    lines = (LOGS / f"{name}.jsonl").read_text(encoding="utf-8").splitlines()[1:]
    return [json.loads(line) for line in lines if '"event"' in line]


def test_the_walk_is_driven_by_the_mouse_and_the_swap_key():
    events = _events("biped-walk")
    kinds = {e["event"]["type"] for e in events}
    assert kinds == {"mouse", "key", "action"}
    assert {e["event"]["key"] for e in events if e["event"]["type"] == "key"} == {"space"}
    assert {e["event"]["name"] for e in events if e["event"]["type"] == "action"} \
        == {"checkpoint"}
    moved_late = [e for e in events if e["event"]["type"] == "mouse" and e["step"] > 480 * 5]
    assert len(moved_late) > 100  # the mouse moves all along, not only at the start


def test_the_march_parks_the_mouse_after_the_first_second():
    events = _events("biped-march")
    mice = [e for e in events if e["event"]["type"] == "mouse"]
    assert mice and max(e["step"] for e in mice) <= 480  # dt 1/480 s: by t = 1 s
    late = [e["event"] for e in events if e["step"] > 480 and e["event"]["type"] != "action"]
    assert late and all(e["type"] == "key" and e["key"] == "space" for e in late)
    assert sum(e["down"] for e in late) >= 20  # strides


@pytest.mark.parametrize("name", ["biped-walk", "biped-march"])
def test_the_log_fails_with_weak_hips(name, tmp_path):
    assert {"never_fell", "x_at_end"} <= _failed(with_weak_hips(name, "biped-walk", tmp_path,
                                                                300.0, 75.0))


@pytest.mark.parametrize("name", ["biped-walk", "biped-march"])
def test_the_log_fails_on_slippery_ground(name, tmp_path):
    assert {"never_fell", "x_at_end"} <= _failed(_weakened(name, Path(tmp_path), friction=0.3))


def test_pressing_space_at_each_footfall_walks_on_with_the_mouse_parked():
    """Not a searched performance: a rule a person can follow - the mouse parked, space
    pressed 0.05 s after each footfall - keeps the figure walking on the flat track.
    (The searched logs are open-loop: moving one press by 2 ms fells them.)"""
    import math

    from puppet.data.catalog import load_setup
    from puppet.interface import events as ev
    from puppet.session import Session

    s = Session(load_setup("biped-walk", "biped-track"))
    c = s.character

    def press():
        s.handle(ev.key("space"))
        s.handle(ev.key("space", False))

    def tilt(name):
        return abs(math.degrees(math.remainder(c.bodies[name].angle, 2 * math.pi)))

    s.advance(240)
    s.handle(ev.mouse(0.55, 0.3))
    s.advance(240)
    press()
    landed, presses = None, 1
    while s.time < 20.0:
        s.advance(8)
        assert max(tilt("pelvis"), tilt("chest")) < 45.0, (s.time, c.com())
        state = s.runtime.state
        swing = "foot_far" if state.endswith("near") else "foot_near"
        if state.startswith("down") and c.in_contact(swing):
            landed = s.time if landed is None else landed
            if s.time - landed >= 0.05:
                press()
                presses, landed = presses + 1, None
        else:
            landed = None
    assert c.com()[0] > 10.0 and presses >= 25, (c.com(), presses)


def test_at_a_swap_the_mouse_drives_the_new_swing_leg_without_moving():
    """One 'stepping' mode serves both legs: entering the state whose roles swap puts
    the mouse's targets on the new swing leg at once, the mouse held still."""
    import math

    from puppet.data.catalog import load_setup
    from puppet.interface import events as ev
    from puppet.session import Session

    s = Session(load_setup("biped-walk"))
    servos = s.character.servos
    s.handle(ev.mouse(0.5, 1.0))  # y at the top: the swing knee bent 90 deg
    s.handle(ev.key("space", True))
    s.handle(ev.key("space", False))
    assert s.runtime.role_binding == "near"
    assert math.degrees(servos["knee_far"].target) == pytest.approx(-90)
    before = servos["knee_near"].target
    s.advance(48)
    s.handle(ev.key("space", True))  # swap: the near leg swings now
    assert s.runtime.role_binding == "far" and s.runtime.mode == "stepping"
    assert math.degrees(servos["knee_near"].target) == pytest.approx(-90)
    assert servos["knee_near"].target != before
