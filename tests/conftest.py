import collections
import os
from pathlib import Path

import pytest

# The tests name shipped files as a user at the project's root does (assets/logs/...):
# run from there, whichever folder pytest was started in.
os.chdir(Path(__file__).resolve().parents[1])
os.environ.setdefault("SDL_VIDEODRIVER", "dummy")
os.environ.setdefault("SDL_AUDIODRIVER", "dummy")
os.environ.setdefault("PYGAME_HIDE_SUPPORT_PROMPT", "1")


# Under pytest-xdist the fuzz tests count in the worker processes: each worker hands its
# counts back (workeroutput) and the controller adds them up for the summary.
_FROM_WORKERS: collections.Counter = collections.Counter()


def _local_stats():
    import sys

    return getattr(sys.modules.get("fuzzing"), "STATS", None) or {}


def pytest_sessionfinish(session):
    workeroutput = getattr(session.config, "workeroutput", None)
    if workeroutput is not None:  # an xdist worker
        workeroutput["fuzz_stats"] = [[k, o, n] for (k, o), n in _local_stats().items()]


@pytest.hookimpl(optionalhook=True)
def pytest_testnodedown(node, error):
    for kind, outcome, n in getattr(node, "workeroutput", {}).get("fuzz_stats", ()):
        _FROM_WORKERS[(kind, outcome)] += n


def pytest_terminal_summary(terminalreporter):
    """The fuzz harness's counts (kind, outcome), when fuzz tests ran."""
    stats = collections.Counter(_local_stats()) + _FROM_WORKERS
    if not stats:
        return
    terminalreporter.section("fuzz cases")
    kinds = sorted({k for k, _ in stats})
    outcomes = sorted({o for _, o in stats})
    for kind in kinds:
        row = ", ".join(f"{o} {stats[(kind, o)]}" for o in outcomes if stats[(kind, o)])
        terminalreporter.write_line(f"{kind:10} {row}")
    total = sum(stats.values())
    bad = {o: sum(n for (_, oo), n in stats.items() if oo == o) for o in outcomes
           if o not in ("accepted", "refused")}
    terminalreporter.write_line(f"total {total} cases; " + ", ".join(
        f"{o} {n}" for o, n in sorted(bad.items())) if bad else f"total {total} cases")


@pytest.fixture
def path_of(monkeypatch):
    """``path_of("c")`` / ``path_of("python")``: run on the compiled kernel or on the
    pure-Python path from now on (``PUPPET_KERNEL``); the loaded kernel is forgotten
    after the test. A compiler but no cache to build in skips the test."""
    from puppet.physics import kernel

    def choose(how: str):
        monkeypatch.setenv(kernel.ENV, how)
        kernel.reset()
        try:
            return kernel.get()
        except kernel.KernelError as exc:
            pytest.skip(str(exc))
    yield choose
    kernel.reset()
