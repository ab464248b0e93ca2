"""The monkey bars (interfaces/biped-bars.yaml, log biped-monkey-bars): the log's
expectations (every bar crossed hand over hand; that they hold is tests/test_logs.py's)
fail by name when the physics or the interface breaks: the figure's own weak elbows, a
grasp tolerance too small, the pull-up key missing; letting go with both hands drops the
figure (no safeguard)."""

from __future__ import annotations

from puppet.data.catalog import ROOT, load_setup
from puppet.interface import events as ev
from puppet.session import Session
from puppet.testing import replay_log
from puppet.timeline.expectations import evaluate_all, parse_expectations
from puppet.timeline.trajectory import Sampler
from tests.helpers import with_changed_interface

LOG = ROOT / "assets" / "logs" / "biped-monkey-bars.jsonl"


def _outcomes(result) -> dict[str, bool]:
    return {str(o).split(":")[0][5:]: o.passed for o in result.outcomes}


def _variant(tmp_path, change) -> dict[str, bool]:
    """Replay the log against a copy of biped-bars changed by ``change(spec)``."""
    return _outcomes(replay_log(with_changed_interface(LOG, "biped-bars", tmp_path, change)))


def _regrasps_failed(outcomes: dict[str, bool]) -> bool:
    return not next(ok for name, ok in outcomes.items() if name.startswith("regrasps"))


def test_with_the_figures_own_elbows_the_bars_are_not_crossed(tmp_path):
    """The pull-up is the elbow's: at the figure's own 25 N*m (not a gymnast's 220) it
    cannot lift 70 kg, the swing stays short and a bar is missed. (The figure's own
    shoulders alone no longer stop it: since the next bar's reach takes 0.3 s, the hand
    arrives before the swing turns, and a 40 N*m shoulder gets it there.)"""
    def weak(spec):
        for j in ("elbow_near", "elbow_far"):
            spec["gains"][j] = {"stiffness": 30, "damping": 1.5, "max_torque": 25}
    assert _regrasps_failed(_variant(tmp_path, weak))


def test_a_grasp_tolerance_of_5_mm_misses_bars(tmp_path):
    def tight(spec):
        for state in ("near_support", "far_support"):
            for key in spec["states"][state]["keys"]:
                if "reach" in key:
                    key["reach"]["tolerance"] = 0.005
    assert _regrasps_failed(_variant(tmp_path, tight))


def test_without_the_pull_up_key_the_swing_falls_short(tmp_path):
    def no_pull(spec):
        spec["keys"] = [k for k in spec["keys"] if k["key"] != "w"]
    assert _regrasps_failed(_variant(tmp_path, no_pull))


def test_letting_go_with_both_hands_drops_the_figure():
    s = Session(load_setup("biped-bars"))
    sampler = Sampler(s)
    for key in ("x", "z"):  # at 3 s, hanging: the far hand lets go, then the near one
        s.advance(round(3.0 / s.sim.dt) - s.steps)
        s.handle(ev.key(key, True))
        s.handle(ev.key(key, False))
    while s.time < 4.5:
        s.advance(4)
        sampler(s)
    assert s.sim.grasps == {}
    traj = sampler.trajectory()
    items = parse_expectations([{"always_holding": {"chains": ["hand_near", "hand_far"]}},
                                {"airborne": {"link": "foot_near", "min_seconds": 1.4}}])
    assert [o.passed for o in evaluate_all(items.items, traj, "")] == [False, False]
    assert s.character.com()[1] < 1.2  # on the floor (hanging, it is about 1.5 m up)


def _held_trajectory(rows):
    """A trajectory from the recorded log with its held column replaced by ``rows``."""
    import numpy as np

    traj = replay_log(LOG).trajectory
    held = np.empty(len(traj.t), dtype=object)
    for i in range(len(held)):
        held[i] = rows(float(traj.t[i]))
    traj.held = held
    return traj


def test_regrasps_by_turns_count_only_alternating_hands():
    def rows(t):  # the near hand takes bars 2, 3 and 4 alone, then the far hand bar 5
        near = "bar1" if t < 3 else "bar2" if t < 5 else "bar3" if t < 7 else "bar4"
        held = [("hand_near", "bars", near)]
        if t >= 9:
            held.append(("hand_far", "bars", "bar5"))
        return tuple(held)
    traj = _held_trajectory(rows)
    items = parse_expectations([
        {"regrasps": {"chains": ["hand_near", "hand_far"], "prop": "bars", "min": 4}},
        {"regrasps": {"chains": ["hand_near", "hand_far"], "prop": "bars", "min": 3,
                      "alternate": True}},
        {"regrasps": {"chains": ["hand_near", "hand_far"], "prop": "bars", "min": 2,
                      "alternate": True}},
        {"held_point": {"prop": "bars", "point": "bar5", "chain": "hand_far"}},
        {"held_point": {"prop": "bars", "point": "bar5", "chain": "hand_near"}},
        {"always_holding": {"chains": ["hand_far"]}},
        {"always_holding": {"chains": ["hand_far"], "from": 9.5}}])
    assert [o.passed for o in evaluate_all(items.items, traj, "")] == [
        True, False, True, True, False, False, True]


def test_the_key_map_draws_the_bar_each_reach_key_goes_for():
    import pygame

    from puppet.app.keymap import TARGET, draw_keymap, reach_key_bindings

    setup = load_setup("biped-bars")
    keys = dict(reach_key_bindings(setup.interface, "far_support"))
    assert {k: r.point.offset for k, r in keys.items()} == {"a": -1, "s": 0, "d": 1, "f": 2}
    assert {r.chain for r in keys.values()} == {"hand_near"}
    pygame.font.init()
    font = pygame.font.SysFont(None, 14)
    plain, with_scene = pygame.Surface((800, 400)), pygame.Surface((800, 400))
    draw_keymap(plain, setup.interface, setup.character, font, (0, 0), state="far_support")
    rect = draw_keymap(with_scene, setup.interface, setup.character, font, (0, 0),
                       state="far_support", scene=setup.scene)
    ringed = [(x, y) for x in range(rect.width) for y in range(rect.height)
              if tuple(with_scene.get_at((x, y)))[:3] == TARGET]
    assert ringed and not any(tuple(plain.get_at(p))[:3] == TARGET for p in ringed)
