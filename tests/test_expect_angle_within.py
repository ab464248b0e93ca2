"""The expectation ``angle_within``: a link's signed angle from upright kept within
bounds over a window (on its back at the start; never on its front), on made-up
trajectories whose answers are known."""

from types import SimpleNamespace

import numpy as np
import pytest

from puppet.data.errors import DataError
from puppet.timeline.expectations import evaluate_all, parse_expectations

LINKS = ["pelvis", "chest"]


def _traj(t, pelvis_deg):
    t = np.asarray(t, dtype=float)
    a = np.radians(np.asarray(pelvis_deg, dtype=float))
    return SimpleNamespace(t=t, angle=np.column_stack([a, np.zeros(len(t))]),
                           links=LINKS, index=LINKS.index)


def _check(traj, expect):
    items = parse_expectations(expect)
    items.check_links(traj.links)
    return [str(o) for o in evaluate_all(items.items, traj, "")]


def test_angle_within_checks_the_signed_angle_in_the_window():
    t = np.round(np.arange(0, 3.001, 0.1), 1)
    # on the back (90 deg) until 1 s, then up to standing (0) by 2 s, then 30 deg forward;
    # the last sample one turn on (the angle is taken modulo full turns)
    deg = np.interp(t, [0, 1, 2, 2.5, 3], [90, 90, 0, -30, -30])
    deg[-1] -= 360
    traj = _traj(t, deg)
    assert _check(traj, [{"angle_within": {"link": "pelvis", "min": 70, "until": 0.5}},
                         {"angle_within": {"link": "pelvis", "min": 70, "until": 1.5}},
                         {"angle_within": {"link": "pelvis", "min": -40}},
                         {"angle_within": {"link": "pelvis", "min": -20, "max": 100}},
                         {"angle_within": {"link": "pelvis", "max": 10, "from": 2.0}},
                         {"angle_within": {"link": "pelvis", "min": 0, "from": 5}}]) == [
        "ok   angle_within pelvis at least 70 deg (signed) from 0 s to 0.5 s: pelvis "
        "90..90 deg from t = 0.00 to 0.50 s",
        "FAIL angle_within pelvis at least 70 deg (signed) from 0 s to 1.5 s: pelvis "
        "45..90 deg from t = 0.00 to 1.50 s; out at t = 1.30 s (63 deg)",
        "ok   angle_within pelvis at least -40 deg (signed) from 0 s to the end: pelvis "
        "-30..90 deg from t = 0.00 to 3.00 s",
        "FAIL angle_within pelvis at least -20 and at most 100 deg (signed) from 0 s to "
        "the end: pelvis -30..90 deg from t = 0.00 to 3.00 s; out at t = 2.40 s (-24 deg)",
        "ok   angle_within pelvis at most 10 deg (signed) from 2 s to the end: pelvis "
        "-30..0 deg from t = 2.00 to 3.00 s",
        "FAIL angle_within pelvis at least 0 deg (signed) from 5 s to the end: no samples "
        "in the window (the run is 3.00 s)",
    ]


def test_a_max_over_180_takes_the_angle_across_upside_down():
    """Rocked back past upside down (190 deg: -170 signed) is not on the front (-90)."""
    t = np.round(np.arange(0, 2.001, 0.5), 1)
    traj = _traj(t, [90, 150, 190, 60, 0])
    front = _traj(t, [90, 150, 60, -90, 0])
    never_front = [{"angle_within": {"link": "pelvis", "min": -70, "max": 200}}]
    assert _check(traj, never_front) == [
        "ok   angle_within pelvis at least -70 and at most 200 deg (signed) from 0 s to the "
        "end: pelvis 0..190 deg from t = 0.00 to 2.00 s"]
    assert _check(front, never_front) == [
        "FAIL angle_within pelvis at least -70 and at most 200 deg (signed) from 0 s to the "
        "end: pelvis -90..150 deg from t = 0.00 to 2.00 s; out at t = 1.50 s (-90 deg)"]
    assert _check(traj, [{"angle_within": {"link": "pelvis", "min": -70}}])[0].startswith(
        "FAIL angle_within pelvis at least -70 deg (signed) from 0 s to the end: pelvis "
        "-170..150 deg")


