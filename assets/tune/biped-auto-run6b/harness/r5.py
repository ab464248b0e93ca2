"""run5's candidate structure (sensor-phased stance, SIMBICON stance hip, 480 Hz run states)
with the longjump's stronger speed regulation on top."""
import json, os, sys
os.environ["H2BASE"] = os.path.join(os.path.dirname(os.path.abspath(__file__)), "../../biped-auto-run5/biped-auto.interface.yaml")
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from h2 import evaluate

C40 = {"hold": -18.2741, "spin": 0.0655, "torq": -0.0098, "hip_damp": 16.0687, "drive": 52.9967, "push_thigh": -6.4415, "stance_time": 0.2288, "reach": 8.5064, "cd": 5.4411, "cv": 2.5938, "vd": 2.5734, "push_knee": -11.1591, "push_ankle": -25.2869, "push_k": 1006.3734, "st_knee": -13.4568, "st_knee_k": 1136.8699, "st_ankle": 6.8882, "sw_knee": -135.0509, "fly_knee": -31.1983, "waist": -0.2231}

def edits(p):
    e = {}
    for m in ("driving", "flying"):
        e[f"modes.{m}.1.to"] = [p["hold"], p["hold"]]
        e[f"modes.{m}.8.to"] = [0, p["spin"]]
        e[f"modes.{m}.9.to"] = [0, p["torq"]]
    e["modes.driving.0.to"] = [p["drive"], p["drive"]]
    e["modes.flying.0.to"] = [p["reach"], p["reach"]]
    e["modes.flying.2.to"] = [0, p["cd"]]
    e["modes.flying.3.from"] = [p["vd"], p["vd"] + 1]
    e["modes.flying.3.to"] = [0, p["cv"]]
    e["poses.run_stance.damping.stance_hip"] = p["hip_damp"]
    e["poses.run_stance.joints.waist"] = {"world": p["waist"]}
    e["poses.run_stance.joints.stance_knee"] = p["st_knee"]
    e["poses.run_stance.stiffness.stance_knee"] = p["st_knee_k"]
    e["poses.run_stance.joints.stance_ankle"] = p["st_ankle"]
    e["poses.run_stance.joints.swing_knee"] = p["sw_knee"]
    e["poses.run_push.joints.stance_knee"] = p["push_knee"]
    e["poses.run_push.joints.stance_ankle"] = p["push_ankle"]
    e["poses.run_push.stiffness.stance_knee"] = p["push_k"]
    e["poses.run_push.stiffness.stance_ankle"] = p["push_k"]
    e["poses.run_fly.joints.swing_knee"] = p["fly_knee"]
    for X in ("near", "far"):
        e[f"states.run_{X}.transitions.1.when.below"] = p["push_thigh"]
        e[f"states.run_{X}.transitions.3.after"] = p["stance_time"]
    for k, v in p.items():
        if "." in k:
            e[k] = v
    return e

E = edits
if __name__ == "__main__":
    if os.environ.get("S5"):
        from search5 import edits as E, START
        C40.update(START)
    for kw in json.loads(sys.argv[1]):
        p = dict(C40); p.update(kw)
        evaluate(E(p), json.dumps(kw), verbose=os.environ.get("V") == "1")
