"""A log names only what it may (issue 32): its header reaches catalog entries, or
files of the right kind directly beside the log - never a folder under it, never a
hidden one; no message quotes what a file the log pointed at holds, nor tells whether
a file exists outside what the log may name; a log downloaded into a home folder reads
nothing else there."""

import json
import os
from pathlib import Path

import pytest

from puppet.data import catalog, yamlfile
from puppet.data.catalog import load_setup
from puppet.data.errors import DataError
from puppet.interface import events as ev
from puppet.session import Session
from puppet.session.playback import play
from puppet.timeline.log import Recorder
from puppet.timeline.replay import replay

ROOT = Path(__file__).resolve().parents[1]
SECRET = "hunter2-5e1c"
SECRET_YAML = f'ground: ["{SECRET}"]\npassword: {SECRET}\n'


@pytest.fixture
def reads(monkeypatch):
    """Every data file the loader reads (resolved)."""
    seen = []
    real = yamlfile.read_text
    monkeypatch.setattr(yamlfile, "read_text", lambda p: seen.append(Path(p).resolve())
                        or real(p))
    monkeypatch.setattr(catalog, "read_text", yamlfile.read_text)
    return seen


@pytest.fixture(scope="module")
def recorded(tmp_path_factory) -> str:
    """The text of a short log of luxo-mouse on flat."""
    folder = tmp_path_factory.mktemp("rec")
    session = Session(load_setup("luxo-mouse"))
    with Recorder(session, folder / "run.jsonl"):
        play(session, [(0, ev.mouse(0.9, 0.2))], 60)
    return (folder / "run.jsonl").read_text()


def _log(folder: Path, text: str, **changes) -> Path:
    lines = text.splitlines()
    header = json.loads(lines[0])
    for key, value in changes.items():
        if value is None:
            header.pop(key, None)
        else:
            header[key] = value
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / "run.jsonl"
    path.write_text("\n".join([json.dumps(header)] + lines[1:]) + "\n")
    return path


def _message(log: Path) -> str:
    try:
        replay(log, check=False)
    except DataError as exc:
        return str(exc)
    return "(replayed)"


def _plant(path: Path, text: str = SECRET_YAML) -> Path:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text)
    return path


@pytest.mark.parametrize("name", ["sub/scene.yaml", ".config/scene.yaml", ".scene.yaml",
                                  "sub/../.config/scene.yaml", "./sub/scene.yaml"])
def test_a_header_reaches_no_file_under_or_hidden_beside_the_log(tmp_path, recorded,
                                                                 reads, name):
    log = _log(tmp_path / "dl", recorded, scene=name)
    secret = _plant(log.parent / name)
    message = _message(log)
    assert "it was not read" in message and SECRET not in message, message
    assert secret.resolve() not in reads


@pytest.mark.parametrize("name", ["sub/scene.yaml", ".config/scene.yaml", "../scene.yaml",
                                  ".scene.yaml", "sub/../../up/scene.yaml"])
def test_messages_do_not_tell_whether_a_file_exists_outside(tmp_path, recorded, name):
    absent = _message(_log(tmp_path / "a" / "dl", recorded, scene=name))
    log = _log(tmp_path / "b" / "dl", recorded, scene=name)
    _plant(log.parent / name)
    present = _message(log)
    assert present.replace("/b/", "/a/") == absent, (present, absent)


def test_a_file_beside_the_log_that_fails_is_not_quoted(tmp_path, recorded, reads):
    log = _log(tmp_path / "dl", recorded, scene="notes.yaml")
    notes = _plant(log.parent / "notes.yaml")
    message = _message(log)
    assert SECRET not in message and "password" not in message, message
    assert message.startswith(f"{log}:1: header: the files it names beside the log "
                              "(notes.yaml) do not make a valid session"), message
    assert f"puppet check {notes.resolve()}" in message
    assert "\n" not in message


