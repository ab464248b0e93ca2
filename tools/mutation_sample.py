"""The mutation run's driver (started by tools/mutation.sh in a scratch copy of the tree,
which holds tools/mutation.cfg as setup.cfg): mutmut generates every mutant of the
configured packages and records which tests reach which function; a seeded sample of
the mutants is then run, one process at a time, and a report written: the kill rate, by
package, and every survivor with its diff. See docs/mutation.md."""

from __future__ import annotations

import argparse
import collections
import hashlib
import json
import subprocess
import sys
import time
from pathlib import Path

# mutmut's exit codes (mutmut/stats.py, 3.8): 1 and 3 killed, 0 survived, 5/33 no tests,
# 36/24/-24/152/255 timeout, 37 caught by a type check; anything else "suspicious".
KILLED = {1, 3}
SURVIVED = {0}
NO_TESTS = {5, 33}
TIMEOUT = {36, 24, -24, 152, 255}


BATCH = 10  # mutants per mutmut call: the budget is checked between calls


def mutant_codes() -> dict[str, int | None]:
    codes: dict[str, int | None] = {}
    for meta in sorted(Path("mutants").rglob("*.py.meta")):
        codes.update(json.loads(meta.read_text())["exit_code_by_key"])
    return codes


def draw(names: list[str], n: int, seed: int) -> list[str]:
    """A seeded sample of ``n`` mutant names: those ranked first by a hash of the seed
    and the name. Unlike ``random.sample`` over the list, the same seed keeps drawing
    the same mutants of unchanged functions when mutants are added or removed elsewhere
    (a new module, an edited function), so a survivor stays in the sample until a test
    kills it."""
    def rank(name: str) -> bytes:
        return hashlib.sha256(f"{seed}:{name}".encode()).digest()

    return sorted(sorted(names, key=rank)[:n])


def package_of(name: str) -> str:
    return ".".join(name.split(".")[:2])  # puppet.physics, puppet.interface, ...


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("--mutmut", required=True)
    ap.add_argument("--sample", type=int, default=250)
    ap.add_argument("--seed", type=int, default=17)
    ap.add_argument("--budget", type=float, default=0.0,
                    help="minutes for running the sample (0: no limit); the mutants are "
                         "run in batches of BATCH, and none is started once it is spent")
    args = ap.parse_args()
    log = open("mutmut.log", "w")  # noqa: SIM115 - every mutmut run of main() writes here
    t0 = time.monotonic()
    # 1. Generate the mutants and collect which tests reach each function. Given a name
    # that matches no mutant, mutmut does just that and then stops (an assertion).
    subprocess.run([args.mutmut, "run", "--max-children", "1", "__list_only__"],
                   stdout=log, stderr=subprocess.STDOUT)
    codes = mutant_codes()
    if not codes or not Path("mutants/mutmut-stats.json").exists():
        print("mutation: mutmut made no mutants or no stats; see "
              f"{Path('mutmut.log').resolve()}", file=sys.stderr)
        return 2
    names = sorted(codes)
    by_package = collections.Counter(package_of(n) for n in names)
    sample = draw(names, args.sample, args.seed)
    print(f"{len(names)} mutants ({', '.join(f'{p} {n}' for p, n in sorted(by_package.items()))});"
          f" running a sample of {len(sample)} (seed {args.seed})", flush=True)
    # 2. Run the sample (mutmut reuses the stats; each mutant runs only the tests that
    # reach its function, stopping at the first failure).
    started = time.monotonic()
    for at in range(0, len(sample), BATCH):  # mutmut keeps the stats: each batch reuses them
        if args.budget and time.monotonic() - started > args.budget * 60:
            print(f"budget of {args.budget:g} min spent: {at} of {len(sample)} mutants run",
                  flush=True)
            break
        subprocess.run([args.mutmut, "run", "--max-children", "1", *sample[at:at + BATCH]],
                       stdout=log, stderr=subprocess.STDOUT)
    codes = mutant_codes()
    result = {n: codes.get(n) for n in sample}
    kinds = collections.Counter()
    rows = collections.defaultdict(collections.Counter)
    for n, code in result.items():
        kind = ("killed" if code in KILLED else "survived" if code in SURVIVED
                else "no tests" if code in NO_TESTS else "timeout" if code in TIMEOUT
                else "not run" if code is None else f"suspicious ({code})")
        kinds[kind] += 1
        rows[package_of(n)][kind] += 1
    killed = kinds["killed"] + kinds["timeout"]  # a mutant that hangs the tests is caught
    ran = len(sample) - kinds["not run"]  # (the budget may stop the run early)
    lines = [f"mutation run: {len(sample)} of {len(names)} mutants (seed {args.seed}), "
             f"{time.monotonic() - t0:.0f} s",
             f"killed {killed} of the {ran} run ({100.0 * killed / max(1, ran):.1f} %); "
             + ", ".join(f"{k} {v}" for k, v in sorted(kinds.items()))]
    for package, counter in sorted(rows.items()):
        lines.append(f"  {package}: " + ", ".join(f"{k} {v}" for k, v in sorted(counter.items())))
    lines.append("")
    for n, code in result.items():
        if code in KILLED or code in TIMEOUT or code is None:
            continue
        shown = subprocess.run([args.mutmut, "show", n], capture_output=True, text=True).stdout
        lines.append(shown.rstrip())
        lines.append("")
    report = "\n".join(lines) + "\n"
    Path("report.txt").write_text(report)
    print(report)
    print(f"report: {Path('report.txt').resolve()}; "
          f"mutmut's output: {Path('mutmut.log').resolve()}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
