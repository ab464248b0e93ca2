"""Names are not paths: a name written in a data file or a log header reaches only the
catalog or a file inside a folder the user named on the command line; anything else is
refused without being read (a log someone sends you cannot read your files)."""

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from puppet.data import catalog, yamlfile
from puppet.data.catalog import find, load_setup
from puppet.data.errors import DataError
from puppet.interface import events as ev
from puppet.session import Session
from puppet.session.playback import play
from puppet.timeline.log import Recorder
from puppet.timeline.replay import replay

ROOT = Path(__file__).resolve().parents[1]
SECRET = "name: top-secret-9f3a\ndescription: a file of yours\n"


@pytest.fixture
def reads(monkeypatch):
    """Every data file the loader reads."""
    seen = []
    real = yamlfile.read_text
    monkeypatch.setattr(yamlfile, "read_text", lambda p: seen.append(Path(p).resolve())
                        or real(p))
    monkeypatch.setattr(catalog, "read_text", yamlfile.read_text)
    return seen


@pytest.fixture
def secret(tmp_path):
    folder = tmp_path / "home"
    folder.mkdir()
    path = folder / "secret.yaml"
    path.write_text(SECRET)
    return path


def _record(tmp_path, name="shared") -> Path:
    """A log of luxo-mouse on flat in its own folder, its header edited later."""
    folder = tmp_path / name
    folder.mkdir()
    session = Session(load_setup("luxo-mouse"))
    path = folder / "run.jsonl"
    with Recorder(session, path):
        play(session, [(0, ev.mouse(0.9, 0.2))], 100)
    return path


def _edit_header(path: Path, **changes) -> None:
    lines = path.read_text().splitlines()
    header = json.loads(lines[0])
    for key, value in changes.items():
        if value is None:
            header.pop(key, None)
        else:
            header[key] = value
    path.write_text("\n".join([json.dumps(header)] + lines[1:]) + "\n")


@pytest.mark.parametrize("key", ["scene", "character"])
def test_a_log_header_cannot_name_a_file_outside(tmp_path, secret, reads, key):
    log = _record(tmp_path)
    _edit_header(log, **{key: str(secret)}, interface_text=None)
    if key == "scene":
        with pytest.raises(DataError) as info:
            replay(log)
        message = str(info.value)
        assert "is neither a scene of the catalog" in message and "not read" in message
        assert "top-secret" not in message
    else:  # the character in the header is informative: the interface names its own
        replay(log)
    assert secret.resolve() not in reads


@pytest.mark.parametrize("how", ["absolute", "dotdot"])
def test_a_log_header_interface_outside_is_not_read_the_copy_replays(tmp_path, secret,
                                                                     reads, how):
    log = _record(tmp_path)
    evil = secret.with_name("evil-iface.yaml")
    evil.write_text((ROOT / "interfaces" / "luxo-mouse.yaml").read_text())
    name = str(evil) if how == "absolute" else os.path.relpath(evil, log.parent)
    assert how == "absolute" or name.startswith("..")
    _edit_header(log, interface=name)
    result = replay(log)
    assert evil.resolve() not in reads
    assert any(w.endswith(f"note: interface file '{name}' is outside the catalog and the log's "
                   "folder, so it is not read (a log reads no other files); the copy "
                   "recorded in the log plays") for w in result.warnings), result.warnings
    assert result.same_end


def test_without_a_copy_an_outside_interface_is_a_header_error(tmp_path, secret, reads):
    log = _record(tmp_path)
    _edit_header(log, interface=str(secret), interface_text=None)
    with pytest.raises(DataError, match=r"run.jsonl:1: header: .*is neither an? interface"):
        replay(log)
    assert secret.resolve() not in reads


def test_the_embedded_interface_cannot_name_a_file_outside(tmp_path, secret, reads):
    log = _record(tmp_path)
    text = (ROOT / "interfaces" / "luxo-mouse.yaml").read_text()
    _edit_header(log, interface="gone-away",
                 interface_text=text.replace("character: luxo", f"character: {secret}"))
    with pytest.raises(DataError) as info:
        replay(log)
    assert "is neither a character of the catalog" in str(info.value)
    assert secret.resolve() not in reads and "top-secret" not in str(info.value)


