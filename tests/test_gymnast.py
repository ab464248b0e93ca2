"""The gymnast (interfaces/biped-gymnast.yaml) on the high bar: giant swings, and the
expectation kinds they need (revolutions, held)."""

from __future__ import annotations

import math

import numpy as np
import pytest
import yaml

from puppet.data.catalog import ROOT, find, load_setup
from puppet.session import Session
from puppet.testing import replay_log
from puppet.timeline.expectations import evaluate, parse_expectations
from tests.helpers import copy_log

LOG = ROOT / "assets" / "logs" / "biped-giant-swings.jsonl"


def _variant(tmp_path, edit) -> object:
    """The giant swings replayed against a copy of the interface changed by ``edit``."""
    spec = yaml.safe_load(find("interface", "biped-gymnast").read_text(encoding="utf-8"))
    edit(spec)
    spec["name"] = "biped-gymnast-variant"
    iface = tmp_path / "biped-gymnast-variant.yaml"
    iface.write_text(yaml.safe_dump(spec), encoding="utf-8")
    log = copy_log(LOG, tmp_path, interface=str(iface),
                   interface_text=iface.read_text(encoding="utf-8"))
    return replay_log(log)


def _failed(result) -> set[str]:
    return {o.expectation.split()[0] for o in result.failed}


def test_the_figure_starts_hanging_from_the_bar_with_both_hands():
    session = Session(load_setup("biped-gymnast"))
    session.advance(48)
    held = {name: prop for name, (_, prop) in session.sim.grasps.items()}
    assert held == {"hand_near": "bar", "hand_far": "bar"}
    _, y = session.character.com()
    session.advance(480)  # a second later it still hangs (feet clear of the floor)
    assert abs(session.character.com()[1] - y) < 0.01
    feet = min(sh.cache_bb().bottom for n in ("foot_near", "foot_far")
               for sh in session.character.shapes[n])
    assert feet > 0.5


def test_giant_swings_fail_without_a_grasp(tmp_path):
    """The hands never close (each hand's 'holding' state arms no grasp): the figure
    drops off the bar and neither the turns nor the hold are there."""
    def no_grasp(spec):
        for hand in ("near_hand", "far_hand"):
            spec["machines"][hand]["states"]["holding"]["enter"] = {"release": "all"}

    assert {"revolutions", "held"} <= _failed(_variant(tmp_path, no_grasp))


@pytest.mark.parametrize("stiffness, damping, max_torque", [(60, 3, 40), (1500, 10, 150)])
def test_giant_swings_fail_with_weaker_shoulders(tmp_path, stiffness, damping, max_torque):
    """With a standing figure's shoulders (60 N*m/rad, 40 N*m), or half the gymnast's
    torque, the arms cannot shape the body against its swing: it never goes round."""
    def weak(spec):
        for j in ("shoulder_near", "shoulder_far"):
            spec["gains"][j] = {"stiffness": stiffness, "damping": damping,
                                "max_torque": max_torque}

    assert "revolutions" in _failed(_variant(tmp_path, weak))


def test_giant_swings_fail_when_the_pump_does_not_pike(tmp_path):
    """The pump's pike made its stretch (key 5 then only holds the body stretched): the
    figure just hangs, so the turns are the pumping's."""
    def no_pike(spec):
        spec["poses"]["pike"]["joints"] = dict(spec["poses"]["stretch"]["joints"])

    assert "revolutions" in _failed(_variant(tmp_path, no_pike))


def test_giant_swings_fail_when_the_pump_pikes_on_the_fall(tmp_path):
    """The pump's poses swapped (stretched on the rise, piked on the fall): pumping out of
    phase never builds the swing, so it is the sensor cues' order that pumps."""
    def swapped(spec):
        poses = spec["poses"]
        poses["pike"]["joints"], poses["stretch"]["joints"] = (
            poses["stretch"]["joints"], poses["pike"]["joints"])

    assert "revolutions" in _failed(_variant(tmp_path, swapped))


@pytest.mark.parametrize("physics", [{"iterations": 36}, {"dt": 1 / 240}],
                         ids=["36-passes", "1-240-step"])
def test_the_pumped_giant_swings_are_not_a_knife_edge(physics):
    """Issue 28: the pump's phases come from the centre of mass, so the recorded `5`
    goes round on 36 solver passes and on a 1/240 s step too (a recorded schedule of
    mouse sweeps did not on the 1/240 s step)."""
    from puppet.timeline.other_physics import OtherPhysics
    from puppet.timeline.replay import replay

    result = replay(LOG, physics=OtherPhysics(**physics))
    assert not result.failed, [str(o) for o in result.outcomes]


def _traj(com, held, t=None):
    """A minimal trajectory for the expectation kinds: com rows and held rows."""
    from types import SimpleNamespace

    n = len(com)
    return SimpleNamespace(t=np.arange(n) * 0.1 if t is None else t,
                           com=np.array(com, dtype=float), held=held)


