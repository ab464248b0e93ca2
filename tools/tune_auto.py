"""Search the numbers of interfaces/biped-auto.yaml (the walk with the legs swapping by
themselves) on a log's own script and expectations.

    python tools/tune_auto.py [--log biped-auto-walk] [--budget 600] [--seed 5]
                              [--from-file interfaces/biped-auto.yaml]
    python tools/tune_auto.py --log biped-auto-run --run --speed-weight 5 \
                              [--values start.json] [--save best.json]

Every try is the interface file with some of its numbers changed (``PARAMS``: one name
for each number, with the places in the file it is written, near and far alike, and its
range), played through the real Session on the log's script (assets/scripts/LOG.yaml:
the mouse moving slowly from the march spot to the faster one) and judged by the log's
sidecar (assets/logs/LOG.expect.yaml) exactly as ``puppet replay --check`` judges it.
The score is ten points per expectation met, plus the centre of mass's mean speed over
the last 5 s, less how early the figure fell (pelvis or chest past 45 deg, or the head
below 1.2 m). The search is random to start, then changes four numbers of one of the
twelve best at a time. It prints the best tries' numbers (as ``path: value``, for a
person to write into the file, comments kept) and exits 0 if the best met every
expectation, else 1. The shipped numbers came from a search of this kind run
from a scratch copy (much the same numbers and ranges: random tries, then local changes;
a few thousand tries of 11-20 s, the mouse spots searched too), scored by the same
kind of criteria, but at its worst over three glide timings (the glide of 12, 15 and
20 s) rather than on the one script: a walk is chaotic, and numbers tuned on one
performance alone fell on others. Started from the shipped file this tool
re-plays the log to its measured figures (0.564 m/s over the last 5 s, 9.99 m). The log
was then recorded with ``puppet play biped-auto --headless --input biped-auto-walk
--record assets/logs/biped-auto-walk.jsonl``.

``--run`` searches the run's numbers instead (``RUN_PARAMS``: the states run_X, rpush_X
and fly_X, the modes driving and flying, the caps the run's stance pose raises), on the
log biped-auto-run (the mouse on from the walk spot to the run spot). The walk's numbers
are not touched, so the walk log still replays to its bits. ``--speed-weight`` scores
each m/s over the last 5 s that many points (the run's searches used 5); ``--values``
starts from a JSON of name: value, ``--save`` writes the best one so. ``--also
SCRIPT ...`` plays each try on more script files too (the same glide with other timings,
or run on longer), judged by the same expectations, and scores it at its worst: the
shipped run was searched on its log alone and is fragile; with ``--also`` (the 8 and
12 s glides, the log's script run on to 34 s) the best found held on all of them but at
2.45 m/s (docs/interfaces.md 9.5).
"""

from __future__ import annotations

import argparse
import copy
import json
import math
import random
import sys
import time
from pathlib import Path

import yaml

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from puppet.data.catalog import find, setup_from_text  # noqa: E402
from puppet.session import Session  # noqa: E402
from puppet.session.playback import play  # noqa: E402
from puppet.timeline.expectations import evaluate_all, load_expectations  # noqa: E402
from puppet.timeline.replay import Sampler  # noqa: E402
from puppet.timeline.script import compile_script, load_script, run_seconds  # noqa: E402

SIDES = ("near", "far")
OTHER = {"near": "far", "far": "near"}


def _both(fmt: str) -> list[str]:
    return [fmt.format(s=s, o=OTHER[s]) for s in SIDES]


