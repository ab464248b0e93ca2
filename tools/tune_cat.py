"""Tune the cat's scripted performances: a small, seeded random search over timings.

A bound (cat-bound, keys) is a cycle of four key moments, each pressing one back-leg
key and one front-leg key:

    launch   back legs push (ctrl+a, held = over-extended and stiff), front legs fold forward
    swing    back legs fold under, front legs reach forward to land
    land     front legs push back, back legs reach forward to land under the body
    gather   front legs fold, back legs stand (ready to push again)

The search varies the moments' times within a cycle and the cycle period; a
candidate scores its centre-of-mass distance, and fails if the cat tips over (root
more than 60 deg from upright while touching the ground) or ends not upright.
A trot (cat-trot, mouse) is a circle of the mouse around a centre; the search varies
the centre, radii and period.

    python tools/tune_cat.py bound --trials 40 --seed 1      # search, print the best
    python tools/tune_cat.py bound --write assets/scripts/cat-bound.yaml  # write the best
    python tools/tune_cat.py trot --trials 30

Each trial runs a few simulated seconds of the real Session (no window), so a trial
takes about a second; keep --trials modest.
"""

from __future__ import annotations

import argparse
import json
import math
import random
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from puppet.data.catalog import load_setup  # noqa: E402
from puppet.data.validate import validate  # noqa: E402
from puppet.data.yamlfile import Located  # noqa: E402
from puppet.physics.upright_watch import UprightWatch  # noqa: E402
from puppet.session import Session  # noqa: E402
from puppet.session.playback import play  # noqa: E402
from puppet.timeline.script import ScriptSpec, compile_script  # noqa: E402

# -- bound ---------------------------------------------------------------------------
BOUND_DEFAULT = {"period": 0.42, "swing": 0.10, "land": 0.22, "gather": 0.32,
                 "push_hold": 0.10, "start": 0.3, "cycles": 7, "back_push": "ctrl+a",
                 "front_launch": "o", "front_push": "j", "back_land": "d"}
BOUND_RANGES = {"period": (0.32, 0.55), "swing": (0.05, 0.2), "land": (0.12, 0.35),
                "gather": (0.2, 0.45), "push_hold": (0.05, 0.2)}


def bound_events(p: dict) -> list[dict]:
    """Script entries for ``cycles`` bound cycles, then stand."""
    ev = []
    t = p["start"]
    for _ in range(int(p["cycles"])):
        ev.append({"t": round(t, 3), "key": p["back_push"], "hold": round(p["push_hold"], 3)})
        ev.append({"t": round(t, 3), "key": p["front_launch"]})
        ev.append({"t": round(t + p["swing"], 3), "key": "w"})
        ev.append({"t": round(t + p["swing"], 3), "key": "l"})
        ev.append({"t": round(t + p["land"], 3), "key": p["front_push"]})
        ev.append({"t": round(t + p["land"], 3), "key": p["back_land"]})
        ev.append({"t": round(t + p["gather"], 3), "key": "i"})
        ev.append({"t": round(t + p["gather"], 3), "key": "s"})
        t += p["period"]
    ev.append({"t": round(t, 3), "key": "s"})
    ev.append({"t": round(t, 3), "key": "k"})
    return ev


# -- trot ----------------------------------------------------------------------------
BOUND_CHOICES = {"back_push": ("a", "ctrl+a"), "front_launch": ("o", "l", "i", "k"),
                 "front_push": ("j", "k", "ctrl+j"), "back_land": ("d", "s", "e")}
TROT_DEFAULT = {"cx": 0.5, "cy": 0.5, "rx": 0.45, "ry": 0.45, "period": 0.36,
                "start": 0.3, "cycles": 9, "samples": 12}
TROT_RANGES = {"cx": (0.35, 0.65), "cy": (0.3, 0.7), "rx": (0.2, 0.5), "ry": (0.2, 0.5),
               "period": (0.25, 0.6)}


def trot_events(p: dict) -> list[dict]:
    """The mouse goes round an ellipse (clockwise on screen: forward while up, back
    while down, so a leg swings forward in the air and pushes back on the ground)."""
    n = int(p["samples"])
    ev = [{"t": 0.0, "mouse": [0.5, 0.5]}]
    t = p["start"]

    def at(phase):
        x = p["cx"] + p["rx"] * math.cos(phase)
        y = p["cy"] + p["ry"] * math.sin(phase)
        return [round(min(1, max(0, x)), 3), round(min(1, max(0, y)), 3)]

    ev.append({"t": round(t, 3), "mouse": at(math.pi), "over": 0.2})
    t += 0.2
    for _ in range(int(p["cycles"])):
        for i in range(1, n + 1):
            dt = p["period"] / n
            ev.append({"t": round(t, 4), "mouse": at(math.pi - 2 * math.pi * i / n),
                       "over": round(dt, 4)})
            t += dt
    ev.append({"t": round(t, 3), "mouse": [0.5, 0.5], "over": 0.2})
    return ev