def test_angle_within_needs_a_bound_and_a_known_link():
    with pytest.raises(DataError, match="give 'min' and/or 'max'"):
        parse_expectations([{"angle_within": {"link": "pelvis"}}])
    with pytest.raises(DataError, match="must be greater than 'min'"):
        parse_expectations([{"angle_within": {"link": "pelvis", "min": 10, "max": 0}}])
    with pytest.raises(DataError, match="unknown link 'tail'"):
        parse_expectations([{"angle_within": {"link": "tail", "min": 0}}]).check_links(LINKS)


def test_swung_needs_the_angle_about_the_point_to_reach_both_sides():
    """A pendulum 3 m under (0, 4.4) swinging 10 deg, then 25 deg."""
    t = np.round(np.arange(0, 4.001, 0.05), 2)
    amp = np.where(t < 2, 10.0, 25.0)
    theta = np.radians(amp * np.sin(2 * np.pi * t))
    com = np.column_stack([3 * np.sin(theta), 4.4 - 3 * np.cos(theta)])
    traj = SimpleNamespace(t=t, com=com, links=LINKS, index=LINKS.index)
    got = _check(traj, [{"swung": {"about": [0, 4.4], "min": 20, "from": 2}},
                        {"swung": {"about": [0, 4.4], "min": 20, "until": 1.95}},
                        {"swung": {"about": [0, 4.4], "min": 5, "until": 1.95}},
                        {"swung": {"about": [1, 4.4], "min": 20, "from": 2}}])
    assert got[0] == ("ok   swung min 20 deg each way about [0, 4.4] from 2 s to the end: "
                      "-25.0..25.0 deg from t = 2.00 to 4.00 s")
    assert got[1].startswith("FAIL") and "-10.0..10.0 deg" in got[1]
    assert got[2].startswith("ok")
    assert got[3].startswith("FAIL")  # about a point off to the side: one way only


@pytest.mark.parametrize("bounds", [{"max": 200}, {"min": -180}, {"min": -170, "max": 200},
                                    {"max": 180}])
def test_a_range_that_holds_every_angle_is_refused(bounds):
    with pytest.raises(DataError, match="holds every angle"):
        parse_expectations([{"angle_within": {"link": "pelvis", **bounds}}])


def test_the_kips_range_across_upside_down_is_taken():
    parse_expectations([{"angle_within": {"link": "pelvis", "min": -70, "max": 200}}])


def test_mean_angle_averages_the_signed_angle_over_the_window():
    """A trunk that swings -25..-5 deg about -15 leans 15 deg forward on average, though
    no bound holds at every sample; the angle is taken -180..180 (one turn on is the
    same)."""
    t = np.round(np.arange(0, 4.001, 0.05), 2)
    deg = -15 + 10 * np.sin(2 * np.pi * 2 * t)
    deg[t < 1] = 0.0
    deg[-1] -= 360
    traj = _traj(t, deg)
    out = _check(traj, [{"mean_angle": {"link": "pelvis", "min": -20, "max": -10, "from": 1}},
                        {"mean_angle": {"link": "pelvis", "max": -12}},
                        {"mean_angle": {"link": "pelvis", "min": 0, "from": 9}}])
    assert out[0].startswith("ok   mean_angle pelvis at least -20 and at most -10 deg (signed) "
                             "from 1 s to the end: pelvis -15.0 deg on average (-25..-5)")
    assert out[1].startswith("FAIL mean_angle pelvis at most -12 deg (signed) from 0 s to "
                             "the end: pelvis -11.")
    assert out[2].startswith("FAIL mean_angle pelvis at least 0 deg (signed) from 9 s")
    items = parse_expectations([{"mean_angle": {"link": "pelvis", "min": -20, "from": 1}}])
    (o,) = evaluate_all(items.items, traj, "")
    assert o.unit == "deg" and o.margin == pytest.approx(5.0, abs=0.05)


@pytest.mark.parametrize("entry, words", [
    ({"link": "pelvis"}, "give 'min' and/or 'max'"),
    ({"link": "pelvis", "min": -5, "max": -10}, "must be greater"),
    ({"link": "pelvis", "min": -5, "from": 3, "until": 2}, "later than 'from'"),
])
def test_mean_angle_refuses_bounds_that_check_nothing(entry, words):
    with pytest.raises(DataError, match=words):
        parse_expectations([{"mean_angle": entry}])
