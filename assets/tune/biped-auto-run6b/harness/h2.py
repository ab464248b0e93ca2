"""Experiment harness 2: in-process replays on three settings, per-second trace."""
import copy, json, sys, os
os.environ.setdefault("SDL_VIDEODRIVER", "dummy")
from concurrent.futures import ProcessPoolExecutor
import numpy as np, yaml
ROOT = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "../../../.."))
sys.path.insert(0, ROOT)
IF = f"{ROOT}/interfaces/biped-auto.yaml"
BASE = yaml.safe_load(open(os.environ.get("H2BASE", f"{ROOT}/assets/tune/biped-auto-run6b/harness/base.yaml")))
SETS = {"40": {}, "36": {"iterations": 36}, "240": {"dt": 1 / 240}}
LOG = f"{ROOT}/assets/logs/biped-auto-run.jsonl"

def setp(d, path, v):
    ks = path.split(".")
    for k in ks[:-1]:
        d = d[int(k)] if isinstance(d, list) else d[k]
    k = ks[-1]
    if isinstance(d, list):
        k = int(k)
        if k == len(d):
            d.append(v); return
    if v is None:
        del d[k]; return
    d[k] = v

def make(edits):
    d = copy.deepcopy(BASE)
    for p, v in edits.items():
        setp(d, p, v)
    return d

def write(edits, path=IF):
    with open(path, "w") as f:
        yaml.safe_dump(make(edits), f, sort_keys=False, width=200)

def run(setting, log=LOG, trace=False):
    from puppet.timeline.replay import replay
    from puppet.timeline.other_physics import OtherPhysics
    r = replay(log, physics=OtherPhysics(**SETS[setting]), check=True)
    tr = r.trajectory
    out = {"fails": [o.kind for o in r.outcomes if not o.passed]}
    for o in r.outcomes:
        if "min 2.5" in str(getattr(o, "label", "")) or False:
            pass
    t = tr.t; cx = tr.com[:, 0]
    m = t >= 25.0
    out["v"] = round(float((cx[-1] - cx[m][0]) / (t[-1] - t[m][0])), 3)
    pel = np.degrees(tr.angle[:, tr.index("pelvis")])
    sec = []
    for s in range(12, 30):
        w = (t >= s) & (t < s + 1)
        if w.sum() < 2: break
        sec.append((round(float((cx[w][-1] - cx[w][0]) / (t[w][-1] - t[w][0])), 2), int(round(float(pel[w].mean())))))
    out["sec"] = sec
    out["details"] = [o.kind + ": " + o.measured[:60] for o in r.outcomes if not o.passed]
    return out

def evaluate(edits, label="", verbose=False, pool=None):
    write(edits)
    with ProcessPoolExecutor(2) as ex:
        res = dict(zip(SETS, ex.map(run, SETS)))
    ok = sum(not r["fails"] for r in res.values())
    print(f"{ok}/3 {label} " + "  ".join(f"{k}: {r['v']} F{len(r['fails'])}" for k, r in res.items()), flush=True)
    if verbose:
        for k, r in res.items():
            print("   ", k, " ".join(f"{v}/{p}" for v, p in r["sec"]), r["details"][:2], flush=True)
    return res

if __name__ == "__main__":
    edits = json.loads(sys.argv[1]) if len(sys.argv) > 1 else {}
    evaluate(edits, sys.argv[2] if len(sys.argv) > 2 else "", verbose=True)
