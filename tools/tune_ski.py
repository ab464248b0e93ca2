"""Search a mouse performance for Luxo's ski jump (assets/scenes/ski-jump.yaml) and
write it as a script.

    python tools/tune_ski.py [--interface luxo-mouse] [--tries 600] [--climbs 3]
                             [--refine 300] [--seed 1] [--write assets/scripts/luxo-ski-jump.yaml]

The run, as the paper's user does it: hop off the start platform onto the snow (the
first hop of assets/scripts/luxo-hop.yaml, fixed), checkpoint, then - the searched
part - ride the in-run in a pose (rx, ry), crouch (cx, cy) at `crouch_at`, flick to
the take-off pose (px, py) at `jump_at` (time the jump at the lip), hold a flight pose
(fx, fy) `fly_after` s later and open for the landing (lx, ly) `land_after` s after
that. Mouse coordinates as in luxo-mouse: ankle = 80 - 160 x deg, knee = 160 - 180 y.

A random search, then hill climbs from the best few (tools/gestures.py). The score
wants a long flight (where the longest stretch with nothing touching ends, the
landing, as far down the hill as possible), upright at the end, never more than
90 deg from upright while touching the snow, and nothing blown up. Every try replays
through the real Session from the checkpoint, so the written script gives the same bits.
"""

from __future__ import annotations

import argparse
import random
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from tools.gestures import Runner, compile_entries, search  # noqa: E402

STAND = (0.656, 0.583)
HOP_OFF = [  # the first hop of luxo-hop.yaml: off the start platform onto the snow
    {"t": 0.0, "mouse": list(STAND)},
    {"t": 0.30, "mouse": [1.0, 0.159], "over": 0.15},
    {"t": 1.00, "mouse": [0.123, 0.378], "over": 0.03},
    {"t": 1.20, "mouse": [0.58, 0.582], "over": 0.15},
    {"t": 1.70, "mouse": list(STAND), "over": 0.3},
]
CHECKPOINT_AT = 2.05  # s: on the snow, sliding
BOUNDS = {
    "rx": (0.2, 0.9), "ry": (0.2, 0.8),
    "crouch_at": (0.0, 0.6), "cx": (0.2, 1.0), "cy": (0.0, 0.5),
    "jump_at": (3.4, 4.6), "px": (0.0, 0.8), "py": (0.4, 1.0), "flick": (0.01, 0.1),
    "fly_after": (0.05, 0.4), "fx": (0.2, 0.9), "fy": (0.2, 0.9),
    "land_after": (0.1, 0.8), "lx": (0.2, 0.9), "ly": (0.2, 0.9),
}
SECONDS = 9.0


def entries(p: dict) -> list[dict]:
    r = lambda v: round(v, 4)  # noqa: E731
    t_ride = CHECKPOINT_AT + 0.05
    t_jump = p["jump_at"]
    t_crouch = t_jump - 0.15 - p["crouch_at"]
    t_crouch = max(t_crouch, t_ride + 0.25)
    t_fly = t_jump + p["flick"] + p["fly_after"]
    t_land = t_fly + 0.1 + p["land_after"]
    return [
        {"t": r(t_ride), "mouse": [r(p["rx"]), r(p["ry"])], "over": 0.2},
        {"t": r(t_crouch), "mouse": [r(p["cx"]), r(p["cy"])], "over": 0.15},
        {"t": r(t_jump), "mouse": [r(p["px"]), r(p["py"])], "over": r(p["flick"])},
        {"t": r(t_fly), "mouse": [r(p["fx"]), r(p["fy"])], "over": 0.1},
        {"t": r(t_land), "mouse": [r(p["lx"]), r(p["ly"])], "over": 0.1},
    ]


def score(o) -> float:
    landed = o.flight_x[1]
    s = 10.0 * min(landed, 12.0)
    s -= 2.0 * min(100.0, max(0.0, o.max_tilt_ground - 45.0))
    s -= 1.0 * min(90.0, max(0.0, o.tilt_end - 10.0))
    s -= 1000.0 * o.blowups
    return s


def good(o, mark: float) -> bool:
    return o.flight_x[1] >= mark and o.upright and not o.fell


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--interface", default="luxo-mouse")
    ap.add_argument("--tries", type=int, default=600)
    ap.add_argument("--climbs", type=int, default=3)
    ap.add_argument("--refine", type=int, default=300)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--mark", type=float, default=6.0, help="landing mark to clear, m")
    ap.add_argument("--write", metavar="SCRIPT")
    args = ap.parse_args(argv)

    runner = Runner(args.interface, "ski-jump")
    until = runner.steps(SECONDS)
    runner.run(compile_entries(HOP_OFF, runner.dt), runner.steps(CHECKPOINT_AT))
    runner.checkpoint()

    def evaluate(p):
        runner.back()
        return runner.run(compile_entries(entries(p), runner.dt, STAND), until)

    def report(rank, s0, s1, o1):
        print(f"climb {rank}: score {s0:.1f} -> {s1:.1f}, landed at {o1.flight_x[1]:.2f} m, "
              f"tilt at end {o1.tilt_end:.0f}, on the snow {o1.max_tilt_ground:.0f}",
              flush=True)

    best_s, best_p, best_o = search(evaluate, score, BOUNDS, random.Random(args.seed),
                                    args.tries, args.climbs, args.refine, report)
    o = best_o
    print(f"best: score {best_s:.1f}: flight {o.flight_x[0]:.2f} -> {o.flight_x[1]:.2f} m "
          f"({o.airborne:.2f} s), x at end {o.x_end:.2f} m, tilt at end {o.tilt_end:.0f}, "
          f"largest tilt on the snow {o.max_tilt_ground:.0f}, "
          f"{'GOOD' if good(o, args.mark) else 'not good enough'}")
    print({k: round(v, 4) for k, v in best_p.items()})
    if args.write:
        write_script(args.write, HOP_OFF, [{"t": CHECKPOINT_AT, "action": "checkpoint"}],
                     entries(best_p), args.interface)
        print(f"wrote {args.write}")
    return 0 if good(o, args.mark) else 1


def write_script(path, hop, mark, ents, interface) -> None:
    comments = (["stand", "crouch, leaning forward", "flick: hop off the platform",
                 "tuck for landing", "stand"] + ["checkpoint on the snow"]
                + ["ride the in-run", "crouch before the lip", "flick: jump at the lip",
                   "flight pose", "open for the landing"])
    lines = ["description: Ski jump on the mouse - hop onto the snow, ride the in-run, "
             "jump at the lip, land upright down the hill.",
             "# Found by tools/tune_ski.py.",
             f"interface: {interface}", "scene: ski-jump", f"seconds: {SECONDS}", "events:"]
    for e, c in zip(hop + mark + ents, comments):
        body = ", ".join(f"{k}: {v}" for k, v in e.items() if not (k == "over" and v == 0))
        lines.append(f"  - {{{body}}}   # {c}")
    Path(path).write_text("\n".join(lines) + "\n", encoding="utf-8")


if __name__ == "__main__":
    sys.exit(main())
