"""The bench's feat-log measure: the bare run fed the controlled run's writes is the
same motion, to the log's recorded end state (a checkpoint's re-seat, a push, key
sequences and feedback on the way). No timing assertions: targets live in the bench."""

from pathlib import Path

import pytest

from puppet.commands.bench.feats import bare_run, measure_feat, record
from puppet.commands.bench.report import format_feats
from puppet.timeline.log import read_log
from puppet.timeline.replay import setup_for_log

LOGS = Path(__file__).resolve().parents[1] / "assets" / "logs"


@pytest.mark.parametrize("name", ["luxo-back-headspring",  # a manual checkpoint on the way
                                  "luxo-ski-jump"])  # a keyframe's re-seat at the last step
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
    assert at[push][3], "the push's velocity change is written at its step"
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
