"""Input logs: written line by line as the session goes, read back strictly."""

import datetime
import json
import subprocess
import sys
from pathlib import Path

import pytest

from puppet.data.catalog import load_setup
from puppet.data.errors import DataError
from puppet.interface import events as ev
from puppet.session import Session
from puppet.session.playback import play
from puppet.testing import record_script
from puppet.timeline.log import Recorder, default_path, read_log
from puppet.timeline.replay import replay

ROOT = Path(__file__).resolve().parents[1]


def _cli(*args, cwd=None):
    return subprocess.run([sys.executable, "-m", "puppet", *map(str, args)],
                          capture_output=True, text=True, cwd=cwd or ROOT, timeout=60)


def test_header_events_and_end_line(tmp_path):
    session = Session(load_setup("luxo-mouse"))
    path = tmp_path / "a.jsonl"
    rec = Recorder(session, path, description="two events", expect=[{"upright_at_end": True}])
    session.handle(ev.mouse(0.2, 0.3))
    session.advance(100)
    session.handle(ev.key("space", True))
    # flushed as it goes: everything so far is on disk before close
    lines = path.read_text().splitlines()
    assert len(lines) == 3
    rec.close()
    lines = [json.loads(x) for x in path.read_text().splitlines()]
    head = lines[0]
    assert head["format"] == "puppet-log" and head["version"] == 1
    for key in ("puppet", "interface", "interface_hash", "character", "character_hash",
                "scene", "scene_hash", "dt", "seed", "slowdown", "checkpoint_interval"):
        assert key in head, key
    assert head["interface"] == "luxo-mouse" and head["character"] == "luxo"
    assert head["dt"] == session.sim.dt and head["description"] == "two events"
    assert head["expect"] == [{"upright_at_end": True}]
    assert lines[1] == {"step": 0, "event": {"type": "mouse", "x": 0.2, "y": 0.3}}
    assert lines[2] == {"step": 100, "event": {"type": "key", "key": "space", "down": True}}
    assert lines[3] == {"end": 100, "hash": session.sim.state_hash()}
    assert session.listener is None  # unhooked


def test_killed_recording_keeps_its_events_and_replays(tmp_path):
    session = Session(load_setup("luxo-mouse"))
    path = tmp_path / "killed.jsonl"
    Recorder(session, path)  # never closed, like a killed process
    session.handle(ev.mouse(1.0, 0.1))
    session.advance(50)
    session.handle(ev.mouse(0.1, 0.9))
    log = read_log(path)
    assert [e.step for e in log.events] == [0, 50] and log.end is None
    result = replay(path, check=False)  # replays, and says why there is no end state
    assert result.steps == 50 and result.same_end is None  # to compare
    assert any("no end line" in w and "killed" in w for w in result.warnings)
    with pytest.raises(DataError) as info:  # a checked replay refuses it (the next test),
        replay(path)  # at its last line (3 lines: no line 4 to point at)
    assert info.value.line == 3 and "--allow-truncated" in info.value.message
    assert "after this last line" in info.value.message
    assert "the lines before it" not in info.value.message  # there is no bad line
    assert "on its 2 events, to step 50," in info.value.message


def _cut_end(hop_log: Path, tmp_path: Path) -> Path:
    """``hop_log`` without its end line (``head -n -1``), with expectations beside it."""
    cut = _write(tmp_path / "cut-end.jsonl", hop_log.read_text().splitlines()[:-1])
    (tmp_path / "cut-end.expect.yaml").write_text(
        "expect:\n  - upright_at_end: true\n  - x_at_end: {link: base, min: -1}\n")
    return cut


