"""A character's own simulation step (``solver: {step: 1/240}``, issue 29): a new
session runs on it (window, headless play, tuning, the benchmark), its log's header
records it ('dt'), and a replay runs on the header's step whatever the character says
today, so a log recorded before a character changed its step replays bit for bit."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from puppet.data.catalog import ROOT, load_setup
from puppet.data.characters import parse_character
from puppet.data.errors import DataError
from puppet.data.yamlfile import load_text
from puppet.interface import events as ev
from puppet.physics.simulation import DEFAULT_DT, step_of
from puppet.session import Session
from puppet.session.playback import play
from puppet.timeline.log import Recorder, read_log
from puppet.timeline.replay import apply_log, new_session, replay

LUXO = (ROOT / "characters" / "luxo.yaml").read_text()


def _luxo(solver: str) -> str:
    """luxo.yaml with a solver line (its own has none)."""
    assert "\nsolver:" not in LUXO
    return LUXO.replace("\nview_height:", f"\nsolver: {solver}\nview_height:", 1)


def _with_step(setup, step):
    from puppet.data.characters import SolverSpec

    return setup.__class__(**{**setup.__dict__, "character": setup.character.model_copy(
        update={"solver": SolverSpec(step=step)})})


@pytest.mark.parametrize("written, dt", [("1/240", 1 / 240), ("0.0041667", 0.0041667),
                                         ("1/480", 1 / 480), ("1/2000", 1 / 2000)])
def test_the_step_is_a_fraction_or_seconds(written, dt):
    spec = parse_character(load_text(_luxo(f"{{step: {written}}}"), "lamp.yaml"))
    assert spec.solver.dt == pytest.approx(dt, rel=1e-12)
    assert step_of(spec) == spec.solver.dt


def test_without_a_step_the_engine_default():
    spec = parse_character(load_text(LUXO, "lamp.yaml"))
    assert spec.solver.step is None and spec.solver.dt is None
    assert step_of(spec) == DEFAULT_DT == 1 / 480


@pytest.mark.parametrize("written", ["1/10", "0", "fast", "1/0", "true", "[1, 240]"])
def test_a_bad_step_is_one_line_at_its_place(written):
    with pytest.raises(DataError) as info:
        parse_character(load_text(_luxo(f"{{step: {written}}}"), "lamp.yaml"))
    said = str(info.value)
    assert said.startswith("lamp.yaml:") and "'solver.step'" in said and "\n" not in said


def test_a_session_runs_on_its_characters_step_and_its_log_records_it(tmp_path):
    """The window, headless play and the tests build a Session without a step: the
    character's. The recorded log's header keeps it, and a replay (which takes the
    header's) reaches the recorded end state, on today's luxo.yaml (no step)."""
    setup = _with_step(load_setup("luxo-mouse"), "1/240")
    session = Session(setup)
    assert session.sim.dt == 1 / 240
    assert session.runtime.dt == 1 / 240
    path = tmp_path / "lamp-240.jsonl"
    with Recorder(session, path):
        play(session, [(0, ev.mouse(0.9, 0.2)), (120, ev.mouse(0.5, 0.6))], 240)
    log = read_log(path)
    assert log.header["dt"] == 1 / 240 and log.end["end"] == 240
    result = replay(path)
    assert result.same_end, result
    plain = Session(load_setup("luxo-mouse"))  # today's luxo: the engine's step
    assert plain.sim.dt == DEFAULT_DT


@pytest.mark.parametrize("name", ["luxo-keys-sit-stand", "luxo-hop"])
def test_a_log_replays_on_its_headers_step_whatever_the_character_says(name):
    """A Luxo log recorded at 1/480 s, replayed on a Luxo whose file says 1/240: the
    header's step plays, bit for bit."""
    path = ROOT / "assets" / "logs" / f"{name}.jsonl"
    log = read_log(path)
    assert log.header["dt"] == 1 / 480
    from puppet.timeline.replay import setup_for_log

    setup, _ = setup_for_log(log)
    session = new_session(log, _with_step(setup, "1/240"))
    assert session.sim.dt == 1 / 480
    apply_log(session, log)
    assert session.sim.state_hash() == log.end["hash"]


def test_headless_play_records_the_characters_step(tmp_path, monkeypatch):
    """``puppet play --headless --record`` with an interface whose character (a file
    beside it) says 1/240: the log's header says 1/240, a scripted run's events land on
    that step, and the log replays to its end state."""
    from puppet.commands import main

    folder = tmp_path / "lamp"
    folder.mkdir()
    (folder / "lamp240.yaml").write_text(_luxo("{step: 1/240}"))
    text = (ROOT / "interfaces" / "luxo-mouse.yaml").read_text()
    text = text.replace("\ncharacter: luxo\n", "\ncharacter: lamp240.yaml\n", 1)
    assert "character: lamp240.yaml" in text
    (folder / "lamp-mouse.yaml").write_text(text)
    (folder / "moves.yaml").write_text(
        "events:\n  - {t: 0.5, mouse: [0.9, 0.2]}\n  - {t: 1.0, mouse: [0.5, 0.6]}\n")
    out = folder / "run.jsonl"  # beside its interface and character
    monkeypatch.setenv("SDL_VIDEODRIVER", "dummy")
    code = main(["play", str(folder / "lamp-mouse.yaml"), "--headless", "--seconds", "1.5",
                 "--input", str(folder / "moves.yaml"), "--record", str(out)])
    assert code in (0, None)
    lines = [json.loads(line) for line in Path(out).read_text().splitlines()]
    assert lines[0]["dt"] == 1 / 240
    steps = [line["step"] for line in lines[1:-1]]
    assert steps == [120, 240]  # 0.5 s and 1 s on a 1/240 s step
    assert lines[-1]["end"] == 360
    assert replay(out).same_end
