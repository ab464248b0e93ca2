"""Search the long jump of interfaces/biped-longjump.yaml on its log's own expectations
(assets/logs/biped-longjump.expect.yaml), and write the performance as a script.

    python tools/tune_longjump.py [--write assets/scripts/biped-longjump.yaml]
    python tools/tune_longjump.py --poses 600 [--seed 8]     # the leap's poses

The performance is what a person does on the interface: the mouse parked low, then
seven strides of the walk interface (space swaps the legs; the mouse sweeps up and
right, where the new swing leg lifts to, then down: ``tools/tune_walk.py``'s first
stride, quicker for the small figure), then ``l`` (the leap). The script checkpoints
at the last swap, one step before the leap, as the paper did; from that checkpoint
the search presses ``l`` at every 5 ms of the stride, each try played through the
real Session (``Session.checkpoint`` / ``restore``: a try gives the bits the recorded
script gives), sampled as ``puppet replay`` samples it (``Sampler``) and judged by the
log's own expectations. The press kept is the middle of the longest run of passing
offsets (so a press a little earlier or later also jumps); when none passes, the one
passing the most expectations (ties: the longest jump) and exit 1.

``--poses N`` searches the leap itself (the interface's poses crouch, push, sail,
land and squat, the push's stiffness, the lean that ends the crouch, the holds and the press
offset), N tries around the interface's own numbers (Gaussian steps of 6%, for the
last third 2%, of each range; the numbers came from such searches begun at a hand-made
leap, with random tries among them), every try the whole performance from
the start (the poses are the interface's data: there is no checkpoint to start from).
A try is scored by how far past 1.0 m the first foot lands, how far behind the line
the last foot leaves (both capped), the jump's length, the flight time, feet first,
and sitting up at the end (the chest within 40 deg of upright, the head above
0.35 m), the chest never more than 70 deg from upright (no dive, no roll), at its worst
over the press and the press 5 ms earlier and later; the best is printed as YAML to
paste into the interface. Seeded: the same arguments find the same numbers.

The run-up (the log biped-longjump-run, scene biped-longjump-run, judged by its sidecar
assets/logs/biped-longjump-run.expect.yaml): the mouse parked at (--mouse-x, 0.9) -
past 0.68 the run states run by themselves - space at 0.5 s, a checkpoint at
--check-at, l at a press.

    python tools/tune_longjump.py --leap 300 --check-at 6.0 [--values a.json --save b.json]
                                  [--presses 6.15 6.17 6.19 6.2 6.21 6.22 6.23]
    python tools/tune_longjump.py --run-up --check-at 6.0 \
                                  [--write assets/scripts/biped-longjump-run.yaml]
    python tools/tune_longjump.py --robust --check-at 6.0 --press 6.16
    python tools/tune_longjump.py --robust --retry --check-at 5.5 --span 1.2

The shipped numbers: --leap 300 from the walk-up's sail, land and squat and a hand-made
take-off (--check-at 3.5, then 4.0, on a run-up 3 m long before the run had its
velocity feedback), then on this run-up (5 m, c_v 4) --leap 300 --check-at 6.0, and
--leap 150 with --presses twice (6.03 6.06 6.15 6.205 6.22 6.36, then the presses
above), seeds 7, 8, 9; the press by --run-up --check-at 6.0.

``--leap N`` searches the run's take-off and landing (the poses takeoff, rsail, rland,
rsquat and their holds; Gaussian steps of 8 %, for the last third 3 %, of each range)
and the press: the run-up is played once to the checkpoint, then every try restores
it and reloads the interface with the try's numbers (the "reload" event: the run's
own states are unchanged, so the run-up is the same), presses l and is scored by
``run_score`` (ten points for run_up, took_off and first_touch each, three for each
other expectation met, plus how near each is to its bound); with ``--presses`` a try
scores its mean over l at those times (the press not searched). ``--run-up`` is the
press search above for the run-up log (every 5 ms of the 0.5 s after its checkpoint),
``--write`` its script. ``--robust`` plays the whole performance with space moved by
-0.1 .. +0.1 s (the checkpoint and l with it), l by -20 .. +20 ms more and the mouse's
x at --mouse-x and 0.03 less, and counts those that pass; with ``--retry``, for each
run-up every press from its checkpoint (what a person with the checkpoint does).
``--run N`` searches the run's own numbers too (every try the whole performance; slow).
"""

from __future__ import annotations

import argparse
import json
import math
import random
import sys
from pathlib import Path

import numpy as np
import yaml

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from puppet.data.catalog import ROOT, setup_from_text  # noqa: E402
from puppet.interface import events as ev  # noqa: E402
from puppet.session import Session  # noqa: E402
from puppet.session.playback import play  # noqa: E402
from puppet.timeline.expectations import evaluate_all, load_expectations  # noqa: E402
from puppet.timeline.expectations.measure import runs as _runs  # noqa: E402
from puppet.timeline.script import ScriptSpec, compile_script  # noqa: E402
from puppet.timeline.trajectory import SAMPLE_EVERY, Sampler  # noqa: E402
from tools.tune_walk import stride_entries  # noqa: E402