# name -> (places in the file, lo, hi); a place is a dotted path (list items by index)
PARAMS = {
    "ankle_torque": (_both("gains.ankle_{s}.max_torque"), 150, 300),
    "knee_torque": (_both("gains.knee_{s}.max_torque"), 200, 350),
    "hip_torque": (_both("gains.hip_{s}.max_torque"), 200, 350),
    "waist": (["poses.stride.joints.waist.world"], -20, 5),
    "stance_knee": (["poses.stride.joints.stance_knee"], -25, -2),
    "push_ankle": (["poses.push.joints.stance_ankle"], -40, -5),
    "push_knee": (["poses.push.joints.stance_knee"], -10, 0),
    "push_ankle_stiffness": (["poses.push.stiffness.stance_ankle"], 300, 1500),
    "push_knee_stiffness": (["poses.push.stiffness.stance_knee"], 500, 2000),
    "lift_lo": (["modes.stepping.0.to.0"], -30, 10),
    "lift_hi": (["modes.stepping.0.to.1"], 10, 70),
    "lean_lo": (["modes.stepping.2.to.0", "modes.reaching.1.to.0"], -5, 5),
    "lean_hi": (["modes.stepping.2.to.1", "modes.reaching.1.to.1"], -30, 0),
    "c_d": (["modes.stepping.3.to.1", "modes.reaching.2.to.1"], 0, 40),
    "c_v": (["modes.stepping.4.to.1", "modes.reaching.3.to.1"], 3, 25),
    "reach_lo": (["modes.reaching.0.to.0"], -10, 15),
    "reach_hi": (["modes.reaching.0.to.1"], -45, 30),
    "lift_time": (_both("states.on_{s}.transitions.0.after"), 0.1, 0.35),
    "push_at": (_both("states.down_{s}.transitions.0.when.above"), -0.1, 0.3),
    "push_time": (_both("states.push_{s}.transitions.0.after"), 0.03, 0.15),
    "land_after": (_both("states.down_{s}.transitions.1.after")
                   + _both("states.push_{s}.transitions.1.after"), 0.0, 0.15),
}

# the run's numbers (``--run``: the states run_X, rpush_X, fly_X and the modes driving
# and flying), with the caps the run's stance pose raises (the walk's stride puts the
# walk's back: gains: is the walk's, which this search must not change)
RUN_PARAMS = {
    "run_waist": (["poses.run_stance.joints.waist.world"], -25, 15),
    "run_stance_knee": (["poses.run_stance.joints.stance_knee"], -45, 0),
    "run_stance_knee_stiffness": (["poses.run_stance.stiffness.stance_knee"], 300, 2000),
    "run_stance_ankle": (["poses.run_stance.joints.stance_ankle"], -20, 25),
    "run_drive_knee": (["poses.run_stance.joints.swing_knee"], -145, -40),
    "run_push_knee": (["poses.run_push.joints.stance_knee"], -20, 0),
    "run_push_ankle": (["poses.run_push.joints.stance_ankle"], -45, 0),
    "run_push_stiffness": (["poses.run_push.stiffness.stance_knee",
                            "poses.run_push.stiffness.stance_ankle"], 300, 2500),
    "run_fly_knee": (["poses.run_fly.joints.swing_knee"], -60, 0),
    "run_drive_lo": (["modes.driving.0.to.0"], 0, 80),
    "run_drive_hi": (["modes.driving.0.to.1"], 0, 80),
    "run_lean_lo": (["modes.driving.1.to.0", "modes.flying.1.to.0"], -25, 5),
    "run_lean_hi": (["modes.driving.1.to.1", "modes.flying.1.to.1"], -25, 5),
    "run_reach_lo": (["modes.flying.0.to.0"], -10, 60),
    "run_reach_hi": (["modes.flying.0.to.1"], -10, 60),
    "run_c_d": (["modes.driving.2.to.1", "modes.flying.2.to.1"], 0, 60),
    "run_c_v": (["modes.driving.3.to.1", "modes.flying.3.to.1"], 0, 30),
    "run_stance_time": (_both("states.run_{s}.transitions.1.after"), 0.02, 0.25),
    "run_push_time": (_both("states.rpush_{s}.transitions.0.after"), 0.0, 0.2),
    "run_land_after": (_both("states.fly_{s}.transitions.0.after"), 0.0, 0.08),
    "run_hip_torque": (["poses.run_stance.max_torque.stance_hip",
                        "poses.run_stance.max_torque.swing_hip"], 200, 450),
    "run_knee_torque": (["poses.run_stance.max_torque.stance_knee",
                         "poses.run_stance.max_torque.swing_knee"], 250, 450),
    "run_ankle_torque": (["poses.run_stance.max_torque.stance_ankle",
                          "poses.run_stance.max_torque.swing_ankle"], 150, 350),
}


def _walk(tree, path: str):
    *parents, last = [int(k) if k.isdigit() else k for k in path.split(".")]
    for k in parents:
        tree = tree[k]
    return tree, last


def get(tree, name: str) -> float:
    node, key = _walk(tree, (PARAMS | RUN_PARAMS)[name][0][0])
    return float(node[key])


def put(tree, values: dict) -> dict:
    out = copy.deepcopy(tree)
    for name, v in values.items():
        for path in (PARAMS | RUN_PARAMS)[name][0]:
            node, key = _walk(out, path)
            node[key] = round(float(v), 3)
    return out


