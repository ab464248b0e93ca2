"""Which recorded feats still hold on other solver settings: every log of a character
replayed with its solver's iterations (and collision slop) changed, judged by the log's
own expectations (the hash aside: it changes with any setting).

    python tools/solver_sensitivity.py --characters biped,biped-small --iterations 40,39,36,30
                                       [--slop 0.0001] [--jobs 2] [LOG ...]

Why: the figure's speed is Chipmunk's step (40 iterations at 480 Hz for the biped), and
fewer iterations are the one setting that makes it much cheaper (about 1.1-1.2x at 30,
1.35-1.5x at 20, on the bench's gesture). Every feat is an open-loop performance of a
chaotic system, so a cheaper solver means re-performing the feats it breaks: this says
which, before anyone changes ``solver:`` in a character file. (Measured 2026-12-02: one
iteration fewer breaks 8 of the biped's 23 logs, the walk and the march among them.)
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
from puppet.timeline.log import read_log
from puppet.timeline.replay import replay

LOGS = Path(__file__).resolve().parents[1] / "assets" / "logs"


def character_of(path: Path) -> str:
    """The character a log plays (its header's)."""
    return read_log(path).header.get("character", "")


def failures(path: Path, iterations: int, slop: float | None) -> list[str]:
    """The expectations of ``path`` that fail with its character's solver at
    ``iterations`` passes and ``slop`` (None: the file's), the end hash left out."""
    def adjust(setup):
        old = setup.character.solver
        solver = SolverSpec(iterations=iterations,
                            collision_slop=old.collision_slop if slop is None else slop)
        return dataclasses.replace(
            setup, character=setup.character.model_copy(update={"solver": solver}))

    result = replay(path, adjust=adjust)
    return [o.expectation for o in result.outcomes
            if not o.passed and o.expectation != "same end as the recording"]


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
    ap.add_argument("--jobs", "-j", type=int, default=2)
    args = ap.parse_args(argv)
    logs = args.logs or sorted(LOGS.glob("*.jsonl"))
    logs = [p for p in logs if character_of(p) in args.characters]
    if not logs:
        print(f"no logs of {', '.join(args.characters)}", file=sys.stderr)
        return 2
    settings = list(itertools.product(args.iterations, args.slop))
    jobs = [(p, n, s) for n, s in settings for p in logs]
    with ProcessPoolExecutor(max_workers=max(1, args.jobs)) as pool:
        results = list(pool.map(failures, *zip(*jobs)))
    broken = False
    for i, (n, s) in enumerate(settings):
        rows = results[i * len(logs):(i + 1) * len(logs)]
        held = [p.stem for p, r in zip(logs, rows) if not r]
        slop = "" if s is None else f", slop {s:g} m"
        print(f"{n} iterations{slop}: {len(held)}/{len(logs)} logs hold"
              + (f" ({', '.join(held)})" if held and len(held) < len(logs) else ""))
        for path, failed in zip(logs, rows):
            if failed:
                broken = True
                kinds = dict.fromkeys(f.split(" ")[0].rstrip(":") for f in failed)  # in order, once
                print(f"  {path.stem}: {', '.join(kinds)}")
    return 1 if broken else 0


if __name__ == "__main__":
    sys.exit(main())
