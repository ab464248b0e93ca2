import os

os.environ.setdefault("SDL_VIDEODRIVER", "dummy")
os.environ.setdefault("SDL_AUDIODRIVER", "dummy")
os.environ.setdefault("PYGAME_HIDE_SUPPORT_PROMPT", "1")


def pytest_terminal_summary(terminalreporter):
    """The fuzz harness's counts (kind, outcome), when fuzz tests ran."""
    import sys

    fuzzing = sys.modules.get("fuzzing")
    stats = getattr(fuzzing, "STATS", None)
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
