"""The gymnast climbs the ladder (interfaces/biped-gymnast.yaml on the ladder scene, logs
biped-gymnast-climb-bound and -trot): the logs' expectations (which hold: tests/test_logs.py)
fail by name without rigid grasps (of the feet, or of the hands), with the figure's own
shoulders, or without the mapping's mode key (2 for the bound, 3 for the trot); each
climb's hands seek the next rung on a 1/240 s step (the trot's from behind, the bound's
from ahead)."""

from __future__ import annotations

import pytest

from puppet.data.catalog import ROOT
from puppet.testing import replay_log
from tests.helpers import with_changed_interface

LOGS = [ROOT / "assets" / "logs" / f"biped-gymnast-climb-{p}.jsonl" for p in ("bound", "trot")]
CLIMB = {"regrasps", "always_holding", "reached_height", "held_point"}


def _failed(tmp_path, log, change) -> set[str]:
    copy = with_changed_interface(log, "biped-gymnast", tmp_path, change)
    return {o.expectation.split(" ")[0] for o in replay_log(copy).outcomes if not o.passed}


def _grasps(spec):
    for machine in spec["machines"].values():
        for state in machine["states"].values():
            grasp = state.get("enter", {}).get("grasp")
            if grasp is not None:
                yield grasp


@pytest.mark.parametrize("log", LOGS, ids=lambda p: p.stem)
@pytest.mark.parametrize("limbs", ["foot", "hand"])
def test_without_rigid_grasps_the_climb_fails(tmp_path, log, limbs):
    """Pivots for the feet (the body tips back off them) or for the hands (the arms no
    longer set how it hangs): either way the climb stalls or falls."""
    def pivots(spec):
        for grasp in _grasps(spec):
            if grasp["chain"].startswith(limbs):
                grasp.pop("rigid", None)
    assert CLIMB & _failed(tmp_path, log, pivots)


@pytest.mark.parametrize("log", LOGS, ids=lambda p: p.stem)
def test_with_the_figures_own_shoulders_the_climb_fails(tmp_path, log):
    def weak(spec):
        for j in ("shoulder_near", "shoulder_far"):
            spec["gains"][j] = {"stiffness": 60, "damping": 3, "max_torque": 40}
    assert CLIMB & _failed(tmp_path, log, weak)


@pytest.mark.parametrize("log", LOGS, ids=lambda p: p.stem)
def test_without_the_mode_key_the_mouse_climbs_nothing(tmp_path, log):
    mode = "2" if log.stem.endswith("bound") else "3"

    def no_key(spec):
        spec["keys"] = [k for k in spec["keys"] if str(k["key"]) != mode]
    failed = _failed(tmp_path, log, no_key)
    assert "stayed_in_mode" in failed and CLIMB & failed


def test_with_the_arms_gathering_with_their_diagonal_legs_the_trot_climbs_nothing(tmp_path):
    """The trot map before the climb: each arm gathered with its diagonal leg, so the
    hand that reaches came down as its diagonal foot went up."""
    def old_trot(spec):
        for row in spec["modes"]["trot"]:
            if set(row.get("joints", {})) & {"shoulder_near", "elbow_near", "shoulder_far",
                                               "elbow_far"}:
                row["to"] = list(reversed(row["to"]))
    assert CLIMB & _failed(tmp_path, LOGS[1], old_trot)


@pytest.mark.parametrize("physics", [{"iterations": 36}, {"dt": 1 / 240}],
                         ids=["36-passes", "1-240-step"])
def test_the_trot_climb_is_not_a_knife_edge(physics):
    """Issue 28: one key a regrasp (t / g, skip_released) and the hands seeking the
    ladder: the trot climb meets its feat on 36 solver passes and a 1/240 s step too."""
    from puppet.timeline.other_physics import OtherPhysics
    from puppet.timeline.replay import replay

    result = replay(LOGS[1], physics=OtherPhysics(**physics))
    assert not result.failed, [str(o) for o in result.outcomes]


@pytest.mark.parametrize("physics", [{"iterations": 36}, {"dt": 1 / 240}],
                         ids=["36-passes", "1-240-step"])
def test_the_bound_climb_is_not_a_knife_edge(physics):
    """Issue 28: with the ankles a servo again on the ladder (reach_low's ankle damping)
    and every stroke searched on all three physics, the bound climb meets its feat on 36
    solver passes and a 1/240 s step too (before, the second hands-up stroke went up
    behind rung 7 there)."""
    from puppet.timeline.other_physics import OtherPhysics
    from puppet.timeline.replay import replay

    result = replay(LOGS[0], physics=OtherPhysics(**physics))
    assert not result.failed, [str(o) for o in result.outcomes]


def test_with_the_figures_own_ankle_damping_the_bound_climb_fails(tmp_path):
    """reach_low's ankle gains removed: the light foot's servo is damped so hard that the
    ankle keeps whatever angle it is left at and creeps under load, the body leans back
    another way and the strokes miss their rungs."""
    def own_ankles(spec):
        pose = spec["poses"]["reach_low"]
        for key in ("damping", "max_torque"):
            pose.pop(key)
    assert CLIMB & _failed(tmp_path, LOGS[0], own_ankles)


def test_without_the_seek_the_trot_climb_misses_on_a_1_240_step(tmp_path):
    """The hands' stepping states without their seek map: on a 1/240 s step the near
    hand swings up behind rung 9 and the climb stops there."""
    from puppet.timeline.other_physics import OtherPhysics
    from puppet.timeline.replay import replay

    def no_seek(spec):
        for hand in ("near_hand", "far_hand"):
            spec["machines"][hand]["states"]["stepping"].pop("maps")
    copy = with_changed_interface(LOGS[1], "biped-gymnast", tmp_path, no_seek)
    failed = {o.expectation.split(" ")[0]
              for o in replay(copy, physics=OtherPhysics(dt=1 / 240)).failed}
    assert CLIMB & failed


@pytest.mark.parametrize("seek", [True, False], ids=["with", "without"])
def test_the_bound_climbs_hands_seek_the_rung_from_ahead_on_a_1_240_step(tmp_path, seek):
    """Issue 29: a person's try of the bound climb (human noise, seed 0, try 2) on a
    1/240 s step throws both hands 14-17 cm in front of rung 7; with the seek in the
    hands' `climbing` states they turn up and back and catch it, without it they miss
    it and the figure falls when the feet let go next."""
    from puppet.data.playtest import noise_at
    from puppet.timeline.other_physics import OtherPhysics
    from puppet.timeline.playtest.trial import run_try

    def no_seek(spec):
        if not seek:
            for hand in ("near_hand", "far_hand"):
                spec["machines"][hand]["states"]["climbing"].pop("maps")
    copy = with_changed_interface(LOGS[0], "biped-gymnast", tmp_path, no_seek)
    result = run_try(str(copy), noise_at("human"), 0, 2, OtherPhysics(dt=1 / 240))
    assert result.passed == seek, result.failed
