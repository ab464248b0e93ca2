"""Build a multi-hop Luxo performance hop by hop, as the paper's users did with
checkpoints, and write it as a script.

    python tools/tune_hops.py [--interface luxo-mouse] [--scene terrain] [--finish 10]
                              [--tries 60] [--refine 40] [--seed 1] [--max-hops 40]
                              [--write assets/scripts/luxo-terrain.yaml]

From the state after the hops kept so far it checkpoints (a ``checkpoint`` action in
the script), then tries hop gestures from that checkpoint - each a glide to a crouch
pose, a hold, a flick to a push pose, a tuck and a stand (mouse coordinates as in
luxo-mouse: ankle = 80 - 160 x deg, knee = 160 - 180 y deg) with their timings - and
keeps the one that gets furthest while landing upright and calm: the base within a
few degrees of upright and nearly at rest when the next hop starts, and never more
than 40-odd degrees from upright while touching the ground. The first try is always
the shipped hop (assets/scripts/luxo-hop.yaml); then random gestures around it, then
a short hill climb (tools/gestures.py). Hops are added until the base is past
``--finish`` m. When no gesture from a checkpoint lands upright (say, just before the
step), the search backtracks: the previous hop is replaced by its next-best gesture
(a few, landing at different places, are kept per hop) and the search goes on from
there. Giving up exits with code 1.

Every try is played through the real Session from the checkpoint, and the checkpoint
action re-seats the run exactly as the recorded script does, so the written script
replays to the same bits as the search saw.
"""

from __future__ import annotations

import argparse
import random
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from tools.gestures import Runner, climb, compile_entries  # noqa: E402

STAND = (0.656, 0.583)
DEFAULT = {  # the hop of assets/scripts/luxo-hop.yaml
    "cx": 1.0, "cy": 0.159, "crouch_over": 0.15, "hold": 0.55,
    "px": 0.123, "py": 0.378, "flick": 0.03,
    "tuck_after": 0.2, "ux": 0.58, "uy": 0.582, "stand_after": 0.5,
}
BOUNDS = {
    "cx": (0.6, 1.0), "cy": (0.0, 0.4), "crouch_over": (0.08, 0.3), "hold": (0.25, 0.8),
    "px": (0.0, 0.4), "py": (0.25, 0.7), "flick": (0.01, 0.08),
    "tuck_after": (0.08, 0.35), "ux": (0.4, 0.8), "uy": (0.4, 0.75),
    "stand_after": (0.25, 0.7),
}
SETTLE = 0.45  # s after the stand glide before the next hop may start


def hop_entries(t0: float, p: dict) -> tuple[list[dict], float]:
    """One hop's script entries from ``t0`` (mouse at STAND), and when it is done."""
    r = lambda v: round(v, 4)  # noqa: E731
    t_crouch = t0 + 0.05
    t_push = t_crouch + p["crouch_over"] + p["hold"]
    t_tuck = t_push + p["flick"] + p["tuck_after"]
    t_stand = t_tuck + 0.15 + p["stand_after"]
    end = r(t_stand + 0.3 + SETTLE)
    return [
        {"t": r(t_crouch), "mouse": [r(p["cx"]), r(p["cy"])], "over": r(p["crouch_over"])},
        {"t": r(t_push), "mouse": [r(p["px"]), r(p["py"])], "over": r(p["flick"])},
        {"t": r(t_tuck), "mouse": [r(p["ux"]), r(p["uy"])], "over": 0.15},
        {"t": r(t_stand), "mouse": list(STAND), "over": 0.3},
    ], end


def score_from(x0: float):
    def score(o) -> float:
        s = o.x_end - x0  # m advanced
        s -= 0.01 * max(0.0, o.max_tilt_ground - 35.0)  # a wobbly landing
        s -= 0.004 * o.tilt_end  # not standing level for the next hop
        s -= 0.3 * min(1.0, o.motion_end)  # still moving when the next hop starts
        s -= 100.0 * o.blowups
        if o.max_tilt_ground > 60.0 or o.tilt_end > 20.0:
            s -= 10.0  # nearly a fall: never keep it
        return s
    return score


