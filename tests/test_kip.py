"""The gymnast's kip (interfaces/biped-kip.yaml): a figure that starts lying on its back."""

from __future__ import annotations

import math

from puppet.data.catalog import load_setup
from puppet.session import Session


def test_start_angle_lays_the_figure_on_its_back_on_the_ground():
    """start_angle: 90 turns the root counter-clockwise (a figure facing +x on its back),
    and the figure is put on the ground, not through it (the root is turned before it
    is placed: pymunk turns a body about its centre of gravity)."""
    session = Session(load_setup("biped-kip", None))
    c = session.sim.character
    assert math.degrees(c.bodies["pelvis"].angle) == 90.0
    assert abs(c.lowest_point() - 0.002) < 1e-9
    chest, pelvis = c.bodies["chest"].position, c.bodies["pelvis"].local_to_world((0, 0))
    assert c.bodies["head"].local_to_world(c.bodies["head"].center_of_gravity).x < pelvis.x
    assert abs(chest.y - pelvis.y) < 1e-9


# -- the log ------------------------------------------------------------------------------
from puppet.testing import replay_log  # noqa: E402
from tests.test_floor import LOGS, _variant  # noqa: E402


def test_kip_log_starts_on_its_back_flies_lands_on_its_feet_and_stands():
    result = replay_log(LOGS / "biped-kip.jsonl")
    assert not result.failed, [str(o) for o in result.failed]
    kinds = {o.expectation.split()[0].rstrip(":") for o in result.outcomes}
    assert {"angle_within", "flight_phases", "first_touch", "took_off", "turned",
            "bent_after_flight", "got_up", "tilt_at_end", "height_at_end",
            "touching_at_end"} <= kinds


def _hips(torque):
    def edit(iface):
        for j in ("hip_near", "hip_far"):
            iface["gains"][j] = {"max_torque": torque}
    return edit


def test_kip_fails_with_the_characters_own_hips(tmp_path):
    """At the character's 250 N*m the kick still lands on the feet, but the body does not
    come up over them: it falls back."""
    failed = _variant("biped-kip", tmp_path, _hips(250))
    assert {"got_up", "height_at_end"} <= failed, failed


def test_kip_fails_on_a_slippery_floor(tmp_path):
    failed = _variant("biped-kip", tmp_path, friction=0.3)
    assert {"tilt_at_end", "height_at_end"} & failed, failed


def test_kip_fails_without_the_snap(tmp_path):
    """The sequence with its snap pose taken out: the rock alone does not kip."""
    def no_snap(iface):
        iface["sequences"]["kip"] = [s for s in iface["sequences"]["kip"]
                                     if s["pose"] != "snap"]
    failed = _variant("biped-kip", tmp_path, no_snap)
    assert {"first_touch", "took_off", "turned"} <= failed, failed


def test_kip_fails_without_the_push_from_the_hands(tmp_path):
    """The snap's arms held as in the rock (no push off the floor): it lands on its feet
    and falls back."""
    def no_push(iface):
        for j in ("shoulder_near", "shoulder_far", "elbow_near", "elbow_far"):
            iface["poses"]["snap"]["joints"][j] = iface["poses"]["rock"]["joints"][j]
    failed = _variant("biped-kip", tmp_path, no_push)
    assert {"got_up", "height_at_end"} <= failed, failed


def test_kip_fails_without_its_key(tmp_path):
    def no_key(iface):
        for k in iface["keys"]:  # the kip on a key the log never presses
            if k.get("key") == "k":
                k["key"] = "j"
    failed = _variant("biped-kip", tmp_path, no_key)
    assert {"got_up", "height_at_end", "flight_phases"} <= failed, failed


def test_kip_does_not_stand_where_it_lay_without_the_kipping_maps(tmp_path):
    """The ankle maps of the state kipping gone (in the air they barely turn the locked
    ankles, but their torque sets the feet's angle as they meet the floor): it still
    lands on its feet first and gets up, but it does not stay where it lay (it ends
    more than a metre ahead)."""
    def no_maps(iface):
        iface["states"]["kipping"]["maps"] = []
    failed = _variant("biped-kip", tmp_path, no_maps)
    assert "first_touch" not in failed and "x_at_end" in failed, failed


def test_kip_stands_when_k_comes_at_other_moments():
    """Not only at the log's press time: k at 1.7 s and at 2.6 s, once the figure lies
    still, kips and stands too, judged by the log's own expectations (control_rate 480:
    the press's step no longer shifts the poses' changes against a 60 Hz control tick)."""
    import yaml

    from puppet.data.catalog import ROOT
    from puppet.testing import replay_script_text
    script = yaml.safe_load((ROOT / "assets" / "scripts" / "biped-kip.yaml").read_text())
    for at in (1.7, 2.6):
        script["events"][-1]["t"] = at
        result = replay_script_text(yaml.safe_dump(script), "biped-kip",
                                    LOGS / "biped-kip.expect.yaml")
        assert not result.failed, (at, [str(o) for o in result.failed])


def test_kip_stands_on_cheaper_physics():
    """Not a knife edge (issue 28): the log's expectations hold replayed on 36 solver
    passes and on a 1/240 s step. Before the stand was taken from sensors the 1/240 s
    step fell back: the standing pose snapped the knees straight, the feet left the
    floor and came down ahead of the weight (guide 17.5)."""
    from puppet.timeline.other_physics import OtherPhysics
    from puppet.timeline.replay import replay

    for physics in (OtherPhysics(iterations=36), OtherPhysics(dt=1 / 240)):
        result = replay(LOGS / "biped-kip.jsonl", physics=physics)
        assert not result.failed, (physics.label(), [str(o) for o in result.failed])


def test_kip_stands_up_through_its_states():
    """touch-down -> landed -> rising -> standing, each entered by the state machine
    (not the sequence's clock), and the log ends standing."""
    result = replay_log(LOGS / "biped-kip.jsonl")
    states = [s for i, s in enumerate(result.trajectory.state)
              if i == 0 or s != result.trajectory.state[i - 1]]
    assert states == ["lying", "kipping", "landed", "rising", "standing"], states


def test_kip_without_the_travelling_rise_falls_back_on_a_coarser_step(tmp_path):
    """The rise as a plain pose (its targets jump, no over:): the knees snap straight,
    and on a 1/240 s step the body tips back - what the travelling rise fixed."""
    from puppet.timeline.other_physics import OtherPhysics
    from puppet.timeline.replay import replay

    def snap(iface):
        del iface["states"]["rising"]["enter"]["over"]
    _variant("biped-kip", tmp_path, snap)  # writes the variant's log into tmp_path
    result = replay(tmp_path / "biped-kip.jsonl", physics=OtherPhysics(dt=1 / 240))
    failed = {o.expectation.split()[0].rstrip(":") for o in result.failed}
    assert {"got_up", "height_at_end"} & failed, failed