def test_checked_replay_refuses_a_log_without_its_end_line(tmp_path, hop_log):
    """Under --check a log that lost only its end line is refused as a log cut mid-line
    is (exit 2, the same hint): it would stop at its last event, not where the recording
    stopped, and its end state could not be compared. --allow-truncated checks the
    events it has and says the end state was not checked; a plain replay goes on with
    the warning."""
    cut = _cut_end(hop_log, tmp_path)
    n = len(cut.read_text().splitlines())
    proc = _cli("replay", cut, "--headless", "--check")
    assert proc.returncode == 2, proc.stdout + proc.stderr
    err = proc.stderr.strip().splitlines()
    assert len(err) == 1 and "Traceback" not in proc.stderr, proc.stderr
    assert err[0].startswith(f"puppet replay: {cut}:{n}: no end line"), err  # its last
    last = read_log(cut).events[-1].step
    assert err[0].endswith(f"(--allow-truncated checks the expectations on its {n - 1} "
                           f"events, to step {last}, without the end state)"), err
    assert proc.stdout == ""
    proc = _cli("replay", cut, "--headless", "--check", "--allow-truncated")
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert "ok   upright_at_end" in proc.stdout
    assert ("not checked: same end as the recording (the log has no end line"
            in proc.stdout), proc.stdout
    assert "'same end as the recording' is not checked" in proc.stderr, proc.stderr
    proc = _cli("replay", cut, "--headless")  # no --check: replays, with the warning
    assert proc.returncode == 0 and "state=" in proc.stdout, proc.stderr
    assert "no end line" in proc.stderr and "no recorded end state" in proc.stderr


def test_replay_log_follows_the_rule_of_check(tmp_path, hop_log):
    """puppet.testing.replay_log refuses a log without its end line as --check does,
    with its own expectations or a test's (expect=); allow_truncated checks what there
    is and says so."""
    from puppet.testing import replay_log

    cut = _cut_end(hop_log, tmp_path)
    for expect in (None, [{"upright_at_end": True}]):
        with pytest.raises(DataError, match="no end line.*allow_truncated=True"):
            replay_log(cut, expect=expect)
    result = replay_log(cut, allow_truncated=True)
    assert result.same_end is None and not result.failed and len(result.outcomes) == 2
    assert result.unchecked and "no end line" in result.unchecked[0]
    assert result.summary["unchecked"] == result.unchecked
    result = replay_log(cut, allow_truncated=True, expect=[{"upright_at_end": True}])
    assert [o.expectation for o in result.outcomes] == ["upright_at_end true"]
    assert any("is not checked" in w for w in result.warnings)
    whole = replay_log(hop_log)  # a closed log: nothing left out
    assert whole.same_end is True and whole.unchecked == []


def test_default_path_never_overwrites(tmp_path):
    now = datetime.datetime(2024, 5, 6, 7, 8, 9)
    first = default_path("luxo-mouse", tmp_path, now)
    assert first == tmp_path / "recordings" / "luxo-mouse-20240506-070809.jsonl"
    first.parent.mkdir()
    first.write_text("x")
    second = default_path("luxo-mouse", tmp_path, now)
    assert second.name == "luxo-mouse-20240506-070809-2.jsonl"
    second.write_text("x")
    assert default_path("luxo-mouse", tmp_path, now).name.endswith("-3.jsonl")


def _write(path: Path, lines: list[str]) -> Path:
    path.write_text("\n".join(lines) + "\n")
    return path


@pytest.fixture
def hop_log(tmp_path) -> Path:
    return record_script("luxo-hop", tmp_path / "hop.jsonl", seconds=1.0)


def test_corrupt_line_names_its_line(hop_log, tmp_path):
    lines = hop_log.read_text().splitlines()
    lines[4] = lines[4][:20]  # cut mid-line
    bad = _write(tmp_path / "bad.jsonl", lines)
    with pytest.raises(DataError) as info:
        read_log(bad)
    assert info.value.line == 5 and "not valid JSON" in info.value.message
    log = read_log(bad, allow_truncated=True)
    assert len(log.events) == 3 and log.truncated_at == 5


@pytest.mark.parametrize("line, fragment", [
    ('{"step": 3}', 'expected {"step": N'),
    ('{"step": -1, "event": {"type": "mouse", "x": 0, "y": 0}}', "'step' must be"),
    ('{"step": 1, "event": {"type": "teleport"}}', "unknown event type 'teleport'"),
    ('{"step": 1, "event": {"type": "mouse", "x": 0}}', "without 'y'"),
    ('{"step": 1, "event": {"type": "action", "name": "rewind"}}', "to_step"),
    ('[1, 2]', 'expected {"step": N'),
])
def test_bad_event_lines(tmp_path, hop_log, line, fragment):
    lines = hop_log.read_text().splitlines()[:3] + [line]
    with pytest.raises(DataError) as info:
        read_log(_write(tmp_path / "x.jsonl", lines))
    assert info.value.line == 4 and fragment in info.value.message, str(info.value)