INTERFACE = ROOT / "interfaces" / "biped-longjump.yaml"
WALK_SCENE = "biped-longjump"  # the walk-up's (the interface's own is the run-up's)
RUN_SCENE = "biped-longjump-run"
RUN_LOG = ROOT / "assets" / "logs" / "biped-longjump-run.jsonl"
LOG = ROOT / "assets" / "logs" / "biped-longjump.jsonl"
STRIDE = {"period": 0.38, "lx": 0.65, "ly": 0.65, "lift": 0.09, "reach_at": 0.22,
          "rx": 0.4, "ry": 0.05}  # tune_walk's first stride, 0.76x the period
STRIDES = 7
START = 1.0  # s standing before the first press
AFTER = 2.5  # s played after the last swap (the leap, the landing, sitting)
OFFSETS = [round(0.005 * i, 3) for i in range(101)]  # l after the last swap, s (to 0.5)


def run_up() -> tuple[list[dict], float]:
    """The script's entries to the last swap (its checkpoint included) and that time."""
    entries: list[dict] = [{"t": 0.2, "mouse": [0.5, 0.2]}]
    t = START
    for k in range(STRIDES):
        if k == STRIDES - 1:
            entries.append({"t": t, "action": "checkpoint"})
            last = t
        more, t = stride_entries(t, STRIDE)
        entries += more
    return entries, last


def script(entries: list[dict], press: float) -> list[dict]:
    return entries + [{"t": round(press, 3), "key": "l", "hold": 0.05}]


def pairs(entries: list[dict], dt: float):
    return compile_script(ScriptSpec.model_validate({"events": entries}), dt)


def longest_flight(free) -> tuple[int, int]:
    """(samples, first index) of the longest stretch with nothing touching, the first if
    tied, (0, 0) without one: the jump (the expectations' stretches, ``_runs``)."""
    best = (0, 0)
    for i, j in _runs(free):
        if j - i + 1 > best[0]:
            best = (j - i + 1, i)
    return best


def judge(sampler: Sampler, items) -> tuple[int, float, list]:
    """(expectations passed, the jump's length, the outcomes) of what was sampled."""
    traj = sampler.trajectory()
    outcomes = evaluate_all(items, traj, "")
    free = ~traj.contact.any(axis=1)
    best, first = longest_flight(free)
    length = 0.0
    if best and first > 0 and first + best < len(free):  # the touching feet, off to down
        feet = [traj.index("foot_near"), traj.index("foot_far")]
        off = [traj.x[first - 1, k] for k in feet if traj.contact[first - 1, k]]
        down = [traj.x[first + best, k] for k in feet if traj.contact[first + best, k]]
        if off and down:
            length = float(min(down) - max(off))
    return sum(o.passed for o in outcomes), length, outcomes


