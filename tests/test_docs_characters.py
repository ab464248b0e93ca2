"""docs/characters.md and docs/scenes.md: every complete file they show is valid; the
characters stand as the chapter says (the stability check), the report shown is the
report printed, and the frog's first version fails the way the chapter tells."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from puppet.commands import main
from puppet.commands.check import check_file
from puppet.data.catalog import ROOT, load_setup
from puppet.interface import events as ev
from puppet.session import Session
from puppet.session.playback import play
from tests.test_docs import yaml_blocks

DOCS = ROOT / "docs"
MARK = re.compile(r"# file: (characters|interfaces|assets/scenes)/([A-Za-z0-9_.-]+\.yaml)\s*$")


def files(doc: str) -> list[tuple[str, str, int, str]]:
    """(folder, name, line, text) of every complete file a doc shows."""
    out = []
    for line, text in yaml_blocks(DOCS / doc):
        m = MARK.match(text.splitlines()[0])
        if m:
            out.append((m.group(1).split("/")[-1], m.group(2), line, text))
    return out


def write_all(tmp_path: Path, doc: str) -> dict[str, Path]:
    """Every file of ``doc`` written out; characters also beside the interfaces (an
    interface reads a character from its own folder)."""
    paths = {}
    for folder, name, _, text in files(doc):
        path = tmp_path / folder / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text, encoding="utf-8")
        if folder == "characters":
            (tmp_path / "interfaces").mkdir(exist_ok=True)
            (tmp_path / "interfaces" / name).write_text(text, encoding="utf-8")
        paths[name] = path
    return paths


def test_the_chapter_shows_characters_an_interface_and_scenes():
    names = {name for _, name, _, _ in files("characters.md")}
    assert {"stick.yaml", "frog.yaml", "frog-try.yaml"} <= names
    assert len(files("scenes.md")) >= 4


@pytest.mark.parametrize("doc", ["characters.md", "scenes.md"])
def test_every_file_the_docs_show_is_valid(tmp_path, doc):
    paths = write_all(tmp_path, doc)
    for folder, name, line, _ in files(doc):
        kind = check_file(paths[name])
        assert kind == {"characters": "character", "interfaces": "interface",
                        "scenes": "scene"}[folder], (doc, line)


def test_the_chapters_characters_stand_without_a_warning(tmp_path, capsys):
    paths = write_all(tmp_path, "characters.md")
    for name in ("stick.yaml", "frog.yaml"):
        assert main(["check", str(paths[name])]) == 0
        out, err = capsys.readouterr()
        assert err == "", err
        assert "  stands: held its start pose 5 s" in out and "nudged" in out


def test_the_report_the_chapter_shows_is_what_check_prints(capsys, monkeypatch):
    text = (DOCS / "characters.md").read_text(encoding="utf-8")
    block = text.split("$ puppet check characters/luxo.yaml\n", 1)[1].split("```", 1)[0]
    monkeypatch.chdir(ROOT)
    assert main(["check", "characters/luxo.yaml"]) == 0
    assert capsys.readouterr().out == block


def test_the_frogs_first_version_sinks_and_tips_as_the_chapter_says(tmp_path, capsys):
    frog = write_all(tmp_path, "characters.md")["frog.yaml"]
    text = frog.read_text(encoding="utf-8")
    first = re.sub(r"start:\n.*", "start:\n  joints: {hip_near: 100, knee_near: -160, "
                   "ankle_near: 60, hip_far: 100, knee_far: -160, ankle_far: 60}\n", text,
                   flags=re.S)
    assert first != text
    path = tmp_path / "characters" / "frog-first.yaml"
    path.write_text(first.replace("name: frog\n", "name: frog-first\n"), encoding="utf-8")
    assert main(["check", str(path)]) == 0
    err = capsys.readouterr().err
    assert "warning: it sinks onto body" in err and "warning: it tips +2" in err, err


def test_the_frog_interface_plays_and_the_mouse_folds_the_hind_legs(tmp_path):
    paths = write_all(tmp_path, "characters.md")
    session = Session(load_setup(str(paths["frog-try.yaml"])))
    servos = session.character.servos
    play(session, [(0, ev.mouse(0.5, 0.0))], 240)
    assert servos["hip_near"].target == pytest.approx(0.0 + 80 * 3.14159265 / 180, rel=1e-6)
    assert session.character.upright()
