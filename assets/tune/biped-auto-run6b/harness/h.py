"""Experiment harness (issue 27, run6b): edit interfaces/biped-auto.yaml by dotted paths,
replay the run log on the three settings, print the feat figures."""
import copy, json, re, subprocess, sys, os
from concurrent.futures import ThreadPoolExecutor
import yaml
ROOT = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "../../../.."))
IF = f"{ROOT}/interfaces/biped-auto.yaml"
BASE = yaml.safe_load(open(f"{ROOT}/assets/tune/biped-auto-run6b/harness/base.yaml"))
SETS = {"40": [], "36": ["--solver-passes", "36"], "240": ["--step", "1/240"]}

def setp(d, path, v):
    ks = path.split(".")
    for k in ks[:-1]:
        d = d[int(k)] if isinstance(d, list) else d[k]
    k = ks[-1]
    if isinstance(d, list):
        k = int(k)
        if k == len(d):
            d.append(v); return
    d[k] = v

def write(edits):
    d = copy.deepcopy(BASE)
    for p, v in edits.items():
        setp(d, p, v)
    with open(IF, "w") as f:
        yaml.safe_dump(d, f, sort_keys=False, width=200)

def run(setting, log="assets/logs/biped-auto-run.jsonl"):
    env = dict(os.environ, PYTHONPATH=ROOT, SDL_VIDEODRIVER="dummy", SDL_AUDIODRIVER="dummy")
    out = subprocess.run(["/work/main/.venv/bin/puppet", "replay", "--headless", "--check", *SETS[setting], log],
                         cwd=ROOT, env=env, capture_output=True, text=True).stdout
    sp = re.search(r"min 2.5 m/s from 25 s to the end: ([\d.-]+)", out)
    fl = re.search(r"(\d+) flights of 0.04", out)
    ti = re.search(r"pelvis (\d+) deg from upright at t = ([\d.]+)", out)
    fails = out.count("FAIL")
    return dict(v=float(sp.group(1)) if sp else None, fl=int(fl.group(1)) if fl else 0,
                tilt=ti.group(1)+"@"+ti.group(2) if ti else "?", fails=fails)

def evaluate(edits, label=""):
    write(edits)
    with ThreadPoolExecutor(2) as ex:
        res = dict(zip(SETS, ex.map(run, SETS)))
    ok = sum(r["fails"] == 0 for r in res.values())
    print(f"{ok}/3 {label} " + "  ".join(f"{k}: {r['v']} fl{r['fl']} t{r['tilt']} F{r['fails']}" for k, r in res.items()), flush=True)
    return res

if __name__ == "__main__":
    edits = json.loads(sys.argv[1]) if len(sys.argv) > 1 else {}
    evaluate(edits, sys.argv[2] if len(sys.argv) > 2 else "")