class Judge:
    """Scores a try on the log's script, and with ``also`` (other scripts, judged by
    the same expectations: other glide timings, a longer run) at its worst over all."""

    def __init__(self, log: str, iface: Path, speed_weight: float = 1.0, also=()):
        self.speed_weight = speed_weight
        self.base = yaml.safe_load(iface.read_text(encoding="utf-8"))
        self.path = iface
        script = find("script", log)
        self.specs = [load_script(script)] + [load_script(Path(a)) for a in also]
        log_path = ROOT / "assets" / "logs" / f"{log}.jsonl"
        self.expect = load_expectations(log_path, {})

    def __call__(self, values: dict):
        text = yaml.safe_dump(put(self.base, values), sort_keys=False)
        results = [self._one(text, spec) for spec in self.specs]
        worst = min(r[0] for r in results)
        return (worst, *results[0][1:])

    def _one(self, text: str, spec):
        self.seconds = run_seconds(spec)
        session = Session(setup_from_text(text, self.path))
        sampler = Sampler(session)
        until = round(self.seconds / session.sim.dt)
        play(session, compile_script(spec, session.sim.dt), until, 4, sampler)
        traj = sampler.trajectory()
        outcomes = evaluate_all(self.expect.items, traj, "")
        passed = sum(o.passed for o in outcomes)
        i = traj.links.index
        tilt = [abs(math.degrees(math.remainder(a, 2 * math.pi)))
                for a in traj.angle[:, [i("pelvis"), i("chest")]].max(axis=1)]
        bad = [k for k in range(len(traj.t)) if tilt[k] > 45 or traj.y[k, i("head")] < 1.2]
        fell_at = traj.t[bad[0]] if bad else None
        last = traj.t >= traj.t[-1] - 5.0
        k0 = int(last.argmax())
        speed = float((traj.com[-1, 0] - traj.com[k0, 0]) / (traj.t[-1] - traj.t[k0]))
        score = 10 * passed + (self.speed_weight * speed if fell_at is None
                               else -10 + 5 * fell_at / self.seconds)
        return score, passed, len(outcomes), outcomes


def main(argv=None) -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("--log", default="biped-auto-walk")
    ap.add_argument("--budget", type=float, default=600.0, help="seconds of searching")
    ap.add_argument("--seed", type=int, default=5)
    ap.add_argument("--from-file", default="interfaces/biped-auto.yaml")
    ap.add_argument("--run", action="store_true",
                    help="search the run's numbers (RUN_PARAMS) rather than the walk's")
    ap.add_argument("--speed-weight", type=float, default=1.0,
                    help="points per m/s of the mean speed over the last 5 s")
    ap.add_argument("--also", nargs="*", default=[],
                    help="more script files, judged by the log's expectations too; a "
                         "try scores its worst")
    ap.add_argument("--values", help="a JSON file of name: value to start from")
    ap.add_argument("--save", help="write the best try's name: value here (JSON)")
    a = ap.parse_args(argv)
    params = RUN_PARAMS if a.run else PARAMS
    judge = Judge(a.log, ROOT / a.from_file, a.speed_weight, a.also)
    rng = random.Random(a.seed)
    start = {n: get(judge.base, n) for n in params}
    if a.values:
        start.update(json.loads(Path(a.values).read_text(encoding="utf-8")))
    first = judge(start)
    pop = [(first[0], start, first)]
    t0 = time.time()
    while time.time() - t0 < a.budget:
        if rng.random() < 0.1:
            values = {n: rng.uniform(lo, hi) for n, (_, lo, hi) in params.items()}
        else:
            parent = pop[min(int(rng.expovariate(0.5)), len(pop) - 1)][1]
            values = dict(parent)
            for n in rng.sample(sorted(params), 4):
                _, lo, hi = params[n]
                values[n] = min(hi, max(lo, values[n] + rng.gauss(0, 0.12 * (hi - lo))))
        res = judge(values)
        pop.append((res[0], values, res))
        pop.sort(key=lambda p: -p[0])
        del pop[12:]
    best = pop[0]
    if a.save:
        Path(a.save).write_text(json.dumps(best[1], indent=1), encoding="utf-8")
    print(f"best: {best[2][1]} of {best[2][2]} expectations, score {best[0]:.2f}")
    for o in best[2][3]:
        print(" ", o)
    for n, v in best[1].items():
        for path in params[n][0]:
            print(f"{path}: {round(v, 3)}")
    return 0 if best[2][1] == best[2][2] else 1


if __name__ == "__main__":
    sys.exit(main())
