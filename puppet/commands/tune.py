"""``puppet tune SPEC.yaml``: search a performance stage by stage from checkpoints and
write the best one as a log (with its sidecar), as docs/tuning.md describes.

Progress goes to stderr (a tqdm bar per stage, on a terminal); what each stage kept and
the verdict go to stdout. The tries played are kept beside the log (``NAME.tune.json``):
run the same command again after an interruption (Ctrl+C, ``--max-tries``) and it goes
on where it stopped. Exit 0 when the feat holds in the written log, 1 when the search
found no performance that meets it (the best one is written all the same), 2 for a bad
spec or option, 130 when interrupted.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from puppet.commands.engine import add_cluster_option, add_jobs_option, default_jobs, executor_for
from puppet.commands.options import in_range

EXIT_NOT_FOUND, EXIT_ERROR, EXIT_INTERRUPTED = 1, 2, 130


def register(subparsers) -> argparse.ArgumentParser:
    """Add ``puppet tune`` to the command's sub-parsers."""
    p = subparsers.add_parser(
        "tune", help="search a performance stage by stage from checkpoints (a tuning "
                     "spec), write the best as a log",
        description="Search the performance a tuning spec describes (docs/tuning.md): "
                    "stage by stage, each from a checkpoint where the kept performance "
                    "has got to, many tries of it scored by expectations and their "
                    "margins. Writes the best as a log with its sidecar; run again to "
                    "resume an interrupted search. Exit 0: the feat holds; 1: not found "
                    "(the best is written); 2: a bad spec or option; 130: interrupted.")
    p.add_argument("spec", metavar="SPEC", help="a tuning spec (.yaml), e.g. "
                                                "assets/tune/luxo-backflip.yaml")
    p.add_argument("--out", "-o", metavar="LOG",
                   help="the log to write (.jsonl; default recordings/tune/NAME.jsonl); "
                        "its sidecar, state and tuned interface go beside it")
    p.add_argument("--script", metavar="FILE",
                   help="also write the performance as a script (.yaml)")
    p.add_argument("--seed", type=in_range(int, "seed", 0, 2 ** 32 - 1),
                   help="the random seed (default: the spec's): the same seed gives the "
                        "same log, whatever --jobs or --cluster")
    p.add_argument("--scale", type=in_range(float, "budget scale", 0.001, 100.0), default=1.0,
                   help="multiply every stage's tries (0.1: a tenth, for a quick look)")
    p.add_argument("--max-tries", type=in_range(int, "number of tries", 1, 10 ** 9),
                   metavar="N", help="stop after playing N tries (run again to go on)")
    p.add_argument("--fresh", action="store_true",
                   help="forget the tries of an earlier run of this search")
    add_jobs_option(p, default_jobs())
    add_cluster_option(p)
    p.set_defaults(func=run)
    return p


class _Bars:
    """The search's progress as tqdm bars on stderr (none when stderr is a file)."""

    def __init__(self):
        self.bar = None

    def stage(self, label: str, total: int) -> None:
        from tqdm import tqdm

        self.close()
        # disable=None: a bar on a terminal, nothing when stderr is a file or a pipe
        self.bar = tqdm(total=total, unit="try", desc=label, file=sys.stderr,
                        disable=None, leave=False)

    def advance(self, n: int = 1) -> None:
        if self.bar is not None:
            if self.bar.n + n > self.bar.total:  # a climb ended later than guessed
                self.bar.total = self.bar.n + n
            self.bar.update(n)

    def line(self, text: str) -> None:
        if self.bar is not None:
            self.bar.clear()
        print(text, flush=True)

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()
            self.bar = None


def out_path(args, name: str) -> Path:
    from puppet.data.catalog import folder

    if args.out:
        return _file("--out", args.out, ".jsonl")
    return folder("recording") / "tune" / f"{name}.jsonl"


def _file(option: str, text: str, ext: str) -> Path:
    from puppet.data.errors import UsageError

    path = Path(text)
    if path.is_dir() or path.suffix != ext:
        raise UsageError(f"{option} {text}: expected a file name ending in {ext}")
    if path.parent.exists() and not path.parent.is_dir():
        raise UsageError(f"{option} {text}: {path.parent} is a file, not a folder")
    return path


def run(args) -> int:
    from puppet.timeline.tuning import Interrupted, Search, load_tune_spec
    from puppet.timeline.tuning.writer import write_all

    loaded = load_tune_spec(args.spec)
    log_path = out_path(args, loaded.name)
    if args.script:
        _file("--script", args.script, ".yaml")
    state_path = log_path.with_name(log_path.name.removesuffix(".jsonl") + ".tune.json")
    if args.fresh:
        state_path.unlink(missing_ok=True)
    bars = _Bars()
    with executor_for(args) as executor:
        search = Search(loaded, executor, state_path, bars, args.max_tries, args.scale,
                        args.seed)
        print(f"tuning {args.spec}: {len(loaded.spec.stages)} stage(s), seed "
              f"{search.seed}, tries on {executor.name}", flush=True)
        try:
            result = search.run()
        except (Interrupted, KeyboardInterrupt) as exc:
            bars.close()
            why = str(exc) if isinstance(exc, Interrupted) else "interrupted"
            print(f"{why}: {search.played} tries played this run, kept in {state_path}; "
                  f"run the same command again to go on", file=sys.stderr)
            return EXIT_INTERRUPTED
        finally:
            bars.close()
    written = write_all(loaded, result, log_path, Path(args.script) if args.script else None)
    print(f"{result.played} tries played, {result.looked_up} looked up; the performance "
          f"lasts {result.seconds:.2f} s")
    for what, path in (("log", written.log), ("sidecar", written.sidecar),
                       ("script", written.script), ("tuned interface", written.interface)):
        if path is not None:
            print(f"wrote {what} {path}")
    for note in written.notes:
        print(note, file=sys.stderr)
    print(f"replayed {written.log.name} with its sidecar:")
    for o in written.outcomes:
        print(f"  {o}")
    if not written.same_as_search:
        print("warning: the log replayed to another end state than the search reached "
              "(its checkpoints did not re-seat the run the same way)", file=sys.stderr)
    if not result.found:
        print(f"not found: {result.message}")
        return EXIT_NOT_FOUND
    if not written.passed:
        print("not found: the written log misses its sidecar's expectations")
        return EXIT_NOT_FOUND
    print("found: the feat holds")
    return 0
