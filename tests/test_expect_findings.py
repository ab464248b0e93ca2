"""A test-suite author's findings on expectations and puppet.testing: bounds nothing can
meet refused at load, ``puppet check LOG`` checking state names and windows as the replay
would, the sidecar-wins warning, the first sample's contacts, ``flight_phases``'s
``max_count``, one-line messages, and the API's small edges (``Outcome.kind``,
``DataError``, ``allow_truncated=True``, ``Trajectory.index``, ``repr``, ``adjust``)."""

import json
import re
import shutil
from pathlib import Path

import numpy as np
import pytest

from puppet.commands.check import check_file
from puppet.timeline.expectations import (
    Expectation,
    evaluate_all,
    load_expectations,
    parse_expectations,
)
from puppet.timeline.trajectory import Trajectory

ROOT = Path(__file__).resolve().parents[1]
HOP = ROOT / "assets" / "logs" / "luxo-hop.jsonl"  # 4.5 s, luxo-mouse: no states


def _error(expect) -> str:
    from puppet.data.errors import DataError

    with pytest.raises(DataError) as info:
        parse_expectations(expect)
    return str(info.value)


# -- 1. bounds nothing can meet ---------------------------------------------------------
@pytest.mark.parametrize("entry, said", [
    ({"x_at_end": {"link": "base", "min": -0.3, "max": -1}}, "x_at_end: 'max' (-1) is less "
                                                             "than 'min' (-0.3)"),
    ({"mean_speed": {"min": 0.1, "max": 0.05}}, "mean_speed: 'max' (0.05) is less than"),
    ({"flight_phases": {"from": 4, "until": 1, "min_count": 1, "min_seconds": 0.01}},
     "flight_phases: 'until' (1 s) is before 'from' (4 s)"),
    ({"airborne": {"link": "base", "min_seconds": 0.5, "max_seconds": 0.1}},
     "'max_seconds' (0.1) is less than 'min_seconds' (0.5)"),
    ({"height_at_end": {"link": "base", "min": 1, "max": 0.5}}, "'max' (0.5) is less"),
    ({"followed_channels": {"joints": ["a"], "min_rms": 9, "max_rms": 3}}, "'max_rms' (3)"),
    ({"stayed_in_state": {"state": "s", "from": 3, "until": 2}}, "'until' (2 s) is before"),
    ({"flight_phases": {"min_count": 3, "max_count": 2, "min_seconds": 0.01}},
     "'max_count' (2) is less than 'min_count' (3)"),
])
def test_bounds_that_nothing_meets_are_refused(entry, said):
    assert said in _error([entry])


def test_bounds_refusal_has_the_file_and_line(tmp_path):
    side = tmp_path / "x.expect.yaml"
    side.write_text("expect:\n  - never_fell: true\n"
                    "  - mean_speed: {min: 0.1, max: 0.05}\n", encoding="utf-8")
    from puppet.data.errors import DataError

    with pytest.raises(DataError) as info:
        check_file(side)
    assert str(info.value).startswith(f"{side}:3:")
    assert "expected 'max' at least 'min'" in str(info.value)


def test_equal_bounds_and_a_one_instant_window_still_pass_load():
    parse_expectations([{"flight_phases": {"min_count": 2, "max_count": 2,
                                           "min_seconds": 0.01}},
                        {"x_at_end": {"com": True, "min": 1, "max": 1}},
                        {"stayed_in_state": {"state": "s", "from": 2, "until": 2}}])


# -- 2. puppet check LOG: the names and windows the replay would refuse or fail --------
def _log_with(tmp_path, expect_yaml: str, header_expect=None) -> Path:
    log = tmp_path / "hop.jsonl"
    lines = HOP.read_text(encoding="utf-8").splitlines(keepends=True)
    if header_expect is not None:
        head = json.loads(lines[0])
        head["expect"] = header_expect
        lines[0] = json.dumps(head) + "\n"
    log.write_text("".join(lines), encoding="utf-8")
    if expect_yaml is not None:
        (tmp_path / "hop.expect.yaml").write_text(expect_yaml, encoding="utf-8")
    return log


def _check_error(log) -> str:
    from puppet.data.errors import DataError

    with pytest.raises(DataError) as info:
        check_file(log)
    return str(info.value)


def test_check_log_refuses_a_state_the_interface_does_not_have(tmp_path):
    log = _log_with(tmp_path, "expect:\n  - stayed_in_state: uprihgt\n")
    said = _check_error(log)
    assert re.match(r".*hop\.expect\.yaml:2:\d+: unknown state 'uprihgt'; the interface has "
                    r"no states$", said), said


