"""``puppet bench --quick --json`` runs and reports a well-formed, positive set of figures.

No timing assertions here: the speed targets live in the benchmark's own report.
"""

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def report() -> dict:
    """One quick bench, as the command line runs it (15 s here): every test reads it."""
    proc = subprocess.run([sys.executable, "-m", "puppet", "bench", "--quick", "--json"],
                          capture_output=True, text=True, cwd=ROOT, timeout=180)
    assert proc.returncode == 0, proc.stderr
    return json.loads(proc.stdout)


def test_quick_bench_reports_every_character_with_positive_figures(report):
    shipped = [p.stem for p in sorted((ROOT / "characters").glob("*.yaml"))]
    assert [c["character"] for c in report["characters"]] == shipped
    assert report["quick"] is True
    assert isinstance(report["all_pass"], bool)
    interfaces = {p.stem for p in (ROOT / "interfaces").glob("*.yaml")}
    measured = set()
    for c in report["characters"]:
        cp, rw = c["checkpoint"], c["rewind"]
        for value in (cp["bytes"], cp["snapshot_ms"], cp["restore_ms"], cp["checkpoint_ms"],
                      rw["entries"], rw["keyframe_bytes"], rw["traced_peak_bytes"],
                      rw["control_with_history_speed_x"], rw["restore_ms"], rw["resume_ms"],
                      rw["rewound_s"]):
            assert value > 0, c
        names = {t["name"] for t in c["targets"]}
        for entry in c["interfaces"]:
            sp, name = entry["speed"], entry["interface"]
            measured.add(name)
            for value in (sp["control_speed_x"], sp["bare_same_motion_speed_x"],
                          sp["bare_at_rest_speed_x"], sp["sim_seconds"],
                          sp["with_keyframes_speed_x"]):
                assert value > 0, (name, sp)
            assert isinstance(sp["control_overhead_pct"], float)
            # the bare run goes through the same trajectory as the controlled one, keys
            # and pose sequences included
            assert sp["same_motion_state_identical"] is True, name
            assert {f"speed with control: {name}", f"control overhead: {name}"} <= names
        assert {"checkpoint", "rewind 60 s and resume", "scrub frame, worst"} <= names
        sc = c["scrub"]  # every scrub frame timed; the scrub went back; the release too
        assert sc["frames"] > 0 and 0 < sc["p50_ms"] <= sc["p99_ms"] <= sc["max_ms"]
        assert sc["scrubbed_s"] > 0 and sc["release_ms"] > 0
        for t in c["targets"]:
            assert set(t) == {"name", "value", "op", "limit", "unit", "pass"}
            assert isinstance(t["pass"], bool)
    assert measured == interfaces  # every shipped interface is measured
    pr = report["processes"]  # whole puppet processes: startup, a replay, a check
    assert pr["startup_ms"] > 0 and pr["replay_ms"] > 0 and pr["check_ms"] > 0
    assert {t["name"] for t in report["targets"]} == {"headless replay process (luxo-hop)",
                                                      "check process (one file)",
                                                      "check process (an interface)"}
    logs = report["logs"]
    assert isinstance(logs["status"], str) and isinstance(logs["items"], list)
    if not list((ROOT / "assets" / "logs").glob("*.jsonl")):
        assert logs["status"] == "no logs"
    clips = sorted(p.name for p in (ROOT / "assets" / "mocap").glob("*.bvh"))
    assert [i["clip"] for i in report["mocap"]["items"]] == clips
    for item in report["mocap"]["items"]:
        assert item["read_ms"] > 0 and item["fk_ms"] > 0 and item["frames"] > 0
    assert [t["name"] for t in report["mocap"]["targets"]] == [f"read {c}" for c in clips]


def test_bench_table_names_targets_and_verdicts(report):
    from puppet.commands.bench.report import format_report

    text = format_report(report)  # the table of the same figures the JSON holds
    assert "speed with control" in text and "checkpoint" in text
    assert "read cmu-01_01-jumps.bvh" in text
    assert "PASS" in text or "MISS" in text


def test_the_cpu_clock_leaves_out_the_time_spent_waiting():
    import time

    from puppet.commands.bench import config

    for name, counts_sleep in (("wall", True), ("cpu", False)):
        config.use_clock(name)
        try:
            t0 = config.clock()
            time.sleep(0.05)
            slept = config.clock() - t0
        finally:
            config.use_clock("wall")
        assert (slept >= 0.05) is counts_sleep, (name, slept)


def test_the_quick_bench_replays_each_log_for_its_first_second_only(report):
    from puppet.commands.bench.config import QUICK

    got, seconds = report["logs"], QUICK["log_seconds"]
    assert got["status"] == f"ok, the first {seconds:g} s of each"
    shipped = [p.stem for p in sorted((ROOT / "assets" / "logs").glob("*.jsonl"))]
    assert [i["log"] for i in got["items"]] == shipped
    assert all(abs(i["sim_seconds"] - seconds) < 0.01 and i["speed_x"] > 0
               for i in got["items"]), got["items"]


def test_quick_bench_measures_every_feat_log_against_the_same_motion(report):
    """Every shipped log is played with control and bare (the writes the controlled run
    made, fed to Chipmunk); the bare run ends where the controlled one does."""
    shipped = sorted(p.stem for p in (ROOT / "assets" / "logs").glob("*.jsonl"))
    feats = report["feats"]
    assert sorted(i["log"] for i in feats["items"]) == shipped
    for item in feats["items"]:
        assert "error" not in item, item
        assert item["same_motion"] is True, item["log"]
        assert item["steps"] > 0 and item["bare_us_per_step"] > 0
        assert item["control_us_per_step"] > 0 and isinstance(item["overhead_pct"], float)
    names = {t["name"] for t in feats["targets"]}
    assert {f"control overhead: {log}" for log in shipped} <= names
    assert "control overhead: median over the feat logs" in names


def test_quick_bench_times_frames_with_the_hud_and_f1_on_the_biped_scenes(report):
    frames = report["hud_frames"]
    assert {f["log"] for f in frames} >= {"biped-walk", "biped-ladder-climb"}
    for f in frames:
        assert f["frames"] > 0 and 0 < f["p50_ms"] <= f["p99_ms"] <= f["max_ms"]
        assert f["target"]["name"].startswith("frame with the HUD and F1")


def test_pygame_says_nothing_on_stdout_after_a_command_so_json_output_parses():
    """`puppet bench --json` draws HUD frames with pygame; its import banner on stdout
    would make the JSON unreadable."""
    code = ("from puppet.commands import main; main(['check', 'interfaces/luxo-mouse.yaml']);"
            " import pygame")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         cwd=Path(__file__).resolve().parents[1],
                         env={k: v for k, v in os.environ.items()
                              if k != "PYGAME_HIDE_SUPPORT_PROMPT"})
    assert out.returncode == 0, out.stderr
    assert "pygame" not in out.stdout, out.stdout
