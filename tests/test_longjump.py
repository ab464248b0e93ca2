"""The long jump's expectation kinds (took_off, first_touch) on hand-made trajectories,
and the shipped long-jump log (assets/logs/biped-longjump.jsonl)."""

from __future__ import annotations

import numpy as np

from puppet.timeline.expectations import evaluate, parse_expectations


class _Run:
    """A sampled run of three links (foot, hand, pelvis) every 0.1 s."""

    links = ["foot", "hand", "pelvis"]

    def __init__(self, contact, x):
        n = len(contact)
        self.t = np.arange(n) * 0.1
        self.contact = np.array(contact, dtype=bool)
        self.x = np.array(x, dtype=float)

    def index(self, link):
        return self.links.index(link)


def _outcome(item, traj):
    e, = parse_expectations([item]).items
    return evaluate(e, traj, "")


# on the foot at x -0.2, 0.3 s in the air, down on the foot at x 1.1
JUMP = _Run([[1, 0, 0], [1, 0, 0], [0, 0, 0], [0, 0, 0], [0, 0, 0], [1, 0, 0], [1, 1, 0]],
            [[-0.4, -0.3, -0.3], [-0.2, 0.0, 0.0], [0.1, 0.3, 0.3], [0.4, 0.6, 0.6],
             [0.8, 0.9, 0.9], [1.1, 1.0, 1.0], [1.1, 1.0, 1.0]])


def test_took_off_names_the_links_on_the_ground_before_the_longest_flight():
    got = _outcome({"took_off": {"links": ["foot"], "max_x": -0.1, "min_seconds": 0.25}},
                   JUMP)
    assert got.passed
    assert got.measured == ("longest flight 0.30 s from t = 0.20 s; on the ground before "
                            "it: foot at x = -0.200")
    assert not _outcome({"took_off": {"links": ["foot"], "max_x": -0.3}}, JUMP).passed
    assert not _outcome({"took_off": {"links": ["foot"], "min_seconds": 0.4}}, JUMP).passed
    assert not _outcome({"took_off": {"links": ["hand"]}}, JUMP).passed


def test_first_touch_fails_when_a_hand_lands_first_or_short():
    assert _outcome({"first_touch": {"links": ["foot"], "min_x": 1.0}}, JUMP).passed
    assert not _outcome({"first_touch": {"links": ["foot"], "min_x": 1.2}}, JUMP).passed
    hands = _Run([[1, 0, 0], [0, 0, 0], [0, 0, 0], [1, 1, 0]], JUMP.x[:4])
    got = _outcome({"first_touch": {"links": ["foot"]}}, hands)
    assert not got.passed
    assert got.measured.endswith("touching first: foot at x = 0.400, hand at x = 0.600")
    ground = _Run([[1, 0, 0]] * 3, JUMP.x[:3])
    assert _outcome({"first_touch": {"links": ["foot"]}}, ground).measured == \
        "never in the air"
    still_flying = _Run([[1, 0, 0], [0, 0, 0], [0, 0, 0]], JUMP.x[:3])
    assert not _outcome({"first_touch": {"links": ["foot"]}}, still_flying).passed


class _Moving(_Run):
    """A _Run with the centre of mass moving: ``speed`` m/s along +x."""

    def __init__(self, contact, speed):
        super().__init__(contact, [[0.0, 0.0, 0.0]] * len(contact))
        self.com = np.stack([self.t * speed, np.full(len(contact), 0.5)], axis=1)


# three strides off the ground (0.1 s each), then the jump (0.3 s), down on the foot
RUN = [[1, 0, 0], [0, 0, 0], [1, 0, 0], [0, 0, 0], [1, 0, 0], [0, 0, 0], [1, 0, 0],
       [0, 0, 0], [0, 0, 0], [0, 0, 0], [1, 0, 0], [1, 0, 0]]
RUN_UP = {"links": ["foot"], "min_flights": 3, "flight_seconds": 0.1, "min_speed": 1.5,
          "over": 0.5}


def test_run_up_counts_the_flights_before_the_jump_and_its_speed():
    got = _outcome({"run_up": RUN_UP}, _Moving(RUN, 2.0))
    assert got.passed
    assert got.measured == ("the jump from t = 0.70 s; 3 flights of 0.1 s or more before "
                            "it; 2.000 m/s over t = 0.20 to 0.70 s")
    assert not _outcome({"run_up": RUN_UP}, _Moving(RUN, 1.0)).passed  # a walk's speed
    assert not _outcome({"run_up": dict(RUN_UP, min_flights=4)}, _Moving(RUN, 2.0)).passed
    # a walk-up: a foot always down until the jump
    walk = [[1, 0, 0]] * 7 + RUN[7:]
    got = _outcome({"run_up": RUN_UP}, _Moving(walk, 2.0))
    assert not got.passed and "0 flights" in got.measured
    # only the flights begun within 0.35 s of the jump: the one at 0.5 s
    assert not _outcome({"run_up": dict(RUN_UP, within=0.35)}, _Moving(RUN, 2.0)).passed
    assert _outcome({"run_up": dict(RUN_UP, within=0.35, min_flights=1)},
                    _Moving(RUN, 2.0)).passed
    # the jump too early for the speed's window
    got = _outcome({"run_up": dict(RUN_UP, over=1.0)}, _Moving(RUN, 2.0))
    assert not got.passed and "less than 1 s" in got.measured
    assert _outcome({"run_up": RUN_UP}, _Moving([[1, 0, 0]] * 5, 2.0)).measured == \
        "never in the air"
    # a window that is not a whole number of samples long: the run is long enough
    for over in (0.45, 0.55, 0.33):
        got = _outcome({"run_up": dict(RUN_UP, over=over)}, _Moving(RUN, 2.0))
        assert got.passed, (over, got.measured)


