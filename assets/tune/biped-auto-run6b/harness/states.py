import json, os, sys
os.environ["H2BASE"] = os.path.join(os.path.dirname(os.path.abspath(__file__)), "../../biped-auto-run5/biped-auto.interface.yaml")
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import numpy as np
from h2 import write, LOG, SETS
from search5 import START, edits
from puppet.timeline.replay import replay
from puppet.timeline.other_physics import OtherPhysics
p = dict(START); p.update(json.loads(sys.argv[1]) if len(sys.argv) > 1 else {})
write(edits(p))
for s in sys.argv[2].split(",") if len(sys.argv) > 2 else ["40", "240"]:
    r = replay(LOG, physics=OtherPhysics(**SETS[s]), check=True)
    tr = r.trajectory; t = tr.t; st = tr.state
    ti = tr.joints.index("hip_near")
    thn = np.degrees(tr.angle[:, tr.index("thigh_near")]); thf = np.degrees(tr.angle[:, tr.index("thigh_far")])
    # segments from 24 s
    segs = []; cur = None; t0 = None
    for i in range(len(t)):
        if t[i] < 24: continue
        if st[i] != cur:
            if cur is not None: segs.append((cur, round(t[i] - t0, 3), t0, i0))
            cur, t0, i0 = st[i], t[i], i
    from collections import defaultdict
    d = defaultdict(list)
    for name, dur, a, i0 in segs: d[name[:-5] if name.endswith("_near") else name[:-4]].append(dur)
    print(s, {k: (len(v), round(float(np.mean(v)), 3), round(float(np.min(v)), 3), round(float(np.max(v)), 3)) for k, v in d.items()})
    # thigh angles at run_ start and at rpush start (stance thigh)
    a, b = [], []
    for name, dur, t0_, i0 in segs:
        th = thn if name.endswith("near") else thf
        if name.startswith("run_"): a.append(th[i0])
        if name.startswith("rpush_"): b.append(th[i0])
    print("   stance thigh at touch-down %.1f +- %.1f, at push %.1f +- %.1f (deg)" % (np.mean(a), np.std(a), np.mean(b), np.std(b)))
