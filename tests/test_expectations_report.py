"""What each expectation measures and says of itself: the numbers in its line (where,
how far, how long, which link), its edge cases (a bound met exactly, a window's ends,
a turn made on the ground), and where its entries are read from (a sidecar's name,
entries given in code)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest


class _Samples:
    """A trajectory as evaluate() reads it, for one link: angle and contact per sample."""

    def __init__(self, degrees, contact):
        import numpy as np

        self.t = np.arange(len(degrees)) * 0.1
        self.angle = np.radians(np.asarray(degrees, dtype=float))[:, None]
        self.contact = np.asarray(contact, dtype=bool)[:, None]

    def index(self, link):
        assert link == "base"
        return 0


class _Flip:
    """A trajectory as evaluate() reads it: upright on the ground, upside down in the air."""

    def __init__(self):
        import numpy as np

        degrees = [0, 0, 0, 90, 180, 270, 360, 360, 360]
        self.contact = np.array([[c] for c in (1, 1, 1, 0, 0, 0, 0, 1, 1)], dtype=bool)
        self.t = np.arange(len(degrees)) * 0.1
        self.root_angle = np.radians(degrees)


class _States:
    """A trajectory as _stayed reads it: a state per sample, every 0.1 s."""

    def __init__(self, states):
        import numpy as np

        self.t = np.arange(len(states)) * 0.1
        self.state = np.array(states, dtype=object)
        self.state_names = dict.fromkeys(states)


class _Run:
    """A trajectory of two links (base, head) every 0.1 s, as evaluate() reads it."""

    links = ["base", "head"]

    def __init__(self, degrees, base_contact, head_contact, x=None, y=None):
        import numpy as np

        n = len(degrees)
        self.t = np.arange(n) * 0.1
        self.root_angle = np.radians(np.asarray(degrees, dtype=float))
        self.contact = np.array(list(zip(base_contact, head_contact)), dtype=bool)
        self.x = np.array(x if x is not None else [[0.1 * i, 0.1 * i] for i in range(n)],
                          dtype=float)
        self.y = np.array(y if y is not None else [[0.0, 0.3]] * n, dtype=float)
        self.com = np.stack([self.x[:, 0], self.y[:, 0]], axis=1)

    def index(self, link):
        return self.links.index(link)


def _outcome(item, traj):
    from puppet.timeline.expectations import evaluate, parse_expectations

    e, = parse_expectations([item]).items
    return evaluate(e, traj, "")


HEADSTAND = _Run([0, 90, 180, 180, 180, 90, 0], [1, 0, 0, 0, 0, 0, 1], [0, 0, 1, 1, 1, 0, 0])


def _evaluate(item, traj):
    from puppet.timeline.expectations import evaluate, parse_expectations

    e, = parse_expectations([item]).items
    return evaluate(e, traj, ""), e


@pytest.mark.parametrize("least, passed", [(350, True), (400, False)])
def test_turned_in_flight_counts_only_the_turn_made_in_the_air(least, passed):
    from puppet.timeline.expectations import evaluate, parse_expectations

    # 90 degrees on the ground, then 360 in one flight, then 45 more on the ground
    degrees = [0, 45, 90, 150, 240, 330, 420, 450, 480, 495]
    contact = [True, True, True, False, False, False, False, True, True, True]
    e, = parse_expectations([{"turned": {"link": "base", "min_degrees": least,
                                         "in_flight": True}}]).items
    outcome = evaluate(e, _Samples(degrees, contact), "")
    assert outcome.passed is passed, str(outcome)
    assert "360" in outcome.measured and "t = 0.20 s" in outcome.measured, str(outcome)


def test_a_flip_is_no_fall_and_the_tilt_reported_is_the_one_on_the_ground():
    from puppet.timeline.expectations import evaluate, parse_expectations

    e, = parse_expectations([{"never_fell": True}]).items
    outcome = evaluate(e, _Flip(), "")
    assert outcome.passed, str(outcome)
    assert outcome.measured == "largest tilt on the ground 0 deg at t = 0.00 s"


def test_stayed_in_state_counts_the_samples_at_both_ends_of_its_time_span():
    from puppet.timeline.expectations import evaluate, parse_expectations

    traj = _States(["sit", "sit", "up", "up", "up", "sit"])  # up from 0.2 s to 0.4 s
    for window, passed in (({"from": 0.2, "until": 0.4}, True),
                           ({"from": 0.2, "until": 0.5}, False),  # sits again at 0.5 s
                           ({"from": 0.1, "until": 0.4}, False)):  # still sat at 0.1 s
        e, = parse_expectations([{"stayed_in_state": {"state": "up", **window}}]).items
        outcome = evaluate(e, traj, "")
        assert outcome.passed is passed, (window, str(outcome))
    e, = parse_expectations([{"stayed_in_state": {"state": "up", "from": 0.2,
                                                  "until": 0.5}}]).items
    assert evaluate(e, traj, "").measured == "left 'up' for 'sit' at t = 0.50 s"


def test_a_sidecar_named_after_the_whole_log_file_name_is_read(tmp_path):
    import shutil

    from puppet.timeline.replay import replay

    hop = Path(__file__).resolve().parents[1] / "assets" / "logs" / "luxo-hop.jsonl"
    log = tmp_path / "hop.jsonl"
    shutil.copy(hop, log)
    (tmp_path / "hop.jsonl.expect.yaml").write_text(
        "expect:\n  - x_at_end: {link: base, min: 100.0}\n")
    result = replay(log, until_step=240)
    assert [o.expectation for o in result.failed] == ["x_at_end base min 100.0"], \
        [str(o) for o in result.outcomes]


def test_stood_on_reports_the_longest_stretch_upside_down_on_that_link_alone():
    got = _outcome({"stood_on": {"link": "head", "min_seconds": 0.3}}, HEADSTAND)
    assert got.passed and got.measured == ("longest stretch on head alone, upside down: "
                                           "0.300 s (t = 0.20 to 0.40 s)")
    never = _outcome({"stood_on": {"link": "base", "min_seconds": 0.1}}, HEADSTAND)
    assert not never.passed
    assert never.measured == "longest stretch on base alone, upside down: 0.000 s"


def test_landed_at_reports_where_the_longest_flight_touched_down():
    hop = _Run([0] * 7, [1, 0, 0, 1, 0, 0, 0], [0] * 7)  # the last flight is the longest
    got = _outcome({"landed_at": {"link": "head", "min": 0.5}}, hop)
    assert got.passed and got.measured == ("longest flight 0.30 s from t = 0.40 s, touched "
                                           "down at x = 0.600 m (t = 0.60 s)")
    ground = _Run([0] * 3, [1, 1, 1], [0, 0, 0])
    assert _outcome({"landed_at": {"link": "base", "min": 0.0}}, ground).measured == \
        "never in the air"


def test_x_and_height_at_end_report_what_they_measured():
    run = _Run([0] * 5, [1] * 5, [0] * 5, y=[[0.0, 0.3], [0.0, 0.5], [0.0, 0.4],
                                             [0.0, 0.35], [0.0, 0.31]])
    assert _outcome({"x_at_end": {"link": "head", "min": 0.3}}, run).measured == \
        "x = 0.400 m at t = 0.40 s"
    assert _outcome({"height_at_end": {"link": "head", "min": 0.3}}, run).measured == \
        "y = 0.310 m at t = 0.40 s"
    held = _outcome({"height_at_end": {"link": "head", "max": 0.45, "held": 0.2}}, run)
    assert held.passed and held.measured == "y = 0.310..0.400 m over the last 0.2 s"


def test_got_up_without_ever_lying_says_so():
    got = _outcome({"got_up": {"lay_seconds": 0.1, "within_seconds": 1.0}},
                   _Run([0, 10, 0], [1, 1, 1], [0, 0, 0]))
    assert not got.passed and got.measured == "never lay (root >= 80 deg on the ground)"


def test_an_expectation_given_in_code_names_its_unknown_link():
    from puppet.data.errors import DataError
    from puppet.timeline.expectations import parse_expectations

    with pytest.raises(DataError) as info:
        parse_expectations([{"x_at_end": {"link": "tail", "min": 0}}]).check_links(["base"])
    assert str(info.value) == "expect: unknown link 'tail'; the character has: base"


def test_more_of_what_expectations_report():
    still_lying = _Run([0, 90, 90, 90, 90], [1, 1, 1, 1, 1], [0, 0, 0, 0, 0])
    got = _outcome({"got_up": {"lay_seconds": 0.1, "within_seconds": 1.0}}, still_lying)
    assert not got.passed and got.measured == ("lay 0.40 s until t = 0.40 s, not standing "
                                               "at the end (90 deg)")
    assert got.expectation.startswith("got_up")  # the failing line names what was expected
    hop = _Run([0] * 7, [1, 0, 0, 1, 0, 0, 0], [0] * 7)  # flights of 0.2 s and 0.3 s
    for most, passed in ((0.3, True), (0.29, False)):
        got = _outcome({"airborne": {"link": "base", "max_seconds": most}}, hop)
        assert got.passed is passed, (most, str(got))
    assert got.measured == "longest time out of contact 0.300 s (from t = 0.40 s)"
    both = _Run([180] * 4, [1, 1, 0, 0], [1, 1, 1, 1])  # upside down; base down at first
    got = _outcome({"stood_on": {"link": "head", "min_seconds": 0.1}}, both)
    assert got.measured == ("longest stretch on head alone, upside down: 0.200 s "
                            "(t = 0.20 to 0.30 s)")


def test_tilt_never_above_reports_the_most_tilted_link_also_when_all_stand_upright():
    import numpy as np

    run = _Run([0, 0, 0], [1, 1, 1], [0, 0, 0])
    run.angle = np.zeros((3, 2))
    got = _outcome({"tilt_never_above": {"links": ["base", "head"], "max": 10}}, run)
    assert got.passed and got.measured == "base 0 deg from upright at t = 0.00 s (the most)"
    run.angle[1, 1] = math.radians(30)
    got = _outcome({"tilt_never_above": {"links": ["base", "head"], "max": 10}}, run)
    assert not got.passed and got.measured == "head 30 deg from upright at t = 0.10 s (the most)"


def test_a_turn_on_the_ground_reports_no_flight_span():
    from puppet.timeline.expectations import evaluate, parse_expectations

    class Run:
        t = np.arange(5) * 0.1
        names = ["base"]
        angle = np.radians(np.array([[0.0], [90.0], [180.0], [270.0], [360.0]]))
        contact = np.ones((5, 1), dtype=bool)

        def index(self, name):
            return self.names.index(name)

    e, = parse_expectations([{"turned": {"link": "base", "direction": "forward",
                                         "min_degrees": 300}}]).items
    got = evaluate(e, Run(), "")
    assert got.measured == "turned -360 deg forward"


def test_revolutions_either_way_counts_a_backward_turn_once():
    from types import SimpleNamespace

    a = np.linspace(0, 2 * math.pi * 1.5, 200) - math.pi / 2
    com = np.stack([np.cos(a), np.sin(a)], 1)
    traj = SimpleNamespace(t=np.arange(200) * 0.1, com=com, held=[()] * 200)
    got, _ = _evaluate({"revolutions": {"about": [0.0, 0.0], "min": 1, "direction": "either"}},
                       traj)
    assert got.passed and got.measured.startswith("1.50 turns in a row backward")


def test_a_tilt_exactly_at_its_bound_passes():
    from types import SimpleNamespace

    traj = SimpleNamespace(t=np.arange(3) * 0.1, names=["base"],
                           angle=np.radians(np.array([[0.0], [30.0], [-30.0]])),
                           index=lambda n: 0)
    got, _ = _evaluate({"tilt_never_above": {"links": ["base"], "max": 30}}, traj)
    assert got.passed, got
    upright = SimpleNamespace(t=traj.t, names=["base"], angle=np.zeros((3, 1)),
                              index=lambda n: 0)
    got, _ = _evaluate({"tilt_at_end": {"links": ["base"], "max": 0, "held": 0.1}}, upright)
    assert got.passed and got.measured == "base at most 0.0 deg from upright over the last 0.1 s"


def test_what_holding_expectations_say_of_themselves():
    from puppet.timeline.expectations import parse_expectations

    said = [e.describe() for e in parse_expectations([
        {"held": {"chains": ["a", "b"], "prop": "bar"}},
        {"held": {"chains": ["a"], "from": 1.0, "until": 2.0}},
        {"always_holding": {"chains": ["a", "b"]}},
        {"always_holding": {"chains": ["a"], "from": 3.0}},
        {"stayed_in_state": {"state": "up", "until": 4.0}},
    ]).items]
    assert said == ["held a, b on bar", "held a from 1.0 s until 2.0 s",
                    "always_holding one of a, b", "always_holding one of a from 3.0 s",
                    "stayed_in_state up until 4.0 s"]


def test_a_got_up_over_two_samples_reads_their_spacing():
    from types import SimpleNamespace

    traj = SimpleNamespace(t=np.array([0.0, 0.5]), root_angle=np.radians([90.0, 0.0]),
                           contact=np.ones((2, 1), dtype=bool))
    got, _ = _evaluate({"got_up": {"lay_seconds": 0.4, "within_seconds": 1.0}}, traj)
    assert got.passed, got


def test_regrasps_exactly_the_minimum_pass():
    from types import SimpleNamespace

    rows = [(("l", "bars", "b1", 0, 0),), (("l", "bars", "b1", 0, 0), ("r", "bars", "b2", 0, 0)),
            (("r", "bars", "b2", 0, 0), ("l", "bars", "b3", 0, 0))]
    traj = SimpleNamespace(t=np.arange(3) * 0.1, held=rows,
                           prop_points={"bars": ["b1", "b2", "b3"]})
    got, _ = _evaluate({"regrasps": {"chains": ["l", "r"], "prop": "bars", "min": 2}}, traj)
    assert got.passed and got.measured.startswith("2 progressing grasps")


def test_what_the_leap_and_seat_expectations_say_of_themselves():
    from puppet.timeline.expectations import parse_expectations

    said = [e.describe() for e in parse_expectations([
        {"on_ground": {"links": ["thigh_near"], "min_seconds": 1, "min_root_angle": 30,
                       "max_root_angle": 80}},
        {"first_touch": {"links": ["foot_near", "foot_far"], "min_x": 1.0}},
        {"first_touch": {"links": ["foot_near"]}},
    ]).items]
    assert said == ["on_ground thigh_near min 1 s, root at least 30 and at most 80 deg (signed)",
                    "first_touch foot_near, foot_far only, each at x >= 1 m",
                    "first_touch foot_near only"]
