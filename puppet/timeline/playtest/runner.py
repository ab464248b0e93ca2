"""Run a playtest: N tries of each log, in one process or several, and count the passes.

Each try is a task of its own (``trial.run_try``) that depends only on (log, noise,
seed, try index), so the counts and every try's end state are the same whatever
``jobs`` is and whichever process ran it. Each log is prepared in this process first:
a log that cannot be played is one error line, said once, not once per try.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

from puppet.data.errors import DataError
from puppet.data.playtest import Noise
from puppet.data.playtest_bar import PlaytestBar
from puppet.timeline.other_physics import OtherPhysics
from puppet.timeline.playtest.trial import SHIPPED, TryResult, prepare, run_try


@dataclass
class Plan:
    """What to run for one log: ``tries`` tries at ``noise`` from ``seed``, on
    ``physics`` (default: the log's own settings); ``level`` names the noise as the
    table shows it ('human', 'human*' with a parameter changed)."""

    log: str
    noise: Noise
    level: str
    tries: int
    seed: int = 0
    physics: OtherPhysics = SHIPPED


@dataclass
class LogPlaytest:
    """One log's playtest: its tries in index order, or the error that stopped it."""

    plan: Plan
    results: list[TryResult] = field(default_factory=list)
    error: str | None = None
    warnings: list[str] = field(default_factory=list)
    path: str = ""  # the log's file

    @property
    def passes(self) -> int:
        return sum(r.passed for r in self.results)

    @property
    def rate(self) -> float:
        return self.passes / len(self.results) if self.results else 0.0


def load_bar(log_path: str) -> PlaytestBar | None:
    """The ``playtest:`` bar of a log's sidecar (``LOG.expect.yaml``), or None."""
    from puppet.data.yamlfile import load_file
    from puppet.timeline.expectations import sidecar_path, validate_expect_file

    side = sidecar_path(log_path)
    if not side.is_file():
        return None
    return validate_expect_file(load_file(side)).playtest


def _task(args: tuple) -> TryResult | str:
    """A worker's try; an error as its one line (the log was prepared before, so this
    is rare: a file changed meanwhile)."""
    log, noise, seed, index, physics = args
    try:
        return run_try(log, noise, seed, index, physics)
    except DataError as exc:
        return str(exc)


def run(plans: list[Plan], jobs: int = 1,
        progress: Callable[[int], None] | None = None, executor=None) -> list[LogPlaytest]:
    """Every plan's tries, on ``executor`` (``puppet.timeline.executor``: here, local
    processes or a Dask cluster), else in ``jobs`` local processes (1: here).
    ``progress(n)`` is called as tries finish (n tries at a time)."""
    from puppet.timeline.executor import make_executor

    out = [LogPlaytest(p) for p in plans]
    tasks: list[tuple[int, int]] = []  # (plan, try index)
    for k, p in enumerate(plans):
        try:
            prepared = prepare(p.log, p.physics)
        except DataError as exc:
            out[k].error = str(exc)
            if progress is not None:
                progress(p.tries)
            continue
        out[k].path = prepared.path
        out[k].warnings = list(prepared.warnings)
        tasks.extend((k, i) for i in range(p.tries))
    args = [(out[k].path, plans[k].noise, plans[k].seed, i, plans[k].physics)
            for k, i in tasks]
    if executor is not None:
        results = executor.map(_task, args, progress)
    else:
        with make_executor(jobs if len(tasks) > 1 else 1) as local:
            results = local.map(_task, args, progress)
    for (k, _), res in zip(tasks, results, strict=True):
        if isinstance(res, str):
            out[k].error = out[k].error or res
        else:
            out[k].results.append(res)
    for r in out:
        if r.error is not None:
            r.results = []
    return out


def playtest(log: str | Path, noise: Noise, tries: int = 20, seed: int = 0, jobs: int = 1,
             level: str = "", physics: OtherPhysics = SHIPPED) -> LogPlaytest:
    """One log's playtest (a test's or a tool's entry point)."""
    return run([Plan(str(log), noise, level, tries, seed, physics)], jobs)[0]
