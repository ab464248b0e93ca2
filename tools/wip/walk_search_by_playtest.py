"""Search the walk's numbers on what counts: the walk script recorded, then a small
playtest of it at --noise human (tries with a person's timing and aim errors)."""
import sys, os, ast, json, random, subprocess, shutil, tempfile
sys.path.insert(0, "/tmp/walkh")
os.environ.setdefault("SDL_VIDEODRIVER", "dummy")
from walk_forgiving import walk
from puppet.data.playtest import noise_at
from puppet.timeline.playtest import playtest

SPACE = ast.literal_eval(open(os.environ["SPACE"]).read())
SCRIPT = os.environ.get("SCRIPT", "/work/wt/walk/assets/scripts/biped-walk.yaml")
TRIES = int(os.environ.get("TRIES", "4"))
EXPECT = open("/work/wt/walk/assets/logs/biped-walk.expect.yaml").read()

def evaluate(p):
    d = tempfile.mkdtemp(dir="/tmp/walkh/real")
    iface = os.path.join(d, "biped-walk.yaml")
    open(iface, "w").write(walk(p, "x"))
    log = os.path.join(d, "w.jsonl")
    r = subprocess.run(["/work/wt/walk/.venv/bin/puppet", "play", iface, "--headless", "--input", SCRIPT,
                        "--record", log], capture_output=True, text=True, cwd="/work/wt/walk")
    open(os.path.join(d, "w.expect.yaml"), "w").write(EXPECT)
    res = playtest(log, noise_at("human"), tries=TRIES, seed=int(os.environ.get("PSEED", "0")), jobs=2)
    passes = res.passes if res.error is None else 0
    out = subprocess.run(["/work/wt/walk/.venv/bin/puppet", "replay", "--headless", "--check", log],
                         capture_output=True, text=True, cwd="/work/wt/walk").stdout
    own = "FAIL" not in out.replace("FAIL same end", "")
    shutil.rmtree(d, ignore_errors=True)
    return passes + 0.5 * own, passes, own

def main():
    rng = random.Random(int(os.environ.get("SEED", "1")))
    best = None
    base = ast.literal_eval(open(os.environ["INIT"]).read())
    out = open(os.environ["OUT"], "a")
    for i in range(int(os.environ.get("N", "100"))):
        if best is None:
            p = dict(base)
            if os.environ.get("BEST0"):
                best = (float(os.environ["BEST0"]), dict(base))
                continue
        else:
            p = dict(best[1])
            for k in rng.sample(list(SPACE), int(os.environ.get("NMUT", "3"))):
                lo, hi = SPACE[k]
                p[k] = min(hi, max(lo, p[k] + rng.gauss(0, float(os.environ.get("SIG", "0.08")) * (hi - lo))))
        s, passes, own = evaluate(p)
        print(json.dumps({"i": i, "score": s, "passes": passes, "own": own, "p": p}), file=out, flush=True)
        if best is None or s > best[0]:
            best = (s, p)
            print(i, "BEST", s, passes, own, flush=True)

if __name__ == "__main__":
    main()