def test_check_log_refuses_a_mode_by_the_replays_words(tmp_path):
    log = _log_with(tmp_path, "expect:\n  - in_mode_at_end: kyes\n")
    assert "unknown mode 'kyes'; the interface has no modes" in _check_error(log)


def test_check_log_refuses_a_window_after_the_end(tmp_path):
    log = _log_with(tmp_path, "expect:\n  - mean_speed: {from: 100, min: 0}\n")
    said = _check_error(log)
    assert ":2:" in said and "'from' (100 s) is after the log's end (4.50 s)" in said


def test_check_log_passes_a_window_inside_the_run(tmp_path):
    log = _log_with(tmp_path, "expect:\n  - mean_speed: {from: 4.0, min: -9}\n")
    warnings = []
    assert check_file(log, warnings) == "log" and warnings == []


# -- 3. header and sidecar: the sidecar wins, said; an empty list, said -----------------
def test_header_entries_left_out_for_the_sidecars_are_a_warning(tmp_path):
    log = _log_with(tmp_path, "expect:\n  - never_fell: true\n",
                    header_expect=[{"upright_at_end": True}])
    notes = load_expectations(log, json.loads(log.read_text().splitlines()[0])).notes
    assert len(notes) == 1 and "the header's 1 expectation(s) are not checked" in notes[0]
    assert "the sidecar wins" in notes[0]
    warnings = []
    check_file(log, warnings)
    assert notes[0] in warnings


def test_an_empty_expect_list_is_a_warning(tmp_path):
    log = _log_with(tmp_path, "expect: []\n")
    warnings = []
    check_file(log, warnings)
    assert any("'expect' is an empty list" in w for w in warnings), warnings
    warnings = []
    check_file(tmp_path / "hop.expect.yaml", warnings)
    assert any("'expect' is an empty list" in w for w in warnings), warnings
    header_only = tmp_path / "h"
    header_only.mkdir()
    log = _log_with(header_only, None, header_expect=[])
    assert any("empty list" in n for n in load_expectations(log, {"expect": []}).notes)


# -- 4, 5. the first sample's contacts; flight_phases max_count --------------------------
def _traj(contact_rows):
    contact = np.array(contact_rows, dtype=bool)[:, None]
    n = len(contact)
    z = np.zeros((n, 1))
    return Trajectory(links=["base"], joints=[], step=np.arange(n) * 4,
                      t=np.arange(n) / 120.0, x=z.copy(), y=z.copy(), angle=z.copy(),
                      lowest=z.copy(), contact=contact, com=np.zeros((n, 2)),
                      root_angle=np.zeros(n), joint_angle=np.zeros((n, 0)),
                      joint_target=np.zeros((n, 0)), joint_channel=np.zeros((n, 0)),
                      state=np.array([None] * n, dtype=object),
                      mode=np.array([None] * n, dtype=object), state_names=[],
                      mode_names=[])


def _outcomes(traj, expect):
    return [str(o) for o in evaluate_all(parse_expectations(expect).items, traj, "")]


def test_the_first_sample_takes_the_next_ones_contacts():
    # step 0 has no contacts yet (before the first step): not a flight of a standing start
    traj = _traj([0, 1, 1, 0, 0, 1, 1])
    assert traj.contact[:, 0].tolist() == [True, True, True, False, False, True, True]
    said = _outcomes(traj, [{"flight_phases": {"min_count": 1, "min_seconds": 0.001}}])
    assert said == ["ok   flight_phases at least 1 of 0.001 s or more (no link touching) "
                    "from 0 s to the end: 1 flights of 0.001 s or more (1 in all, the "
                    "longest 0.017 s)"]


def test_a_start_in_the_air_stays_in_the_air():
    assert _traj([0, 0, 1]).contact[:, 0].tolist() == [False, False, True]


def test_flight_phases_max_count_exactly_two_hops():
    two = _traj([1, 1, 0, 0, 1, 1, 0, 0, 1])
    three = _traj([1, 0, 0, 1, 0, 0, 1, 0, 0, 1])
    exactly = [{"flight_phases": {"min_count": 2, "max_count": 2, "min_seconds": 0.01}}]
    assert _outcomes(two, exactly)[0].startswith(
        "ok   flight_phases at least 2 and at most 2 of 0.01 s or more")
    assert _outcomes(three, exactly)[0].startswith("FAIL")
    assert _outcomes(two, [{"flight_phases": {"max_count": 1, "min_seconds": 0.01}}]
                     )[0].startswith("FAIL flight_phases at most 1 of")
    assert "give 'min_count', 'max_count' or both" in _error(
        [{"flight_phases": {"min_seconds": 0.01}}])