# -- running -------------------------------------------------------------------------
def run(interface: str, scene: str | None, events: list[dict], seconds: float) -> dict:
    spec = validate(Located("tune", {"events": events}), ScriptSpec)
    session = Session(load_setup(interface, scene))
    c = session.character
    worst = [0.0]
    watch = UprightWatch()  # upright over the last second, not at the last step

    def sample(s):
        watch(s)
        tilt = abs(math.degrees(math.remainder(c.root_angle(), 2 * math.pi)))
        if tilt > worst[0]:
            worst[0] = tilt

    until = round(seconds / session.sim.dt)
    play(session, compile_script(spec, session.sim.dt), until, 8, sample)
    x, y = c.com()
    return {"x": x, "y": y, "tilt": worst[0], "upright": watch.stayed(session),
            "blown": session.sim.blown_up() or session.blowups > 0}


def score(r: dict) -> float:
    if r["blown"] or r["tilt"] > 60 or not r["upright"]:
        return -10 + r["x"] * 0.1
    return r["x"]


def search(kind: str, trials: int, seed: int, base: dict, seconds: float,
           scene: str | None) -> tuple[dict, dict]:
    rng = random.Random(seed)
    ranges = BOUND_RANGES if kind == "bound" else TROT_RANGES
    make = bound_events if kind == "bound" else trot_events
    interface = f"cat-{kind}"
    best_p, best_r = dict(base), run(interface, scene, make(base), seconds)
    print(f"start: {fmt(best_r)}  {json.dumps(short(best_p))}")
    for i in range(trials):
        p = dict(best_p)
        for k, (lo, hi) in ranges.items():  # perturb around the best so far
            if rng.random() < 0.5:
                p[k] = min(hi, max(lo, p[k] + rng.gauss(0, 0.15 * (hi - lo))))
        if kind == "bound":
            for k, options in BOUND_CHOICES.items():
                if rng.random() < 0.15:
                    p[k] = rng.choice(options)
            p["land"] = max(p["land"], p["swing"] + 0.04)
            p["gather"] = min(max(p["gather"], p["land"] + 0.04), p["period"] - 0.02)
        r = run(interface, scene, make(p), seconds)
        if score(r) > score(best_r):
            best_p, best_r = p, r
            print(f"{i:3d}: {fmt(r)}  {json.dumps(short(p))}")
    return best_p, best_r


def short(p: dict) -> dict:
    return {k: round(v, 3) if isinstance(v, float) else v for k, v in p.items()}


def fmt(r: dict) -> str:
    return (f"x={r['x']:.2f} m tilt={r['tilt']:.0f} upright={r['upright']} "
            f"blown={r['blown']}")


def write_script(path: str, kind: str, p: dict, seconds: float, r: dict) -> None:
    events = bound_events(p) if kind == "bound" else trot_events(p)
    text = (f"cat {kind} (tools/tune_cat.py, params {json.dumps(short(p))}); "
            f"measured com x = {r['x']:.2f} m")
    lines = [f"description: {json.dumps(text)}",
             f"interface: cat-{kind}", f"seconds: {seconds:g}", "events:"]
    for e in events:
        lines.append("  - " + json.dumps(e).replace('"', ""))
    Path(path).write_text("\n".join(lines) + "\n")
    print(f"wrote {path}")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("kind", choices=["bound", "trot"])
    ap.add_argument("--trials", type=int, default=0)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--seconds", type=float, default=None)
    ap.add_argument("--scene", default=None)
    ap.add_argument("--params", default=None, help="JSON overrides of the start parameters")
    ap.add_argument("--write", metavar="SCRIPT", help="write the best as a script")
    args = ap.parse_args(argv)
    base = dict(BOUND_DEFAULT if args.kind == "bound" else TROT_DEFAULT)
    if args.params:
        base.update(json.loads(args.params))
    make = bound_events if args.kind == "bound" else trot_events
    seconds = args.seconds or (max(e["t"] for e in make(base)) + 1.5)
    p, r = search(args.kind, args.trials, args.seed, base, seconds, args.scene)
    print(f"best: {fmt(r)}\nparams: {json.dumps(short(p))}")
    if args.write:
        write_script(args.write, args.kind, p, seconds, r)
    return 0


if __name__ == "__main__":
    sys.exit(main())
