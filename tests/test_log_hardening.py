"""A log from anyone: every number finite and bounded, every malformed line one
``LOG:N: what is wrong`` error (exit 2), never an internal error."""

import json
import subprocess
import sys
from pathlib import Path

import pytest

from puppet.data.errors import DataError
from puppet.timeline.log import read_log

ROOT = Path(__file__).resolve().parents[1]
HOP = ROOT / "assets" / "logs" / "luxo-hop.jsonl"


def header(**changes) -> str:
    h = json.loads(HOP.read_text(encoding="utf-8").splitlines()[0])
    h.update(changes)
    return json.dumps(h)


def write(tmp_path, lines, name="bad.jsonl") -> Path:
    path = tmp_path / name
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path


MOUSE = '{"step": 0, "event": {"type": "mouse", "x": 0.5, "y": 0.5}}'


@pytest.mark.parametrize("line,fragment", [
    ('{"step": 0, "event": {"type": "mouse", "x": NaN, "y": 0.5}}',
     "NaN is not a number a log may hold"),
    ('{"step": 0, "event": {"type": "mouse", "x": Infinity, "y": 0.5}}', "Infinity is not"),
    ('{"step": 0, "event": {"type": "mouse", "x": -Infinity, "y": 0.5}}', "-Infinity is not"),
    ('{"step": 0, "event": {"type": "mouse", "x": 1e400, "y": 0.5}}', "too large a number"),
    ('{"step": 0, "event": {"type": "mouse", "x": 1e30, "y": 0.5}}',
     "mouse event: 'x' must be a finite number in -10..10"),
    ('{"step": 1000000000000, "event": {"type": "mouse", "x": 0.5, "y": 0.5}}',
     "'step' must be a whole number 0..41472000 (24 h at this log's dt)"),
    ('{"step": 0, "event": {"type": "gamepad", "name": "axis0", "value": 1e300}}',
     "gamepad event: 'value' must be a finite number in -1e6..1e6"),
    ('{"step": 0, "event": {"type": "channel", "name": "lean", "value": true}}',
     "channel event: 'value' must be a number"),
    ('{"step": 0, "event": {"type": "drag", "phase": "start", "link": "base", '
     '"point": [0, 0], "target": [1e9, 0]}}', "-10000..10000 m"),
    ('{"step": 0, "event": {"type": "action", "name": "rewind", "to_step": 99999999999}}',
     "rewind action needs a whole-number 'to_step', 0..41472000"),
    ('{"step": 0, "event": {"type": "drag", "phase": "move", "target": [0, -1e9]}}',
     "drag move: 'target' y must be a finite number in -10000..10000 m"),
    ('{"step": 0, "event": {"type": "action", "name": "take", "branch": -1}}',
     "take action needs a whole-number 'branch' >= 0"),
    ('{"step": 0, "event": {"type": "action", "name": "take", "branch": 1.5}}',
     "take action needs a whole-number 'branch' >= 0"),
    ('{"step": 0, "event": {"type": "drag", "phase": "start", "link": "base", '
     '"point": [1e9, 0], "target": [0, 0]}}',
     "drag start: 'point' x must be a finite number in"),
    ('{"step": 0, "event": {"type": "gesture", "key": "h", "path": [[0, 0.5, 1e9]]}}',
     "gesture event: a path value must be a finite number in -1e6..1e6"),
    ('{"step": 1.5, "event": {"type": "mouse", "x": 0.5, "y": 0.5}}',
     "'step' must be a whole number 0..41472000"),
    ('{"step": true, "event": {"type": "mouse", "x": 0.5, "y": 0.5}}',
     "'step' must be a whole number 0..41472000"),
    ('{"step": 0, "event": {"type": "channel", "name": "a b", "value": 1}}',
     "channel event: 'name' must be a channel name, got 'a b'"),
    ('{"end": 99999999999, "hash": "x"}', "bad end line"),
    ('{"step": 0, "event": {"type": "gesture", "key": "h", "path": [[0, 0.5, 1e999]]}}',
     "too large a number"),
])
def test_log_numbers_are_finite_and_bounded(tmp_path, line, fragment):
    path = write(tmp_path, [header(), MOUSE, line])
    with pytest.raises(DataError) as info:
        read_log(path)
    assert info.value.line == 3 and fragment in info.value.message, str(info.value)
    assert "\n" not in str(info.value)


