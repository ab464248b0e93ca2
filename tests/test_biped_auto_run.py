"""biped-auto's run (interfaces/biped-auto.yaml: the states run_X, rpush_X, fly_X) and
its log assets/logs/biped-auto-run: the mouse glides slowly from the march spot up the
walking diagonal and on to the run spot, space pressed once; past mouse x 0.68 (an
``input.mouse.x`` transition) the walk's states hand over to the run's. The log's
expectations must fail when the physics under it breaks."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from helpers import with_weak_hips
from test_luxo_feats import _failed, _weakened

from puppet.data.catalog import ROOT
from puppet.testing import check, replay_log

LOGS = ROOT / "assets" / "logs"
NAME = "biped-auto-run"


@pytest.fixture(scope="module")
def replayed():
    return replay_log(str(LOGS / f"{NAME}.jsonl"))


def test_the_log_meets_its_expectations(replayed):
    assert not replayed.failed, [str(o) for o in replayed.outcomes]
    kinds = {o.expectation.split()[0] for o in replayed.outcomes}
    assert {"mean_speed", "flight_phases", "never_fell", "tilt_never_above"} <= kinds


def test_the_mouse_alone_takes_it_from_the_march_through_the_walk_to_the_run(replayed):
    lines = (LOGS / f"{NAME}.jsonl").read_text(encoding="utf-8").splitlines()[1:]
    events = [json.loads(line)["event"] for line in lines if '"event"' in line]
    keys = [e for e in events if e["type"] == "key"]
    assert [(e["key"], e["down"]) for e in keys] == [("space", True), ("space", False)]
    traj = replayed.trajectory
    states = list(traj.state)
    walked = {s for s, t in zip(states, traj.t) if t < 12.0}
    ran = [s for s, t in zip(states, traj.t) if t > 20.0]
    assert {"on_near", "on_far"} <= walked and not walked & {"run_near", "run_far"}
    assert not set(ran) & {"on_near", "on_far", "down_near", "down_far"}
    strides = sum(1 for a, b in zip(ran, ran[1:]) if a != b and b in ("run_near", "run_far"))
    assert strides >= 10  # the swing foot's touch-down swaps the legs
    # the march is no walk, the walk no run: the speed comes with the mouse
    assert check(replayed, [{"mean_speed": {"from": 1.0, "until": 5.0, "min": 0.2}}])
    assert check(replayed, [{"mean_speed": {"from": 9.0, "until": 14.0, "min": 1.0}}])


def test_the_log_fails_with_weak_hips(tmp_path):
    assert _failed(with_weak_hips(NAME, "biped-auto", tmp_path, 300.0, 75.0)) \
        >= {"never_fell", "mean_speed"}


def test_the_log_fails_on_slippery_ground(tmp_path):
    assert "mean_speed" in _failed(_weakened(NAME, Path(tmp_path), friction=0.3))
