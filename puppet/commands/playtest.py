"""``puppet playtest LOG...``: how forgiving a feat is, measured by a simulated player.

Each log is replayed ``--tries`` times with a person's imprecision (the human model of
``puppet.data.playtest``, at ``--noise`` or each parameter on its own flag) and judged
by its feat expectations; stdout gets one row per log (or ``--json``), stderr a
progress bar. Exit 1 when a log misses its own ``playtest:`` bar, 2 when a log cannot
be played or an option is wrong, else 0. The figures are kept for the window's HUD
(``puppet.timeline.playtest.store``) unless ``--no-save``.
"""

from __future__ import annotations

import argparse
import json
import sys
from collections import Counter
from pathlib import Path

from puppet.commands import options
from puppet.commands.engine import add_cluster_option, executor_for
from puppet.commands.options import in_range
from puppet.data.playtest import LEVELS, PARAMETERS

EXIT_MISSED, EXIT_ERROR = 1, 2
DEFAULT_TRIES = 20
DEFAULT_LEVEL = "human"


def _number(name: str):
    lo, hi, unit, _ = PARAMETERS[name]
    return in_range(float, "number", float(lo), float(hi), unit=" " + unit if unit else "")


def register(subparsers) -> argparse.ArgumentParser:
    """Add ``puppet playtest`` to the command's sub-parsers."""
    p = subparsers.add_parser(
        "playtest", help="replay logs many times with a person's imprecision; how often "
                         "the feat still comes off",
        description="Replay each log --tries times, every event moved by a person's "
                    "timing error (real time, so a slowed-down log moves less in "
                    "simulated time) and every mouse or stick stroke by an aim error "
                    "plus tremor, and judge each try by the log's feat expectations "
                    "(its sidecar LOG.expect.yaml, else its header; the recorded end "
                    "state is not judged). Prints one row per log; exit 1 if a log "
                    "misses its own 'playtest:' bar, 2 on an error. The human model "
                    "and how to read the figures: docs/interfaces.md, Playtests.")
    p.add_argument("logs", nargs="+", metavar="LOG",
                   help="log file(s) (.jsonl), or names (assets/logs/NAME.jsonl, else "
                        "recordings/NAME.jsonl)")
    p.add_argument("--tries", "-n", type=in_range(int, "number of tries", 1, 10000),
                   help=f"tries per log (default: the log's bar's, else {DEFAULT_TRIES})")
    p.add_argument("--seed", type=in_range(int, "seed", 0, 2 ** 32 - 1), default=0,
                   help="the random seed (default 0): the same seed gives the same "
                        "tries, bit for bit")
    p.add_argument("--jobs", "-j", type=in_range(int, "number of processes", 1, 256), default=1,
                   metavar="N", help="run the tries in N processes (the figures do not "
                                     "depend on it)")
    add_cluster_option(p)
    p.add_argument("--noise", choices=list(LEVELS),
                   help="how imprecise the player is: "
                        + "; ".join(f"{n} +-{v.timing_ms:g} ms, {v.aim_px:g} px"
                                    for n, v in LEVELS.items())
                        + f" (default: the log's bar's level, else {DEFAULT_LEVEL})")
    for name, (lo, hi, unit, what) in PARAMETERS.items():
        p.add_argument("--" + name.replace("_", "-"), type=_number(name), dest=name,
                       metavar=unit.upper() or "X",
                       help=f"{what} ({lo:g}..{hi:g}; replaces the level's)")
    p.add_argument("--from-rest", metavar="KEY",
                   help="instead of a person's noise: move the log's first press of KEY "
                        "(and all after it) to --count moments of --between, each copy "
                        "judged by the feat expectations; exit 1 when fewer than 9 in 10 "
                        "land (a single-key move must not depend on when it starts)")
    p.add_argument("--between", nargs=2, type=in_range(float, "time", 0.0, 3600.0),
                   metavar=("FROM", "TO"), default=(0.5, 3.0),
                   help="--from-rest: the stretch of the log, in s, in which the "
                        "character stands still in the move's start pose (default 0.5 3)")
    p.add_argument("--count", type=in_range(int, "number of presses", 1, 1000), default=10,
                   help="--from-rest: how many presses (default 10)")
    p.add_argument("--solver-passes", type=options.solver_passes, metavar="N",
                   help="play the tries on N constraint-solver passes a step instead of "
                        "the character's (the cheaper physics a feat must survive: issue "
                        "29 chooses the settings by these pass rates); the figures are not "
                        "kept for the HUD")
    p.add_argument("--step", type=options.sim_step, metavar="S",
                   help="play the tries on a simulation step of S s (1/240 or "
                        "0.0041667) instead of the log's, every event at the step nearest "
                        "its recorded time (as puppet replay --step moves them)")
    p.add_argument("--json", action="store_true", help="print the results as JSON")
    p.add_argument("--no-save", action="store_true",
                   help="do not keep the figures for the window's HUD "
                        "(recordings/playtests.json)")
    p.set_defaults(func=run)
    return p


