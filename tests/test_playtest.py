"""Playtests: the human model moves a log's events as it says (in real time, scaled by
the slowdown; order kept; markers with the next event), tries are deterministic per
(seed, try) in any process, the sidecar's bar is validated, and the command reports.
The feats' own figures are in test_playtest_feats.py and test_playtest_bars.py."""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from puppet.data.catalog import ROOT, load_setup
from puppet.data.errors import DataError
from puppet.data.playtest import LEVELS, PARAMETERS, noise_at
from puppet.interface import events as ev
from puppet.session import Session
from puppet.timeline.log import read_log, record_events
from puppet.timeline.playtest import judge, perturb, perturbation, perturbed_log, prepare, run_try
from puppet.timeline.playtest.slowdown import in_force

DT = 1 / 480
APP_KEYS = {"checkpoint": "c", "restore": "backspace", "rewind": "b", "forward": "shift+b"}
FIXTURES = Path(__file__).parent / "fixtures" / "playtest"
OFF = {k: 0.0 for k in PARAMETERS if k != "stroke_gap_ms"}


def _taps(n: int = 40, gap: int = 120, hold: int = 1) -> list:
    """Presses of 'space' every ``gap`` steps, each held ``hold`` steps, and a mouse
    stroke between them: a log's events."""
    pairs = []
    for k in range(n):
        s = 200 + k * gap
        pairs += [(s, ev.key("space", True)), (s + hold, ev.key("space", False))]
        pairs += [(s + 10 + i, ev.mouse(0.5 + 0.01 * i, 0.5)) for i in range(0, 20, 4)]
    return pairs


def _moved(pairs, slowdown: float, seed: int = 0, noise=None, end: int = 10 ** 6):
    return perturb(pairs, [slowdown] * len(pairs), DT, end, noise or LEVELS["human"], seed,
                   0, APP_KEYS)


def test_timing_noise_is_real_time_divided_by_the_slowdown():
    pairs = _taps()
    at1, at8 = _moved(pairs, 1.0), _moved(pairs, 8.0)
    keys = [i for i, (_, e) in enumerate(pairs) if e["type"] == "key"]
    for i in keys:
        m1, m8 = at1.moves[i], at8.moves[i]
        assert m1.real_shift == m8.real_shift  # the same person's error...
        assert abs(m1.real_shift) <= 0.030
    # ... is an eighth of the steps at slowdown 8 (for the presses, which nothing pushed)
    downs = [i for i in keys if pairs[i][1]["down"]]
    for i in downs:
        m1, m8 = at1.moves[i], at8.moves[i]
        assert m1.new_step - m1.step == round(m1.real_shift / DT)
        assert m8.new_step - m8.step == round(m8.real_shift / 8 / DT)
    spread1 = max(abs(at1.moves[i].new_step - pairs[i][0]) for i in downs)
    spread8 = max(abs(at8.moves[i].new_step - pairs[i][0]) for i in downs)
    assert spread1 >= 12 and spread8 <= round(spread1 / 8) + 1  # +-14.4 and +-1.8 steps


@pytest.mark.parametrize("level", list(LEVELS))
def test_no_key_up_precedes_its_down_and_one_inputs_events_keep_their_order(level):
    pairs = _taps(n=60, gap=30, hold=1)  # quick taps, closer than the errors
    for seed in range(25):
        moved = _moved(pairs, 1.0, seed, LEVELS[level]).pairs
        held = False
        last_key = last_mouse = -1
        xs = []
        for step, e in moved:
            if e["type"] == "key":
                assert e["down"] != held, f"seed {seed}: a key-up before its key-down"
                held = e["down"]
                assert step > last_key  # distinct steps stay distinct
                last_key = step
            elif e["type"] == "mouse":
                assert step > last_mouse
                last_mouse = step
                xs.append(e["x"])
        assert len(moved) == len(pairs)
        assert not held


def test_a_stroke_moves_as_a_whole_plus_tremor():
    stroke = [(100 + 4 * i, ev.mouse(0.2 + 0.01 * i, 0.3)) for i in range(30)]
    for seed in range(10):
        moved = _moved(stroke, 1.0, seed, noise_at("novice", tempo=0.0)).pairs
        shifts = {s - s0 for (s, _), (s0, _) in zip(moved, stroke)}
        assert len(shifts) == 1  # one time shift for the whole stroke
        dx = [e["x"] - e0["x"] for (_, e), (_, e0) in zip(moved, stroke)]
        mean = sum(dx) / len(dx)
        assert abs(mean) <= 10 / 1024 + 1e-9  # the aim: +-10 px of 1024
        assert max(dx) - min(dx) <= 2 * 2.5 / 1024 + 1e-9  # the tremor: +-2.5 px
        assert max(dx) - min(dx) > 0


