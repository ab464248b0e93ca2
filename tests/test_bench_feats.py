"""The bench's feat-log measure: the bare run fed the controlled run's writes is the
same motion, to the log's recorded end state (a checkpoint's re-seat, a push, key
sequences and feedback on the way). No timing assertions: targets live in the bench."""

from pathlib import Path

import pytest
from pymunk._chipmunk_cffi import lib as cp

from puppet.commands.bench.feats import (
    SERVO_GET,
    SERVO_SET,
    SET_SPIN,
    SET_VELOCITY,
    bare_run,
    measure_feat,
    record,
)
from puppet.commands.bench.report import format_feats
from puppet.timeline.log import read_log
from puppet.timeline.replay import setup_for_log

LOGS = Path(__file__).resolve().parents[1] / "assets" / "logs"


@pytest.mark.parametrize("name", ["luxo-back-headspring",  # a manual checkpoint on the way
                                  "luxo-ski-jump",  # a keyframe's re-seat at the last step
                                  "biped-gymnast-climb-trot"])  # two grasps let go at once
def test_the_bare_run_reaches_the_logs_own_end_state(name):
    item = measure_feat(str(LOGS / f"{name}.jsonl"), rounds=1)
    assert item["same_motion"] is True and item["recorded_end"] is True
    assert item["writes"] > 0 and item["steps"] == read_log(LOGS / f"{name}.jsonl").last_step
    lines = format_feats({"items": [item], "rounds": 1, "seconds": None,
                          "targets": [{"name": f"control overhead: {name}", "value": 1.0,
                                       "op": "<=", "limit": 15.0, "unit": "%",
                                       "pass": True}]})
    assert any(line.strip().startswith(name) and "PASS" in line for line in lines)


def test_the_trace_holds_the_push_and_the_checkpoints_and_replays_to_the_end():
    log = read_log(LOGS / "biped-push-step.jsonl")
    setup, _ = setup_for_log(log)
    trace = record(log, setup)
    bare = bare_run(log, setup, trace)
    next(bare)
    assert bare.send(trace.steps).state_hash() == trace.end_hash == log.end_hash
    push = next(e.step for e in log.events if e.event["type"] == "push")
    at = {op[0]: op for op in trace.ops}
    assert any(w[0] is SET_VELOCITY for w in at[push][2]), \
        "the push's velocity change is written at its step"
    every = round(float(log.header["checkpoint_interval"]) / float(log.header["dt"]))
    reseats = [op[0] for op in trace.ops if op[1]]
    assert reseats[:2] == [every, 2 * every]  # the timeline's keyframes re-seat the run


def test_log_picks_the_named_shipped_logs_and_refuses_an_unknown_one():
    from puppet.commands.bench.feats import measure_feats
    from puppet.data.errors import UsageError

    report = measure_feats(1, 0.05, logs=["luxo-hop", "luxo-hop.jsonl"])
    assert [i["log"] for i in report["items"]] == ["luxo-hop"]
    with pytest.raises(UsageError, match="no shipped log named nope"):
        measure_feats(1, 0.05, logs=["nope"])


def test_log_names_given_two_ways_are_one_and_a_filter_leaving_none_says_so():
    from puppet.commands.bench.feats import measure_feats
    from puppet.data.errors import UsageError

    report = measure_feats(1, 0.05, logs=["assets/logs/luxo-hop", "luxo-hop",
                                          "a/luxo-hop.jsonl"])
    assert [i["log"] for i in report["items"]] == ["luxo-hop"]
    with pytest.raises(UsageError, match="leave out every log named: luxo-hop is luxo's"):
        measure_feats(1, 0.05, only=["biped"], logs=["luxo-hop"])


def _velocity(handle):
    v = cp.cpBodyGetVelocity(handle)
    return (v.x, v.y)


GETTER = dict(zip(SERVO_SET, SERVO_GET)) | {SET_VELOCITY: _velocity,
                                            SET_SPIN: cp.cpBodyGetAngularVelocity}


@pytest.mark.parametrize("name", ["biped-push-step", "cat-trot"])
def test_the_bare_run_writes_each_changed_value_once_and_nothing_else(name):
    """The bare run is the cheapest honest run: every value it writes is one that
    changed (a redundant write - all four servo values when one changed - fails here),
    each through the C setter, and those writes alone take it to the log's end."""
    log = read_log(LOGS / f"{name}.jsonl")
    setup, _ = setup_for_log(log)
    trace = record(log, setup)
    written = []

    def checked(setter):
        get = GETTER[setter]

        def write(handle, value):
            assert get(handle) != value, "a write that changes nothing"
            written.append(value)
            setter(handle, value)
        return write

    trace.ops = [(at, reseat, tuple((checked(s), i, v) for s, i, v in writes), grasps, world)
                 for at, reseat, writes, grasps, world in trace.ops]
    bare = bare_run(log, setup, trace)
    next(bare)
    for _ in range(0, trace.steps, 240):  # in the bench's turns
        sim = bare.send(240)
    assert sim.state_hash() == trace.end_hash == log.end_hash
    assert len(written) == trace.writes > 0