# -- 6. one clean line for an entry with two checks ----------------------------------------
def test_two_checks_in_one_entry_one_clean_line(tmp_path):
    said = _error([{"never_fell": True, "upright_at_end": True}])
    assert said.count("got") == 0 and "{" not in said and "\n" not in said
    assert "this entry names 2: never_fell, upright_at_end" in said
    side = tmp_path / "x.expect.yaml"
    side.write_text("expect:\n  - never_fell: true\n    upright_at_end: true\n",
                    encoding="utf-8")
    from puppet.data.errors import DataError

    with pytest.raises(DataError) as info:
        check_file(side)
    assert str(info.value).startswith(f"{side}:2:")


# -- 7. the API ------------------------------------------------------------------------------
def test_outcome_kind_and_data_error_from_testing():
    from puppet.data.errors import DataError
    from puppet.testing import DataError as TestingDataError

    assert TestingDataError is DataError
    traj = _traj([1, 1, 0, 1])
    items = parse_expectations([{"never_fell": True}, {"airborne": {"link": "base",
                                                                    "min_seconds": 0.0}}])
    assert [o.kind for o in evaluate_all(items.items, traj, "")] == ["never_fell", "airborne"]


def test_a_bare_name_or_a_dict_is_not_a_list_of_entries():
    from puppet.data.errors import DataError
    from puppet.testing import check, replay_log

    with pytest.raises(DataError, match="expected a list of expectation entries.*got str "
                                        "'never_fell'"):
        check(None, "never_fell")
    with pytest.raises(DataError, match="expected a list of expectation entries.*got dict"):
        replay_log(HOP, expect={"never_fell": True})


def test_trajectory_index_names_the_links_and_where_joints_are():
    traj = _traj([1, 1])
    traj.joints = ["ankle"]
    with pytest.raises(ValueError) as info:
        traj.index("ankle")
    said = str(info.value)
    assert "no link 'ankle'" in said and "the links are: base" in said
    assert "trajectory.joints.index('ankle')" in said and "joint_angle" in said


def test_replay_log_speaks_python_repr_is_short_kinds_and_adjust(tmp_path):
    from puppet.data.errors import DataError
    from puppet.testing import replay_log, weaker_joints

    cut = tmp_path / "hop.jsonl"
    lines = HOP.read_text(encoding="utf-8").splitlines(keepends=True)
    cut.write_text("".join(lines[:-1]), encoding="utf-8")  # no end line
    shutil.copy(HOP.with_name("luxo-hop.expect.yaml"), tmp_path / "hop.expect.yaml")
    with pytest.raises(DataError) as info:
        replay_log(cut)
    assert "allow_truncated=True" in str(info.value)
    assert "--allow-truncated" not in str(info.value)

    result = replay_log(HOP)
    text = repr(result)
    assert text == (f"ReplayResult(path='{HOP}', steps={result.steps}, "
                    f"hash='{result.final_hash}', ok)")
    assert [o.kind for o in result.outcomes][-1] == "same_end"
    assert all(o.kind for o in result.outcomes)
    with pytest.raises(DataError, match="weaker_joints: no driven joint 'wrist'"):
        replay_log(HOP, adjust=weaker_joints(["wrist"], 0.5))


def test_weaker_hips_fail_the_push_step_the_docs_example():
    from puppet.testing import replay_log, weaker_joints

    log = ROOT / "assets" / "logs" / "biped-push-step.jsonl"
    weak = replay_log(log, adjust=weaker_joints(["hip_near", "hip_far"], 0.3))
    assert "never_fell" in [o.kind for o in weak.failed]
    assert repr(weak).endswith(f"{len(weak.failed)} of {len(weak.outcomes)} failed)")


# -- 8. every kind documented (docs/expectations.md), and docs/testing.md points there -----
def test_every_kind_is_documented_and_the_testing_page_points_there():
    doc = (ROOT / "docs" / "expectations.md").read_text(encoding="utf-8")
    readme = (ROOT / "docs" / "testing.md").read_text(encoding="utf-8")
    start = readme.index("Expectations live in the log's header")
    listing = readme[start:readme.index("Test\nsuites use", start)]
    for kind in Expectation.__struct_fields__:
        assert f"\n### `{kind}`\n" in doc, kind
    assert "(expectations.md)" in listing
