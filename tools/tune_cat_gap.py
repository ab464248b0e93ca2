"""Build the cat's bound over the gap and up the steps (cat-gap) stride by stride from
checkpoints, as the paper's users did, and write it as a script.

    python tools/tune_cat_gap.py [--scene cat-gap] [--finish 3.9] [--tries 60]
                                 [--refine 30] [--hard-tries 400] [--seed 3]
                                 [--write assets/scripts/cat-gap.yaml]

``--seed 5`` wrote assets/scripts/cat-gap.yaml (16 strides, no backtracks, 40 s on one
core). The search does not check everything tests/test_cat.py does (no touch between
the gap's two sides, airborne from the last near-side touch to the first far-side
one): seeds 3 and 4 gave performances that pass the log's expectations but not
that test, so run it on what this writes.

Each stride is one bound cycle on the cat-bound keys (tools/tune_cat.py): at the
stride's start the back pair pushes (a, or ctrl+a held = over-extended and stiff) and
the front pair launches; at ``swing`` the back pair folds (w under, or e gathered
forward) and the front pair reaches (l) or folds forward (o, to clear a step's riser);
at ``land`` the front pair pushes and the back pair lands; at ``gather`` the front pair
folds (i) and the back pair stands (s). Its timings (period, swing, land, gather, push
hold) and key choices are searched.

From the state after the strides kept so far the search checkpoints (a
``checkpoint`` action in the script: the paper's checkpoints, one per stride, about
0.4 s apart) and tries strides from there - the shipped bound stride first, then
random strides around it and anywhere, then a short hill climb - keeping the one
that gets furthest while staying on its feet: never tipped more than 50 deg while
touching the ground, within 35 deg of level at the stride's end, never touching the
gap's pit (walls or floor) and never bridging the gap (touching both sides at once:
the cat must leap it, its back feet leaving the near side before its front feet
reach the far side) - plus a look-ahead: the same stride played
twice more from there (a human keeps the rhythm), scored by how far that gets and
whether it stays on its feet; only the first stride is kept, the next is searched
afresh from its end (a stride that leaves the cat where it cannot go on scores low).
When no stride from a checkpoint is acceptable (say, at the gap's edge) the search
backtracks: the previous stride is replaced by its next-best alternative, and so on.
Once the centre of mass is past ``--finish`` the cat stands (s, k) and must stay
upright for ``--settle`` s.

Every try is played through the real Session from the checkpoint, and the checkpoint
action re-seats the run exactly as the recorded script does, so the written script
replays to the same bits as the search saw.
"""

from __future__ import annotations

import argparse
import json
import math
import random
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from puppet.session.playback import play  # noqa: E402
from tools.gestures import SessionRunner, climb, compile_entries, tilt_deg  # noqa: E402

INTERFACE = "cat-bound"
# the stride of assets/scripts/cat-bound.yaml (tuned on flat ground)
DEFAULT = {"period": 0.386, "swing": 0.05, "land": 0.227, "gather": 0.338,
           "push_hold": 0.184, "back_push": "ctrl+a", "front_launch": "k",
           "front_push": "j", "back_land": "s", "front_swing": "l", "back_swing": "w"}
BOUNDS = {"period": (0.28, 0.6), "swing": (0.02, 0.2), "land": (0.1, 0.4),
          "gather": (0.18, 0.55), "push_hold": (0.04, 0.3)}
CHOICES = {"back_push": ("a", "ctrl+a"), "front_launch": ("o", "l", "i", "k", "u"),
           "front_push": ("j", "k", "ctrl+j"), "back_land": ("d", "s", "e"),
           "front_swing": ("l", "o"), "back_swing": ("w", "e")}
FIRST = 0.3  # s: the first stride starts here (the cat stands until then)
PIT = -0.03  # any part of the cat below this y is in the gap's pit
GAP = (1.5, 1.75)  # the gap's near and far edges (assets/scenes/cat-gap.yaml), m
RIM = 0.005  # m: a touch more than this below the rim is a touch of the pit's walls


def contact_points(c) -> list[tuple[float, float]]:
    """World points where the cat touches the ground now."""
    pts = []
    for n in c.link_order:
        c.bodies[n].each_arbiter(
            lambda arb: pts.extend((p.point_a.x, p.point_a.y)
                                   for p in arb.contact_point_set.points))
    return pts


