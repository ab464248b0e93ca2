"""Replay: file order, --until-step, expectations, --check, parallel runs, replay_log."""

import json
import re
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest
from helpers import ANKLE_IFACE

from puppet.data.catalog import load_setup
from puppet.data.errors import DataError
from puppet.interface import events as ev
from puppet.session import Session
from puppet.session.playback import play
from puppet.testing import check, record_script, replay_log
from puppet.timeline.log import read_log, record_events
from puppet.timeline.replay import replay

ROOT = Path(__file__).resolve().parents[1]

HOP_EXPECT = [
    {"x_at_end": {"link": "base", "min": 0.5}},
    {"x_at_end": {"com": True, "min": 0.5, "max": 3.0}},
    {"upright_at_end": True},
    {"never_fell": True},
    {"reached_height": {"link": "base", "min": 0.03}},
    {"airborne": {"link": "base", "min_seconds": 0.1}},
]


def _cli(*args):
    return subprocess.run([sys.executable, "-m", "puppet", *map(str, args)],
                          capture_output=True, text=True, cwd=ROOT, timeout=60)


@pytest.fixture(scope="module")
def hop(tmp_path_factory) -> Path:
    path = tmp_path_factory.mktemp("logs") / "hop.jsonl"
    return record_script("luxo-hop", path, expect=HOP_EXPECT)


def test_play_applies_events_in_file_order_not_sorted():
    session = Session(load_setup("luxo-mouse"))
    seen = []
    session.listener = lambda step, e: seen.append((step, e["x"]))
    play(session, [(10, ev.mouse(0.1, 0.5)), (5, ev.mouse(0.2, 0.5)),
                   (20, ev.mouse(0.3, 0.5))], None)
    assert seen == [(10, 0.1), (10, 0.2), (20, 0.3)]
    assert session.steps == 20


def test_play_until_step_stops_the_first_time_it_gets_there():
    session = Session(load_setup("luxo-mouse"))
    session.advance(96)
    rewind = {"type": "action", "name": "rewind", "to_step": 48}
    events = [(100, ev.mouse(0.1, 0.5)), (100, rewind), (60, ev.mouse(0.2, 0.5))]
    play(session, events, 100)  # the events at 100 act (one goes back), then on to 100
    assert session.steps == 100 and session.runtime.inputs["mouse.x"] == 0.2
    session2 = Session(load_setup("luxo-mouse"))
    play(session2, [(100, ev.mouse(0.1, 0.5)), (120, ev.mouse(0.2, 0.5))], 110)
    assert session2.steps == 110 and session2.runtime.inputs["mouse.x"] == 0.1


def test_replay_log_is_bit_identical_and_meets_expectations(hop):
    result = replay_log(hop)
    assert result.final_hash == result.recorded_hash
    assert result.ok, [str(f) for f in result.failed]
    assert len(result.outcomes) == len(HOP_EXPECT) + 1  # + same end as the recording
    traj = result.trajectory
    n = len(traj)
    assert n > 500 and traj.t[0] == 0.0 and np.all(np.diff(traj.t) > 0)
    assert traj.x.shape == (n, 3) and traj.joint_angle.shape == (n, 2)
    assert traj.joint_target.shape == (n, 2) and traj.contact.dtype == bool
    base = traj.index("base")
    assert traj.x[-1, base] - traj.x[0, base] > 0.5
    assert not traj.contact[:, base].all() and traj.contact[:, base].any()
    assert result.summary["hash"] == result.final_hash


def test_failed_expectations_say_what_was_measured(hop):
    failed = check(replay_log(hop), [{"x_at_end": {"link": "base", "min": 5.0}},
                                     {"airborne": {"link": "base", "min_seconds": 3}},
                                     {"final_hash": "0000000000000000"},
                                     {"upright_at_end": False},
                                     {"reached_height": {"link": "upper_arm", "min": 1.0}}])
    text = [str(f) for f in failed]
    assert len(failed) == 5, text
    assert text[0].startswith("FAIL x_at_end base min 5.0: x = 0.")
    assert "longest time out of contact 0.3" in text[1]
    assert "final hash " in text[2]


