"""Search a mouse gesture for a Luxo back flip on the flat floor, and write it as a script.

    python tools/tune_flip.py [--interface luxo-mouse-strong] [--tries 1200] [--climbs 4]
                              [--refine 300]
                              [--seed 1] [--write assets/scripts/luxo-backflip.yaml]

The gesture, in mouse coordinates (x 0..1 left..right, y 0..1 bottom..top; in
luxo-mouse(-strong) ankle target = 80 - 160 x deg, knee target = 160 - 180 y deg):

    stand -> crouch (cx, cy) -> after `hold` s, flick to the push pose (px, py) in
             `flick` s -> `tuck_at` s later tuck (tx, ty) -> `open_at` s later open
             for landing (lx, ly) -> stand.

A random search over those 12 numbers, then hill climbs from the best few
(tools/gestures.py: coordinate steps that halve when nothing improves). The score wants
an accumulated backward turn of the base near 360 deg, upright at the end, never more
than 45 deg from upright while touching the floor (a clean flip lands on its base; the
``never_fell`` expectation allows 90), and the lamp at rest at the end.
Every try is played through the real Session from a checkpoint, so the written script
replays to the same bits.
"""

from __future__ import annotations

import argparse
import random
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from tools.gestures import Runner, compile_entries, search  # noqa: E402

STAND = (0.656, 0.583)
# name: (low, high)
BOUNDS = {
    "cx": (0.0, 1.0), "cy": (0.0, 0.5), "hold": (0.2, 0.8),
    "px": (0.0, 0.6), "py": (0.4, 1.0), "flick": (0.01, 0.1),
    "tuck_at": (0.0, 0.3), "tx": (0.0, 1.0), "ty": (0.0, 0.6),
    "open_at": (0.05, 0.6), "lx": (0.2, 0.9), "ly": (0.2, 0.8),
}
START = 0.1  # s: the crouch starts here
SECONDS = 3.5


def entries(p: dict) -> list[dict]:
    t_push = START + 0.15 + p["hold"]
    t_tuck = t_push + p["flick"] + p["tuck_at"]
    t_open = t_tuck + 0.05 + p["open_at"]
    r = lambda v: round(v, 4)  # noqa: E731
    return [
        {"t": 0.0, "mouse": list(STAND)},
        {"t": r(START), "mouse": [r(p["cx"]), r(p["cy"])], "over": 0.15},
        {"t": r(t_push), "mouse": [r(p["px"]), r(p["py"])], "over": r(p["flick"])},
        {"t": r(t_tuck), "mouse": [r(p["tx"]), r(p["ty"])], "over": 0.05},
        {"t": r(t_open), "mouse": [r(p["lx"]), r(p["ly"])], "over": 0.1},
        {"t": r(t_open + 0.6), "mouse": list(STAND), "over": 0.3},
    ]


def score(o) -> float:
    s = -abs(o.turned - 360.0)
    # capped, so that a full turn landed badly still beats no turn (the climb goes on)
    s -= 2.0 * min(100.0, max(0.0, o.max_tilt_ground - 45.0))
    s -= 1.0 * min(90.0, max(0.0, o.tilt_end - 10.0))
    s -= 0.0 if o.still else 20.0
    s -= 1000.0 * o.blowups
    return s


def good(o) -> bool:
    return o.turned >= 300 and o.upright and not o.fell


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--interface", default="luxo-mouse-strong")
    ap.add_argument("--tries", type=int, default=1200)
    ap.add_argument("--refine", type=int, default=300, help="tries per climb")
    ap.add_argument("--climbs", type=int, default=4, help="climb from this many of the best")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--write", metavar="SCRIPT")
    args = ap.parse_args(argv)

    runner = Runner(args.interface, "flat")
    runner.checkpoint()
    until = runner.steps(SECONDS)

    def evaluate(p):
        runner.back()
        # the checkpoint is at step 0: entries act from there on
        return runner.run(compile_entries(entries(p), runner.dt, STAND), until)

    def report(rank, s0, s1, o1):
        print(f"climb {rank}: score {s0:.1f} -> {s1:.1f}, turned {o1.turned:.0f}, "
              f"tilt at end {o1.tilt_end:.0f}, on the floor {o1.max_tilt_ground:.0f}")

    best_s, best_p, best_o = search(evaluate, score, BOUNDS, random.Random(args.seed),
                                    args.tries, args.climbs, args.refine, report)
    o = best_o
    print(f"best: score {best_s:.1f} turned {o.turned:.0f} deg, tilt at end "
          f"{o.tilt_end:.0f}, largest tilt on the floor {o.max_tilt_ground:.0f}, "
          f"airborne {o.airborne:.2f} s, x {o.x_end:.2f} m, still {o.still}, "
          f"{'GOOD' if good(o) else 'not good enough'}")
    print({k: round(v, 4) for k, v in best_p.items()})
    if args.write:
        write_script(args.write, entries(best_p), args.interface)
        print(f"wrote {args.write}")
    return 0 if good(o) else 1


def write_script(path: str, ents: list[dict], interface: str) -> None:
    comments = ["stand", "crouch", "flick: push off, arm swinging back", "tuck: spin",
                "open for the landing", "stand"]
    lines = ["description: A back flip on the mouse (stronger servos) - crouch, flick up "
             "and back, tuck, open, land upright.",
             "# Found by tools/tune_flip.py.",
             f"interface: {interface}", "scene: flat", f"seconds: {SECONDS}", "events:"]
    for e, c in zip(ents, comments):
        body = ", ".join(f"{k}: {v}" for k, v in e.items() if not (k == "over" and v == 0))
        lines.append(f"  - {{{body}}}   # {c}")
    Path(path).write_text("\n".join(lines) + "\n", encoding="utf-8")


if __name__ == "__main__":
    sys.exit(main())
