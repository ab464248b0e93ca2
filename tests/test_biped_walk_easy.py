"""The forgiving walk (interfaces/biped-walk-easy.yaml; assets/logs/biped-walk-easy,
-reactive, -newcomer): space takes a step, but the step happens at the swing foot's
touch-down - a press during the step is kept (`buffer:`) until then - and with no press
the figure stands in double support. Its logs are not press schedules found by a search:
presses on a plain clock, or by watching the feet. That the three logs meet their
expectations is tests/test_logs.py's (every shipped log, replayed once)."""

from __future__ import annotations

import json
import math

from helpers import with_weak_hips
from test_luxo_feats import _failed

from puppet.data.catalog import ROOT, load_setup
from puppet.interface import events as ev
from puppet.session import Session

LOGS = ROOT / "assets" / "logs"
STEPS_PER_S = 480  # dt 1/480 s


def _presses(name: str) -> list[int]:
    lines = (LOGS / f"{name}.jsonl").read_text(encoding="utf-8").splitlines()[1:]
    rows = [json.loads(line) for line in lines if '"event"' in line]
    return [r["step"] for r in rows if r["event"].get("key") == "space" and r["event"]["down"]]


def _press(s: Session) -> None:
    s.handle(ev.key("space"))
    s.handle(ev.key("space", False))


def _tilt(s: Session, link: str) -> float:
    return abs(math.degrees(math.remainder(s.character.bodies[link].angle, 2 * math.pi)))


def _run_until(s: Session, prefix: str, limit: float) -> float:
    while not s.runtime.state.startswith(prefix):
        assert s.time < limit, s.runtime.state
        s.advance(1)
    return s.time


def test_the_walk_presses_on_a_clock_not_on_the_steps():
    """Every 0.6 s (288 steps): the presses know nothing of the feet."""
    for name in ("biped-walk-easy", "biped-walk-easy-newcomer"):
        steps = _presses(name)
        assert len(steps) > 100 and {b - a for a, b in zip(steps, steps[1:])} == {288}


def test_a_press_during_the_step_acts_at_the_touch_down():
    s = Session(load_setup("biped-walk-easy"))
    s.handle(ev.mouse(0.5, 0.5))
    s.advance(240)
    _press(s)
    assert s.runtime.state == "on_near"
    s.advance(48)  # 0.1 s into the step: too early to swap ...
    _press(s)
    assert s.runtime.state == "on_near"  # ... so it is kept
    _run_until(s, "on_far", 3.0)  # the next step begins, with no new press ...
    assert s.character.in_contact("foot_far")  # ... as the far foot lands


def test_with_no_press_it_stands_in_double_support():
    s = Session(load_setup("biped-walk-easy"))
    s.handle(ev.mouse(0.5, 0.5))
    s.advance(240)
    for _ in range(6):  # six steps, one press each, pressed as each foot lands
        _press(s)
        s.advance(8)
        _run_until(s, "land", s.time + 3.0)
    x = s.character.com()[0]
    s.advance(5 * STEPS_PER_S)  # 5 s without a press
    assert s.runtime.state.startswith("land")
    assert abs(s.character.com()[0] - x) < 0.3 and max(_tilt(s, "pelvis"), _tilt(s, "chest")) < 15
    feet = [s.character.bodies[f].position[1] for f in ("foot_near", "foot_far")]
    assert max(feet) < 0.03, feet  # both feet down (a contact flickers: their heights)
    _press(s)  # and a press walks on
    assert s.runtime.state.startswith("on_")


def test_the_walk_fails_with_weak_hips(tmp_path):
    assert {"never_fell", "x_at_end"} <= _failed(
        with_weak_hips("biped-walk-easy", "biped-walk-easy", tmp_path, 300.0, 75.0))

