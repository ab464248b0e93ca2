"""Random search + climb (run6b): the shipped run plus the speed regulation, scored on the
three settings at once (worst setting first)."""
import json, os, random, sys, copy
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from h2 import evaluate

def reg(v0, k):
    return {"input": "sensor.com.vx", "joint": "swing_hip", "from": [v0, v0 + 1], "to": [0, k], "clamp": False, "combine": "add"}

DIMS = {  # name: (lo, hi, shipped)
    "reg_k": (0, 14, 5), "reg_v0": (2.3, 3.2, 2.7),
    "lean": (-18, -6, -10), "reach": (6, 20, 13.52), "fcd": (0, 12, 5.34), "fcv": (0, 4, 0.46),
    "fpel": (0, 1.5, 0.5), "dpel": (0, 1, 0), "hipd": (30, 70, 50), "hips": (700, 2000, 1000),
    "drive": (50, 66, 60.7), "pushdx": (0.18, 0.32, 0.2466), "swank": (400, 1000, 814.77),
    "dcd": (5, 16, 11.23),
}

def edits(p):
    e = {
        "modes.flying.8": reg(p["reg_v0"], p["reg_k"]),
        "modes.driving.1.to": [p["lean"], p["lean"]], "modes.flying.1.to": [p["lean"], p["lean"]],
        "modes.flying.0.to": [p["reach"], p["reach"]],
        "modes.flying.2.to": [0, p["fcd"]], "modes.flying.3.to": [0, p["fcv"]],
        "modes.flying.7.to": [0, p["fpel"]], "modes.driving.7.to": [0, p["dpel"]],
        "modes.driving.2.to": [0, p["dcd"]],
        "poses.run_stance.damping.stance_hip": p["hipd"],
        "poses.run_stance.stiffness.stance_hip": p["hips"],
        "poses.run_stance.stiffness.swing_ankle": p["swank"],
        "modes.driving.0.to": [p["drive"], p["drive"]],
        "states.run_near.transitions.1.when.above": p["pushdx"],
        "states.run_far.transitions.1.when.above": p["pushdx"],
    }
    return e

def score(res):
    per = []
    for r in res.values():
        v = min(r["v"], 2.8)
        per.append(v - 1.0 * len([f for f in r["fails"] if f != "same_end"]))
    return min(per) + 0.3 * sum(per) / len(per)

def main(seed, n, start=None, sigma=0.15, out="exp/search.jsonl"):
    rnd = random.Random(seed)
    best = dict(start or {k: d[2] for k, d in DIMS.items()})
    r = evaluate(edits(best), "start"); bs = score(r)
    with open(out, "a") as f:
        f.write(json.dumps({"p": best, "s": bs, "r": {k: (x["v"], x["fails"]) for k, x in r.items()}}) + "\n")
    for i in range(n):
        p = {}
        for k, (lo, hi, _) in DIMS.items():
            p[k] = round(min(hi, max(lo, best[k] + rnd.gauss(0, sigma * (hi - lo)))), 4)
        r = evaluate(edits(p), f"#{i}")
        s = score(r)
        with open(out, "a") as f:
            f.write(json.dumps({"p": p, "s": s, "r": {k: (x["v"], x["fails"]) for k, x in r.items()}}) + "\n")
        if s > bs:
            best, bs = p, s
            print(f"  NEW BEST {bs:.3f} {json.dumps(best)}", flush=True)

if __name__ == "__main__":
    start = json.loads(sys.argv[4]) if len(sys.argv) > 4 else None
    main(int(sys.argv[1]), int(sys.argv[2]), start, float(sys.argv[3]) if len(sys.argv) > 3 else 0.15)