def _plans(args) -> list:
    """One plan per log: the noise and tries asked for, else the log's bar's."""
    from puppet.data.errors import DataError, UsageError
    from puppet.data.playtest import noise_at
    from puppet.timeline.playtest import Plan, load_bar
    from puppet.timeline.replay import find_log

    overrides = {n: getattr(args, n) for n in PARAMETERS if getattr(args, n) is not None}
    physics = options.other_physics(args)
    plans, bars = [], []
    for name in args.logs:
        try:
            bar = load_bar(find_log(name))
        except DataError:
            bar = None  # the log's own error is said when it is prepared
        level = args.noise or (bar.noise if bar else DEFAULT_LEVEL)
        tries = args.tries or (bar.tries if bar else DEFAULT_TRIES)
        try:
            noise = noise_at(level, **overrides)
        except ValueError as exc:
            raise UsageError(str(exc)) from None
        label = level + ("*" if overrides else "")
        plans.append(Plan(name, noise, label, tries, args.seed, physics))
        bars.append(bar)
    return plans, bars


def _bar_verdict(result, bar) -> tuple[str, bool | None]:
    """(what the bar column says, met: True/False, None when not checked)."""
    if bar is None:
        return "-", None
    want = f">= {bar.min_pass:.0%} at {bar.noise}"
    if result.error is not None:
        return want, None
    if result.plan.level != bar.noise:  # another level (or a parameter changed)
        return f"{want} (not checked)", None
    met = result.passes >= bar.needed(len(result.results))
    return f"{want}: {'met' if met else 'MISSED'}", met


def _failures(result) -> Counter:
    """How the failed tries failed: for each kind of expectation, the tries that
    missed one of that kind (a blow-up or leaving the world: 'blow-up')."""
    kinds: Counter = Counter()
    for r in result.results:
        if not r.passed:
            missed: dict[str, None] = {}  # in the expectations' order (a set's order is
            for line in r.failed:          # the hash seed's: ties would shuffle the table)
                words = line.split()
                missed[words[1].rstrip(":") if len(words) > 1 and words[0] == "FAIL"
                       else line] = None
            kinds.update(list(missed))
    return kinds


def _row(result, bar_text: str) -> tuple[str, ...]:
    if result.error is not None:
        return (result.plan.log, result.plan.level, "-", "-", bar_text, "ERROR")
    n = len(result.results)
    kinds = _failures(result)
    how = ", ".join(f"{k} {c}" for k, c in kinds.most_common(3)) or "-"
    return (result.plan.log, result.plan.level, f"{result.passes}/{n}",
            f"{result.rate:.0%}", bar_text, how)


def table(rows: list[tuple[str, ...]]) -> str:
    head = ("log", "noise", "pass", "rate", "bar", "what the failed tries missed")
    rows = [head] + rows
    widths = [max(len(r[i]) for r in rows) for i in range(len(head) - 1)]
    return "\n".join("  ".join(c.ljust(w) for c, w in zip(r, widths)) + "  " + r[-1]
                     for r in rows)


def _as_json(result, bar, met) -> dict:
    out = {"log": result.plan.log, "path": result.path, "noise": result.plan.level,
           "parameters": {k: getattr(result.plan.noise, k) for k in PARAMETERS},
           "seed": result.plan.seed, "tries": result.plan.tries,
           "physics": result.plan.physics.label() or "as recorded"}
    if result.error is not None:
        return dict(out, error=result.error)
    return dict(out, passes=result.passes, rate=result.rate,
                bar=None if bar is None else {"noise": bar.noise, "tries": bar.tries,
                                              "min_pass": bar.min_pass, "met": met},
                failures=dict(_failures(result)),
                results=[r.to_dict() for r in result.results], warnings=result.warnings)


