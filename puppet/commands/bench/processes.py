"""Whole ``puppet`` processes as a user starts them, timed end to end."""

from __future__ import annotations

import os
import statistics
import sys
import time


def measure_processes(repeats: int) -> dict:
    """Wall ms of whole ``puppet`` processes, as a user starts them: the import alone
    (``--version``), a short headless replay (luxo-hop) and a check of one file (a
    character's, and an interface's: it loads all three kinds of models). Beside each,
    the CPU ms the process used (user + system): on a shared machine the wall time
    also counts the time the process waited for a core."""
    import subprocess

    from puppet.data.catalog import ROOT

    commands = {"startup": ["--version"],
                "replay": ["replay", "luxo-hop", "--headless"],
                # (the validation alone: a character's stability check simulates 10 s)
                "check": ["check", "--no-stability", str(ROOT / "characters" / "luxo.yaml")],
                "check_interface": ["check", str(ROOT / "interfaces" / "luxo-keys.yaml")]}
    out = {}
    for name, args in commands.items():
        walls, cpus = [], []
        for _ in range(repeats):
            t0 = time.perf_counter()
            child = subprocess.Popen([sys.executable, "-m", "puppet", *args], cwd=ROOT,
                                     stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
            _, _, usage = os.wait4(child.pid, 0)
            walls.append((time.perf_counter() - t0) * 1e3)
            cpus.append((usage.ru_utime + usage.ru_stime) * 1e3)
        out[f"{name}_ms"] = statistics.median(walls)
        out[f"{name}_cpu_ms"] = statistics.median(cpus)
    return out