def test_nothing_after_the_end_line(tmp_path, hop_log):
    lines = hop_log.read_text().splitlines()
    lines.append(lines[1])
    with pytest.raises(DataError) as info:
        read_log(_write(tmp_path / "x.jsonl", lines))
    assert info.value.line == len(lines) and "end line" in info.value.message


def test_other_format_version_says_so(tmp_path, hop_log):
    lines = hop_log.read_text().splitlines()
    head = json.loads(lines[0])
    head["version"] = 2
    lines[0] = json.dumps(head)
    with pytest.raises(DataError) as info:
        read_log(_write(tmp_path / "v2.jsonl", lines))
    assert info.value.line == 1 and "version 2 is not supported" in info.value.message
    assert "reads version 1" in info.value.message
    with pytest.raises(DataError, match="not a puppet log"):
        read_log(_write(tmp_path / "n.jsonl", ['{"hello": 1}']))


def test_cli_corrupt_log_one_line_exit_2_and_allow_truncated(tmp_path, hop_log):
    lines = hop_log.read_text().splitlines()
    lines[6] = "{not json"
    bad = _write(tmp_path / "bad.jsonl", lines)
    proc = _cli("replay", bad, "--headless")
    assert proc.returncode == 2, proc.stderr
    err = proc.stderr.strip().splitlines()
    assert len(err) == 1, proc.stderr
    assert err[0].startswith(f"puppet replay: {bad}:7: not valid JSON"), proc.stderr
    assert "Traceback" not in proc.stderr
    proc = _cli("replay", bad, "--headless", "--allow-truncated")
    assert proc.returncode == 0, proc.stderr
    assert f"{bad}:7: warning" in proc.stderr and "state=" in proc.stdout


def test_changed_data_file_warns_and_still_replays(tmp_path):
    """A changed interface, scene or character file warns and replays anyway: the
    interface is today's file (--as-recorded replays the log's own copy of it)."""
    iface = tmp_path / "my-iface.yaml"
    iface.write_text((ROOT / "interfaces" / "luxo-mouse.yaml").read_text())
    scene = tmp_path / "my-scene.yaml"
    scene.write_text((ROOT / "assets" / "scenes" / "flat.yaml").read_text())
    session = Session(load_setup(str(iface), str(scene)))
    path = tmp_path / "log.jsonl"
    with Recorder(session, path):
        play(session, [(0, ev.mouse(0.9, 0.2))], 200)
    head = json.loads(path.read_text().splitlines()[0])
    assert head["interface"] == str(iface)  # not a catalog name: the path
    original = iface.read_text()
    iface.write_text(original.replace("[80, -80]", "[0, 0]"))
    proc = _cli("replay", path, "--headless")  # today's interface: it ends elsewhere
    assert proc.returncode == 1 and "DIFFERENT" in proc.stdout
    assert "interface" in proc.stderr and "differs from the one recorded" in proc.stderr
    proc = _cli("replay", path, "--headless", "--as-recorded")
    assert proc.returncode == 0, proc.stderr
    assert "warning" not in proc.stderr and "(same as recorded)" in proc.stdout
    iface.write_text(original)
    scene.write_text(scene.read_text() + "\n# edited\n")
    proc = _cli("replay", path, "--headless")
    assert proc.returncode == 0, proc.stderr
    warnings = [x for x in proc.stderr.splitlines() if "warning" in x]
    assert len(warnings) == 1 and "scene" in warnings[0] and "changed" in warnings[0]
    assert "state=" in proc.stdout


def test_play_record_headless_writes_a_replayable_log(tmp_path):
    path = tmp_path / "rec.jsonl"
    proc = _cli("play", "luxo-mouse", "--headless", "--input", "luxo-hop", "--seconds", "1",
                "--record", path)
    assert proc.returncode == 0, proc.stderr
    played = proc.stdout.split("state=")[1].split()[0]
    proc = _cli("replay", path, "--headless")
    assert proc.returncode == 0, proc.stderr
    assert f"state={played} (same as recorded)" in proc.stdout


