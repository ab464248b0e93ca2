"""The expectation ``bent_after_flight``: how far links are turned from another (thighs
from the chest: the hips and waist folded) at some sample within a time after the
longest flight ended, on made-up trajectories whose answers are known."""

from types import SimpleNamespace

import numpy as np
import pytest

from puppet.data.errors import DataError
from puppet.timeline.expectations import evaluate_all, parse_expectations

LINKS = ["chest", "thigh_near", "thigh_far"]
OPEN = [{"bent_after_flight": {"links": ["thigh_near", "thigh_far"], "from_link": "chest",
                               "max": 100, "within": 0.1}}]


def _traj(t, chest, thigh, down):
    """Samples at ``t``; angles in deg; ``down``: the samples touching the ground."""
    t = np.asarray(t, dtype=float)
    a = np.radians(np.column_stack([chest, thigh, thigh]).astype(float))
    contact = np.zeros((len(t), len(LINKS)), dtype=bool)
    contact[np.asarray(down), 1] = True
    return SimpleNamespace(t=t, angle=a, contact=contact, links=LINKS, index=LINKS.index)


def _check(traj, expect):
    items = parse_expectations(expect)
    items.check_links(traj.links)
    return [str(o) for o in evaluate_all(items.items, traj, "")]


T = np.round(np.arange(0, 1.001, 0.05), 2)  # 21 samples; in the air from 0.2 to 0.45 s
DOWN = [0, 1, 2, 3] + list(range(10, 21))


def test_a_landing_with_the_trunk_up_passes_and_a_folded_one_fails():
    thigh = np.full(len(T), 60.0)
    # up: the chest upright (0) at the landing (0.5 s): thighs 60 deg from it
    up = _traj(T, np.zeros(len(T)), thigh, DOWN)
    # folded: the chest pitched 90 deg forward at the landing, upright only at 0.7 s
    chest = np.interp(T, [0, 0.5, 0.7, 1], [0, -90, 0, 0])
    folded = _traj(T, chest, thigh, DOWN)
    assert _check(up, OPEN) == [
        "ok   bent_after_flight thigh_near, thigh_far from chest at most 100 deg within "
        "0.1 s of the landing: the flight ended at t = 0.50 s; from chest: thigh_near "
        "60..60, thigh_far 60..60 deg to t = 0.60 s; in range at t = 0.50 s"]
    assert _check(folded, OPEN) == [
        "FAIL bent_after_flight thigh_near, thigh_far from chest at most 100 deg within "
        "0.1 s of the landing: the flight ended at t = 0.50 s; from chest: thigh_near "
        "105..150, thigh_far 105..150 deg to t = 0.60 s"]
    # given 0.2 s it is open in time (at 0.65 s: chest -22.5, thighs 82.5 deg from it)
    later = [{"bent_after_flight": {**OPEN[0]["bent_after_flight"], "within": 0.2}}]
    assert _check(folded, later)[0].endswith("in range at t = 0.65 s")
    assert _check(folded, later)[0].startswith("ok")


def test_it_fails_without_a_flight_or_one_that_has_not_ended():
    thigh = np.zeros(len(T))
    assert _check(_traj(T, thigh, thigh, range(21)), OPEN)[0].endswith("never in the air")
    assert "had not ended" in _check(_traj(T, thigh, thigh, [0, 1]), OPEN)[0]


def test_the_angle_is_taken_in_a_half_turn_either_way():
    """Chest at 170, thighs at -170: 20 deg apart, not -340."""
    traj = _traj(T, np.full(len(T), 170.0), np.full(len(T), -170.0), DOWN)
    out = _check(traj, [{"bent_after_flight": {"links": ["thigh_near"], "from_link": "chest",
                                               "min": 10, "max": 30, "within": 0.1}}])
    assert out[0].startswith("ok") and "thigh_near 20..20 deg" in out[0]


def test_bent_after_flight_needs_a_bound_and_known_links():
    base = {"links": ["thigh_near"], "from_link": "chest", "within": 0.1}
    with pytest.raises(DataError, match="give 'min' and/or 'max'"):
        parse_expectations([{"bent_after_flight": base}])
    with pytest.raises(DataError, match="must be greater than 'min'"):
        parse_expectations([{"bent_after_flight": {**base, "min": 10, "max": 0}}])
    with pytest.raises(DataError, match="unknown link 'tail'"):
        parse_expectations([{"bent_after_flight": {**base, "links": ["tail"], "max": 9}}]
                           ).check_links(LINKS)
    thigh = np.zeros(len(T))
    with pytest.raises(DataError, match="unknown link 'tail'"):
        _check(_traj(T, thigh, thigh, DOWN),
               [{"bent_after_flight": {**base, "from_link": "tail", "max": 9}}])
