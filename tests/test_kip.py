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
        iface["keys"] = [k for k in iface["keys"] if k.get("key") != "k"]
        del iface["states"]["rising"]  # nothing leads there any more
    failed = _variant("biped-kip", tmp_path, no_key)
    assert {"got_up", "height_at_end", "flight_phases"} <= failed, failed


def test_kip_falls_back_after_the_landing_without_the_rising_maps(tmp_path):
    """The ankle maps of the state rising gone: it still lands on its feet first, then
    falls back."""
    def no_maps(iface):
        iface["states"]["rising"]["maps"] = []
    failed = _variant("biped-kip", tmp_path, no_maps)
    assert "first_touch" not in failed and {"got_up", "height_at_end"} <= failed, failed


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