def test_checkpoint_interval_from_the_interface_or_the_command_line(tmp_path):
    """Automatic checkpoints come every ``checkpoint_every`` s of the interface, or of
    ``--checkpoint-every``; the log records the interval and its replay uses it."""
    import textwrap

    from puppet.data.catalog import load_setup
    from puppet.session import Session
    from puppet.timeline.log import read_log
    from puppet.timeline.replay import new_session, setup_for_log

    iface = tmp_path / "iface.yaml"
    iface.write_text(textwrap.dedent("""\
        name: t
        description: test
        character: luxo
        checkpoint_every: 1.5
        maps: [{input: mouse.x, joint: ankle, to: [30, -80]}]
        """))
    session = Session(load_setup(str(iface)))
    session.advance(round(4.0 / session.sim.dt))
    assert [s.step * session.sim.dt for s in session.history.auto] == [0.0, 1.5, 3.0]
    path = tmp_path / "rec.jsonl"
    proc = _cli("play", iface, "--headless", "--input", "luxo-hop", "--seconds", "2",
                "--checkpoint-every", "0.5", "--record", path)
    assert proc.returncode == 0, proc.stderr
    log = read_log(path)
    assert log.header["checkpoint_interval"] == 0.5
    replayed = new_session(log, setup_for_log(log)[0])
    assert replayed.history.checkpoint_every * replayed.sim.dt == 0.5
    proc = _cli("play", iface, "--headless", "--checkpoint-every", "0.01")
    assert proc.returncode != 0 and "Traceback" not in proc.stderr
    assert proc.returncode == 2 and "is not a checkpoint interval from 0.5 to 600" in proc.stderr


def test_record_never_overwrites_an_existing_file(tmp_path, monkeypatch):
    """``--record PATH`` with PATH taken is a one-line error (exit 2) before anything
    runs, headless or in the window; and the Recorder itself opens exclusively, so a
    file that appears between the check and the open is not overwritten either."""
    from puppet.app import window
    from puppet.commands import main

    taken = tmp_path / "rec.jsonl"
    taken.write_text("precious, not even a log\n")
    proc = _cli("play", "luxo-mouse", "--headless", "--input", "luxo-hop", "--seconds",
                "0.2", "--record", taken)
    assert proc.returncode == 2 and proc.stdout == ""
    assert proc.stderr.strip().splitlines() == [
        f"puppet play: --record {taken}: exists; choose another path or delete it (a log is "
        "never overwritten)"]
    monkeypatch.setattr(window, "run_window", lambda *a, **k: pytest.fail("window opened"))
    assert main(["play", "luxo-mouse", "--record", str(taken)]) == 2
    session = Session(load_setup("luxo-mouse"))
    with pytest.raises(DataError, match="rec.jsonl: exists; choose another path"):
        Recorder(session, taken)
    assert taken.read_text() == "precious, not even a log\n"
    assert session.listener is None


def test_headless_recording_replays_from_any_directory(tmp_path):
    """A headless recording of an interface given by a relative path embeds the
    interface's text as window recordings do, and names its file by absolute path: it
    replays from another directory, even with the file gone."""
    work = tmp_path / "work"
    work.mkdir()
    (work / "mine.yaml").write_text((ROOT / "interfaces" / "luxo-mouse.yaml").read_text())
    proc = _cli("play", "mine.yaml", "--headless", "--input", "luxo-hop", "--seconds", "0.5",
                "--record", "rec.jsonl", cwd=work)
    assert proc.returncode == 0, proc.stderr
    head = read_log(work / "rec.jsonl").header
    assert head["interface"] == str((work / "mine.yaml").resolve())
    assert head["interface_text"] == (work / "mine.yaml").read_text()
    (work / "mine.yaml").unlink()
    proc = _cli("replay", work / "rec.jsonl", "--headless", cwd="/")
    assert proc.returncode == 0, proc.stderr
    assert "(same as recorded)" in proc.stdout


def test_bad_json_line_names_the_column_in_plain_words(tmp_path, hop_log):
    lines = hop_log.read_text().splitlines()
    lines[2] = '{"step": 5, "event": {"type": "key", "key": "q'
    with pytest.raises(DataError) as info:
        read_log(_write(tmp_path / "cut.jsonl", lines))
    assert info.value.line == 3
    assert "not valid JSON (Unterminated string starting at column 45)" in info.value.message
    assert "at at" not in info.value.message
