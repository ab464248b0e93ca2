"""The tools left in tools/ still run against today's code: each imports (a data
library's change broke three of them without a test noticing). The searches that are
a product feature are tuning specs now (assets/tune/, puppet tune: tests/test_tune.py,
tests/test_tune_climbs.py)."""

from __future__ import annotations

import importlib
import sys
from pathlib import Path

import pytest

TOOLS = Path(__file__).resolve().parents[1] / "tools"


@pytest.fixture(scope="module", autouse=True)
def tools_on_path():
    sys.path.insert(0, str(TOOLS))
    yield
    sys.path.remove(str(TOOLS))


@pytest.mark.parametrize("name", sorted(p.stem for p in TOOLS.glob("*.py")))
def test_each_tool_imports(name):
    importlib.import_module(name)


def test_solver_sensitivity_replays_on_the_changed_solver():
    """The tool's verdict rests on the replay using its solver: the file's keeps the
    kip's expectations, 30 iterations break one (tools/solver_sensitivity.py)."""
    tool = importlib.import_module("solver_sensitivity")
    log = Path(__file__).resolve().parents[1] / "assets" / "logs" / "biped-kip.jsonl"
    assert tool.failures(log, 40, None) == []
    assert any(f.startswith("touching_at_end") for f in tool.failures(log, 30, None))


def test_solver_sensitivity_moves_every_event_to_the_same_time_on_another_step():
    """--dt: a log replayed on a 1/240 s step has each event (and its end) at the step
    nearest its recorded time, in the recorded order; a layout of held poses keeps its
    feat there (luxo-keys-sit-stand), a bounced-off push does not have to."""
    from puppet.timeline.log import read_log

    tool = importlib.import_module("solver_sensitivity")
    path = Path(__file__).resolve().parents[1] / "assets" / "logs" / "luxo-keys-sit-stand.jsonl"
    log = read_log(path)
    coarse = tool.rescaled(log, 1 / 240)
    assert coarse.header["dt"] == 1 / 240 and log.header["dt"] == 1 / 480
    assert [e.event for e in coarse.events] == [e.event for e in log.events]
    for old, new in zip(log.events, coarse.events):
        assert abs(new.step / 240 - old.step / 480) <= 0.5 / 240
    assert coarse.end["end"] == round(log.end["end"] / 2)
    assert tool.failures(path, 36, None, 1 / 240) == []
