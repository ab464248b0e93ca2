"""Search an interface's numbers by a playtest's pass rate, not by one schedule's score.

    python tools/search_by_playtest.py LOG PARAMS.json N TRIES SEED [--eval] [--detail]

LOG is a feat log with a sidecar (its feat expectations judge each try); PARAMS.json
names the numbers searched: ``{"name": [value, low, high, "path.in.the.yaml", ...]}``,
each path a dotted path into the interface's YAML (list items by index, e.g.
``states.afly_near.transitions.0.when.1.above``). Each candidate is played on TRIES
tries of LOG moved as ``puppet playtest --noise human`` moves them (seed SEED: the
same tries for every candidate) and scored by the tries that pass, plus a little for
the expectations met and for how far past 1 m the first foot lands (the long jump's
``first_touch``), so a search that passes none still has a slope. Random Gaussian
steps on a third of the numbers at a time (10 % of each range, the last third 4 %),
kept when not worse. ``--eval`` scores the starting values only; ``--detail`` prints
what the failed tries' take-off and landing were. The best values are written to
PARAMS.json.best and printed; the interface file itself is not changed.
"""

from __future__ import annotations

import contextlib
import copy
import dataclasses
import json
import random
import sys
from pathlib import Path

import yaml

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from puppet.data.catalog import setup_from_text  # noqa: E402
from puppet.data.playtest import noise_at  # noqa: E402
from puppet.timeline.playtest.trial import judge, perturbed_log, prepare  # noqa: E402


def set_path(spec, path: str, value: float) -> None:
    *head, last = path.split(".")
    node = spec
    for key in head:
        node = node[int(key)] if isinstance(node, list) else node[key]
    if isinstance(node, list):
        node[int(last)] = value
    else:
        node[last] = value


def main(argv: list[str]) -> int:
    log, pfile, ncand, tries, seed = argv[0], argv[1], int(argv[2]), int(argv[3]), int(argv[4])
    detail = "--detail" in argv
    params = json.loads(Path(pfile).read_text(encoding="utf-8"))
    prep = prepare(log)
    iface = Path(prep.setup.interface_path)
    base = yaml.safe_load(iface.read_text(encoding="utf-8"))
    logs = [perturbed_log(prep, noise_at("human"), seed, i) for i in range(tries)]

    def score(values: dict) -> tuple[float, int, dict]:
        spec = copy.deepcopy(base)
        for name, v in values.items():
            for path in params[name][3:]:
                set_path(spec, path, round(v, 3))
        try:
            setup = setup_from_text(yaml.safe_dump(spec, sort_keys=False), str(iface))
        except Exception as exc:  # a number outside a joint's limits, say
            print("refused:", str(exc)[-120:], flush=True)
            return -1.0, 0, {}
        p = dataclasses.replace(prep, setup=dataclasses.replace(prep.setup,
                                                                 interface=setup.interface))
        passes, partial, dist, fails = 0, 0.0, 0.0, {}
        n = len(p.expectations.items)
        for lg in logs:
            r = judge(p, lg)
            passes += r.passed
            partial += (n - len(r.failed)) / n
            touch = [f for f in r.failed if "first_touch" in f]
            if r.passed or not touch:
                dist += 1.0
            else:
                first = touch[0].split("touching first:")[-1]
                if first.strip().startswith("foot") and "," not in first:
                    with contextlib.suppress(IndexError, ValueError):
                        dist += min(1.0, max(0.0, float(first.rsplit("x = ", 1)[1].split()[0])))
            for f in r.failed:
                if detail and ("first_touch" in f or "took_off" in f):
                    print("   ", f[f.find(":", 40):][:140])
                fails[f.split()[1]] = fails.get(f.split()[1], 0) + 1
        return passes + 0.3 * partial / tries + 0.5 * dist / tries, passes, fails

    values = {k: v[0] for k, v in params.items()}
    best = score(values)
    print(f"start {best[1]}/{tries} {best[2]}", flush=True)
    if "--eval" in argv:
        return 0
    rng = random.Random(seed)
    for i in range(ncand):
        frac = 0.10 if i < 2 * ncand // 3 else 0.04
        cand = dict(values)
        for k in rng.sample(list(params), k=max(1, len(params) // 3)):
            lo, hi = params[k][1], params[k][2]
            cand[k] = min(hi, max(lo, cand[k] + rng.gauss(0, frac * (hi - lo))))
        s = score(cand)
        if s[0] >= best[0]:
            if s[0] > best[0]:
                print(f"{i}: {s[1]}/{tries} score {s[0]:.3f} {s[2]}",
                      json.dumps({k: round(v, 3) for k, v in cand.items()}), flush=True)
            best, values = s, cand
    print("best", best[1], json.dumps({k: round(v, 3) for k, v in values.items()}))
    Path(pfile + ".best").write_text(json.dumps(
        {k: [round(v, 3)] + params[k][1:] for k, v in values.items()}, indent=0),
        encoding="utf-8")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