def _save(results) -> None:
    from puppet.timeline.playtest import prepare
    from puppet.timeline.playtest.store import save

    figures = []
    for r in results:
        if r.error is None and r.results:
            figures.append({"log": Path(r.path).name.removesuffix(".jsonl"),
                            "interface": prepare(r.plan.log, r.plan.physics).setup.interface.name,
                            "passes": r.passes, "tries": len(r.results),
                            "noise": r.plan.level, "seed": r.plan.seed})
    if figures:
        save(figures)


def from_rest(args) -> int:
    """``--from-rest KEY``: each log's press of KEY at --count moments; a line a press,
    then how many landed."""
    from puppet.data.errors import DataError
    from puppet.timeline.log import read_log
    from puppet.timeline.playtest.from_rest import LAND_SHARE, failures, press_step, steps_between
    from puppet.timeline.replay import find_log

    start, stop = args.between
    short = []
    physics = options.other_physics(args)
    if physics and not args.json:
        print(f"on {physics.label()}: each press judged by the feat's expectations",
              file=sys.stderr)
    for name in args.logs:
        try:
            path = find_log(name)
            log = read_log(path)
            press_step(log, args.from_rest)
        except DataError as exc:
            print(f"puppet playtest: {exc}", file=sys.stderr)
            return EXIT_ERROR
        dt = float(log.header["dt"])
        steps = steps_between(dt, min(start, stop), max(start, stop), args.count)
        try:
            with executor_for(args) as executor:
                found = executor.map(failures, [(path, args.from_rest, s, physics)
                                                for s in steps])
        except DataError as exc:
            print(f"puppet playtest: {exc}", file=sys.stderr)
            return EXIT_ERROR
        out = []
        for step, failed in zip(steps, found):
            words = "lands" if not failed else "fails: " + ", ".join(failed)
            out.append({"step": step, "t": round(step * dt, 4), "failed": failed})
            if not args.json:
                print(f"  {args.from_rest} at {step * dt:.3f} s (step {step}): {words}")
        landed = sum(1 for f in found if not f)
        if args.json:
            print(json.dumps({"log": name, "key": args.from_rest, "landed": landed,
                              "presses": out}, indent=1))
        else:
            print(f"{Path(path).stem}: {landed}/{len(steps)} presses of "
                  f"{args.from_rest} from rest land")
        if landed < LAND_SHARE * len(steps) - 1e-9:
            short.append(name)
    return EXIT_MISSED if short else 0


def run(args) -> int:
    """The command: plans, the tries (with a progress bar), the table or JSON."""
    if args.from_rest:
        return from_rest(args)
    from tqdm import tqdm

    from puppet.timeline.playtest import run as run_plans

    plans, bars = _plans(args)
    physics = plans[0].physics if plans else None
    if physics and not args.json:  # said once, before the results
        print(f"on {physics.label()}: each try judged by the feat's expectations",
              file=sys.stderr)
    total = sum(p.tries for p in plans)
    # disable=None: a bar on a terminal, nothing when stderr is a file or a pipe
    with tqdm(total=total, unit="try", desc="playtest", file=sys.stderr,
              disable=None) as bar, executor_for(args) as executor:
        results = run_plans(plans, progress=bar.update, executor=executor)
    verdicts = [_bar_verdict(r, b) for r, b in zip(results, bars)]
    for r in results:
        for w in r.warnings:
            print(w, file=sys.stderr)
        if r.error is not None:
            print(f"puppet playtest: {r.error}", file=sys.stderr)
    if args.json:
        print(json.dumps([_as_json(r, b, v[1]) for r, b, v in zip(results, bars, verdicts)],
                         indent=1))
    else:
        print(table([_row(r, v[0]) for r, v in zip(results, verdicts)]))
        missed = sum(v[1] is False for v in verdicts)
        met = sum(v[1] is True for v in verdicts)
        errors = sum(r.error is not None for r in results)
        print(f"{len(results)} log{'' if len(results) == 1 else 's'}, {total} tries: "
              f"bars {met} met, {missed} missed; "
              f"{errors} error{'' if errors == 1 else 's'}")
    if not args.no_save and not physics:  # the HUD shows the shipped settings' figures
        _save(results)
    if any(r.error is not None for r in results):
        return EXIT_ERROR
    return EXIT_MISSED if any(v[1] is False for v in verdicts) else 0
