"""Random search + climb on run5's structure (candidate40) with the speed regulation's
gain and target free, scored on the three settings at once."""
import json, os, random, sys
os.environ["H2BASE"] = os.path.join(os.path.dirname(os.path.abspath(__file__)), "../../biped-auto-run5/biped-auto.interface.yaml")
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from h2 import evaluate
from r5 import C40, edits as e5

DIMS = {"hold": (-24, -14), "spin": (0.03, 0.09), "torq": (-0.03, 0), "hip_damp": (10, 30),
        "drive": (48, 58), "push_thigh": (-12, -2), "stance_time": (0.18, 0.27), "reach": (3, 12),
        "cd": (2, 10), "cv": (0, 12), "vd": (2.5, 3.0), "push_knee": (-16, -4), "push_k": (700, 1300),
        "st_knee": (-20, -8), "st_knee_k": (800, 1500), "st_ankle": (0, 12), "sw_knee": (-140, -115),
        "fly_knee": (-40, -20), "waist": (-6, 4), "pushdx": (0.2, 0.3), "ank_cap": (205, 240),
        "fpel": (0, 1.0)}
START = dict(C40, pushdx=0.2466, ank_cap=212.743, fpel=0.5)

def edits(p):
    e = e5(p)
    for X in ("near", "far"):
        e[f"states.run_{X}.transitions.2.when.above"] = p["pushdx"]
    e["poses.run_stance.max_torque.stance_ankle"] = p["ank_cap"]
    e["poses.run_stance.max_torque.swing_ankle"] = p["ank_cap"]
    e["modes.flying.7.to"] = [0, p["fpel"]]
    return e

def score(res):
    per = [min(r["v"], 2.8) - len([f for f in r["fails"] if f not in ("same_end", "mean_speed")])
           for r in res.values()]
    return min(per) + 0.3 * sum(per) / len(per)

def main(seed, n, sigma, out):
    rnd = random.Random(seed)
    best = dict(START); best.update(json.load(open(os.environ["S5START"])) if os.environ.get("S5START") else {})
    r = evaluate(edits(best), "start"); bs = score(r)
    for i in range(n):
        p = dict(best)
        for k, (lo, hi) in DIMS.items():
            if rnd.random() < 0.5:
                p[k] = round(min(hi, max(lo, best[k] + rnd.gauss(0, sigma * (hi - lo)))), 4)
        r = evaluate(edits(p), f"#{i}")
        s = score(r)
        with open(out, "a") as f:
            f.write(json.dumps({"p": p, "s": s, "r": {k: (x["v"], x["fails"]) for k, x in r.items()}}) + "\n")
        if s > bs:
            best, bs = p, s
            print(f"  NEW BEST {bs:.3f} {json.dumps(best)}", flush=True)

if __name__ == "__main__":
    main(int(sys.argv[1]), int(sys.argv[2]), float(sys.argv[3]), sys.argv[4])