@pytest.mark.parametrize("changes,fragment", [
    ({"dt": 1e308}, "header: 'dt' must be a finite number in 1e-5..0.05 s"),
    ({"dt": 0}, "header: 'dt' must be a finite number"),
    ({"dt": -0.002}, "header: 'dt' must be"),
    ({"slowdown": 1e300}, "header: 'slowdown'"),
    ({"checkpoint_interval": 1e-300}, "header: 'checkpoint_interval'"),
    ({"interface": "x" * 5000}, "header: 'interface' must be a name or path of 1..4096"),
    ({"description": {"a": 1}}, "header: 'description' must be a string"),
    ({"expect": {"never_fell": True}}, "header: 'expect' must be a list"),
    ({"version": "9" * 100}, "log format version '99999999999999999999999999999999999"
                             "9... is not supported"),
    ({"scene": 5}, "header: 'scene' is missing or not a string"),
    ({"dt": "0.002"}, "header: 'dt' is missing or not a number"),
])
def test_header_numbers_are_bounded(tmp_path, changes, fragment):
    path = write(tmp_path, [header(**changes), MOUSE])
    with pytest.raises(DataError) as info:
        read_log(path)
    assert info.value.line == 1 and fragment in info.value.message, str(info.value)


def test_header_nan_is_refused(tmp_path):
    path = write(tmp_path, [header().replace('"dt":', '"dt": NaN, "x":'), MOUSE])
    with pytest.raises(DataError, match=r"bad.jsonl:1: .*NaN is not a number"):
        read_log(path)


# -- every malformed line: LOG:N: what is wrong ---------------------------------------
BAD_LINES = [
    ('{"step": 0, "event": {"type": {}}}', "unknown event type {}"),
    ('{"step": 0, "event": {"type": ["mouse"]}}', "unknown event type ['mouse']"),
    ('{"step": 0, "event": ' + "[" * 100000 + "]" * 100000 + "}", "nested too deeply"),
    ('{"step": 0, "event": {"type": "key", "key": "' + "k" * 500 + '", "down": true}}',
     "key event: 'key' must be a name of 1..200 characters"),
    ('{"step": 0, "event": {"type": "action", "name": "format_disk"}}',
     "action event: unknown action 'format_disk'"),
    ('{"step": 0, "event": {"type": "drag", "phase": "start", "link": "nope", '
     '"point": [0, 0], "target": [0, 0]}}', "drag: unknown link 'nope'; the character has"),
    ('{"step": 0, "event": {"type": "gamepad", "name": "../x", "value": 0}}',
     "gamepad event: 'name' must be a standard name (left_x, a, ...), axisN or buttonN"),
    ('{"step": 0, "event": {"type": "mouse_button", "button": "nose", "down": true}}',
     "mouse_button event: 'button' must be left, middle or right"),
    ('{"step": 0, "event": {"type": "gesture", "key": "h", "path": [[0, 2, 0.5]]}}',
     "gesture x = 2 is outside 0..1"),
    ('{"step": 0, "event": {"type": "reload", "text": "a: &x 1\\nb: *x\\n"}}',
     "anchors (&name) and aliases"),
    ('{"step": 0, "event": {"type": "mouse", "x": ' + "9" * 5000 + ', "y": 0}}',
     "not valid JSON"),
    ("[1, 2, 3]", 'expected {"step": N, "event": {...}}'),
    ("\x00\x01\x02", "not valid JSON"),
    ('{"step": 0, "event": {"type": "action", "name": "rewind", "to_step": 99}}',
     "cannot rewind to step 99"),
]


@pytest.mark.parametrize("line,fragment", BAD_LINES, ids=range(len(BAD_LINES)))
def test_every_malformed_line_is_one_line_naming_it(tmp_path, line, fragment):
    from puppet.timeline.replay import replay

    path = write(tmp_path, [header(), MOUSE, line])
    with pytest.raises(DataError) as info:  # a plain replay: the log has no end line,
        replay(path, check=False)  # which a checked one refuses before any event acts
    err = info.value
    assert (err.path, err.line) == (str(path), 3), str(err)
    assert fragment in err.message and "\n" not in str(err), str(err)


def test_cli_malformed_lines_exit_2_without_internal_error(tmp_path):
    for i, (line, fragment) in enumerate(BAD_LINES[:6]):
        path = write(tmp_path, [header(), MOUSE, line], name=f"bad{i}.jsonl")
        proc = subprocess.run([sys.executable, "-m", "puppet", "replay", str(path),
                               "--headless"], capture_output=True, text=True)
        assert proc.returncode == 2, proc.stderr
        assert proc.stderr.startswith(f"{path}:3: ") or f" {path}:3: " in proc.stderr, \
            proc.stderr
        assert fragment in proc.stderr, (fragment, proc.stderr)  # what the reader says, too
        assert "internal error" not in proc.stderr and "Traceback" not in proc.stderr