def test_a_symlink_in_the_log_folder_to_a_file_outside_is_refused(tmp_path, secret, reads):
    log = _record(tmp_path)
    (log.parent / "scene.yaml").symlink_to(secret)
    _edit_header(log, scene="scene.yaml")
    with pytest.raises(DataError, match="not read"):
        replay(log)
    assert secret.resolve() not in reads


def test_files_beside_the_log_and_catalog_paths_resolve(tmp_path, reads):
    log = _record(tmp_path)
    mine = log.parent / "my-flat.yaml"
    mine.write_text((ROOT / "assets" / "scenes" / "flat.yaml").read_text())
    _edit_header(log, scene="my-flat.yaml")
    assert replay(log).same_end and mine.resolve() in reads
    # an absolute path into this checkout's catalog is that catalog file
    _edit_header(log, scene=str(ROOT / "assets" / "scenes" / "flat.yaml"),
                 interface=str(ROOT / "interfaces" / "luxo-mouse.yaml"), interface_text=None)
    assert replay(log).same_end


def test_an_interface_names_files_only_in_the_catalog_or_its_own_folder(tmp_path, secret):
    folder = tmp_path / "mine"
    folder.mkdir()
    text = (ROOT / "interfaces" / "luxo-mouse.yaml").read_text()
    (folder / "lamp.yaml").write_text((ROOT / "characters" / "luxo.yaml").read_text())
    iface = folder / "iface.yaml"
    iface.write_text(text.replace("character: luxo", "character: lamp"))
    assert load_setup(str(iface)).character_path == (folder / "lamp.yaml").resolve()
    for bad in (str(secret), f"../home/{secret.name}", "/etc/passwd", "../../x.yaml"):
        iface.write_text(text.replace("character: luxo", f"character: '{bad}'"))
        with pytest.raises(DataError) as info:
            load_setup(str(iface))
        assert info.value.path == str(iface) and info.value.line is not None, info.value
        assert "not read" in info.value.message or "no character named" in info.value.message


def test_a_name_too_long_or_with_nul_is_refused_in_one_line():
    with pytest.raises(DataError, match="no interface named|no such file"):
        find("interface", "x" * 300 + ".yaml")
    with pytest.raises(DataError, match="not a scene name"):
        find("scene", "fl\x00at", within=())


def test_shipped_log_headers_use_catalog_names():
    for log in sorted((ROOT / "assets" / "logs").glob("*.jsonl")):
        header = json.loads(log.read_text().splitlines()[0])
        for key in ("interface", "character", "scene"):
            assert "/" not in header[key], (log, key)


def test_cli_replay_of_a_hostile_log_is_one_line_exit_2(tmp_path, secret):
    log = _record(tmp_path)
    _edit_header(log, scene=str(secret))
    proc = subprocess.run([sys.executable, "-m", "puppet", "replay", str(log), "--headless"],
                          capture_output=True, text=True)
    assert proc.returncode == 2, proc.stderr
    assert proc.stderr.count("\n") == 1 and "not read" in proc.stderr, proc.stderr
    assert "top-secret" not in proc.stderr + proc.stdout


LOGS = ROOT / "assets" / "logs"


def test_a_bare_log_name_is_found_among_the_saved_recordings(tmp_path, monkeypatch):
    """assets/logs/ first, then recordings/ (where the window saves its sessions)."""
    from puppet.data import catalog
    from puppet.timeline.replay import find_log

    monkeypatch.setitem(catalog.FOLDERS, "recording", (str(tmp_path), ".jsonl"))
    shutil.copy(LOGS / "luxo-hop.jsonl", tmp_path / "my-take.jsonl")
    assert find_log("my-take") == str(tmp_path / "my-take.jsonl")
    assert find_log("luxo-hop") == str(LOGS / "luxo-hop.jsonl")
    with pytest.raises(DataError) as info:
        find_log("no-such-take")
    assert "no log named 'no-such-take'" in str(info.value)
