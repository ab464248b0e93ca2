"""``puppet playtest LOG --from-rest KEY``: a single-key move pressed at other moments
from rest, each copy judged by the log's feat expectations (issue 28: a move that
starts from rest must not depend on when it starts)."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest

from puppet.commands import main
from puppet.data.catalog import ROOT
from puppet.data.errors import DataError
from puppet.timeline.log import read_log
from puppet.timeline.playtest.from_rest import failures, moved, press_step, steps_between

FIXTURES = Path(__file__).parent / "fixtures" / "playtest"


def _timed_flip(tmp_path: Path) -> Path:
    """The back flip as shipped on 2026-12-06 (tests/fixtures/playtest/: its log, its
    sidecar and its interface, a timed sequence into ballistic motion) in ``tmp_path``."""
    for name in ("biped-backflip-2026-12.jsonl", "biped-backflip-2026-12.expect.yaml",
                 "biped-floor-2026-12.yaml"):
        shutil.copy(FIXTURES / name, tmp_path / name)
    return tmp_path / "biped-backflip-2026-12.jsonl"


def test_the_press_and_everything_after_it_move_together(tmp_path):
    """The first press of the key and all that follows move by the same steps (the end
    too); at its own step the timed back flip of 2026-12 lands, a press 48 steps later
    (0.1 s, the figure still at rest) does not: what the sweep measures."""
    flip = _timed_flip(tmp_path)
    log = read_log(flip)
    at = press_step(log, "f")
    later = moved(log, "f", at + 48)
    assert [e.step for e in later.events] == [e.step + 48 for e in log.events]
    assert later.end["end"] == log.end["end"] + 48
    assert steps_between(1 / 480, 0.5, 1.0, 3) == [240, 361, 482]
    assert failures((str(flip), "f", at)) == []
    assert failures((str(flip), "f", at + 48))  # the flip fails 0.1 s later


def test_a_press_at_the_start_or_before_earlier_input_is_refused():
    log = read_log(ROOT / "assets" / "logs" / "luxo-keys-sit-stand.jsonl")
    with pytest.raises(DataError, match="before an event"):
        moved(log, "z", 0)
    first = log.events[0].step
    if first < press_step(log, "z"):  # input before the press: a press may not pass it
        with pytest.raises(DataError, match="before an event"):
            moved(log, "z", first)


def test_the_command_counts_the_landings_and_exits_1_below_nine_in_ten(tmp_path, capsys):
    code = main(["playtest", str(_timed_flip(tmp_path)), "--from-rest", "f", "--count", "2",
                 "--between", "0.5", "1.5", "--jobs", "1"])
    out = capsys.readouterr().out
    assert code == 1  # 1 of 2 lands: the timed flip
    assert "f at 0.500 s (step 240): lands" in out
    assert "biped-backflip-2026-12: 1/2 presses of f from rest land" in out


def test_a_move_that_follows_the_body_lands_every_time(capsys):
    """Luxo's back somersault (d, its phases from the body) lands from every moment:
    exit 0, JSON."""
    code = main(["playtest", "luxo-keys-somersaults", "--from-rest", "d", "--count", "2",
                 "--between", "0.3", "0.8", "--jobs", "1", "--json"])
    out = json.loads(capsys.readouterr().out)
    assert code == 0 and out["landed"] == 2 and out["key"] == "d"


def test_a_key_the_log_never_presses_is_one_line(capsys):
    code = main(["playtest", "biped-backflip", "--from-rest", "q"])
    err = capsys.readouterr().err
    assert code == 2
    assert err.count("\n") == 1 and "no press of 'q' in the log" in err


def test_the_handstand_whose_phases_follow_the_body_lands_from_any_moment(capsys):
    """biped-handstand (h alone, its phases on sensors polled every step): pressed at
    three moments of the stillness it lands each time (the sweep's 10: 10 of 10)."""
    code = main(["playtest", "biped-handstand", "--from-rest", "h", "--count", "3",
                 "--between", "0.5", "2.5", "--jobs", "1"])
    out = capsys.readouterr().out
    assert code == 0 and "biped-handstand: 3/3 presses of h from rest land" in out, out


def test_the_wall_flip_lands_from_rest_whenever_w_is_pressed(capsys):
    """biped-wall-flip (issue 28): w pressed at ten moments of the stillness (0.5 to 3 s)
    lands at least 9 times (exit 0); the knee-first flip without its reach for the wall
    (tuck_reach, which waits for the wall foot alone on the wall) landed 8."""
    code = main(["playtest", "biped-wall-flip", "--from-rest", "w", "--jobs", "1"])
    out = capsys.readouterr().out
    assert code == 0 and "presses of w from rest land" in out, out
