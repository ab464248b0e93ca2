"""play's refusals say what to do instead: a live take's options point at what replay
has (--video), a log given to --input is a log (puppet replay LOG), a headless --loop
needs --seconds (else it would play the clip once, silently)."""

from __future__ import annotations

import pytest

from puppet.commands import main


def _one_line_error(argv, capsys) -> str:
    code = main(argv)
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1, err
    return err


@pytest.mark.parametrize("extra", [["--frames", "out"], ["--loop"], ["--ghost", "x.jsonl"]])
def test_a_live_take_points_at_what_replay_offers(extra, capsys):
    err = _one_line_error(["play", "luxo-mouse", "--headless", "--mocap", "udp://127.0.0.1:1",
                           "--mocap-format", "puppet", *extra], capsys)
    assert ("--mocap udp://... goes without --input, --frames, --ghost, --loop and "
            "--mocap-drop") in err
    assert "puppet replay LOG --video OUT" in err and "replay its log for those" not in err


@pytest.mark.parametrize("headless", [["--headless"], []])
def test_a_log_given_to_input_is_said_to_be_a_log(headless, capsys):
    log = "assets/logs/biped-mocap-live.jsonl"
    err = _one_line_error(["play", "biped-mocap", *headless, "--input", log], capsys)
    assert "YAML" not in err
    assert err == (f"puppet play: --input {log}: a .jsonl file is a recorded log, not a script "
                   f"(assets/scripts/NAME.yaml); play it back with: puppet replay {log}\n")


def test_loop_headless_without_seconds_is_refused_not_played_once(capsys):
    err = _one_line_error(["play", "biped-mocap", "--headless", "--mocap", "cmu-131_01-walk",
                           "--loop", "--no-record"], capsys)
    assert err.startswith("puppet play: --loop headless needs --seconds S: a looping clip has "
                          "no end") and "(8.27 s)" in err


def test_loop_headless_with_seconds_plays_on_past_the_clips_end(capsys):
    assert main(["play", "biped-mocap", "--headless", "--mocap", "cmu-131_01-walk", "--loop",
                 "--seconds", "8.5", "--no-record"]) in (0, 3)
    assert "t=8.500s" in capsys.readouterr().out
