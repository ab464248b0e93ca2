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
