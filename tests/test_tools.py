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