def test_an_over_long_line_and_a_device_are_refused(tmp_path, monkeypatch):
    from puppet.timeline import log as logmod

    monkeypatch.setattr(logmod, "MAX_LINE", 1000)
    path = write(tmp_path, [header(), MOUSE, '{"step": 0, "event": {"type": "reload", '
                            '"text": "' + "x" * 2000 + '"}}'])
    with pytest.raises(DataError, match=r":1: not valid JSON \(line too long"):
        read_log(path)  # the header itself is over 1000 characters
    with pytest.raises(DataError, match="not a regular file"):
        read_log("/dev/null")


def test_a_whole_drag_reads_start_move_and_end(tmp_path):
    lines = [header(), MOUSE,
             '{"step": 1, "event": {"type": "drag", "phase": "start", "link": "base", '
             '"point": [0, 0], "target": [0.1, 0.2]}}',
             '{"step": 2, "event": {"type": "drag", "phase": "move", "target": [0.2, 0.2]}}',
             '{"step": 3, "event": {"type": "drag", "phase": "end"}}']
    log = read_log(write(tmp_path, lines), allow_truncated=True)
    assert [e.event.get("phase") for e in log.events] == [None, "start", "move", "end"]


def test_a_log_may_end_at_its_last_possible_step(tmp_path):
    last = 41472000  # 24 h at the hop's dt
    end = '"hash": "0123456789abcdef"}'
    log = read_log(write(tmp_path, [header(), MOUSE, f'{{"end": {last}, {end}']))
    assert log.end_step == last
    with pytest.raises(DataError, match="bad end line"):
        read_log(write(tmp_path, [header(), MOUSE, f'{{"end": {last + 1}, {end}']))


def test_channel_names_may_have_capitals_digits_dots_and_dashes(tmp_path):
    line = ('{"step": 0, "event": {"type": "channels", "values": '
            '{"Lean": 0.5, "Arm_2.x-y": 1}}}')
    log = read_log(write(tmp_path, [header(), MOUSE, line]), allow_truncated=True)
    assert log.events[-1].event["values"] == {"Lean": 0.5, "Arm_2.x-y": 1}


def test_an_empty_log_and_a_folder_are_one_line_each(tmp_path):
    empty = write(tmp_path, [""], "empty.jsonl")
    with pytest.raises(DataError) as info:
        read_log(empty)
    assert str(info.value) == f"{empty}:1: empty log: line 1 must be a header"
    folder = tmp_path / "folder.jsonl"
    folder.mkdir()
    with pytest.raises(DataError) as info:
        read_log(folder)
    assert str(info.value) == f"{folder}: is a folder; expected a log (.jsonl) or a log name"


LOGS = ROOT / "assets" / "logs"


def _log_with(tmp_path, edit) -> Path:
    lines = (LOGS / "luxo-hop.jsonl").read_text().splitlines()
    lines = edit(lines)
    out = tmp_path / "edited.jsonl"
    out.write_text("\n".join(lines) + "\n")
    return out


def test_an_unknown_action_in_a_log_lists_every_action_a_log_may_hold(tmp_path):
    path = _log_with(tmp_path, lambda ls: ls[:2] + [
        '{"step":10,"event":{"type":"action","name":"frobnicate"}}'] + ls[2:])
    with pytest.raises(DataError) as info:
        read_log(path)
    msg = str(info.value)
    assert msg.startswith(f"{path}:3:") and "unknown action 'frobnicate'" in msg
    listed = msg.split("expected one of: ")[1].split(" (")[0].split(", ")
    assert "rewind" in listed and "take" in listed and "checkpoint" in listed


def test_a_log_of_another_format_version_names_the_file(tmp_path):
    def bump(ls):
        h = json.loads(ls[0])
        h["version"] = 99
        return [json.dumps(h)] + ls[1:]
    path = _log_with(tmp_path, bump)
    with pytest.raises(DataError) as info:
        read_log(path)
    assert str(info.value).startswith(f"{path}:1:")
    assert "log format version 99 is not supported" in str(info.value)


def test_a_log_path_through_a_file_says_why_it_cannot_be_read(tmp_path):
    (tmp_path / "notes.txt").write_text("not a folder")
    path = tmp_path / "notes.txt" / "run.jsonl"
    with pytest.raises(DataError) as info:
        read_log(path)
    assert str(info.value) == f"{path}: cannot read log: Not a directory"


@pytest.mark.parametrize("key", ["description", "puppet", "interface_hash"])
def test_a_header_text_field_that_is_not_text_is_named(tmp_path, key):
    from puppet.timeline.log import read_log

    lines = (ROOT / "assets" / "logs" / "luxo-hop.jsonl").read_text().splitlines()
    h = json.loads(lines[0])
    h[key] = 5
    path = tmp_path / "h.jsonl"
    path.write_text("\n".join([json.dumps(h)] + lines[1:]) + "\n")
    with pytest.raises(DataError) as info:
        read_log(path)
    assert str(info.value).startswith(f"{path}:1:") and key in str(info.value)