def acceptable(o, x0: float) -> bool:
    return (o.x_end - x0 >= 0.1 and o.max_tilt_ground <= 60.0 and o.tilt_end <= 20.0
            and not o.blowups)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--interface", default="luxo-mouse")
    ap.add_argument("--scene", default="terrain")
    ap.add_argument("--finish", type=float, default=10.0, help="base x to pass, m")
    ap.add_argument("--margin", type=float, default=0.15, help="m past the finish")
    ap.add_argument("--tries", type=int, default=60, help="random gestures per hop")
    ap.add_argument("--refine", type=int, default=40, help="hill-climb tries per hop")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--max-hops", type=int, default=40)
    ap.add_argument("--alternatives", type=int, default=3,
                    help="other gestures kept per hop, to backtrack to")
    ap.add_argument("--max-backtracks", type=int, default=30)
    ap.add_argument("--write", metavar="SCRIPT")
    args = ap.parse_args(argv)

    rng = random.Random(args.seed)
    start = [{"t": 0.0, "mouse": list(STAND)}]
    first_mark = 0.2
    kept: list[dict] = []  # per hop: mark, entries, end, alternatives (other gestures)
    runner = rebuild(args, start, kept, first_mark)
    c = runner.session.character
    t = first_mark
    backtracks = 0
    started = time.time()
    while c.bodies["base"].position.x < args.finish + args.margin:
        if len(kept) >= args.max_hops:
            print("too many hops", file=sys.stderr)
            return 1
        x0 = c.bodies["base"].position.x
        runner.checkpoint()
        found = search_hop(runner, rng, t, x0, args)
        if not found:
            # Backtrack: take the previous hop's next-best gesture and go on from there.
            while kept and not kept[-1]["alternatives"]:
                kept.pop()
            if not kept or backtracks >= args.max_backtracks:
                print(f"hop {len(kept) + 1} from x = {x0:.2f} m: nothing advances and "
                      "lands upright; giving up", file=sys.stderr)
                return 1
            backtracks += 1
            hop = kept.pop()
            t = hop["t"]
            print(f"  no good hop from x = {x0:.2f} m: backtrack to hop {len(kept) + 1} "
                  f"(t = {t:.2f} s) and try its next gesture", flush=True)
            runner = rebuild(args, start, kept, t)
            c = runner.session.character
            x0 = c.bodies["base"].position.x
            runner.checkpoint()
            found = hop["alternatives"]
        best_p = found.pop(0)[1]
        o = play_hop(runner, t, best_p)
        ents, end = hop_entries(t, best_p)
        kept.append({"t": t, "entries": ents, "end": end, "alternatives": found})
        print(f"hop {len(kept):2d} at t = {t:6.2f} s: x {x0:5.2f} -> {o.x_end:5.2f} m "
              f"(+{o.x_end - x0:.2f}), tilt at end {o.tilt_end:.0f}, on the ground "
              f"{o.max_tilt_ground:.0f}, motion {o.motion_end:.2f}  "
              f"[{time.time() - started:.0f} s]", flush=True)
        t = end
    seconds = round(t + 0.5, 2)
    runner.run([], runner.steps(seconds))
    print(f"done: {len(kept)} hops ({backtracks} backtracks), base x = "
          f"{c.bodies['base'].position.x:.2f} m at t = {seconds} s, upright {c.upright()}")
    if args.write:
        write_script(args.write, start, kept, args.interface, args.scene, seconds)
        print(f"wrote {args.write}")
    return 0


def play_hop(runner, t0: float, p: dict):
    """Back to the checkpoint at ``t0`` and play one hop gesture."""
    runner.back()
    ents, end = hop_entries(t0, p)
    return runner.run(compile_entries(ents, runner.dt, STAND), runner.steps(end))


def search_hop(runner, rng, t0: float, x0: float, args) -> list:
    """Acceptable hop gestures from the checkpoint, best first (each (score, params)),
    spread out: no two within 3 cm of each other's landing."""
    score = score_from(x0)

    def evaluate(p):
        return play_hop(runner, t0, p)

    pool = []
    for i in range(args.tries):
        if i == 0:
            p = dict(DEFAULT)
        else:  # around the shipped hop half the time, anywhere the other half
            p = {}
            for k, (lo, hi) in BOUNDS.items():
                v = (DEFAULT[k] + rng.gauss(0.0, 0.15 * (hi - lo)) if i % 2
                     else rng.uniform(lo, hi))
                p[k] = min(hi, max(lo, v))
        o = evaluate(p)
        pool.append((score(o), p, o))
    pool.sort(key=lambda item: -item[0])
    best = climb(evaluate, score, BOUNDS, *pool[0], args.refine)
    good = [item for item in [best] + pool if acceptable(item[2], x0)]
    spread = []
    for s, p, o in good:
        if all(abs(o.x_end - q.x_end) > 0.03 for _, _, q in spread):
            spread.append((s, p, o))
    return [(s, p) for s, p, _ in spread[:args.alternatives + 1]]


def rebuild(args, start, kept, t_mark):
    """A fresh session played through the kept hops up to ``t_mark`` (where the next
    checkpoint goes), exactly as the written script plays them."""
    runner = Runner(args.interface, args.scene)
    entries = list(start)
    for hop in kept:
        entries.append({"t": hop["t"], "action": "checkpoint"})
        entries += hop["entries"]
    runner.run(compile_entries(entries, runner.dt, STAND), runner.steps(t_mark))
    return runner


def write_script(path, start, kept, interface, scene, seconds) -> None:
    lines = [f"description: Luxo hops across {scene} on the mouse, hop by hop from "
             "checkpoints.",
             "# Built by tools/tune_hops.py: each hop starts at a checkpoint; its gesture",
             "# (crouch, flick, tuck, stand) was chosen from many tried from there.",
             f"interface: {interface}", f"scene: {scene}", f"seconds: {seconds}", "events:"]

    def line(e, comment):
        body = ", ".join(f"{k}: {v}" for k, v in e.items() if not (k == "over" and v == 0))
        return f"  - {{{body}}}   # {comment}"

    lines.append(line(start[0], "stand"))
    for i, hop in enumerate(kept, start=1):
        lines.append(line({"t": hop["t"], "action": "checkpoint"}, f"hop {i}"))
        for e, c in zip(hop["entries"], ("crouch", "flick: hop", "tuck for landing",
                                         "stand")):
            lines.append(line(e, c))
    Path(path).write_text("\n".join(lines) + "\n", encoding="utf-8")


if __name__ == "__main__":
    sys.exit(main())
