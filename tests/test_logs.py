"""The recorded feats under assets/logs/ replay and still do what their expect files say.

Each ``assets/logs/NAME.jsonl`` is a scripted performance (assets/scripts/NAME.yaml)
recorded through the real session; ``NAME.expect.yaml`` says what it must show (a
hop's distance, a flip's turn, a ski jump's landing...). If the physics, a character,
an interface or a scene changes so that a feat no longer works, these fail - and the
checks below show that they would.
"""

from __future__ import annotations

import math
import subprocess
import sys
from functools import cache

import pytest
import yaml
from helpers import copy_log

from puppet.data.catalog import ROOT, find
from puppet.testing import check, read_log, replay_log
from puppet.timeline.expectations import load_expectations, parse_expectations

LOGS = sorted((ROOT / "assets" / "logs").glob("*.jsonl"))


@cache
def replayed(path: str):
    return replay_log(path)


def test_there_are_feat_logs():
    names = {p.stem for p in LOGS}
    assert {"luxo-hop", "luxo-backflip", "luxo-ski-jump", "luxo-terrain"} <= names, names


@pytest.mark.parametrize("log", LOGS, ids=lambda p: p.stem)
def test_log_replays_and_meets_its_expectations(log):
    result = replayed(str(log))
    assert result.outcomes, f"{log.name}: no expectations were checked"
    assert not result.failed, "\n".join(str(o) for o in result.failed)
    assert result.final_hash == result.recorded_hash
    # each passed with a margin (how far inside its bound, in its unit) that says so
    assert all(math.isfinite(o.margin) and o.margin >= -1e-6 for o in result.outcomes), \
        [(o.kind, o.margin) for o in result.outcomes]


@pytest.mark.parametrize("log", LOGS, ids=lambda p: p.stem)
def test_each_log_expects_more_than_its_end_hash(log):
    header = read_log(log).header
    items = load_expectations(log, header).items
    kinds = {e.kind for e in items} - {"final_hash"}
    assert kinds, f"{log.name}: only the end hash is checked; say what the feat shows"


def test_the_hop_log_fails_with_weakened_servos(tmp_path):
    """Same input, half-strength servos: Luxo no longer hops, and the feat's own
    expectations (not only the end hash) say so."""
    log = ROOT / "assets" / "logs" / "luxo-hop.jsonl"
    spec = yaml.safe_load(find("interface", "luxo-mouse").read_text(encoding="utf-8"))
    for gains in spec["gains"].values():
        gains["stiffness"] *= 0.5
        gains["max_torque"] *= 0.5
    spec["name"] = "luxo-mouse-weak"
    iface = tmp_path / "luxo-mouse-weak.yaml"
    iface.write_text(yaml.safe_dump(spec), encoding="utf-8")
    weak = copy_log(log, tmp_path, interface=str(iface),
                     interface_text=iface.read_text(encoding="utf-8"))
    result = replay_log(weak)
    failed = {o.expectation.split()[0] for o in result.failed} - {"same"}
    assert {"x_at_end", "upright_at_end"} <= failed, [str(o) for o in result.outcomes]


def test_a_tightened_expectation_fails():
    """The checks measure: the flip turns about one full turn, not two."""
    result = replayed(str(ROOT / "assets" / "logs" / "luxo-backflip.jsonl"))
    assert not check(result, [{"turned": {"link": "base", "min_degrees": 330}}])
    failed = check(result, [{"turned": {"link": "base", "min_degrees": 700}},
                            {"turned": {"link": "base", "min_degrees": 300,
                                        "direction": "forward"}},
                            {"x_at_end": {"link": "base", "min": 0.5}}])
    assert len(failed) == 3, [str(o) for o in failed]


def test_turned_measures_backward_and_forward_and_in_flight():
    result = replayed(str(ROOT / "assets" / "logs" / "luxo-backflip.jsonl"))
    items = parse_expectations([
        {"turned": {"link": "base", "min_degrees": 300, "direction": "backward"}},
        {"turned": {"link": "base", "min_degrees": 250, "in_flight": True}},
        {"landed_at": {"link": "base", "min": -2.0}},
    ]).items
    from puppet.timeline.expectations import evaluate_all

    outcomes = evaluate_all(items, result.trajectory, result.final_hash)
    assert all(o.passed for o in outcomes), [str(o) for o in outcomes]
    # The hop turns hardly at all: a flip expectation fails on it.
    hop = replayed(str(ROOT / "assets" / "logs" / "luxo-hop.jsonl"))
    failed = check(hop, [{"turned": {"link": "base", "min_degrees": 90}},
                         {"turned": {"link": "base", "min_degrees": 90,
                                     "direction": "forward"}},
                         {"landed_at": {"link": "base", "min": 2.0}}])
    assert len(failed) == 3


def test_turned_and_landed_at_are_validated():
    from puppet.data.errors import DataError

    with pytest.raises(DataError):
        parse_expectations([{"turned": {"link": "base", "min_degrees": 300,
                                        "direction": "sideways"}}])
    with pytest.raises(DataError):
        parse_expectations([{"landed_at": {"link": "base"}}])


def test_replay_command_checks_logs_in_parallel():
    """The command's own parts (names, --jobs, the summary) on one log per character:
    every log passes ``replay(check=True)`` above, the function ``puppet replay
    --check`` runs for each log (commands.replay.replay_command)."""
    logs = [str(p) for p in LOGS if p.stem in ("luxo-hop", "cat-trot", "biped-walk")]
    assert len(logs) == 3
    proc = subprocess.run([sys.executable, "-m", "puppet", "replay", *logs, "--headless",
                           "--check", "--jobs", "2"], cwd=ROOT, capture_output=True,
                          text=True, timeout=300)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert f"{len(logs)} logs: {len(logs)} ok, 0 failed, 0 errors" in proc.stdout
