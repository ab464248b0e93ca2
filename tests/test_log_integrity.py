"""A log's integrity: events in step order, key names a device sends, hashes of 16 hex
digits, the header's interface text the file of its hash; and the words of the
warnings about the files a header names (one wording for check and replay)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from helpers import recorded_then_edited

from puppet.commands import main
from puppet.data.catalog import ROOT, file_hash
from puppet.data.errors import DataError
from puppet.testing import record_script
from puppet.timeline.log import read_log, text_hash
from puppet.timeline.replay import replay, setup_for_log

LOGS = ROOT / "assets" / "logs"
# the handstand log as shipped on 2026-12-06 (h, then g): line 3: step 241, line 4: step 1292
HANDSTAND = Path(__file__).parent / "fixtures" / "log-integrity" / "biped-handstand-2026-12.jsonl"
HOP = LOGS / "luxo-hop.jsonl"


def _lines(path: Path) -> list[str]:
    return path.read_text(encoding="utf-8").splitlines()


def _write(path: Path, lines: list[str]) -> Path:
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path


def _edited(tmp_path: Path, name: str, line: int, old: str, new: str,
            source: Path = HANDSTAND) -> Path:
    lines = _lines(source)
    assert old in lines[line - 1], lines[line - 1][:200]
    lines[line - 1] = lines[line - 1].replace(old, new)
    return _write(tmp_path / name, lines)


def _run(capsys, *argv) -> tuple[int, str, str]:
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def _refused_by_both(capsys, path: Path, message: str) -> None:
    """check and replay refuse ``path`` with one line (exit 2) that has ``message``."""
    for argv in (("check", path), ("replay", "--headless", path)):
        code, out, err = _run(capsys, *argv)
        assert code == 2 and err.count("\n") == 1 and message in err, (argv, code, err)
        assert "Traceback" not in err


# -- 1. step order ---------------------------------------------------------------------
def test_an_event_moved_before_an_earlier_one_is_refused(tmp_path, capsys):
    moved = _edited(tmp_path, "moved.jsonl", 4, '"step":1292', '"step":100')
    with pytest.raises(DataError) as info:
        read_log(moved)
    assert str(info.value).startswith(
        f"{moved}:4: step 100 comes before step 241 of line 3; a log's events are in step "
        "order"), info.value
    _refused_by_both(capsys, moved, f"{moved}:4: step 100 comes before step 241 of line 3")
    log = read_log(moved, allow_truncated=True)  # the lines before it, on request
    assert log.truncated_at == 4 and len(log.events) == 2


def _hop_with(tmp_path, events: list[dict]) -> Path:
    header = _lines(HOP)[0]
    lines = [header] + [json.dumps(e) for e in events]
    return _write(tmp_path / "made.jsonl", lines)


def _mouse(step):
    return {"step": step, "event": {"type": "mouse", "x": 0.5, "y": 0.5}}


def _key(step, key, down=True):
    return {"step": step, "event": {"type": "key", "key": key, "down": down}}


def test_after_a_rewind_the_steps_go_on_from_its_to_step(tmp_path):
    rewind = {"step": 960, "event": {"type": "action", "name": "rewind", "to_step": 480}}
    assert len(read_log(_hop_with(tmp_path, [_mouse(0), _mouse(960), rewind, _mouse(480),
                                              _mouse(500)])).events) == 5
    bad = _hop_with(tmp_path, [_mouse(0), _mouse(960), rewind, _mouse(479)])
    with pytest.raises(DataError, match=r"made.jsonl:5: step 479 comes before step 480, "
                                        r"where the rewind of line 4 went"):
        read_log(bad)


def test_a_restore_or_a_scrub_may_go_back_anywhere_but_nothing_else_may(tmp_path):
    restore = {"step": 900, "event": {"type": "action", "name": "restore"}}
    for events in ([_mouse(0), _mouse(900), restore, _mouse(10)],
                   [_mouse(0), _key(900, "backspace"), _mouse(10)],  # the restore key
                   [_mouse(0), _key(900, "b"), _mouse(800), _mouse(700),  # scrubbing back
                    {"step": 700, "event": {"type": "action", "name": "rewind",
                                            "to_step": 700}}, _key(700, "b", False)]):
        read_log(_hop_with(tmp_path, events))
    for events in ([_mouse(0), _key(900, "h"), _mouse(10)],  # not an app key
                   [_mouse(0), _key(900, "b"), _key(800, "b", False), _mouse(10)],
                   [_mouse(0), _key(900, "backspace", False), _mouse(10)]):
        with pytest.raises(DataError, match="comes before step"):
            read_log(_hop_with(tmp_path, events))


# -- 2. key names ------------------------------------------------------------------------
def test_a_key_name_no_device_sends_is_refused_with_the_did_you_mean(tmp_path, capsys):
    wq = _edited(tmp_path, "wq.jsonl", 4, '"key":"g"', '"key":"wq"')
    _refused_by_both(capsys, wq, f"{wq}:4: key event: unknown key name 'wq';")
    typo = _edited(tmp_path, "typo.jsonl", 4, '"key":"g"', '"key":"spcae"')
    with pytest.raises(DataError, match="unknown key name 'spcae'; did you mean 'space'"):
        read_log(typo)
    chord = _edited(tmp_path, "chord.jsonl", 4, '"key":"g"', '"key":"ctrl+g"')
    assert read_log(chord).events[2].event["key"] == "ctrl+g"
    gesture = {"step": 0, "event": {"type": "gesture", "key": "gg", "path": [[0, 0.5, 0.5]]}}
    with pytest.raises(DataError, match="gesture event: unknown key name 'gg'"):
        read_log(_hop_with(tmp_path, [gesture]))


# -- 3. hashes ---------------------------------------------------------------------------
def test_a_hash_is_16_hex_digits(tmp_path, capsys):
    end = _lines(HANDSTAND)[-1]
    zz = _edited(tmp_path, "zz.jsonl", len(_lines(HANDSTAND)), end,
                 json.dumps({"end": json.loads(end)["end"], "hash": "zz"}))
    _refused_by_both(capsys, zz, "bad end line: 'hash' must be a state hash of 16 hex digits "
                                 "(0-9, a-f), got 'zz'")
    header = json.loads(_lines(HANDSTAND)[0])
    for key in ("interface_hash", "character_hash", "scene_hash"):
        short = _edited(tmp_path, f"{key}.jsonl", 1, header[key], header[key][:15])
        _refused_by_both(capsys, short, f"{short}:1: header: '{key}' must be a hash of 16 "
                                        f"hex digits (0-9, a-f), got '{header[key][:15]}'")
    upper = _edited(tmp_path, "upper.jsonl", 1, header["scene_hash"],
                    header["scene_hash"].upper())
    with pytest.raises(DataError, match="'scene_hash' must be a hash"):
        read_log(upper)


# -- 4. the interface text the header keeps ----------------------------------------------
def _with_header(tmp_path, name, source=HOP, **changes) -> Path:
    lines = _lines(source)
    header = json.loads(lines[0])
    header.update(changes)
    return _write(tmp_path / name, [json.dumps(header)] + lines[1:])


def test_a_copy_edited_after_the_recording_is_played_with_a_warning(tmp_path, capsys):
    text = json.loads(_lines(HOP)[0])["interface_text"]
    assert text_hash(text.encode()) == json.loads(_lines(HOP)[0])["interface_hash"]
    edited = _with_header(tmp_path, "edited.jsonl",
                          interface_text=text.replace("[80, -80]", "[0, 0]", 1))
    now = text_hash(text.replace("[80, -80]", "[0, 0]", 1).encode())
    recorded = file_hash(ROOT / "interfaces" / "luxo-mouse.yaml")
    warning = (f"{edited}: warning: the header's 'interface_text' (hash {now}) is not the "
               f"file recorded ('interface_hash' {recorded}): the copy was edited after the "
               "recording; ")
    result = replay(edited, as_recorded=True, check=False)
    assert result.warnings == [warning + "playing it, not the session recorded"]
    code, out, err = _run(capsys, "check", edited)  # check says what --as-recorded plays
    assert code == 0 and err == warning + "a replay of the copy (puppet replay " \
                                          "--as-recorded) plays it\n", err
    assert replay(edited, check=False).warnings == []  # today's file plays: no copy
    gone = _with_header(tmp_path, "gone.jsonl", interface="no-such-interface",
                        interface_text=text + "# edited\n")
    assert any("is not the file recorded" in w for w in replay(gone, check=False).warnings)
    assert replay(HOP, as_recorded=True).warnings == []


def test_the_recorder_keeps_the_files_bytes_and_an_old_crlf_copy_is_the_file(tmp_path):
    crlf = tmp_path / "crlf-iface.yaml"
    crlf.write_bytes((ROOT / "interfaces" / "luxo-mouse.yaml").read_bytes()
                     .replace(b"\n", b"\r\n"))
    log = record_script("luxo-hop", tmp_path / "crlf.jsonl", interface=str(crlf), seconds=0.1)
    header = json.loads(_lines(log)[0])
    assert "\r\n" in header["interface_text"]
    assert text_hash(header["interface_text"].encode()) == header["interface_hash"] \
        == file_hash(crlf)
    old = _with_header(tmp_path, "old.jsonl", source=log,  # read with universal newlines
                       interface_text=header["interface_text"].replace("\r\n", "\n"))
    assert replay(old, as_recorded=True, check=False).warnings == []


# -- 5. one wording for a file that differs from the one recorded ------------------------
def test_a_variant_in_the_logs_folder_is_said_to_differ_in_one_wording(tmp_path, capsys):
    variant = tmp_path / "luxo-mouse.yaml"  # a variant of the catalog name, beside the log
    variant.write_text((ROOT / "interfaces" / "luxo-mouse.yaml").read_text()
                       .replace("[80, -80]", "[0, 0]", 1), encoding="utf-8")
    log = _with_header(tmp_path, "hop.jsonl", interface="./luxo-mouse.yaml")
    recorded = json.loads(_lines(HOP)[0])["interface_hash"]
    # (a file beside the log is named without its hash: issue 32, it tells of its content)
    words = (f"{log}: warning: interface './luxo-mouse.yaml': the file found "
             f"({variant}) differs from the one recorded (hash "
             f"{recorded}); the replay may end elsewhere (puppet replay --as-recorded "
             "replays the recorded interface)")
    for_replay = setup_for_log(read_log(log))[1]
    for_check = setup_for_log(read_log(log), for_check=True)[1]
    assert for_replay == for_check == [words], (for_replay, for_check)
    assert "has changed" not in words
    code, out, err = _run(capsys, "check", log)
    assert code == 0 and err == words + "\n"


# -- 6. a recorded path outside the catalog and the log's folder -------------------------
def test_record_script_names_a_path_as_the_cli_records_it_and_the_replay_says_why_the_copy_plays(
        tmp_path, capsys, monkeypatch):
    here = tmp_path / "variants"
    here.mkdir()
    (here / "variant.yaml").write_text((ROOT / "interfaces" / "luxo-mouse.yaml").read_text(),
                                       encoding="utf-8")
    logs = tmp_path / "logs"
    logs.mkdir()
    monkeypatch.chdir(tmp_path)
    log = record_script("luxo-hop", logs / "scripted.jsonl", interface="variants/variant.yaml",
                        seconds=0.5)
    code, _, err = _run(capsys, "play", "variants/variant.yaml", "--headless", "--input",
                        "luxo-hop", "--seconds", "0.5", "--record", logs / "cli.jsonl")
    assert code == 0, err
    scripted, cli = (json.loads(_lines(p)[0]) for p in (log, logs / "cli.jsonl"))
    for key in ("interface", "interface_hash", "interface_text", "character", "scene"):
        assert scripted[key] == cli[key], key
    assert scripted["interface"] == str(here / "variant.yaml")  # as the Recorder names it
    result = replay(log)
    assert result.same_end
    assert result.warnings == [
        f"{log}: note: interface file '{here / 'variant.yaml'}' is outside the catalog and "
        "the log's folder, so it is not read (a log reads no other files); the copy "
        "recorded in the log plays"], result.warnings
    assert "not found" not in result.warnings[0]




def test_a_recorded_log_is_compact_json_one_object_per_line(tmp_path):
    _, log = recorded_then_edited(tmp_path)
    lines = log.read_text().splitlines()
    assert all(", " not in ln.split('"interface_text"')[0] and '": ' not in ln
               for ln in lines[1:])
    assert lines[1] == '{"step":0,"event":{"type":"mouse","x":1.0,"y":0.5}}'