def test_run_up_measures_up_to_the_flight_took_off_and_first_touch_measure():
    """The jump is the longest flight for all three: with a longer flight after the
    landing (0.4 s, from 1.2 s), run_up's jump is that one, as took_off's and
    first_touch's are, and it counts the 0.3 s jump among its run-up's flights."""
    bounce = RUN + [[0, 0, 0]] * 4 + [[1, 0, 0]]
    traj = _Moving(bounce, 2.0)
    traj.x = np.tile(traj.com[:, :1], (1, 3))  # every link where the centre of mass is
    took = _outcome({"took_off": {"links": ["foot"]}}, traj)
    touch = _outcome({"first_touch": {"links": ["foot"]}}, traj)
    run = _outcome({"run_up": dict(RUN_UP, min_flights=4)}, traj)
    assert took.measured.startswith("longest flight 0.40 s from t = 1.20 s"), took.measured
    assert "ended at t = 1.60 s" in touch.measured, touch.measured
    assert run.passed and run.measured.startswith(
        "the jump from t = 1.20 s; 4 flights of 0.1 s or more before it"), run.measured


def test_run_up_needs_flights_or_a_speed():
    import pytest

    from puppet.data.errors import DataError

    with pytest.raises(DataError, match="give 'min_flights', 'min_speed' or both"):
        parse_expectations([{"run_up": {"over": 1.0}}])


# -- the shipped log ---------------------------------------------------------------------
import json  # noqa: E402
from pathlib import Path  # noqa: E402

import yaml  # noqa: E402
from helpers import copy_log, with_weak_hips  # noqa: E402

from puppet.data.catalog import ROOT, find  # noqa: E402
from puppet.testing import check, replay_log  # noqa: E402

LOG = ROOT / "assets" / "logs" / "biped-longjump.jsonl"
JUMP_KINDS = {"took_off", "first_touch", "tilt_at_end", "height_at_end", "tilt_never_above"}


def _failed(path: Path) -> set[str]:
    return {o.expectation.split()[0].rstrip(":") for o in replay_log(path).failed} - {"same"}


def test_the_small_figure_walks_up_and_jumps_a_metre_into_the_pit():
    result = replay_log(LOG)
    assert not result.failed, [str(o) for o in result.outcomes]
    assert {o.expectation.split()[0] for o in result.outcomes} - {"same"} == JUMP_KINDS
    traj = result.trajectory
    # a walk-up first (interfaces/biped-longjump-walk.yaml): the set-off, then steps on
    # alternate feet (the legs swap at each touch-down; l arms the walk's copy), then the
    # leap's states in order
    states = list(dict.fromkeys(traj.state))
    assert states[:3] == ["standing", "setoff", "on_near"], states
    assert {"aon_near", "aon_far"} <= set(states), states
    # (the gather's copy for the legs as they stand: the far foot led here)
    assert states[-5:] == ["gather_near", "push", "sail", "land", "landed"], states
    # the take-off's link is a foot, and the figure did not take off from a hand
    assert check(result, [{"took_off": {"links": ["forearm_near"]}}])
    assert check(result, [{"first_touch": {"links": ["foot_near", "foot_far"],
                                           "min_x": 1.5}}])  # not a 1.5 m jump


def test_weak_hips_do_not_jump_as_far(tmp_path):
    weak = with_weak_hips("biped-longjump", "biped-longjump-walk", tmp_path, 120.0, 30.0)
    assert _failed(weak) & {"took_off", "first_touch"}


def test_a_slippery_runway_spoils_the_jump(tmp_path):
    head = json.loads(LOG.read_text(encoding="utf-8").splitlines()[0])
    scene = yaml.safe_load(find("scene", head["scene"]).read_text(encoding="utf-8"))
    for ground in scene["ground"]:
        ground["friction"] = 0.3
    scene["name"] += "-slippery"
    path = tmp_path / "slippery.yaml"
    path.write_text(yaml.safe_dump(scene), encoding="utf-8")
    assert _failed(copy_log(LOG, tmp_path, scene=str(path))) & {"took_off", "first_touch"}


