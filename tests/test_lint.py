"""The code stays lint-clean: ``ruff check .`` with pyproject.toml's rules (pycodestyle,
pyflakes, bugbear, import order, pyupgrade, simplify; lines of 100), as a habit, in
every run of the suite. ruff is in the ``test`` extra (pip install -e '.[test]')."""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def _ruff() -> list[str]:
    """The command that runs ruff: its module in this Python, else the one on PATH."""
    try:
        import ruff  # noqa: F401 - only asks whether it is installed here

        return [sys.executable, "-m", "ruff"]
    except ImportError:
        found = shutil.which("ruff")
        assert found, "ruff is not installed: pip install -e '.[test]' (the test extra)"
        return [found]


def test_ruff_finds_nothing():
    proc = subprocess.run([*_ruff(), "check", "--no-cache", "--output-format", "concise",
                           "."], cwd=ROOT, capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stdout + proc.stderr


PROBE = """\
import sys
import os
from typing import List


def f(x: List[int], seen=[]):
    if "k" in {}.keys():
        return x
    return seen + [len(x)] + ["a line over one hundred characters long: LONG"]
""".replace("LONG", "x" * 40)


def test_the_configured_rules_catch_their_mistakes():
    """Each rule family the project holds itself to catches one mistake under
    pyproject.toml's settings (a family dropped from the list would stop being checked
    without a word)."""
    proc = subprocess.run([*_ruff(), "check", "--no-cache", "--output-format", "concise",
                           "--stdin-filename", "puppet/lint_probe.py", "-"], cwd=ROOT,
                          input=PROBE, capture_output=True, text=True, timeout=120)
    found = {line.split(": ", 1)[1].split()[0] for line in proc.stdout.splitlines()
             if line.startswith("puppet/lint_probe.py:")}
    assert {"E501", "F401", "B006", "I001", "UP006", "SIM118"} <= found, proc.stdout