def gap_touch(pts, gap=GAP) -> tuple[bool, bool]:
    """(touches the pit - its walls or floor, bridges the gap - touches both sides at
    once). A leap over the gap does neither: the back feet leave the near side before
    the front feet reach the far side."""
    pit = any(y < -RIM for _, y in pts)
    near = any(x <= gap[0] + RIM for x, _ in pts)
    far = any(x >= gap[1] - RIM for x, _ in pts)
    return pit, near and far


def fix(p: dict) -> dict:
    """Keep a stride's moments in order and inside its period."""
    q = dict(p)
    q["land"] = max(q["land"], q["swing"] + 0.03)
    q["gather"] = max(q["gather"], q["land"] + 0.03)
    q["period"] = max(q["period"], q["gather"] + 0.03, q["push_hold"] + 0.02)
    return q


def stride_entries(t0: float, p: dict) -> tuple[list[dict], float]:
    r = lambda v: round(v, 3)  # noqa: E731
    p = fix(p)
    ents = [
        {"t": r(t0), "key": p["back_push"], "hold": r(p["push_hold"])},
        {"t": r(t0), "key": p["front_launch"]},
        {"t": r(t0 + p["swing"]), "key": p.get("back_swing", "w")},
        {"t": r(t0 + p["swing"]), "key": p.get("front_swing", "l")},
        {"t": r(t0 + p["land"]), "key": p["front_push"]},
        {"t": r(t0 + p["land"]), "key": p["back_land"]},
        {"t": r(t0 + p["gather"]), "key": "i"},
        {"t": r(t0 + p["gather"]), "key": "s"},
    ]
    return ents, r(t0 + p["period"])


def stand_entries(t0: float) -> list[dict]:
    return [{"t": round(t0, 3), "key": "s"}, {"t": round(t0, 3), "key": "k"}]


class Runner(SessionRunner):
    """A live session of cat-bound on the scene; plays entries, checkpoints, restores."""

    def __init__(self, scene: str):
        super().__init__(INTERFACE, scene)

    def run(self, entries: list[dict], until: float) -> dict:
        """Play entries to ``until`` s; what happened (sampled every 4 steps)."""
        s = self.session
        c = s.character
        worst = [0.0]  # largest root tilt while touching the ground
        low = [math.inf]  # lowest point of the cat
        gap = [False, False]  # touched the pit, bridged the gap
        blow0 = s.blowups

        def sample(_s):
            tilt = tilt_deg(c.root_angle())
            if tilt > worst[0] and any(c.in_contact(n) for n in c.link_order):
                worst[0] = tilt
            low[0] = min(low[0], c.lowest_point())
            pit, bridge = gap_touch(contact_points(c))
            gap[0] |= pit
            gap[1] |= bridge

        play(s, compile_entries(entries, self.dt), self.steps(until), 4, sample)
        sample(s)
        vx, vy = c.com_velocity()
        return {"x": c.com()[0], "y": c.com()[1], "tilt_end": tilt_deg(c.root_angle()),
                "worst": worst[0], "low": low[0], "blowups": s.blowups - blow0,
                "pit": gap[0], "bridge": gap[1],
                "w": abs(c.bodies[c.spec.root].angular_velocity), "vx": vx, "vy": vy}


def ok(o: dict, tilt_end: float = 35.0) -> bool:
    return (o["worst"] <= 50.0 and o["tilt_end"] <= tilt_end and o["low"] >= PIT
            and not o["blowups"] and not o["pit"] and not o["bridge"])


def evaluate(runner: Runner, t0: float, p: dict, look: int) -> dict:
    """Back to the checkpoint at ``t0``, play one stride, then the same stride ``look``
    times more as a look-ahead (not kept: only the first stride is kept, and the next
    stride is searched afresh from its end)."""
    runner.back()
    ents, end = stride_entries(t0, p)
    o = runner.run(ents, end)
    o["end"] = end
    o["x_look"] = o["x"]
    survived = 0.0
    if ok(o) and look:
        t = end
        for _ in range(look):
            e2, t2 = stride_entries(t, p)
            o2 = runner.run(e2, t2)
            if not ok(o2, 45.0):
                break
            survived += 1.0
            o["x_look"] = o2["x"]
            t = t2
    o["survived"] = survived / look if look else 1.0
    return o


