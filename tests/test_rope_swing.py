"""The gymnast's swing on the rope (assets/logs/biped-rope-swing): the pumping builds
the swing, the hands stay on; without the mouse or the grasps it fails."""

from __future__ import annotations

from puppet.data.catalog import ROOT
from puppet.testing import replay_log
from tests.test_floor import _variant

LOG = ROOT / "assets" / "logs" / "biped-rope-swing.jsonl"


def test_rope_swing_log_builds_a_swing_hands_on():
    result = replay_log(LOG)
    assert not result.failed, [str(o) for o in result.failed]
    assert [o.expectation.split()[0] for o in result.outcomes][:3] == ["held", "swung",
                                                                       "swung"]


def test_rope_swing_fails_when_the_mouse_does_nothing(tmp_path):
    """The swing mode's maps gone: the figure hangs still under the pivot."""
    def no_mouse(spec):
        spec["modes"]["swing"] = []

    assert _variant("biped-rope-swing", tmp_path, no_mouse) == {"swung"}


def test_rope_swing_fails_without_a_grasp(tmp_path):
    """The hands never close: the figure drops to the floor."""
    def no_grasp(spec):
        for hand in ("near_hand", "far_hand"):
            spec["machines"][hand]["states"]["holding"]["enter"] = {"release": "all"}

    assert "held" in _variant("biped-rope-swing", tmp_path, no_grasp)
