"""Expectations about the interface's state machine and mode: ``stayed_in_state``,
``stayed_in_mode``, ``in_state_at_end``, ``in_mode_at_end``, and the trajectory's
``state`` / ``mode`` columns they read (which must follow a rewind in the log)."""

from pathlib import Path

import numpy as np
import pytest

from puppet.data.catalog import load_setup
from puppet.data.errors import DataError
from puppet.interface import events as ev
from puppet.session import Session
from puppet.testing import check, replay_log
from puppet.timeline.expectations import parse_expectations
from puppet.timeline.log import Recorder

LOGS = Path(__file__).resolve().parents[1] / "assets" / "logs"
REWIND = {"type": "action", "name": "rewind"}


@pytest.fixture(scope="module")
def somersaults():
    """Two back somersaults on luxo-keys: 'upright' -> 'on_back' (upside down in the
    air, t = 1.09 to 1.39 s) -> 'upright', twice."""
    return replay_log(LOGS / "luxo-keys-somersaults.jsonl")


def test_the_trajectory_records_state_and_mode(somersaults):
    traj = somersaults.trajectory
    assert traj.state.shape == traj.t.shape and traj.state_names == ["upright", "on_back",
                                                                     "sitting"]
    assert set(traj.state) == {"upright", "on_back"}
    assert traj.mode_names == [] and all(m is None for m in traj.mode)


def test_stayed_in_state_passes_when_it_stayed():
    result = replay_log(LOGS / "luxo-keys-hops.jsonl", expect=[{"stayed_in_state": "upright"}])
    assert [str(o) for o in result.outcomes] == [
        "ok   stayed_in_state upright: in 'upright' from t = 0.00 s to 8.00 s"]


def test_stayed_in_state_fails_naming_the_transition(somersaults):
    failed = check(somersaults, [
        {"stayed_in_state": "upright"},
        {"stayed_in_state": {"state": "upright", "until": 1.0}},          # before the flip
        {"stayed_in_state": {"state": "on_back", "from": 1.15, "until": 1.35}},  # upside down
        {"stayed_in_state": {"state": "on_back", "from": 1.0}},
        {"in_state_at_end": "upright"},
        {"in_state_at_end": "sitting"},
        {"stayed_in_state": {"state": "upright", "from": 60}},
    ])
    assert [str(o) for o in failed] == [
        "FAIL stayed_in_state upright: left 'upright' for 'on_back' at t = 1.09 s",
        "FAIL stayed_in_state on_back from 1.0 s: in 'upright', not 'on_back', at t = 1.00 s",
        "FAIL in_state_at_end sitting: in 'upright' at the end (since t = 3.89 s)",
        "FAIL stayed_in_state upright from 60.0 s: no samples in the window "
        "(the run is 6.00 s)",
    ]


def test_unknown_state_or_mode_is_a_data_error_at_the_entry(somersaults, tmp_path):
    log = tmp_path / "s.jsonl"
    log.write_text((LOGS / "luxo-keys-somersaults.jsonl").read_text())
    side = tmp_path / "s.expect.yaml"
    side.write_text("expect:\n  - upright_at_end: true\n  - stayed_in_state: {state: uprite}\n")
    with pytest.raises(DataError) as info:
        replay_log(log)
    assert (info.value.path, info.value.line, info.value.col) == (str(side), 3, 30)
    assert info.value.message == ("unknown state 'uprite'; the interface has: upright, "
                                  "on_back, sitting")
    with pytest.raises(DataError, match="unknown mode 'keys'; the interface has no modes"):
        check(somersaults, [{"in_mode_at_end": "keys"}])
    with pytest.raises(DataError, match="unknown state 'lying'"):
        replay_log(LOGS / "luxo-hop.jsonl", expect=[{"stayed_in_state": "lying"}])


@pytest.mark.parametrize("entry, message", [
    ({"state": "upright", "form": 1},
     "unknown key 'form'; did you mean 'from'? expected one of: from, state, until"),
    ({"state": "upright", "from": 3, "until": 1},
     "stayed_in_state: 'until' (1 s) is before 'from' (3 s)"),
    ({"from": 1}, "missing required key 'state' in expect.0.stayed_in_state"),
])
def test_the_time_span_is_validated_when_loaded(entry, message):
    with pytest.raises(DataError) as info:
        parse_expectations([{"stayed_in_state": entry}])
    assert message in info.value.message and "\n" not in str(info.value)


def test_stayed_in_mode_follows_mode_keys(tmp_path):
    session = Session(load_setup("luxo-designer"))
    path = tmp_path / "modes.jsonl"
    with Recorder(session, path):
        session.advance(240)
        session.handle(ev.key("m", True))  # mode: still
        session.handle(ev.key("m", False))
        session.advance(240)
    result = replay_log(path, expect=[{"stayed_in_mode": {"mode": "nod", "until": 0.4}},
                                      {"stayed_in_mode": "nod"}, {"in_mode_at_end": "still"}])
    assert [o.passed for o in result.outcomes] == [True, False, True]
    assert result.outcomes[1].measured == "left 'nod' for 'still' at t = 0.51 s"


def _record_sit(path: Path, rewind_to: int | None, end: int) -> Path:
    """luxo-keys: sit (z, a goto 'sitting') at step 48; optionally run on to 480 and
    rewind to ``rewind_to``; then on to ``end``."""
    session = Session(load_setup("luxo-keys"))
    with Recorder(session, path):
        session.advance(48)
        session.handle(ev.key("z", True))
        session.handle(ev.key("z", False))
        if rewind_to is not None:
            session.advance(480 - 48)
            session.handle({**REWIND, "to_step": rewind_to})
        session.advance(end - session.steps)
    return path


def test_the_state_column_follows_a_rewind(tmp_path):
    straight = replay_log(_record_sit(tmp_path / "a.jsonl", None, 700)).trajectory
    # back to 242, still sitting: the same history as never having gone further
    back = replay_log(_record_sit(tmp_path / "b.jsonl", 242, 700)).trajectory
    assert np.array_equal(back.step, straight.step)
    assert list(back.state) == list(straight.state)
    assert back.state[0] == "upright" and back.state[-1] == "sitting"
    # back to 24, before the sit: the abandoned branch's 'sitting' rows are dropped
    before = _record_sit(tmp_path / "c.jsonl", 24, 400)
    result = replay_log(before, expect=[{"stayed_in_state": "upright"}])
    assert result.ok, [str(o) for o in result.outcomes]
    assert np.all(np.diff(result.trajectory.step) > 0) and result.trajectory.step[-1] == 400


def test_an_empty_link_name_in_an_expectation_is_a_clean_error():
    import pytest as _pytest

    from puppet.data.errors import DataError
    from puppet.timeline.expectations import parse_expectations

    for item in ({"height_at_end": {"link": "", "min": 0.5}},
                 {"tilt_never_above": {"links": ["base", ""], "max": 30}}):
        with _pytest.raises(DataError, match="unknown link ''"):
            parse_expectations([item]).check_links(["base", "lower_arm"])