def _circle(turns: float, n: int = 200, back: float = 0.0):
    a = np.linspace(0, 2 * math.pi * turns, n) - math.pi / 2
    pts = [(math.cos(x), math.sin(x)) for x in a]
    if back:  # then turn back by ``back`` turns
        b = np.linspace(a[-1], a[-1] - 2 * math.pi * back, n // 2)
        pts += [(math.cos(x), math.sin(x)) for x in b]
    return pts


def test_revolutions_counts_full_turns_about_a_point_and_fails_short_of_them():
    e = parse_expectations([{"revolutions": {"about": [0.0, 0.0], "min": 3}}]).items[0]
    com = _circle(3.2)
    ok = evaluate(e, _traj(com, [()] * len(com)), "")
    assert ok.passed and ok.measured.startswith("3.2")
    com = _circle(2.5)
    assert not evaluate(e, _traj(com, [()] * len(com)), "").passed
    # two turns, back a quarter, two more: never 3 in a row
    com = _circle(2.0, back=0.25) + _circle(2.0)[1:]
    assert not evaluate(e, _traj(com, [()] * len(com)), "").passed
    # the wrong way round
    fwd = parse_expectations([{"revolutions": {"about": [0, 0], "min": 3,
                                               "direction": "forward"}}]).items[0]
    com = _circle(3.2)
    assert not evaluate(fwd, _traj(com, [()] * len(com)), "").passed


def test_revolutions_about_a_chain_count_only_while_it_holds():
    e = parse_expectations([{"revolutions": {"about": "hand", "min": 3}}]).items[0]
    com = _circle(3.2)
    holding = [(("hand", "bar", None, 0.0, 0.0),)] * len(com)
    assert evaluate(e, _traj(com, holding), "").passed
    let_go = list(holding)
    let_go[len(com) // 2] = ()  # let go half way: two stretches of 1.6 turns
    assert not evaluate(e, _traj(com, let_go), "").passed


def test_held_fails_at_the_first_sample_a_chain_lets_go_or_holds_another_prop():
    e = parse_expectations([{"held": {"chains": ["a", "b"], "prop": "bar"}}]).items[0]
    both = (("a", "bar", None, 0, 0), ("b", "bar", None, 0, 0))
    rows = [both] * 10
    assert evaluate(e, _traj([(0, 0)] * 10, rows), "").passed
    rows[6] = (("a", "bar", None, 0, 0),)
    out = evaluate(e, _traj([(0, 0)] * 10, rows), "")
    assert not out.passed and "b held nothing at t = 0.60 s" in out.measured
    rows[6] = (("a", "bar", None, 0, 0), ("b", "rope", None, 0, 0))
    assert not evaluate(e, _traj([(0, 0)] * 10, rows), "").passed
    late = parse_expectations([{"held": {"chains": ["b"], "from": 0.7}}]).items[0]
    rows[6] = ()
    assert evaluate(late, _traj([(0, 0)] * 10, rows), "").passed


def test_the_guides_gymnast_hangs_swings_its_arms_and_falls_when_it_lets_go(tmp_path):
    from puppet.interface import events as ev
    from tests.test_docs import doc_session, tap

    s = doc_session(tmp_path, "name: my-gymnast")
    s.advance(48)
    assert set(s.sim.grasps) == {"hand_near"}
    assert s.runtime.states["hands"] == "holding"
    s.handle(ev.mouse(0.8, 0.2))  # arms closed to 110, body arched
    s.advance(240)
    shoulder = s.character.servos["shoulder_near"]
    assert abs(math.degrees(shoulder.target) - 110) < 1e-6
    assert s.sim.grasps  # still hanging
    y = s.character.com()[1]
    tap(s, "q")  # let go: it drops
    s.advance(240)
    assert s.runtime.states["hands"] == "free" and not s.sim.grasps
    assert s.character.com()[1] < y - 0.5


def test_on_the_rope_the_hands_hold_its_links_and_the_figure_swings_it():
    """The rope scene: six dynamic links pinned one to the next. Hanging from it by
    both hands (the grasps pin them to a link), a shove swings figure and rope
    together, and the hands stay on."""
    from puppet.interface import events as ev

    session = Session(load_setup("biped-gymnast", "rope"))
    session.advance(48)
    held = {name: prop for name, (_, prop) in session.sim.grasps.items()}
    assert set(held) == {"hand_near", "hand_far"}
    assert all(prop.startswith("rope") for prop in held.values())
    end = session.sim.props["rope6"].body
    session.advance(480)
    x0 = end.position.x
    session.handle(ev.push("pelvis", (60.0, 0.0)))
    swing = 0.0
    for _ in range(60):
        session.advance(16)
        swing = max(swing, abs(end.position.x - x0))
    assert swing > 0.2  # the rope's end swings with the figure (0.27 m)
    assert set(session.sim.grasps) == {"hand_near", "hand_far"}
    hand = session.runtime.chains["hand_near"].end_world(session.character)
    assert math.dist(hand, session.sim.grasp_point("hand_near")) < 0.02


def test_on_the_ladder_e_puts_both_hands_on_the_rung_at_1_8_m():
    from tests.test_docs import tap

    session = Session(load_setup("biped-gymnast", "ladder"))
    tap(session, "q")
    tap(session, "w")  # hands open (the start's grasps disarmed)
    tap(session, "e")
    session.advance(96)
    assert not session.sim.grasps
    tap(session, "q")
    tap(session, "w")  # armed: they close on the rung they reach
    session.advance(480)
    held = {name: round(session.sim.grasp_point(name)[1], 3) for name in session.sim.grasps}
    assert held == {"hand_near": 1.8, "hand_far": 1.8}
    assert {session.sim.grasps[n][1] for n in held} == {"ladder"}


def test_a_chain_that_never_held_is_named_in_the_outcome():
    rev = parse_expectations([{"revolutions": {"about": "hand", "min": 1}}]).items[0]
    com = _circle(1.5)
    out = evaluate(rev, _traj(com, [()] * len(com)), "")
    assert not out.passed and "'hand' never held anything" in out.measured
    held = parse_expectations([{"held": {"chains": ["hnd"]}}]).items[0]
    out = evaluate(held, _traj(com, [(("hand", None, None, 0, 0),)] * len(com)), "")
    assert not out.passed and "hnd never held anything" in out.measured