def score_from(x0: float):
    def score(o: dict) -> float:
        s = 0.5 * (o["x"] - x0) + 0.5 * (o["x_look"] - x0)
        s += 0.1 * o["survived"]
        s -= 0.003 * o["tilt_end"]
        s -= 0.002 * max(0.0, o["worst"] - 30.0)
        if not ok(o) or o["x"] - x0 < 0.02:
            s -= 10.0
        return s
    return score


def search_stride(runner, rng, t0, x0, prev, args) -> list:
    """Acceptable strides from the checkpoint, best first: (score, params), spread out."""
    score = score_from(x0)
    cont = {k: v for k, v in prev.items() if k in CHOICES}

    def ev_(p):
        q = dict(cont)
        q.update(p)
        return evaluate(runner, t0, q, args.look)

    pool = []
    for i in range(args.tries):
        if i == 0:
            p = dict(DEFAULT)
        elif i == 1:
            p = dict(prev)
        else:
            base = DEFAULT if i % 3 == 0 else prev
            p = {}
            for k, (lo, hi) in BOUNDS.items():
                v = (base[k] + rng.gauss(0.0, 0.15 * (hi - lo))) if i % 3 else \
                    rng.uniform(lo, hi)
                p[k] = min(hi, max(lo, v))
            for k, opts in CHOICES.items():
                p[k] = rng.choice(opts) if rng.random() < 0.3 else base[k]
        p = fix(p)
        o = evaluate(runner, t0, p, args.look)
        pool.append((score(o), p, o))
    pool.sort(key=lambda item: -item[0])
    top = []
    for s0, p0, o0 in pool[:args.climbs]:
        cont = {k: v for k, v in p0.items() if k in CHOICES}
        num = {k: p0[k] for k in BOUNDS}
        s1, p1, o1 = climb(ev_, score, BOUNDS, s0, num, o0, args.refine)
        p1 = fix({**cont, **p1})
        top.append((s1, p1, o1))
    good = [it for it in sorted(top + pool, key=lambda it: -it[0])
            if ok(it[2]) and it[2]["x"] - x0 >= 0.02]
    spread = []
    for s, p, o in good:
        if all(abs(o["x"] - q["x"]) > 0.02 for _, _, q in spread):
            spread.append((s, p, o))
    return [(s, p) for s, p, _ in spread[:args.alternatives + 1]]


def rebuild(scene, kept, t_mark) -> Runner:
    runner = Runner(scene)
    runner.run(all_entries(kept), t_mark)
    return runner


