"""The expectation mostly_within: a link's posture (tilt, x, below another link) held
at a share of a window's samples - passes at the share, fails under it, names the
bound that failed, and refuses an entry without bounds."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from puppet.data.errors import DataError
from puppet.timeline.expectations import evaluate, parse_expectations

LINKS = ["pelvis", "chest", "foot"]


def _traj(chest_deg, pelvis_x, foot_y, pelvis_y=1.0):
    n = len(chest_deg)
    angle = np.zeros((n, 3))
    angle[:, 1] = np.radians(chest_deg)
    x = np.zeros((n, 3))
    x[:, 0] = pelvis_x
    y = np.full((n, 3), pelvis_y)
    y[:, 2] = foot_y
    return SimpleNamespace(t=np.arange(n) * 0.1, angle=angle, x=x, y=y, links=LINKS,
                           index=LINKS.index)


def _check(item, traj):
    e, = parse_expectations([{"mostly_within": item}]).items
    return evaluate(e, traj, "")


def test_the_tilt_held_at_the_share_passes_and_under_it_fails():
    traj = _traj([5, 10, 30, -40, 0, 24, -24, 0, 3, 50], 0.0, 0.0)  # 7 of 10 within 25
    assert _check({"link": "chest", "max_tilt": 25, "min_fraction": 0.7}, traj).passed
    got = _check({"link": "chest", "max_tilt": 25, "min_fraction": 0.8}, traj)
    assert not got.passed and "70.0% of 10 samples" in got.measured


def test_x_bounds_and_below_count_together_and_the_window_limits_the_samples():
    x = np.array([0.2, 0.2, -0.3, -0.3, 0.2, 0.2])
    foot = np.array([0.5, 1.2, 0.5, 0.5, 0.5, 0.5])  # above the pelvis at sample 1
    traj = _traj([0] * 6, x, foot)
    got = _check({"link": "pelvis", "x_min": 0.1, "x_max": 0.8, "min_fraction": 0.6}, traj)
    assert got.passed  # 4 of 6
    assert not _check({"link": "pelvis", "x_min": 0.1, "min_fraction": 0.7}, traj).passed
    both = {"link": "foot", "below": "pelvis", "min_fraction": 0.8}
    assert _check(both, traj).passed  # 5 of 6
    assert not _check({**both, "min_fraction": 0.9}, traj).passed
    assert _check({**both, "min_fraction": 1.0, "from": 0.2}, traj).passed
    assert _check({"link": "pelvis", "x_min": 0.1, "min_fraction": 1.0, "from": 0.4},
                  traj).passed


def test_an_entry_without_bounds_or_with_an_unknown_link_is_a_data_error():
    with pytest.raises(DataError, match="max_tilt"):
        parse_expectations([{"mostly_within": {"link": "chest", "min_fraction": 0.5}}])
    with pytest.raises(DataError, match="x_max"):
        parse_expectations([{"mostly_within": {"link": "chest", "x_min": 1, "x_max": 0,
                                               "min_fraction": 0.5}}])
    with pytest.raises(DataError, match="unknown link 'hips'"):
        _check({"link": "foot", "below": "hips", "min_fraction": 0.5}, _traj([0], 0, 0))


def test_a_tilt_under_0_or_a_window_ending_before_it_starts_is_a_data_error():
    with pytest.raises(DataError, match="must be at least 0"):
        parse_expectations([{"mostly_within": {"link": "chest", "max_tilt": -5,
                                               "min_fraction": 0.5}}])
    with pytest.raises(DataError, match="'until' must be later than 'from'"):
        parse_expectations([{"mostly_within": {"link": "chest", "max_tilt": 20,
                                               "min_fraction": 0.5, "from": 3, "until": 2}}])