def test_never_fell_catches_a_fall(tmp_path):
    # Drag the lamp over onto its back and hold it there.
    session = Session(load_setup("luxo-mouse"))
    from puppet.timeline.log import Recorder

    path = tmp_path / "fall.jsonl"
    with Recorder(session, path, expect=[{"never_fell": True}, {"upright_at_end": False}]):
        play(session, [(0, ev.drag_start("upper_arm", (0.0, 0.43), (-0.8, 0.05)))], 1440)
    result = replay_log(path)
    assert [o.expectation for o in result.failed] == ["never_fell true"], \
        [str(o) for o in result.outcomes]


def test_until_step(hop):
    result = replay_log(hop, until_step=300)
    assert result.steps == 300
    assert all(o.expectation != "same end as the recording" for o in result.outcomes)


def test_sidecar_expectations_win_and_report_file_line(hop, tmp_path):
    log = tmp_path / "hop.jsonl"
    log.write_text(hop.read_text())
    side = tmp_path / "hop.expect.yaml"
    side.write_text("expect:\n  - upright_at_end: true\n  - x_at_end: {link: base, max: 0.1}\n")
    result = replay_log(log)
    assert [o.expectation for o in result.failed] == ["x_at_end base max 0.1"]
    assert len(result.outcomes) == 3
    side.write_text("expect:\n  - upright_at_end: true\n  - reached_height: {link: bse, min: 1}\n")
    with pytest.raises(DataError) as info:
        replay_log(log)
    assert info.value.path == str(side) and info.value.line == 3
    assert "unknown link 'bse'" in info.value.message
    side.write_text("expect:\n  - upright_at_end: true\n    never_fell: true\n")
    with pytest.raises(DataError) as info:
        replay_log(log)
    assert info.value.line == 2 and "exactly one check" in info.value.message
    side.write_text("expect:\n  - x_at_end: {link: base, mn: 1}\n")
    with pytest.raises(DataError) as info:
        replay_log(log)
    assert info.value.line == 2 and "did you mean 'min'" in info.value.message


def test_bad_header_expectation_points_at_line_1(hop, tmp_path):
    lines = hop.read_text().splitlines()
    head = json.loads(lines[0])
    head["expect"] = [{"landed": True}]
    lines[0] = json.dumps(head)
    bad = tmp_path / "bad.jsonl"
    bad.write_text("\n".join(lines) + "\n")
    with pytest.raises(DataError) as info:
        replay_log(bad)
    assert info.value.line == 1 and "unknown key 'landed'" in info.value.message


def test_cli_check_exit_codes_and_messages(hop, tmp_path):
    proc = _cli("replay", hop, "--headless", "--check")
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert "(same as recorded)" in proc.stdout and "ok   airborne base" in proc.stdout
    log = tmp_path / "h.jsonl"
    log.write_text(hop.read_text())
    (tmp_path / "h.expect.yaml").write_text("expect:\n  - x_at_end: {com: true, min: 9}\n")
    proc = _cli("replay", log, "--headless", "--check")
    assert proc.returncode == 1
    assert "FAIL x_at_end com min 9.0: x = " in proc.stdout


def test_cli_parallel_summary_table(hop, tmp_path):
    failing = tmp_path / "f.jsonl"
    failing.write_text(hop.read_text())
    (tmp_path / "f.expect.yaml").write_text("expect:\n  - final_hash: abc\n")
    proc = _cli("replay", hop, failing, hop, "--headless", "--check", "--jobs", "2")
    assert proc.returncode == 1, proc.stderr
    rows = proc.stdout.splitlines()
    assert ["log", "steps", "state", "checks", "result"] in [r.split() for r in rows]
    table = [r.split() for r in rows if r.split()[0] in (str(hop), str(failing))]
    results = {r[0]: r[-1] for r in table}
    assert results[str(hop)] == "ok" and results[str(failing)] == "FAIL"
    assert "3 logs: 2 ok, 1 failed, 0 errors" in proc.stdout
    assert f"{failing}: FAIL final_hash abc" in proc.stdout


def test_window_feeder_passes_on_recorded_speed_keys(tmp_path):
    from puppet.timeline.log import Recorder, read_log
    from puppet.timeline.replay import LogFeeder, new_session

    session = Session(load_setup("luxo-mouse"))
    path = tmp_path / "keys.jsonl"
    with Recorder(session, path):
        session.advance(10)
        assert session.handle(ev.key("-", True)) == "slower"
        session.advance(10)
    log = read_log(path)
    actions = []
    feeder = LogFeeder(new_session(log, load_setup("luxo-mouse")), log,
                       on_action=actions.append)
    feeder.advance(100)
    assert feeder.finished and actions == ["slower"]
    assert feeder.session.steps == 20


