"""The command line as a newcomer meets it: every mistake is one line that begins
``puppet COMMAND:``, usage errors exit 2, and nothing is half done."""

import os
import subprocess
import sys

from puppet.data import catalog


def puppet(*args, env=None, cwd=None):
    return subprocess.run([sys.executable, "-m", "puppet", *args], capture_output=True,
                          text=True, env=env, cwd=cwd, timeout=60)


def _no_display_env():
    env = {k: v for k, v in os.environ.items()
           if k not in ("DISPLAY", "WAYLAND_DISPLAY", "SDL_VIDEODRIVER")}
    env["PYTHONPATH"] = str(catalog.ROOT)
    return env


def _recordings():
    folder = catalog.ROOT / "recordings"
    return set(folder.glob("*.jsonl")) if folder.exists() else set()


def test_play_without_a_display_says_so_points_to_headless_and_records_nothing(tmp_path):
    before = _recordings()
    proc = puppet("play", "luxo-mouse", env=_no_display_env())
    assert proc.returncode == 2
    line = proc.stderr.strip().splitlines()[-1]
    assert line.startswith("puppet play: no display found") and "--headless" in line
    assert _recordings() == before
    log = tmp_path / "x.jsonl"
    proc = puppet("play", "luxo-mouse", "--record", str(log), env=_no_display_env())
    assert proc.returncode == 2 and not log.exists()


def test_a_window_replay_without_a_display_says_so_too():
    proc = puppet("replay", "luxo-hop", env=_no_display_env())
    assert proc.returncode == 2
    assert proc.stderr.strip().splitlines()[-1].startswith("puppet replay: no display found")
