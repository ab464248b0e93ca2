"""The run's expectations: ``mean_speed`` (the centre of mass's mean forward speed over a
window) and ``flight_phases`` (how many stretches with the feet off the ground, each long
enough, begin in a window), on made-up trajectories whose answers are known."""

from types import SimpleNamespace

import numpy as np
import pytest

from puppet.data.errors import DataError
from puppet.timeline.expectations import evaluate_all, parse_expectations

LINKS = ["pelvis", "foot_near", "foot_far"]


def _traj(t, x, near, far):
    t = np.asarray(t, dtype=float)
    contact = np.column_stack([np.zeros(len(t), bool), near, far])
    return SimpleNamespace(t=t, com=np.column_stack([x, np.ones(len(t))]), contact=contact,
                           links=LINKS, index=LINKS.index)


def _check(traj, expect):
    items = parse_expectations(expect)
    items.check_links(traj.links)
    return [str(o) for o in evaluate_all(items.items, traj, "")]


def test_mean_speed_is_distance_over_time_in_the_span():
    t = np.arange(0, 10.01, 0.5)
    x = np.where(t < 5, 0.5 * t, 2.5 + 3.0 * (t - 5))  # 0.5 m/s, then 3 m/s
    traj = _traj(t, x, np.ones(len(t), bool), np.ones(len(t), bool))
    assert _check(traj, [{"mean_speed": {"until": 5, "max": 1.0}},
                         {"mean_speed": {"from": 5, "min": 2.5}},
                         {"mean_speed": {"from": 5, "max": 2.5}},
                         {"mean_speed": {"min": 1.8}},
                         {"mean_speed": {"from": 20, "min": 0}}]) == [
        "ok   mean_speed max 1.0 m/s from 0 s to 5 s: 0.500 m/s (x 0.00 to 2.50 m, "
        "t = 0.00 to 5.00 s)",
        "ok   mean_speed min 2.5 m/s from 5 s to the end: 3.000 m/s (x 2.50 to 17.50 m, "
        "t = 5.00 to 10.00 s)",
        "FAIL mean_speed max 2.5 m/s from 5 s to the end: 3.000 m/s (x 2.50 to 17.50 m, "
        "t = 5.00 to 10.00 s)",
        "FAIL mean_speed min 1.8 m/s from 0 s to the end: 1.750 m/s (x 0.00 to 17.50 m, "
        "t = 0.00 to 10.00 s)",
        "FAIL mean_speed min 0.0 m/s from 20 s to the end: fewer than two samples in the "
        "window (the run is 10.00 s)",
    ]


def test_flight_phases_counts_long_enough_flights_that_begin_in_the_span():
    t = np.round(np.arange(0, 2.0, 0.01), 2)
    near = np.ones(len(t), bool)
    far = np.ones(len(t), bool)
    # flights: 0.20-0.25 (0.05 s), 0.50-0.51 (a one-sample bounce), 1.00-1.08, 1.50-1.56
    for a, b in ((0.20, 0.25), (0.50, 0.51), (1.00, 1.08), (1.50, 1.56)):
        off = (t >= a - 1e-9) & (t < b - 1e-9)
        near[off] = far[off] = False
    far[(t >= 0.7) & (t < 0.9)] = False  # one foot up only: not a flight
    traj = _traj(t, t, near, far)
    feet = ["foot_near", "foot_far"]
    assert _check(traj, [
        {"flight_phases": {"min_count": 3, "min_seconds": 0.04, "links": feet}},
        {"flight_phases": {"min_count": 4, "min_seconds": 0.04, "links": feet}},
        {"flight_phases": {"from": 0.9, "min_count": 2, "min_seconds": 0.05, "links": feet}},
        {"flight_phases": {"from": 0.9, "until": 1.2, "min_count": 2, "min_seconds": 0.05,
                           "links": feet}},
        {"flight_phases": {"min_count": 1, "min_seconds": 0.07}},
    ]) == [
        "ok   flight_phases at least 3 of 0.04 s or more (none of foot_near, foot_far "
        "touching) from 0 s to the end: 3 flights of 0.04 s or more (4 in all, the longest "
        "0.080 s)",
        "FAIL flight_phases at least 4 of 0.04 s or more (none of foot_near, foot_far "
        "touching) from 0 s to the end: 3 flights of 0.04 s or more (4 in all, the longest "
        "0.080 s)",
        "ok   flight_phases at least 2 of 0.05 s or more (none of foot_near, foot_far "
        "touching) from 0.9 s to the end: 2 flights of 0.05 s or more (2 in all, the "
        "longest 0.080 s)",
        "FAIL flight_phases at least 2 of 0.05 s or more (none of foot_near, foot_far "
        "touching) from 0.9 s to 1.2 s: 1 flights of 0.05 s or more (1 in all, the longest "
        "0.080 s)",
        "ok   flight_phases at least 1 of 0.07 s or more (no link touching) from 0 s to "
        "the end: 1 flights of 0.07 s or more (4 in all, the longest 0.080 s)",
    ]


def test_flight_phases_names_an_unknown_link():
    traj = _traj([0, 1], [0, 1], [True, True], [True, True])
    with pytest.raises(DataError, match="unknown link 'toe'"):
        _check(traj, [{"flight_phases": {"min_count": 1, "min_seconds": 0.1,
                                         "links": ["foot_near", "toe"]}}])


def test_mean_speed_and_flight_phases_refuse_bad_entries():
    with pytest.raises(DataError, match="give 'min', 'max' or both"):
        parse_expectations([{"mean_speed": {"from": 1}}])
    with pytest.raises(DataError, match="'until' must be later than 'from'"):
        parse_expectations([{"mean_speed": {"from": 5, "until": 5, "min": 1}}])
    with pytest.raises(DataError, match="min_count"):
        parse_expectations([{"flight_phases": {"min_seconds": 0.1}}])
