"""biped-auto (interfaces/biped-auto.yaml): the walk with the legs swapping by
themselves, and its log assets/logs/biped-auto-walk (the mouse glides slowly from the
march spot to the walk spot, space pressed once). The log's expectations must fail when
the physics under it breaks."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from helpers import with_weak_hips
from test_luxo_feats import _failed, _weakened

from puppet.data.catalog import ROOT
from puppet.testing import check, replay_log, replay_script_text

LOGS = ROOT / "assets" / "logs"
NAME = "biped-auto-walk"


@pytest.fixture(scope="module")
def replayed():
    return replay_log(str(LOGS / f"{NAME}.jsonl"))


def test_the_log_meets_its_expectations(replayed):
    assert not replayed.failed, [str(o) for o in replayed.outcomes]
    kinds = {o.expectation.split()[0] for o in replayed.outcomes}
    assert {"mean_speed", "never_fell", "tilt_never_above"} <= kinds


def test_the_legs_swap_by_themselves_after_one_press(replayed):
    lines = (LOGS / f"{NAME}.jsonl").read_text(encoding="utf-8").splitlines()[1:]
    events = [json.loads(line)["event"] for line in lines if '"event"' in line]
    keys = [e for e in events if e["type"] == "key"]
    assert [(e["key"], e["down"]) for e in keys] == [("space", True), ("space", False)]
    assert {e["type"] for e in events} == {"mouse", "key"}
    states = list(replayed.trajectory.state)
    swaps = sum(1 for a, b in zip(states, states[1:])
                if a != b and b in ("on_near", "on_far"))
    assert swaps >= 40  # steps, every one a sensor transition
    pushes = sum(1 for a, b in zip(states, states[1:])
                 if a != b and b in ("push_near", "push_far"))
    assert 0 < pushes < swaps  # some through the push-off, most on touch-down


def test_the_walk_is_faster_than_the_march_and_is_no_run(replayed):
    # the speeds the sidecar bounds, from the other side: the march does not walk, the
    # walk is not the run (over 2.5 m/s)
    assert check(replayed, [{"mean_speed": {"from": 1.0, "until": 5.0, "min": 0.2}}])
    assert check(replayed, [{"mean_speed": {"from": 25.0, "min": 2.5}}])


def test_the_mouse_height_does_nothing_so_the_path_is_a_band():
    # only the mouse's x drives the walk: the log's glide played at other heights
    # (low, and high then low) walks the same (the sidecar's expectations all met)
    script = (ROOT / "assets" / "scripts" / f"{NAME}.yaml").read_text(encoding="utf-8")
    side = LOGS / f"{NAME}.expect.yaml"
    for a, b in (("0.2", "0.2"), ("0.95", "0.3")):
        text = script.replace("[0.5, 0.55]", f"[0.5, {a}]").replace("0.879]", f"{b}]")
        assert text != script
        played = replay_script_text(text, ROOT / "interfaces" / "biped-auto.yaml", side)
        assert not played.failed, [str(o) for o in played.failed]


def test_the_log_fails_with_weak_hips(tmp_path):
    assert _failed(with_weak_hips(NAME, "biped-auto", tmp_path, 300.0, 75.0)) \
        >= {"never_fell", "tilt_never_above", "mean_speed"}


def test_the_log_fails_on_slippery_ground(tmp_path):
    assert _failed(_weakened(NAME, Path(tmp_path), friction=0.3)) \
        >= {"never_fell", "tilt_never_above", "mean_speed"}
