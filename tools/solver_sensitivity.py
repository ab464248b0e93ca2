"""Which recorded feats still hold on other solver settings: every log of a character
replayed with its solver's iterations (and collision slop) changed, judged by the log's
own expectations (the hash aside: it changes with any setting).

    python tools/solver_sensitivity.py --characters biped,biped-small --iterations 40,39,36,30
                                       [--slop 0.0001] [--dt 0.0041667] [--jobs 2] [LOG ...]

Why: the figure's speed is Chipmunk's step (40 iterations at 480 Hz for the biped), and
fewer iterations are the one setting that makes it much cheaper (about 1.1-1.2x at 30,
1.35-1.5x at 20, on the bench's gesture). Every feat is an open-loop performance of a
chaotic system, so a cheaper solver means re-performing the feats it breaks: this says
which, before anyone changes ``solver:`` in a character file. (Measured 2026-12-02: one
iteration fewer breaks 8 of the biped's 23 logs, the walk and the march among them.)
``--dt`` replays on another simulation step too (1/240 s: ``0.0041667``), every event
moved to the step nearest its recorded time (``rescaled``): the other setting that
makes a run cheaper. (The servos' damping means the same on any step: puppet/physics/
servo.py. Before that, every Luxo and cat log failed at 1/240 s, because the engine's
damping grows exponentially with the step on light links; measured 2026-12-07 with it:
Luxo and cat 5/18 logs hold at 1/240 s, 9/18 at 1/360 s, 8/18 at 1/960 s, against 1, 3
and 3; the rest fail at 1/960 s or with their events on 1/240 s steps at 1/480 s too.)
Exit 1 if a log fails at some setting, 0 if all hold.
"""

from __future__ import annotations

import argparse
import dataclasses
import itertools
import sys
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

from puppet.data.characters import SolverSpec
from puppet.timeline.log import Log, LogEvent, read_log
from puppet.timeline.replay import replay

LOGS = Path(__file__).resolve().parents[1] / "assets" / "logs"


def character_of(path: Path) -> str:
    """The character a log plays (its header's)."""
    return read_log(path).header.get("character", "")


def rescaled(log: Log, dt: float) -> Log:
    """``log`` on a simulation step of ``dt`` s: each event (and a rewind's target, and
    the end) at the step nearest its recorded time, in the recorded order."""
    ratio = float(log.header["dt"]) / dt

    def at(step: int) -> int:
        return round(step * ratio)

    events = []
    for e in log.events:
        event = dict(e.event)
        if "to_step" in event:
            event["to_step"] = at(event["to_step"])
        events.append(LogEvent(at(e.step), event, e.line))
    end = None if log.end is None else {**log.end, "end": at(log.end["end"])}
    return dataclasses.replace(log, header={**log.header, "dt": dt}, events=events, end=end)


def failures(path: Path, iterations: int, slop: float | None,
             dt: float | None = None) -> list[str]:
    """The expectations of ``path`` that fail with its character's solver at
    ``iterations`` passes and ``slop`` (None: the file's), and on a step of ``dt`` s
    (None: the log's), the end hash left out."""
    return [o.expectation for o in failed(path, iterations, slop, dt)]


def failed(path: Path, iterations: int, slop: float | None, dt: float | None = None) -> list:
    """The failed Outcomes (kind, words, margin) of ``failures``."""
    def adjust(setup):
        old = setup.character.solver
        solver = SolverSpec(iterations=iterations,
                            collision_slop=old.collision_slop if slop is None else slop)
        return dataclasses.replace(
            setup, character=setup.character.model_copy(update={"solver": solver}))

    log = read_log(path)
    result = replay(log if dt is None else rescaled(log, dt), adjust=adjust)
    return [o for o in result.outcomes if not o.passed and o.kind != "same_end"]


def _numbers(kind, text: str) -> list:
    try:
        values = [kind(v) for v in text.split(",")]
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected comma-separated numbers, got '{text}'") \
            from None
    if not values or any(v <= 0 for v in values):
        raise argparse.ArgumentTypeError(f"expected positive numbers, got '{text}'")
    return values


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("logs", nargs="*", type=Path,
                    help="logs (default: every assets/logs/*.jsonl of the character)")
    ap.add_argument("--characters", type=lambda t: t.split(","), default=["biped", "biped-small"],
                    help="comma-separated character names (default: biped,biped-small)")
    ap.add_argument("--iterations", type=lambda t: _numbers(int, t), default=[40, 39, 36, 30])
    ap.add_argument("--slop", type=lambda t: _numbers(float, t), default=[None],
                    help="collision slops, m (default: the character file's)")
    ap.add_argument("--dt", type=lambda t: _numbers(float, t), default=[None],
                    help="simulation steps, s (default: each log's own; 0.0041667 is 1/240)")
    ap.add_argument("--jobs", "-j", type=int, default=2)
    args = ap.parse_args(argv)
    logs = args.logs or sorted(LOGS.glob("*.jsonl"))
    logs = [p for p in logs if character_of(p) in args.characters]
    if not logs:
        print(f"no logs of {', '.join(args.characters)}", file=sys.stderr)
        return 2
    settings = list(itertools.product(args.iterations, args.slop, args.dt))
    jobs = [(p, n, s, d) for n, s, d in settings for p in logs]
    with ProcessPoolExecutor(max_workers=max(1, args.jobs)) as pool:
        results = list(pool.map(failed, *zip(*jobs)))
    broken = False
    for i, (n, s, d) in enumerate(settings):
        rows = results[i * len(logs):(i + 1) * len(logs)]
        held = [p.stem for p, r in zip(logs, rows) if not r]
        slop = "" if s is None else f", slop {s:g} m"
        step = "" if d is None else f", step {d:g} s"
        print(f"{n} iterations{slop}{step}: {len(held)}/{len(logs)} logs hold"
              + (f" ({', '.join(held)})" if held and len(held) < len(logs) else ""))
        for path, outcomes in zip(logs, rows):
            if outcomes:
                broken = True
                worst: dict = {}  # kind -> its most negative margin, in order, once
                for o in outcomes:
                    if o.kind not in worst or o.margin < worst[o.kind].margin:
                        worst[o.kind] = o
                print(f"  {path.stem}: " + ", ".join(
                    f"{k} ({o.margin:+.3g} {o.unit})".replace(" )", ")")
                    for k, o in worst.items()))
    return 1 if broken else 0


if __name__ == "__main__":
    sys.exit(main())
