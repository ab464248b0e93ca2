import os, sys; sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from h import evaluate
def reg(v0, k, idx=8, mode="flying"):
    return {f"modes.{mode}.{idx}": {"input": "sensor.com.vx", "joint": "swing_hip", "from": [v0, v0 + 1], "to": [0, k], "clamp": False, "combine": "add"}}
for v0 in [2.7, 2.5]:
    for k in [5, 10, 20, 30]:
        evaluate(reg(v0, k), f"v0={v0} k={k}")