def all_entries(kept) -> list[dict]:
    entries = []
    for st in kept:
        entries.append({"t": st["t"], "action": "checkpoint"})
        entries += st["entries"]
    return entries


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--scene", default="cat-gap")
    ap.add_argument("--finish", type=float, default=3.9, help="com x to pass, m")
    ap.add_argument("--tries", type=int, default=60, help="random strides per checkpoint")
    ap.add_argument("--climbs", type=int, default=2, help="hill climbs per checkpoint")
    ap.add_argument("--refine", type=int, default=30, help="tries per hill climb")
    ap.add_argument("--look", type=int, default=2, help="look-ahead strides")
    ap.add_argument("--settle", type=float, default=1.5)
    ap.add_argument("--seed", type=int, default=3)
    ap.add_argument("--hard-tries", type=int, default=400,
                    help="random strides to try where the first search finds none")
    ap.add_argument("--alternatives", type=int, default=4)
    ap.add_argument("--max-strides", type=int, default=40)
    ap.add_argument("--max-backtracks", type=int, default=150)
    ap.add_argument("--write", metavar="SCRIPT")
    args = ap.parse_args(argv)

    rng = random.Random(args.seed)
    kept: list[dict] = []
    runner = rebuild(args.scene, kept, FIRST)
    t = FIRST
    prev = dict(DEFAULT)
    backtracks = 0
    started = time.time()
    best_x, best_kept, best_t = 0.0, [], FIRST
    while True:
        c = runner.session.character
        x0 = c.com()[0]
        if x0 > best_x:
            best_x, best_kept, best_t = x0, [dict(st) for st in kept], t
        found = None
        if x0 >= args.finish:
            # stand and settle; if it does not stay up, treat as a dead end
            runner.checkpoint()
            o = runner.run(stand_entries(t), t + args.settle)
            if ok(o, 20.0) and o["x"] >= args.finish - 0.05:
                break
            print(f"  stand at x = {x0:.2f} m tips over (tilt {o['tilt_end']:.0f})")
            found = []
        if found is None:
            if len(kept) >= args.max_strides:
                print("too many strides", file=sys.stderr)
                return 1
            runner.checkpoint()
            found = search_stride(runner, rng, t, x0, prev, args)
            if not found and args.hard_tries:
                # a hard place (the gap's edge, a step): try much harder before
                # backtracking, as the paper's users did (10-20 tries there)
                hard = argparse.Namespace(**{**vars(args), "tries": args.hard_tries,
                                             "climbs": args.climbs * 3})
                found = search_stride(runner, rng, t, x0, prev, hard)
                print(f"  hard place at x = {x0:.2f} m: {len(found)} strides found with "
                      f"{args.hard_tries} tries", flush=True)
        if not found:
            while kept and not kept[-1]["alternatives"]:
                kept.pop()
            if not kept or backtracks >= args.max_backtracks:
                print(f"stride {len(kept) + 1} from x = {x0:.2f} m: nothing acceptable; "
                      f"giving up (best com x {best_x:.2f} m)", file=sys.stderr)
                if args.write:  # the furthest it got, to look at
                    write_script(args.write, best_kept, args.scene, best_t,
                                 round(best_t + args.settle, 2), backtracks)
                    print(f"wrote the furthest partial run to {args.write}")
                return 1
            backtracks += 1
            st = kept.pop()
            t = st["t"]
            print(f"  no good stride from x = {x0:.2f} m: backtrack to stride "
                  f"{len(kept) + 1} (t = {t:.2f} s), its next alternative", flush=True)
            runner = rebuild(args.scene, kept, t)
            runner.checkpoint()
            x0 = runner.session.character.com()[0]
            found = st["alternatives"]
        p = found.pop(0)[1]
        runner.back()
        ents, end = stride_entries(t, p)
        o = runner.run(ents, end)
        kept.append({"t": t, "entries": ents, "end": end, "alternatives": found, "p": p})
        prev = p
        print(f"stride {len(kept):2d} at t = {t:5.2f} s: x {x0:5.2f} -> {o['x']:5.2f} m, "
              f"tilt end {o['tilt_end']:.0f}, worst {o['worst']:.0f}, low {o['low']:.3f}  "
              f"{json.dumps(short(p))}  [{time.time() - started:.0f} s]", flush=True)
        t = end
    seconds = round(t + args.settle, 2)
    c = runner.session.character
    print(f"done: {len(kept)} strides ({backtracks} backtracks), com x = {c.com()[0]:.2f} m "
          f"at t = {seconds} s, upright {c.upright()}")
    if args.write:
        write_script(args.write, kept, args.scene, t, seconds, backtracks)
        print(f"wrote {args.write}")
    return 0


def short(p: dict) -> dict:
    return {k: round(v, 3) if isinstance(v, float) else v for k, v in p.items()}


def write_script(path, kept, scene, t_stand, seconds, backtracks) -> None:
    lines = [
        "description: >",
        f"  The cat bounds on the keys over {scene}'s gap (a real leap: its back feet leave",
        "  the near edge before its front feet reach the far one) and up its three steps,",
        "  stride by stride from checkpoints (one per stride), built by",
        f"  tools/tune_cat_gap.py ({len(kept)} strides, {backtracks} backtracks). The strides",
        "  at the gap and on the steps change their timings by a few hundredths of a",
        "  second from one to the next: a human would play those at slowdown 40 (the",
        "  paper's for its complex sequence), the run-up at the interface's 10.",
        "# Each stride starts at a checkpoint; its keys and timings were chosen from many",
        "# tried from there (the back pair pushes, then folds; the front pair reaches,",
        "# lands, pushes, folds).",
        f"interface: {INTERFACE}", f"scene: {scene}", f"seconds: {seconds}", "events:"]

    def line(e, comment=""):
        body = ", ".join(f"{k}: {v}" for k, v in e.items() if not (k == "hold" and v == 0))
        return f"  - {{{body}}}" + (f"   # {comment}" if comment else "")

    for i, st in enumerate(kept, start=1):
        lines.append(line({"t": st["t"], "action": "checkpoint"}, f"stride {i}"))
        for e in st["entries"]:
            lines.append(line(e))
    lines.append(line({"t": round(t_stand, 3), "action": "checkpoint"}, "stand"))
    for e in stand_entries(t_stand):
        lines.append(line(e))
    Path(path).write_text("\n".join(lines) + "\n", encoding="utf-8")


if __name__ == "__main__":
    sys.exit(main())