@pytest.fixture(scope="module")
def rewound(tmp_path_factory) -> Path:
    """A short log with mouse moves and a recorded rewind (from step 300 back to 150)."""
    from puppet.timeline.log import Recorder

    session = Session(load_setup("luxo-mouse"))
    path = tmp_path_factory.mktemp("logs") / "rewound.jsonl"
    with Recorder(session, path):
        session.handle(ev.mouse(0.9, 0.1))
        session.advance(120)
        session.handle(ev.mouse(0.1, 0.9))
        session.advance(180)
        session.handle({"type": "action", "name": "rewind", "to_step": 150})
        session.handle(ev.mouse(0.5, 0.5))
        session.advance(100)
    return path


def _fed(path: Path, until: int | None, budget: int) -> Session:
    """The window's and the export's way: a LogFeeder driven ``budget`` steps a frame."""
    from puppet.timeline.log import read_log
    from puppet.timeline.replay import LogFeeder, new_session, setup_for_log

    log = read_log(path)
    feeder = LogFeeder(new_session(log, setup_for_log(log)[0]), log, until)
    feeder.advance(0)
    while not feeder.finished:
        feeder.advance(budget)
    return feeder.session


@pytest.mark.parametrize("until", [None, 100, 150, 200, 250, 280, 300, 420])
def test_window_feeder_stops_where_headless_replay_does(rewound, until):
    # The log ends at 250 (after going back from 300 to 150). 250: the end; 280:
    # first reached before the rewind; 300: the rewind's own step (it acts, then the
    # replay runs on past the end to 300 again); 420: past everything.
    headless = replay(rewound, until_step=until, check=False, trajectory=False)
    for budget in (1, 7, 64):
        fed = _fed(rewound, until, budget)
        assert (fed.steps, fed.sim.state_hash()) == (headless.steps, headless.final_hash), \
            f"until {until}, budget {budget}"
    assert headless.steps == (250 if until is None else until)


@pytest.mark.parametrize("until", [None, 1000, 2880, 3000])
def test_window_feeder_matches_headless_replay_on_a_real_log(until):
    path = ROOT / "assets" / "logs" / "luxo-keys-sit-stand.jsonl"
    headless = replay(path, until_step=until, check=False, trajectory=False)
    fed = _fed(path, until, 97)
    assert (fed.steps, fed.sim.state_hash()) == (headless.steps, headless.final_hash)


def _with_end_hash(src: Path, dst: Path, end_hash: str) -> Path:
    lines = src.read_text().splitlines()
    end = json.loads(lines[-1])
    lines[-1] = json.dumps({"end": end["end"], "hash": end_hash})
    dst.write_text("\n".join(lines) + "\n")
    return dst


def test_a_log_that_ends_elsewhere_is_not_ok_in_table_summary_or_exit_code(hop, tmp_path):
    """Without --check a log whose replay does not end in its recorded state is
    "differs" in the table, counted as "differ" (not ok) in the summary, and exits 1;
    with --check it is a failed check. --until-step has nothing to compare."""
    odd = _with_end_hash(hop, tmp_path / "odd.jsonl", "0123456789abcdef")
    proc = _cli("replay", hop, odd, "--headless", "--jobs", "2")
    assert proc.returncode == 1, proc.stdout + proc.stderr
    results = {r.split()[0]: r.split()[-1] for r in proc.stdout.splitlines()
               if r.split()[0] in (str(hop), str(odd))}
    assert results == {str(hop): "ok", str(odd): "differs"}
    assert "2 logs: 1 ok, 1 differ, 0 errors, 0 blow-ups" in proc.stdout
    proc = _cli("replay", hop, odd, "--headless", "--check", "--jobs", "2")
    assert proc.returncode == 1 and "2 logs: 1 ok, 1 failed, 0 errors" in proc.stdout
    proc = _cli("replay", odd, "--headless")
    assert proc.returncode == 1 and "(recorded 0123456789abcdef: DIFFERENT)" in proc.stdout
    proc = _cli("replay", odd, "--headless", "--until-step", "300")
    assert proc.returncode == 0 and "DIFFERENT" not in proc.stdout, proc.stdout