def search_press(text: str, items, entries=None, last=None, scene: str = WALK_SCENE,
                 quiet: bool = False) -> tuple[float | None, list, int]:
    """From the checkpoint at ``last`` (the walk-up's: at the last swap), ``l`` at each
    offset; the press kept."""
    if entries is None:
        entries, last = run_up()
    session = Session(setup_from_text(text, str(INTERFACE), scene, None))
    dt = session.sim.dt
    sampler = Sampler(session)
    sampler(session)
    mark = round(last / dt)
    everything = pairs(entries, dt)
    # to the checkpoint's step, then the checkpoint, then that step's press: the
    # script's order (its checkpoint entry comes first)
    play(session, [e for e in everything if e[0] < mark], mark, SAMPLE_EVERY, sampler)
    session.handle(ev.action("checkpoint"))
    rest = [e for e in everything if e[0] >= mark and e[1].get("type") != "action"]
    end = round((last + AFTER) / dt)
    tried = []
    for off in OFFSETS:
        press = pairs([{"t": round(last + off, 3), "key": "l", "hold": 0.05}], dt)
        play(session, sorted(rest + press, key=lambda se: se[0]), end, SAMPLE_EVERY,
             sampler)
        passed, length, outcomes = judge(sampler, items)
        tried.append((off, passed, length, outcomes))
        session.handle(ev.action("restore"))
        if not quiet:
            print(f"l at +{off:.3f} s: {passed}/{len(items)} pass, jump {length:.3f} m",
                  flush=True)
    ok = [t for t in tried if t[1] == len(items)]
    if not ok:
        best = max(tried, key=lambda t: (t[1], t[2]))
        return None, best[3], best[0]
    runs, cur, step = [], [ok[0]], OFFSETS[1] - OFFSETS[0]
    for t in ok[1:]:
        if abs(t[0] - cur[-1][0] - step) < 1e-9:
            cur.append(t)
        else:
            runs.append(cur)
            cur = [t]
    runs.append(cur)
    longest = max(runs, key=len)
    mid = longest[len(longest) // 2]
    if not quiet:
        print(f"passing offsets: {', '.join(f'{r[0][0]:.3f}..{r[-1][0]:.3f}' for r in runs)}")
    return last + mid[0], mid[3], len(longest)


# -- the leap's poses (--poses) ---------------------------------------------------------
# name: (low, high, where in the interface); the legs' values go to both sides
BOUNDS = {
    "crouch_waist": (-60, 0), "crouch_hip": (50, 120), "crouch_knee": (-110, -30),
    "crouch_ankle": (10, 30), "crouch_ankle_k": (20, 200), "lean": (-60, -10),
    "crouch_hold": (0.15, 0.6), "push_waist": (-40, 20), "push_hip": (-30, 20),
    "push_ankle": (-45, 0), "push_k": (163, 1500), "waist_k": (98, 1000),
    "shoulder_k": (10, 200), "push_hold": (0.05, 0.25), "sail_waist": (-60, 30),
    "sail_hip": (-30, 130), "sail_knee": (-140, -10), "sail_hold": (0.05, 0.3),
    "land_waist": (-80, 0), "land_hip": (70, 130), "land_knee": (-60, 0),
    "squat_waist": (-80, 0), "squat_hip": (60, 130), "squat_knee": (-150, -60),
    "offset": (0.005, 0.375)}
SHIFTS = [-0.005, 0.0, 0.005]  # s: a try scores its worst of these press shifts


def read_poses(spec: dict, offset: float) -> dict:
    P, st = spec["poses"], spec["states"]
    return {
        "crouch_waist": P["crouch"]["joints"]["waist"],
        "crouch_hip": P["crouch"]["joints"]["hip_near"],
        "crouch_knee": P["crouch"]["joints"]["knee_near"],
        "crouch_ankle": P["crouch"]["joints"]["ankle_near"],
        "crouch_ankle_k": P["crouch"]["stiffness"]["ankle_near"],
        "lean": st["gather"]["transitions"][0]["when"]["below"],
        "crouch_hold": st["gather"]["transitions"][0]["after"],
        "push_waist": P["push"]["joints"]["waist"], "push_hip": P["push"]["joints"]["hip_near"],
        "push_ankle": P["push"]["joints"]["ankle_near"],
        "push_k": P["push"]["stiffness"]["hip_near"], "waist_k": P["push"]["stiffness"]["waist"],
        "shoulder_k": P["push"]["stiffness"]["shoulder_near"],
        "push_hold": st["push"]["transitions"][0]["after"],
        "sail_waist": P["sail"]["joints"]["waist"], "sail_hip": P["sail"]["joints"]["hip_near"],
        "sail_knee": P["sail"]["joints"]["knee_near"],
        "sail_hold": st["sail"]["transitions"][0]["after"],
        "land_waist": P["land"]["joints"]["waist"], "land_hip": P["land"]["joints"]["hip_near"],
        "land_knee": P["land"]["joints"]["knee_near"],
        "squat_waist": P["squat"]["joints"]["waist"],
        "squat_hip": P["squat"]["joints"]["hip_near"],
        "squat_knee": P["squat"]["joints"]["knee_near"], "offset": offset}


def with_poses(base: dict, p: dict) -> dict:
    spec = json.loads(json.dumps(base))
    P, st = spec["poses"], spec["states"]
    r = lambda v: round(v, 3)  # noqa: E731

    def legs(pose, **values):
        for joint, v in values.items():
            for side in ("near", "far"):
                P[pose]["joints"][f"{joint}_{side}"] = r(v)

    legs("crouch", hip=p["crouch_hip"], knee=p["crouch_knee"], ankle=p["crouch_ankle"])
    P["crouch"]["joints"]["waist"] = r(p["crouch_waist"])
    P["crouch"]["stiffness"].update(ankle_near=r(p["crouch_ankle_k"]),
                                    ankle_far=r(p["crouch_ankle_k"]), waist=r(p["waist_k"]))
    legs("push", hip=p["push_hip"], ankle=p["push_ankle"])
    P["push"]["joints"]["waist"] = r(p["push_waist"])
    P["push"]["stiffness"].update({f"{j}_{s}": r(p["push_k"]) for j in ("hip", "knee")
                                   for s in ("near", "far")})
    P["push"]["stiffness"].update(waist=r(p["waist_k"]), shoulder_near=r(p["shoulder_k"]),
                                  shoulder_far=r(p["shoulder_k"]))
    legs("sail", hip=p["sail_hip"], knee=p["sail_knee"])
    P["sail"]["joints"]["waist"] = r(p["sail_waist"])
    legs("land", hip=p["land_hip"], knee=p["land_knee"])
    P["land"]["joints"]["waist"] = r(p["land_waist"])
    legs("squat", hip=p["squat_hip"], knee=p["squat_knee"])
    P["squat"]["joints"]["waist"] = r(p["squat_waist"])
    st["gather"]["transitions"][0].update(after=round(p["crouch_hold"], 3),
                                          when={"sensor": "angle.shank_near",
                                                "below": r(p["lean"])})
    st["push"]["transitions"][0]["after"] = round(p["push_hold"], 3)
    st["sail"]["transitions"][0]["after"] = round(p["sail_hold"], 3)
    return spec


def shaped(text: str, press_offset: float) -> tuple[float, str]:
    """The --poses score of one whole performance (higher is better)."""
    entries, last = run_up()
    session = Session(setup_from_text(text, str(INTERFACE), WALK_SCENE, None))
    c = session.character
    rows = []

    def sample(s):
        rows.append(([c.in_contact(n) for n in c.link_order],
                     {n: c.bodies[n].local_to_world(c.bodies[n].center_of_gravity).x
                      for n in ("foot_near", "foot_far")}, c.bodies["chest"].angle,
                     c.bodies["head"].local_to_world(c.bodies["head"].center_of_gravity).y))

    dt = session.sim.dt
    play(session, pairs(script(entries, last + press_offset), dt),
         round((last + AFTER) / dt), SAMPLE_EVERY, sample)
    free = [not any(r[0]) for r in rows]
    best, run, first = 0, 0, 0
    for i, f in enumerate(free):
        run = run + 1 if f else 0
        if run > best:
            best, first = run, i - run + 1
    flight = best * SAMPLE_EVERY * dt
    if best < 6 or first == 0 or first + best >= len(rows):
        return -10.0 + flight, f"no jump (flight {flight:.2f} s)"
    names = list(c.link_order)
    before, after = rows[first - 1], rows[first + best]
    off = max(after[1][n] for n in after[1])  # the feet's x
    took = max([before[1][n] for n in ("foot_near", "foot_far")
                if before[0][names.index(n)]] or [off + 1.0])  # not off the feet: no jump
    touching = [n for n, t in zip(names, after[0]) if t]
    landed = min(after[1][n] for n in ("foot_near", "foot_far")
                 if n in touching) if set(touching) & {"foot_near", "foot_far"} else off
    feet_first = bool(touching) and all(n.startswith("foot") for n in touching)
    tilt = abs(math.degrees(math.remainder(rows[-1][2], 2 * math.pi)))
    head = min(r[3] for r in rows[-60:])  # the last 0.5 s
    most = max(abs(math.degrees(math.remainder(r[2], 2 * math.pi))) for r in rows)
    value = (min(landed - 1.0, 0.15) + min(-0.08 - took, 0.05) + 0.5 * min(landed - took, 1.4)
             + min(flight, 0.35) + (0.5 if feet_first else 0.0) - 0.05 * max(0.0, tilt - 40)
             - 5 * max(0.0, 0.35 - head) - 0.05 * max(0.0, most - 70))
    return value, (f"off at x {took:.3f}, down at {landed:.3f} ({', '.join(touching)}), "
                   f"flight {flight:.2f} s, chest {tilt:.0f} deg (at most {most:.0f}), "
                   f"head {head:.2f} m at the end")


def worst(base: dict, p: dict) -> tuple[float, str]:
    """``shaped`` at its worst over the press and the press 5 ms earlier and later."""
    text = yaml.safe_dump(with_poses(base, p))
    return min(shaped(text, p["offset"] + d) for d in SHIFTS)


def search_poses(base: dict, tries: int, seed: int, offset: float) -> dict:
    rng = random.Random(seed)
    best_p = read_poses(base, offset)
    best, what = worst(base, best_p)
    print(f"the interface's own: {best:.3f} ({what})", flush=True)
    for i in range(tries):
        spread = 0.06 if i < 2 * tries // 3 else 0.02
        p = {k: min(hi, max(lo, best_p[k] + rng.gauss(0, spread * (hi - lo))))
             for k, (lo, hi) in BOUNDS.items()}
        value, what = worst(base, p)
        if value > best:
            best, best_p = value, p
            print(f"try {i}: {value:.3f} ({what})", flush=True)
    spec = with_poses(base, best_p)
    print(yaml.safe_dump({"poses": {n: spec["poses"][n] for n in ("crouch", "push", "sail",
                                                                 "land", "squat")},
                          "states": {n: spec["states"][n] for n in ("gather", "push",
                                                                    "sail")},
                          "offset": round(best_p["offset"], 3)},
                         sort_keys=False, default_flow_style=None))
    return spec


# -- the run-up (--run) ------------------------------------------------------------------
# The run-up's performance: the mouse parked at (mouse_x, RUN_Y) - past 0.68 the legs
# run by themselves (the run states) - space at RUN_START to start, a checkpoint one
# step (CHECK_BEFORE s) before the leap, l at 'press'.
RUN_Y = 0.9
RUN_START = 0.5
CHECK_BEFORE = 0.25
RUN_BOUNDS = {
    "mouse_x": (0.7, 1.0), "press": (3.0, 6.0), "run_hold": (0.04, 0.1),
    "rpush_hold": (0.03, 0.08), "run_knee_k": (80, 250), "run_push_k": (80, 250),
    "run_lean": (-20, 20),
    "to_waist": (-40, 20), "to_hip": (-45, 10), "to_knee": (-20, 0), "to_ankle": (-45, 0),
    "to_swing_hip": (20, 110), "to_swing_knee": (-130, -20), "to_k": (150, 1500),
    "to_swing_k": (50, 800), "to_hold": (0.05, 0.25),
    **{k: BOUNDS[k] for k in ("sail_waist", "sail_hip", "sail_knee", "sail_hold",
                              "land_waist", "land_hip", "land_knee", "squat_waist",
                              "squat_hip", "squat_knee")}}


def run_entries(p: dict) -> list[dict]:
    """The run-up performance of ``p`` (mouse_x, press) as script entries."""
    r = lambda v: round(v, 3)  # noqa: E731
    return [{"t": 0.2, "mouse": [r(p["mouse_x"]), RUN_Y]},
            {"t": RUN_START, "key": "space", "hold": 0.05},
            {"t": r(p["press"] - CHECK_BEFORE), "action": "checkpoint"},
            {"t": r(p["press"]), "key": "l", "hold": 0.05}]


# the run's landing poses and holds: (pose, joint) for the legs (near and far alike)
RUN_LEGS = {"sail_hip": ("rsail", "hip"), "sail_knee": ("rsail", "knee"),
            "land_hip": ("rland", "hip"), "land_knee": ("rland", "knee"),
            "squat_hip": ("rsquat", "hip"), "squat_knee": ("rsquat", "knee")}
RUN_WAIST = {"sail_waist": "rsail", "land_waist": "rland", "squat_waist": "rsquat"}


def read_run(spec: dict, mouse_x: float, press: float) -> dict:
    P, st = spec["poses"], spec["states"]
    to, tk = P["takeoff"]["joints"], P["takeoff"]["stiffness"]
    p = {k: P[pose]["joints"][f"{joint}_near"] for k, (pose, joint) in RUN_LEGS.items()}
    p.update({k: P[pose]["joints"]["waist"] for k, pose in RUN_WAIST.items()})
    p.update(mouse_x=mouse_x, press=press,
             run_hold=st["run_near"]["transitions"][1]["after"],
             rpush_hold=st["rpush_near"]["transitions"][0]["after"],
             run_knee_k=P["run_stance"]["stiffness"]["stance_knee"],
             run_push_k=P["run_push"]["stiffness"]["stance_knee"],
             run_lean=P["run_stance"]["joints"]["waist"]["world"],
             to_waist=to["waist"]["world"], to_hip=to["stance_hip"]["world"],
             to_knee=to["stance_knee"], to_ankle=to["stance_ankle"],
             to_swing_hip=to["swing_hip"]["world"], to_swing_knee=to["swing_knee"],
             to_k=tk["stance_hip"], to_swing_k=tk["swing_hip"],
             to_hold=st["leap_near"]["transitions"][0]["after"],
             sail_hold=st["rsail"]["transitions"][-1]["after"])  # the tuck's longest
    return p


def with_run(base: dict, p: dict) -> dict:
    spec = json.loads(json.dumps(base))
    P, st = spec["poses"], spec["states"]
    r = lambda v: round(v, 3)  # noqa: E731
    for k, (pose, joint) in RUN_LEGS.items():
        for side in ("near", "far"):
            P[pose]["joints"][f"{joint}_{side}"] = r(p[k])
    for k, pose in RUN_WAIST.items():
        P[pose]["joints"]["waist"] = r(p[k])
    for side in ("near", "far"):
        for armed in ("", "a"):  # the run and its armed copy (l pressed) keep one rhythm
            st[f"{armed}run_{side}"]["transitions"][-1]["after"] = r(p["run_hold"])
            st[f"{armed}rpush_{side}"]["transitions"][0]["after"] = r(p["rpush_hold"])
        st[f"leap_{side}"]["transitions"][0]["after"] = r(p["to_hold"])
    st["rsail"]["transitions"][-1]["after"] = r(p["sail_hold"])
    P["run_stance"]["stiffness"]["stance_knee"] = r(p["run_knee_k"])
    P["run_push"]["stiffness"].update(stance_knee=r(p["run_push_k"]),
                                      stance_ankle=r(p["run_push_k"]))
    P["run_stance"]["joints"]["waist"] = {"world": r(p["run_lean"])}
    P["takeoff"]["joints"].update(
        waist={"world": r(p["to_waist"])}, stance_hip={"world": r(p["to_hip"])},
        stance_knee=r(p["to_knee"]), stance_ankle=r(p["to_ankle"]),
        swing_hip={"world": r(p["to_swing_hip"])}, swing_knee=r(p["to_swing_knee"]))
    P["takeoff"]["stiffness"].update(stance_hip=r(p["to_k"]), stance_knee=r(p["to_k"]),
                                     swing_hip=r(p["to_swing_k"]))
    return spec


def run_traj(text: str, entries: list[dict]):
    """The performance played through the real Session and sampled as replay does."""
    session = Session(setup_from_text(text, str(INTERFACE), None, None))
    dt = session.sim.dt
    sampler = Sampler(session)
    sampler(session)
    end = max(e["t"] for e in entries) + AFTER
    play(session, pairs(entries, dt), round(end / dt), SAMPLE_EVERY, sampler)
    return sampler.trajectory()


JUMP = {"run_up", "took_off", "first_touch"}


def run_score(traj, items) -> tuple[float, str]:
    """The --run score of one sampled performance (higher is better): the log's
    expectations met, ten points each, and how near each is to its bound."""
    outcomes = evaluate_all(items, traj, "")
    passed = sum(o.passed for o in outcomes)
    # the run-up, the take-off and the landing count most: sitting still passes the rest
    points = sum((10 if o.kind in JUMP else 3) * o.passed
                 for o in outcomes)
    free = ~traj.contact.any(axis=1)
    best, first = longest_flight(free)
    dt = float(traj.t[1] - traj.t[0])
    flight = best * dt
    if best < 6 or first == 0 or first + best >= len(free):
        return points - 10.0 + flight, f"{passed}/{len(items)}, no jump"
    feet = [traj.index("foot_near"), traj.index("foot_far")]
    b, a = first - 1, first + best
    took = max([traj.x[b, k] for k in feet if traj.contact[b, k]] or [traj.x[b].max() + 1])
    landed = min([traj.x[a, k] for k in feet if traj.contact[a, k]] or [took])
    touching = set(np.flatnonzero(traj.contact[a]).tolist())
    feet_first = bool(touching) and touching <= set(feet)
    chest = traj.index("chest")
    tilt = np.degrees(np.abs(np.remainder(traj.angle[:, chest] + np.pi, 2 * np.pi) - np.pi))
    head = traj.y[-60:, traj.index("head")].min()
    i0 = int(np.searchsorted(traj.t, traj.t[first] - 1.0))
    speed = float((traj.com[first, 0] - traj.com[i0, 0]) / (traj.t[first] - traj.t[i0]))
    value = (points + min(landed - 1.0, 0.15) + 2 * min(-0.08 - took, 0.05)
             + 0.5 * min(landed - took, 1.4) + min(flight, 0.35)
             + (0.5 if feet_first else 0.0) - 0.05 * max(0.0, tilt[-1] - 40)
             - 5 * max(0.0, 0.35 - head) - 0.05 * max(0.0, tilt.max() - 70)
             + 2 * min(speed - 1.5, 0.4))
    return value, (f"{passed}/{len(items)}: off at x {took:.3f}, down at {landed:.3f}, "
                   f"flight {flight:.2f} s, {speed:.2f} m/s, chest {tilt[-1]:.0f} deg (at "
                   f"most {tilt.max():.0f}), head {head:.2f} m")


def run_worst(base: dict, p: dict, items) -> tuple[float, str]:
    """``run_score`` at its worst over the press moved by SHIFTS."""
    text = yaml.safe_dump(with_run(base, p))
    return min(run_score(run_traj(text, run_entries(dict(p, press=p["press"] + d))), items)
               for d in SHIFTS)


def search_run(base: dict, tries: int, seed: int, mouse_x: float, press: float,
               items, uniform: int = 0) -> dict:
    rng = random.Random(seed)
    best_p = read_run(base, mouse_x, press)
    best, what = run_worst(base, best_p, items)
    print(f"the interface's own: {best:.3f} ({what})", flush=True)
    for i in range(tries):
        spread = 0.06 if i < 2 * tries // 3 else 0.02
        if i < uniform:  # random tries first, over the whole ranges
            p = {k: rng.uniform(lo, hi) for k, (lo, hi) in RUN_BOUNDS.items()}
        else:
            p = {k: min(hi, max(lo, best_p[k] + rng.gauss(0, spread * (hi - lo))))
                 for k, (lo, hi) in RUN_BOUNDS.items()}
        value, what = run_worst(base, p, items)
        if value > best:
            best, best_p = value, p
            print(f"try {i}: {value:.3f} ({what}) mouse_x {p['mouse_x']:.3f} "
                  f"press {p['press']:.3f}", flush=True)
    spec = with_run(base, best_p)
    print(yaml.safe_dump({"poses": {n: spec["poses"][n] for n in (
        "takeoff", "rsail", "rland", "rsquat", "run_stance", "run_push")},
        "states": {n: spec["states"][n] for n in ("rsail", "run_near", "rpush_near",
                                                  "leap_near")},
        "mouse_x": round(best_p["mouse_x"], 3), "press": round(best_p["press"], 3)},
        sort_keys=False, default_flow_style=None))
    return best_p


LEAP_KEYS = [k for k in RUN_BOUNDS if k.startswith(("to_", "sail_", "land_", "squat_"))]


def search_leap(base: dict, tries: int, seed: int, mouse_x: float, check_at: float,
                offset: float, items, values: str = "", save: str = "",
                lo_off: float = 0.0, presses: list[float] = ()) -> dict:
    """--leap: the take-off and the landing (LEAP_KEYS) and the press, the run-up as
    the file has it: played once to a checkpoint at ``check_at`` (as the script takes
    it), then every try restores it, reloads the interface with its numbers (the
    "reload" event: the run's states are the same, so the run-up is too) and presses l
    ``offset`` s later (searched in 0..0.6 s)."""
    rng = random.Random(seed)
    text = yaml.safe_dump(base)
    session = Session(setup_from_text(text, str(INTERFACE), None, None))
    dt = session.sim.dt
    sampler = Sampler(session)
    sampler(session)
    lead = run_entries({"mouse_x": mouse_x, "press": check_at + 1.0})[:2]  # mouse, space
    mark = round(check_at / dt)
    play(session, pairs(lead, dt), mark, SAMPLE_EVERY, sampler)
    session.handle(ev.action("checkpoint"))
    bounds = {k: RUN_BOUNDS[k] for k in LEAP_KEYS}
    bounds["offset"] = (lo_off, 0.6)
    if presses:  # the presses given, not searched
        del bounds["offset"]

    def one(p: dict, at: float) -> tuple[float, str]:
        spec = with_run(base, dict(read_run(base, mouse_x, 0.0), **p))
        session.reload(yaml.safe_dump(spec))
        press = pairs([{"t": round(at, 3), "key": "l", "hold": 0.05}], dt)
        play(session, press, round((at + AFTER) / dt), SAMPLE_EVERY, sampler)
        got = run_score(sampler.trajectory(), items)
        session.handle(ev.action("restore"))
        return got

    def score(p: dict) -> tuple[float, str]:
        if not presses:
            return one(p, check_at + p["offset"])
        got = [one(p, at) for at in presses]  # their mean, and the worst one's story
        return sum(g[0] for g in got) / len(got), min(got)[1]

    start = read_run(base, mouse_x, 0.0)
    best_p = {k: start[k] for k in LEAP_KEYS}
    best_p["offset"] = offset
    if values:  # a --save'd try: its numbers, its press
        got = json.loads(Path(values).read_text())
        best_p.update({k: got[k] for k in LEAP_KEYS})
        best_p["offset"] = min(max(got["press"] - check_at, lo_off), 0.6)
    if presses:
        best_p.pop("offset")
    best, what = score(best_p)
    print(f"the interface's own: {best:.3f} ({what})", flush=True)
    for i in range(tries):
        spread = 0.08 if i < 2 * tries // 3 else 0.03
        p = {k: min(hi, max(lo, best_p[k] + rng.gauss(0, spread * (hi - lo))))
             for k, (lo, hi) in bounds.items()}
        value, what = score(p)
        if value > best:
            best, best_p = value, p
            print(f"try {i}: {value:.3f} ({what})", flush=True)
            if save:
                Path(save).write_text(json.dumps(dict(p, press=check_at + p.get("offset", 0))))
        if i % 50 == 49:
            print(f"({i + 1} tries)", flush=True)
    spec = with_run(base, dict(read_run(base, mouse_x, 0.0), **best_p))
    print(yaml.safe_dump({"poses": {n: spec["poses"][n] for n in (
        "takeoff", "rsail", "rland", "rsquat")},
        "states": {n: spec["states"][n] for n in ("rsail", "leap_near")},
        "press": round(check_at + best_p.get("offset", 0.0), 3)},
        sort_keys=False, default_flow_style=None))
    return best_p


def robustness(text: str, items, mouse_x: float, check_at: float, press: float,
               starts: list[float], presses: list[float], mice: list[float]) -> int:
    """--robust: the run-up performance with space moved by each of ``starts`` (the
    checkpoint and l with it), l moved by each of ``presses`` more, the mouse's x each of
    ``mice``: each played whole and judged by the log's expectations. Prints each and
    the count that pass every one; returns that count."""
    ok = total = 0
    for mx in mice:
        for d in starts:
            row = []
            for e in presses:
                entries = [{"t": 0.2, "mouse": [mx, RUN_Y]},
                           {"t": round(RUN_START + d, 3), "key": "space", "hold": 0.05},
                           {"t": round(check_at + d, 3), "action": "checkpoint"},
                           {"t": round(press + d + e, 3), "key": "l", "hold": 0.05}]
                outcomes = evaluate_all(items, run_traj(text, entries), "")
                passed = all(o.passed for o in outcomes)
                ok, total = ok + passed, total + 1
                row.append("pass" if passed else ",".join(
                    o.kind for o in outcomes if not o.passed))
            print(f"mouse x {mx:g}, space {d:+.3f} s: " + " | ".join(
                f"l {e:+.3f}: {r}" for e, r in zip(presses, row)), flush=True)
    print(f"{ok} of {total} pass")
    return ok


def robustness_with_checkpoint(text: str, items, mouse_x: float, check_at: float,
                               runs: list[tuple[float, float]], span: float = 0.6) -> int:
    """--robust --retry: for each (mouse x, space moved by d) run-up, what a person with
    the checkpoint does: from it (check_at + d) l at every 10 ms of the next ``span`` s, each
    judged by the log's expectations. Prints the passing presses of each run-up; returns
    how many run-ups have at least one."""
    some = 0
    offsets = OFFSETS[:]
    OFFSETS[:] = [round(0.01 * i, 3) for i in range(round(span / 0.01) + 1)]
    try:
        for mx, d in runs:
            lead = [{"t": 0.2, "mouse": [mx, RUN_Y]},
                    {"t": round(RUN_START + d, 3), "key": "space", "hold": 0.05},
                    {"t": round(check_at + d, 3), "action": "checkpoint"}]
            press, _, width = search_press(text, items, lead, check_at + d, RUN_SCENE,
                                           quiet=True)
            some += press is not None
            print(f"mouse x {mx:g}, space {d:+.3f} s: "
                  + (f"{width} passing presses in a row (10 ms apart), the middle at "
                     f"{press:.3f} s" if press is not None else "no press passes"),
                  flush=True)
    finally:
        OFFSETS[:] = offsets
    print(f"{some} of {len(runs)} run-ups have a passing press")
    return some


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--poses", type=int, default=0, metavar="N",
                    help="search the leap's poses with N tries (prints YAML to paste)")
    ap.add_argument("--seed", type=int, default=8)
    ap.add_argument("--offset", type=float, default=0.38,
                    help="--poses: the press after the last swap to start from, s")
    ap.add_argument("--shifts", type=float, nargs="*", default=list(SHIFTS),
                    help="--poses: a try scores its worst over the press moved by these s")
    ap.add_argument("--run", type=int, default=0, metavar="N",
                    help="search the run-up and the leap with N tries (prints YAML to paste)")
    ap.add_argument("--mouse-x", type=float, default=1.0, help="--run: the mouse's x to start from")
    ap.add_argument("--press", type=float, default=4.8, help="--run: the l press to start from, s")
    ap.add_argument("--leap", type=int, default=0, metavar="N",
                    help="search the run's take-off and landing with N tries from a "
                         "checkpoint at --check-at (prints YAML to paste)")
    ap.add_argument("--check-at", type=float, default=3.5,
                    help="--leap: the script's checkpoint, s")
    ap.add_argument("--values", default="", help="--leap: start from this --save'd JSON")
    ap.add_argument("--save", default="", help="--leap: write the best try here (JSON)")
    ap.add_argument("--min-offset", type=float, default=0.0,
                    help="--leap: the press at least this long after the checkpoint, s")
    ap.add_argument("--robust", action="store_true",
                    help="play the run-up log's performance with space, l and the mouse "
                         "moved around the log's (--mouse-x, --check-at, --press)")
    ap.add_argument("--presses", type=float, nargs="*", default=[],
                    help="--leap: score each try by its mean over l at these times (s), "
                         "the press not searched")
    ap.add_argument("--retry", action="store_true",
                    help="--robust: for each run-up, every press from its checkpoint")
    ap.add_argument("--span", type=float, default=0.6,
                    help="--robust --retry: the presses tried after the checkpoint, s")
    ap.add_argument("--run-up", action="store_true",
                    help="the run-up log's press (biped-longjump-run) from its checkpoint "
                         "at --check-at, not the walk-up's")
    ap.add_argument("--random", type=int, default=0, metavar="K",
                    help="--run: the first K tries at random over the whole ranges")
    ap.add_argument("--write", default="", help="write the script here")
    a = ap.parse_args(argv)
    text = INTERFACE.read_text(encoding="utf-8")
    SHIFTS[:] = a.shifts
    if a.robust and a.retry:
        robustness_with_checkpoint(
            text, load_expectations(RUN_LOG, {}).items, a.mouse_x, a.check_at,
            [(a.mouse_x, d) for d in (-0.1, -0.05, -0.02, 0.0, 0.02, 0.05, 0.1)]
            + [(a.mouse_x - 0.03, d) for d in (-0.05, 0.0, 0.05)], a.span)
        return 0
    if a.robust:
        robustness(text, load_expectations(RUN_LOG, {}).items, a.mouse_x, a.check_at,
                   a.press, [-0.1, -0.05, -0.02, 0.0, 0.02, 0.05, 0.1],
                   [-0.02, -0.01, 0.0, 0.01, 0.02], [a.mouse_x, a.mouse_x - 0.03])
        return 0
    if a.leap:
        items = load_expectations(RUN_LOG, {}).items
        search_leap(yaml.safe_load(text), a.leap, a.seed, a.mouse_x, a.check_at,
                    a.offset, items, a.values, a.save, a.min_offset, a.presses)
        return 0
    if a.run:
        items = load_expectations(RUN_LOG, {}).items
        search_run(yaml.safe_load(text), a.run, a.seed, a.mouse_x, a.press, items, a.random)
        return 0
    if a.poses:
        search_poses(yaml.safe_load(text), a.poses, a.seed, a.offset)
        return 0
    if a.run_up:  # the run-up log's press, from its checkpoint
        items = load_expectations(RUN_LOG, {}).items
        lead = run_entries({"mouse_x": a.mouse_x, "press": a.check_at + CHECK_BEFORE})[:3]
        press, outcomes, width = search_press(text, items, lead, a.check_at, RUN_SCENE)
    else:
        items = load_expectations(LOG, {}).items
        press, outcomes, width = search_press(text, items)
    for o in outcomes:
        print(o)
    if press is None:
        print("no press passes every expectation (the closest above)")
        return 1
    print(f"l at {press:.3f} s ({width} passing offsets in a row, 5 ms apart)")
    if a.write and a.run_up:
        Path(a.write).write_text(yaml.safe_dump({
            "description": "The small figure runs up to the take-off line (the mouse parked "
                           f"at ({a.mouse_x:g}, {RUN_Y:g}), past x 0.68: the run states; "
                           "space starts it), the script checkpointing one stride before "
                           "the leap, then takes off from one foot (l) into the sand pit "
                           "and lands feet first, sitting.",
            "interface": "biped-longjump", "scene": RUN_SCENE,
            "seconds": round(press + AFTER, 2),
            "events": run_entries({"mouse_x": a.mouse_x, "press": a.check_at + CHECK_BEFORE})[:3]
            + [{"t": round(press, 3), "key": "l", "hold": 0.05}]}, sort_keys=False),
            encoding="utf-8")
    elif a.write:
        entries, _ = run_up()
        Path(a.write).write_text(yaml.safe_dump({
            "description": "The small figure walks up to the take-off line in seven strides "
                           "(the mouse and space, the walk interface), the script "
                           "checkpointing one step before the leap, then leaps (l) into the "
                           "sand pit and lands feet first, sitting.",
            "interface": "biped-longjump", "scene": "biped-longjump",
            "seconds": round(press + AFTER, 2),
            "events": script(entries, press)}, sort_keys=False), encoding="utf-8")
    return 0


if __name__ == "__main__":
    sys.exit(main())