def test_markers_move_with_the_event_after_them_and_restore_starts_a_segment():
    pairs = [(480, ev.action("checkpoint")), (480, ev.key("space", True)),
             (504, ev.key("space", False)), (900, ev.action("restore")),
             (500, ev.key("space", True)), (520, ev.key("space", False))]
    for seed in range(20):
        p = _moved(pairs, 3.0, seed)
        events = [e for _, e in p.pairs]
        assert events[0]["name"] == "checkpoint" and events[1]["key"] == "space"
        assert p.moves[0].new_step == p.moves[1].new_step  # the checkpoint with the press
        assert events[3]["name"] == "restore"  # segments in log order
        assert p.moves[3].new_step - 900 == p.moves[4].new_step - 500
        assert [e["type"] for e in events] == [e["type"] for _, e in pairs]


def test_nothing_moves_before_the_start_or_past_the_end():
    pairs = [(0, ev.key("a", True)), (1, ev.key("a", False)), (999, ev.key("b", True)),
             (1000, ev.key("b", False))]
    for seed in range(20):
        steps = [s for s, _ in _moved(pairs, 1.0, seed, LEVELS["novice"], end=1000).pairs]
        assert min(steps) >= 0 and max(steps) <= 1000


def test_zero_noise_replays_the_log_to_its_recorded_bits():
    prepared = prepare("luxo-hop")  # the mouse: strokes, aim and tremor all zero
    result = judge(prepared, perturbed_log(prepared, noise_at("human", **OFF), 0, 0))
    assert result.passed and result.final_hash == prepared.log.end_hash


