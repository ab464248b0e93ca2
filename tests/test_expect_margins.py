"""Every Outcome carries a numeric margin - how far inside (+) or outside (-) its bound,
in its kind's unit - so tools score by it and never parse the text (issue 25). The
margins of failures, measured on the hop log and on small hand-made runs, are the
quantities the text says, and their sign is the verdict."""

from __future__ import annotations

import math
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from puppet.testing import replay_log
from puppet.timeline.expectations import KINDS, evaluate_all, parse_expectations
from puppet.timeline.expectations.measure import longest_run, tilt_deg

HOP = Path(__file__).resolve().parents[1] / "assets" / "logs" / "luxo-hop.jsonl"


@pytest.fixture(scope="module")
def hop():
    return replay_log(HOP).trajectory


def _one(traj, entry):
    outcome, = evaluate_all(parse_expectations([entry]).items, traj, "abc")
    # the verdict is the margin's sign (to a rounding), in the kind's unit
    assert outcome.passed == (outcome.margin >= -1e-6), str(outcome)
    assert outcome.kind in KINDS
    return outcome


def test_the_hops_failures_are_as_far_outside_as_measured(hop):
    base = hop.index("base")
    x = hop.x[-1, base]
    far = _one(hop, {"x_at_end": {"link": "base", "min": 5.0}})
    assert (far.passed, far.unit) == (False, "m") and far.margin == pytest.approx(x - 5.0)
    assert f"x = {x:.3f} m" in far.measured  # the same number, said
    band = _one(hop, {"x_at_end": {"link": "base", "min": 0.5, "max": float(x) - 0.01}})
    assert band.margin == pytest.approx(-0.01)  # the nearer bound's
    rise = hop.lowest[:, base] - hop.lowest[0, base]
    assert _one(hop, {"reached_height": {"link": "base", "min": 1.0}}).margin == \
        pytest.approx(rise.max() - 1.0)
    longest = longest_run(~hop.contact[:, base], hop.t)[0]
    short = _one(hop, {"airborne": {"link": "base", "max_seconds": 0.05}})
    assert (short.unit, short.margin) == ("s", pytest.approx(0.05 - longest))
    level = _one(hop, {"tilt_never_above": {"links": ["base"], "max": 1}})
    assert level.unit == "deg" and level.margin == pytest.approx(1 - tilt_deg(
        hop.angle[:, base]).max())
    upside = _one(hop, {"upright_at_end": False})
    assert upside.margin == pytest.approx(tilt_deg(hop.root_angle[-1:])[0] - 45)
    count = _one(hop, {"flight_phases": {"min_count": 5, "min_seconds": 0.05}})
    assert count.unit == "flights" and count.margin < 0 and count.margin == int(count.margin)


def test_failures_with_nothing_to_measure_are_minus_infinity(hop):
    never = _one(hop, {"stood_on": {"link": "upper_arm", "min_seconds": 1.0}})
    assert never.margin == -1.0  # no stretch at all: the whole second short
    wrong = _one(hop, {"took_off": {"links": ["upper_arm"]}})  # the base took off
    assert wrong.margin == -math.inf
    late = _one(hop, {"mean_speed": {"from": 60.0, "min": 0.1}})
    assert late.margin == -math.inf and "fewer than two samples" in late.measured
    hashed = _one(hop, {"final_hash": "abd"})
    assert (hashed.passed, hashed.margin) == (False, -math.inf)
    assert _one(hop, {"final_hash": "abc"}).margin == 0.0


def _states(states, held=None):
    n = len(states)
    return SimpleNamespace(t=np.arange(n) * 0.5, state=np.array(states, dtype=object),
                           state_names=["a", "b"], held=held)


def test_states_and_holds_are_measured_in_seconds_out():
    run = _states(["a", "a", "b", "b", "b", "a"])  # 0.5 s a sample
    out = _one(run, {"stayed_in_state": "a"})
    assert (out.unit, out.margin) == ("s", -1.5)  # three samples in 'b'
    assert _one(run, {"stayed_in_state": {"state": "a", "until": 0.5}}).margin == 0.0
    assert _one(run, {"in_state_at_end": "a"}).margin == 0.5   # a for its last sample
    assert _one(run, {"in_state_at_end": "b"}).margin == -0.5
    rows = [(("hand", "bar", "p1", 0.0, 0.0),), (), (), (("hand", "bar", "p2", 0.0, 0.0),)]
    grip = _states(["a"] * 4, held=rows)
    assert _one(grip, {"always_holding": {"chains": ["hand"]}}).margin == -1.0
    assert _one(grip, {"held_point": {"prop": "bar", "point": "p2"}}).margin == 0.5
    assert _one(grip, {"held_point": {"prop": "bar", "point": "p3"}}).margin == -math.inf
