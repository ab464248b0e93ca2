"""Where a command's tries run, as options: ``--jobs N`` local processes and
``--cluster ADDRESS`` (a Dask scheduler, or 'local'), shared by ``puppet tune`` and
``puppet playtest`` (``puppet.timeline.executor`` runs them)."""

from __future__ import annotations

import argparse

from puppet.commands.options import in_range


def add_jobs_option(p: argparse.ArgumentParser, default: int) -> None:
    p.add_argument("--jobs", "-j", type=in_range(int, "number of processes", 1, 256),
                   default=default, metavar="N",
                   help=f"run the tries in N local processes (default {default}); the "
                        "results do not depend on it")


def add_cluster_option(p: argparse.ArgumentParser) -> None:
    p.add_argument("--cluster", metavar="ADDRESS",
                   help="run the tries on a Dask cluster: its scheduler's address "
                        "(tcp://HOST:8786; every machine with the same puppet checkout), "
                        "or 'local' for a local cluster of --jobs workers; needs "
                        "pip install 'puppet[cluster]'")


def executor_for(args):
    """The executor the options ask for (a context manager: it closes the pool)."""
    from puppet.timeline.executor import make_executor

    return make_executor(args.jobs, getattr(args, "cluster", None))


def default_jobs() -> int:
    """Local processes by default: the machine's cores, at most 4."""
    import os

    return max(1, min(4, os.cpu_count() or 1))