def _other_process(name: str, seed: int, index: int) -> str:
    code = ("import sys; from puppet.data.playtest import noise_at; "
            "from puppet.timeline.playtest import run_try; "
            f"r = run_try({name!r}, noise_at('human'), {seed}, {index}); "
            "print(r.final_hash, r.passed)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True, timeout=300)
    return out.stdout.split()[0]


def test_the_same_seed_gives_the_same_tries_in_two_processes_other_seeds_differ():
    here = [run_try("luxo-keys-hops", noise_at("human"), 7, i).final_hash for i in (0, 1)]
    assert here[0] != here[1]  # two tries of one seed differ
    assert _other_process("luxo-keys-hops", 7, 1) == here[1]
    prepared = prepare("luxo-keys-hops")
    seven = [perturbation(prepared, noise_at("human"), 7, i).pairs for i in range(4)]
    eight = [perturbation(prepared, noise_at("human"), 8, i).pairs for i in range(4)]
    assert seven == [perturbation(prepared, noise_at("human"), 7, i).pairs for i in range(4)]
    assert all(a != b for a, b in zip(seven, eight))
    assert run_try("luxo-keys-hops", noise_at("human"), 8, 1).final_hash != here[1]


def test_the_slowdown_in_force_follows_a_slowdown_key(tmp_path):
    session = Session(load_setup("luxo-keys"))  # 'l': slowdown 4, 'k': real time
    events = [(100, ev.key("w", True)), (101, ev.key("w", False)), (400, ev.key("l", True)),
              (401, ev.key("l", False)), (900, ev.key("w", True)), (901, ev.key("w", False)),
              (1300, ev.key("k", True)), (1301, ev.key("k", False)), (1500, ev.key("w", True)),
              (1501, ev.key("w", False))]
    path = record_events(session, events, 1800, tmp_path / "speed.jsonl")
    log = read_log(path)
    assert in_force(log, load_setup("luxo-keys")) == [1, 1, 1, 4, 4, 4, 4, 1, 1, 1]
    plain = read_log(ROOT / "assets" / "logs" / "luxo-keys-hops.jsonl")
    assert set(in_force(plain, load_setup("luxo-keys"))) == {1.0}


def _sidecar(tmp_path: Path, text: str) -> Path:
    src = ROOT / "assets" / "logs" / "luxo-keys-sit-stand.jsonl"
    log = tmp_path / "sit.jsonl"
    shutil.copy(src, log)
    (tmp_path / "sit.expect.yaml").write_text(text, encoding="utf-8")
    return log


def test_the_sidecar_bar_is_validated_at_its_line(tmp_path):
    from puppet.timeline.playtest import load_bar

    good = _sidecar(tmp_path, "expect:\n  - never_fell: true\n"
                              "playtest: {noise: steady, tries: 4, min_pass: 0.75}\n")
    bar = load_bar(str(good))
    assert (bar.noise, bar.tries, bar.min_pass, bar.needed()) == ("steady", 4, 0.75, 3)
    for text, words in (("playtest: {noise: expert, min_pass: 0.5}", "expert"),
                        ("playtest: {min_pass: 1.5}", "min_pass"),
                        ("playtest: {noise: human}", "min_pass"),
                        ("playtest: {min_pass: 0.5, tries: 0}", "tries")):
        log = _sidecar(tmp_path, "expect:\n  - never_fell: true\n" + text + "\n")
        with pytest.raises(DataError) as caught:
            load_bar(str(log))
        message = str(caught.value)
        assert "sit.expect.yaml:3:" in message and words in message, message
        assert "\n" not in message


def _puppet(*args, cwd=None):
    return subprocess.run([sys.executable, "-m", "puppet", "playtest", *args],
                          capture_output=True, text=True, timeout=600, cwd=cwd)


def test_the_command_reports_a_table_json_and_exits_1_on_a_missed_bar(tmp_path):
    log = tmp_path / "flip.jsonl"
    shutil.copy(FIXTURES / "biped-backflip-2026-12.jsonl", log)
    shutil.copy(FIXTURES / "biped-floor-2026-12.yaml", tmp_path)
    side = (FIXTURES / "biped-backflip-2026-12.expect.yaml").read_text(encoding="utf-8")
    (tmp_path / "flip.expect.yaml").write_text(
        side + "playtest: {noise: human, tries: 20, min_pass: 0.9}\n", encoding="utf-8")
    proc = _puppet(str(log), "--tries", "2", "--no-save")
    assert proc.returncode == 1, proc.stdout + proc.stderr
    row = [line for line in proc.stdout.splitlines() if line.startswith(str(log))][0]
    assert "0/2" in row and "MISSED" in row and "first_touch" in row
    assert "Traceback" not in proc.stderr
    proc = _puppet(str(log), "--tries", "2", "--json", "--no-save", "--noise", "steady")
    assert proc.returncode == 0  # another level: the bar is not checked
    out = json.loads(proc.stdout)[0]
    assert out["tries"] == 2 and out["bar"]["met"] is None and out["noise"] == "steady"
    assert [r["index"] for r in out["results"]] == [0, 1]


@pytest.mark.parametrize("args, words", [
    (["nope-no-such-log"], "no log named 'nope-no-such-log'"),
    (["luxo-hop", "--timing-ms", "-5"], "argument --timing-ms: '-5' is not a number"),
    (["luxo-hop", "--noise", "expert"], "argument --noise: invalid choice"),
    (["luxo-hop", "--jobs", "0"], "argument --jobs/-j"),
])
def test_errors_are_one_line(args, words):
    proc = _puppet(*args, "--no-save", "--tries", "1")
    assert proc.returncode == 2
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and words in lines[0] and lines[0].startswith("puppet playtest"), \
        proc.stderr


def test_a_log_without_feat_expectations_is_an_error(tmp_path):
    log = _sidecar(tmp_path, "expect:\n  - final_hash: 0123456789abcdef\n")
    with pytest.raises(DataError, match="no feat expectations"):
        prepare(str(log))


def test_the_window_shows_the_last_playtest_figure_of_its_interface(tmp_path, monkeypatch):
    import pygame

    from puppet.app import hud, window
    from puppet.timeline.playtest import store

    kept = tmp_path / "playtests.json"
    monkeypatch.setenv("PUPPET_PLAYTESTS", str(kept))  # the command, in its process
    proc = _puppet("luxo-keys-sit-stand", "--tries", "2", "--noise", "steady")
    assert proc.returncode == 0, proc.stderr
    entry = json.loads(kept.read_text(encoding="utf-8"))["interfaces"]["luxo-keys"]
    assert (entry["log"], entry["passes"], entry["tries"], entry["noise"]) == \
        ("luxo-keys-sit-stand", 2, 2, "steady")
    monkeypatch.setattr(store, "STORE", kept)  # the window, here
    shown = []
    real_draw = hud.draw_hud
    monkeypatch.setattr(hud, "draw_hud", lambda surface, session, info, *fonts: (
        shown.append(info.playtest), real_draw(surface, session, info, *fonts)))
    frames = {"n": 0}
    real_get = pygame.event.get

    def fake_get(*args, **kw):
        real_get()
        frames["n"] += 1
        return [pygame.event.Event(pygame.QUIT)] if frames["n"] >= 3 else []

    monkeypatch.setattr(pygame.event, "get", fake_get)
    assert window.run_window(load_setup("luxo-keys"), no_record=True) == 0
    assert shown and shown[-1] == "playtest luxo-keys-sit-stand: 2/2 pass at steady"
    assert store.figure_line(store.last_for("luxo-mouse")) == ""  # none for that one


def test_a_log_with_no_events_moves_nothing():
    assert perturb([], [], DT, 100, LEVELS["novice"], 0, 0, APP_KEYS).pairs == []