def test_an_interface_checked_against_a_character_beside_the_log_quotes_none_of_it(
        tmp_path, recorded, reads):
    """The recorded interface (the log's own copy) names a character beside the log
    whose joints are not the ones it drives: the error would list that file's joints."""
    luxo = (ROOT / "characters" / "luxo.yaml").read_text()
    assert "name: knee" in luxo
    folder = tmp_path / "dl"
    _plant(folder / "lamp.yaml", luxo.replace("name: knee", f"name: {SECRET}")
           .replace("knee: 55", f"{SECRET}: 55"))
    text = json.loads(recorded.splitlines()[0])["interface_text"]
    log = _log(folder, recorded, interface="gone", interface_text=text.replace(
        "character: luxo", "character: lamp"), interface_hash=None)
    message = _message(log)
    assert "(lamp.yaml) do not make a valid session" in message, message
    assert SECRET not in message


def test_a_reload_event_against_a_character_beside_the_log_quotes_none_of_it(
        tmp_path, recorded):
    """The log's reload names a joint the lamp beside it lacks: the error would list
    the lamp's joints, one of them named in that file only."""
    luxo = (ROOT / "characters" / "luxo.yaml").read_text()
    folder = tmp_path / "dl"
    _plant(folder / "lamp.yaml", luxo.replace("name: ankle", f"name: ankle_{SECRET}")
           .replace("{ankle: ", f"{{ankle_{SECRET}: "))
    knee_only = ("name: lamp-knee\ndescription: the knee\ncharacter: lamp\nscene: flat\nmaps:\n"
                 "  - {input: mouse.y, joint: knee, from: [0, 1], to: [160, -20]}\n")
    lines = recorded.splitlines()
    reload = json.dumps({"step": 10, "event": {"type": "reload", "text": knee_only.replace(
        "joint: knee", "joint: ankle")}})
    log = _log(folder, "\n".join([lines[0], lines[1], reload, *lines[2:]]),
               interface="gone", interface_text=knee_only, interface_hash=None)
    message = _message(log)
    assert "cannot apply this event" in message and SECRET not in message, message


def test_a_changed_file_beside_the_log_is_named_without_its_hash(tmp_path, recorded):
    flat = (ROOT / "assets" / "scenes" / "flat.yaml").read_text()
    log = _log(tmp_path / "dl", recorded, scene="my-flat.yaml")
    _plant(log.parent / "my-flat.yaml", flat + "\n# edited\n")
    result = replay(log, check=False)
    warned = [w for w in result.warnings if "my-flat.yaml" in w]
    assert warned and "differs from the one recorded" in warned[0], result.warnings
    assert "hash " + catalog.file_hash(log.parent / "my-flat.yaml") not in warned[0]


def test_a_log_downloaded_into_a_home_folder_reads_nothing_else_there(
        tmp_path, recorded, reads, monkeypatch):
    home = tmp_path / "home" / "me"
    monkeypatch.setenv("HOME", str(home))
    planted = [_plant(home / p) for p in (".ssh/keys.yaml", ".config/puppet/scene.yaml",
                                           "Documents/scene.yaml", "Documents/lamp.yaml",
                                           "Downloads/other/scene.yaml")]
    (home / "creds").write_text(SECRET)
    (home / "Documents" / "linked.yaml").symlink_to(planted[0])
    downloads = home / "Downloads"
    os.symlink(planted[2], downloads / "scene-link.yaml")  # beside, leading into Documents
    os.symlink(home / "Documents", downloads / "docs")
    spellings = []
    for p in planted + [home / "Documents" / "linked.yaml"]:
        spellings += [str(p), os.path.relpath(p, downloads), "~/" + str(p.relative_to(home)),
                      "$HOME/" + str(p.relative_to(home))]
    spellings += ["scene-link.yaml", "docs/scene.yaml", "docs/lamp", "../creds",
                  str(home / "creds"), "other/scene"]
    text = json.loads(recorded.splitlines()[0])["interface_text"]
    for name in spellings:
        for header in ({"scene": name},
                       {"interface": name, "interface_text": None},
                       {"interface": "gone", "interface_hash": None,
                        "interface_text": text.replace("character: luxo",
                                                       f"character: '{name}'")}):
            log = _log(downloads, recorded, **header)
            message = _message(log)
            assert SECRET not in message, (name, message)
            assert "not read" in message or "no " in message, (name, message)
    assert not [p for p in reads if home in p.parents], reads
