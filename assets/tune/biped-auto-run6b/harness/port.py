import os, sys, json; sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from h2 import evaluate
S = 0.571 ** 0.5
def port(v0=2.75, k=30 * S, waist=8.636, clocks=True, lean=-7.99, reach=14.92, drive=53.33,
         cd=15.05 * 0.571, cv=4 * S, extra=None):
    e = {
        "poses.run_stance.joints.waist": {"world": waist},
        "poses.run_stance.joints.stance_knee": -13.318,
        "poses.run_stance.joints.stance_ankle": 7.232,
        "poses.run_stance.joints.swing_knee": -128.199,
        "poses.run_stance.stiffness.stance_knee": 787.0,
        "poses.run_stance.stiffness.stance_ankle": 800.0,
        "poses.run_push.joints.stance_knee": -7.631,
        "poses.run_push.joints.stance_ankle": -31.855,
        "poses.run_push.stiffness.stance_knee": 828.0,
        "poses.run_push.stiffness.stance_ankle": 828.0,
        "poses.run_fly.joints.swing_knee": -11.555,
        "modes.driving.0.to": [drive, drive],
        "modes.driving.1.to": [lean, lean],
        "modes.driving.2.to": [0, cd],
        "modes.driving.3.to": [0, cv],
        "modes.driving.7.to": [0, 0.0],
        "modes.flying.0.to": [reach, reach],
        "modes.flying.1.to": [lean, lean],
        "modes.flying.2.to": [0, cd],
        "modes.flying.3.to": [0, cv],
        "modes.flying.7.to": [0, 0.0],
        "modes.flying.8": {"input": "sensor.com.vx", "joint": "swing_hip", "from": [v0, v0 + 1], "to": [0, k], "clamp": False, "combine": "add"},
    }
    if clocks:
        for X in ("near", "far"):
            e[f"states.run_{X}.transitions"] = [
                {"to": f"on_{X}", "when": {"sensor": "input.mouse.x", "below": 0.66}},
                {"to": f"rpush_{X}", "after": round(0.066 / S, 4)}]
            e[f"states.rpush_{X}.transitions"] = [{"to": f"fly_{X}", "after": round(0.049 / S, 4)}]
    e.update(extra or {})
    return e
if __name__ == "__main__":
    for kw in json.loads(sys.argv[1]):
        evaluate(port(**kw), json.dumps(kw), verbose=True)