def test_on_ground_needs_every_link_down_and_the_root_tipped_back():
    class Sat(_Run):
        def __init__(self, contact, degrees):
            super().__init__(contact, [[0.0, 0.0, 0.0]] * len(contact))
            self.root_angle = np.radians(np.asarray(degrees, dtype=float))

    sat = Sat([[0, 1, 1], [0, 1, 1], [0, 1, 1], [1, 1, 0], [1, 0, 0]], [45, 45, 45, 10, 0])
    got = _outcome({"on_ground": {"links": ["hand", "pelvis"], "min_seconds": 0.3,
                                  "min_root_angle": 30}}, sat)
    assert got.passed
    assert got.measured == "longest stretch: 0.30 s (t = 0.00 to 0.20 s, root 45..45 deg)"
    assert not _outcome({"on_ground": {"links": ["hand", "pelvis"], "min_seconds": 0.4}},
                        sat).passed
    assert not _outcome({"on_ground": {"links": ["hand", "foot"], "min_seconds": 0.2}},
                        sat).passed
    # tipped forward, not back: the same contacts do not count
    ahead = Sat(sat.contact, [-45] * 5)
    assert not _outcome({"on_ground": {"links": ["hand", "pelvis"], "min_seconds": 0.1,
                                       "min_root_angle": 30}}, ahead).passed
    assert _outcome({"on_ground": {"links": ["hand", "pelvis"], "min_seconds": 0.1,
                                   "max_root_angle": -30}}, ahead).passed


# -- the run-up log (assets/logs/biped-longjump-run.jsonl) --------------------------------
from helpers import with_changed_interface  # noqa: E402

RUN_LOG = ROOT / "assets" / "logs" / "biped-longjump-run.jsonl"


def test_the_small_figure_runs_up_and_jumps_a_metre_into_the_pit():
    result = replay_log(RUN_LOG)
    assert not result.failed, [str(o) for o in result.outcomes]
    assert {o.expectation.split()[0] for o in result.outcomes} - {"same"} == \
        JUMP_KINDS | {"run_up"}
    traj = result.trajectory
    states = list(dict.fromkeys(traj.state))  # in the order first entered
    # the run's own states from the first step (on_near hands over within a control
    # tick, 1/60 s, two samples at most: no walking stride), then the one-leg take-off
    assert states[0] == "standing" and [s for s in states[1:3] if s != "on_near"][0] == \
        "run_near"
    assert list(traj.state).count("on_near") <= 2
    assert {"run_near", "fly_near", "run_far", "fly_far"} <= set(states)
    assert not {"down_near", "on_far", "gather"} & set(states)
    assert [s for s in states if s.startswith(("leap_", "rsail", "rland"))] and \
        states[-1] == "rlanded"
    # l armed the take-off (the run's armed copy ran before it), the line's sensor fired it
    assert [s for s in states if s.startswith(("arun_", "afly_"))]
    # not a hop on the spot: 4 m covered on the runway in the 5.5 s before the jump
    assert not check(result, [{"mean_speed": {"from": 0.5, "until": 6.0, "min": 0.72}}])


def test_weak_hips_spoil_the_run_up_or_the_jump(tmp_path):
    weak = with_weak_hips("biped-longjump-run", "biped-longjump", tmp_path, 120.0, 30.0)
    assert _failed(weak) & {"run_up", "took_off", "first_touch"}


def test_a_slippery_run_up_spoils_the_jump(tmp_path):
    head = json.loads(RUN_LOG.read_text(encoding="utf-8").splitlines()[0])
    scene = yaml.safe_load(find("scene", head["scene"]).read_text(encoding="utf-8"))
    scene["ground"][0]["friction"] = 0.3  # the runway only, not the pit
    scene["name"] += "-slippery"
    path = tmp_path / "slippery.yaml"
    path.write_text(yaml.safe_dump(scene), encoding="utf-8")
    assert _failed(copy_log(RUN_LOG, tmp_path, scene=str(path))) & \
        {"run_up", "took_off", "first_touch"}


def test_without_the_take_off_key_there_is_no_jump(tmp_path):
    def no_leap(spec):  # the run without its take-off: l gone, and what only it reached
        gone = ("leap_", "arun_", "arpush_", "afly_", "rs", "rl")
        for name in [n for n in spec["states"] if n.startswith(gone)]:
            del spec["states"][name]
        for name, state in spec["states"].items():
            if name.startswith(("run_", "rpush_", "fly_")):
                state.pop("keys", None)

    broken = with_changed_interface(RUN_LOG, "biped-longjump", tmp_path, no_leap, "noleap")
    assert "took_off" in _failed(broken)  # runs on into the pit: no flight of 0.25 s


def test_a_touch_down_a_stride_before_the_board_takes_the_early_take_off(tmp_path):
    def early_only(spec):  # the near-board mark past the line: every take-off is early
        for side in ("near", "far"):
            spec["states"][f"afly_{side}"]["transitions"][0]["when"][1]["above"] = 5.0

    changed = with_changed_interface(RUN_LOG, "biped-longjump", tmp_path, early_only, "early")
    result = replay_log(changed)
    states = list(dict.fromkeys(result.trajectory.state))
    assert not [s for s in states if s.startswith("leap_") and "early" not in s]
    assert [s for s in states if s.startswith("leap_early_")] and \
        {"rsail_early", "rland_early"} <= set(states) and states[-1] == "rlanded"
    kinds = {o.expectation.split()[0]: o.passed for o in result.outcomes}
    assert kinds["took_off"]  # off the ground from its feet, behind the line
