"""``tools/rerecord.py``: a log re-recorded after a change its run does not see keeps
what its playtests need - the reactive script that played it (a log without its
``script_text`` is played by its recorded events instead, and measures another thing)."""

from __future__ import annotations

import importlib.util
import shutil

from puppet.data.catalog import ROOT
from puppet.timeline.log import read_log

SPEC = importlib.util.spec_from_file_location("rerecord", ROOT / "tools" / "rerecord.py")
rerecord = importlib.util.module_from_spec(SPEC)
SPEC.loader.exec_module(rerecord)


def test_a_reactive_logs_script_stays_in_its_header(tmp_path):
    log = tmp_path / "cat-bound.jsonl"
    shutil.copy(ROOT / "assets" / "logs" / "cat-bound.jsonl", log)
    before = read_log(log)
    assert "script_text" in before.header  # (the premise: a log played by its script)
    said = rerecord.rerecord(log)
    after = read_log(log)
    assert "same end" in said and after.end_hash == before.end_hash
    assert after.header["script"] == before.header["script"] == "cat-bound"
    today = (ROOT / "assets" / "scripts" / "cat-bound.yaml").read_text(encoding="utf-8")
    assert after.header["script_text"] == today


def test_on_another_step_the_log_moves_its_events_and_says_the_step(tmp_path):
    """``--step 1/240 --new-end``: a character whose own step changed (issue 29); the
    same events at the same times on the new step, its header's 'dt' the new step, kept
    only if its expectations pass there (luxo-keys-sit-stand holds at 1/240 s)."""
    name = "luxo-keys-sit-stand"
    for ext in (".jsonl", ".expect.yaml"):
        shutil.copy(ROOT / "assets" / "logs" / f"{name}{ext}", tmp_path / f"{name}{ext}")
    log = tmp_path / f"{name}.jsonl"
    before = read_log(log)
    said = rerecord.rerecord(log, new_end=True, step=1 / 240)
    after = read_log(log)
    assert "a new end" in said, said
    assert after.header["dt"] == 1 / 240 and before.header["dt"] == 1 / 480
    assert [e.event for e in after.events] == [e.event for e in before.events]
    assert [e.step for e in after.events] == [round(e.step / 2) for e in before.events]
    from puppet.timeline.replay import replay

    assert replay(log).same_end


def test_help_prints_the_usage_instead_of_reading_a_log_named_help():
    import subprocess
    import sys

    run = subprocess.run([sys.executable, str(ROOT / "tools" / "rerecord.py"), "--help"],
                         capture_output=True, text=True, timeout=60)
    assert run.returncode == 0, run.stderr
    assert "--new-end" in run.stdout and "--step 1/240" in run.stdout