def test_replay_takes_a_log_by_name_from_the_logs_or_recordings_folder(hop, tmp_path,
                                                                       monkeypatch, capsys):
    from puppet.commands import main
    from puppet.data import catalog

    assert main(["replay", "luxo-hop", "--headless", "--until-step", "50"]) == 0
    assert str(ROOT / "assets" / "logs" / "luxo-hop.jsonl") in capsys.readouterr().out
    mine = tmp_path / "recordings"
    mine.mkdir()
    (mine / "luxo-mouse-20260101-120000.jsonl").write_text(hop.read_text())
    monkeypatch.setitem(catalog.FOLDERS, "recording", (str(mine), ".jsonl"))
    assert main(["list"]) == 0
    listed = capsys.readouterr().out
    assert f"recordings ({mine}/):\n  luxo-mouse-20260101-120000" in listed
    assert main(["replay", "luxo-mouse-20260101-120000", "--headless"]) == 0
    assert "(same as recorded)" in capsys.readouterr().out
    assert main(["replay", "no-such-log", "--headless"]) == 2
    assert "no log named 'no-such-log'; known: " in capsys.readouterr().err


BOOM = """\
name: boom
description: luxo-mouse with a key that blows the simulation up
character: luxo
checkpoint_every: 0.5
maps:
  - {input: mouse.x, joint: ankle, from: [0, 1], to: [80, -80]}
keys:
  - {key: g, gravity: [0, 1000], description: "100 g upward, the largest allowed"}
  - {key: n, gravity: [0, -9.81], description: earth gravity}
"""
BOOM_SCRIPT = """\
seconds: 1.5
events:
  - {t: 0.0, mouse: [0.5, 0.5]}
  - {t: 0.6, key: g}
  - {t: 0.95, key: n}
"""


def test_headless_play_and_replay_report_each_blow_up(tmp_path):
    (tmp_path / "boom.yaml").write_text(BOOM)
    (tmp_path / "boom-script.yaml").write_text(BOOM_SCRIPT)
    log = tmp_path / "boom.jsonl"
    proc = _cli("play", tmp_path / "boom.yaml", "--headless", "--input",
                tmp_path / "boom-script.yaml", "--record", log)
    assert proc.returncode == 3, proc.stderr  # the blow-up's own exit code
    lines = proc.stderr.splitlines()
    assert len(lines) == 1 and lines[0].startswith("puppet play: "), proc.stderr
    note = lines[0][len("puppet play: "):]
    # caught within a frame of passing MAX_SPEED (0.2 s at 100 g), not at a 0.5 s check
    assert re.fullmatch(r"the simulation blew up at t=0\.8\d s; restored the checkpoint "
                        r"of t=0\.50 s", note), note
    result = replay(log)
    assert result.blowups == [note] and result.session.blowups == 1
    end = result.session.steps
    result.session.rewind_to(end - 1)  # re-simulates across the blow-up: not a new one
    assert result.session.blowups == 1 and result.session.blowup_messages == [note]
    proc = _cli("replay", log, "--headless")
    assert proc.returncode == 3, proc.stderr
    assert proc.stderr.splitlines() == [f"{log}: {note}"]
    assert "(same as recorded)  blow-ups=1" in proc.stdout
    calm = ROOT / "assets" / "logs" / "luxo-hop.jsonl"
    proc = _cli("replay", log, calm, "--headless")
    assert proc.returncode == 3 and "2 logs: 2 ok, 0 differ, 0 errors, 1 blow-up" in proc.stdout
    assert proc.stderr.splitlines() == [f"{log}: {note}"]




def test_the_viewer_is_told_only_of_the_app_actions_a_log_asks_for(tmp_path):
    from puppet.timeline.replay import LogFeeder

    iface = tmp_path / "t.yaml"
    iface.write_text(textwrap.dedent(ANKLE_IFACE))
    log = tmp_path / "a.jsonl"
    s = Session(load_setup(str(iface)))
    record_events(s, [(0, ev.mouse(0.2, 0.5)), (10, ev.action("checkpoint")),
                      (20, ev.mouse(0.8, 0.5))], 60, log)
    told = []
    feeder = LogFeeder(Session(load_setup(str(iface))), read_log(log), on_action=told.append)
    feeder.advance(100)
    assert None not in told
    assert np.isfinite(feeder.session.time)
