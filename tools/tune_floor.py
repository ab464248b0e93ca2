"""Search the floor feats of interfaces/biped-floor.yaml on their logs' own expectations
and print the numbers found (to paste into the interface and the script).

    python tools/tune_floor.py FEAT [--tries 300] [--seed 1] [--sigma 0.05] [--random 0.3]
    FEAT: handstand, backflip, kip

A feat is a script (assets/scripts/biped-FEAT.yaml: the keys a person presses) and the
numbers of the interface's poses, sequences and state maps it uses. A try is the
interface and script with other numbers (each rounded as it is written in the files, so
the numbers printed replay to the same bits as the try), played through the real
Session from the start: the numbers are the interface's, so there is no checkpoint to
start a try from (a handstand try is about 9 s of simulation, a few tenths of a second
here). A try is scored on assets/logs/biped-FEAT.expect.yaml: every expectation that
holds counts 10, and the feat adds a graded term on the same quantity (the handstand:
the longest stretch on the hands alone, upside down, feet above the head) so that the
search climbs towards it. The search starts from the files' own numbers, then tries
either a step from the best (``--sigma``, a share of each range) or (``--random``) a
fresh random point. Seeded: the same arguments find the same numbers. The best is then
recorded as a log in a temporary folder and replayed with the log's real expectations
(exit 1 if they fail).

The shipped handstand: ``python tools/tune_floor.py handstand --tries 14 --seed 1``
started from an earlier draft's numbers (themselves from a cruder search of the same
poses, 550 tries) and found the shipped ones at try 13 (4.02 s on the hands); with them
in the files, ``--tries 0`` replays them and passes, and then

    puppet play biped-floor --headless --input biped-handstand --record assets/logs/biped-handstand.jsonl

records the log (the same end hash as the tool's replay).

The back flip (no log yet; its target expectations are in
tools/targets/biped-backflip.expect.yaml): a gated score (its other expectations count
only once the turn in flight holds, or standing still would win); the take-off pose's
leg damping is searched too (the character's 50 N*m*s/rad brake legs straightening at
10-15 rad/s). Three runs of this search, each from the last one's best (run with a copy
of this file that also printed the numbers at each improvement) (--seed 4 --tries 1367 --random 0.5 --sigma 0.08, then from
its best --seed 5 --tries 1500 --random 0.1 --sigma 0.04, then --seed 6 --random 0
--sigma 0.06 for 270 s) gave the interface's flip poses: 326 deg backward in a 0.56 s
flight, landing on both feet in a crouch; it then pitches forward (146 deg on the
ground) and ends sitting, so never_fell and height_at_end fail. Standing up from the
landing is what is left.

The kip (interfaces/biped-kip.yaml, its own interface: the figure starts lying on its
back) searches the rock, snap and landing poses, their damping, the three holds and the
hips' torque cap; only a flight that ends on the feet counts (a gate on flight_phases
and first_touch), and the graded term is the flight (to 0.3 s), how near upright the
trunk ends and the head's height at the end. ``--seed 3 --tries 1500 --random 0.4
--sigma 0.08`` from a hand-made start (rock -60/130/-100, snap arched, 0.4 and 0.3 s)
stood at try 974 (its expectations then had the front check without a max and
lay_seconds 0.5, which the rock past upside down and its short last lie failed);
``--seed 4 --tries 800
--random 0.1 --sigma 0.04`` from there, on the log's expectations, passed all at try 112: the shipped numbers
(``--tries 0`` replays them; the interface's state rising, biped-recover's ankle
maps, came after: with them 14 of 40 press times 50 ms apart stand, 3 without, so the
script presses k at 1.3 s, in the longest run that stands), recorded with

    puppet play biped-kip --headless --input biped-kip --record assets/logs/biped-kip.jsonl

It takes off from the head. A push from the hands was tried with a copy of this feat
whose rock and snap held the upper arms in the world ({world: 120..260}) and whose
expectations added took_off from the forearms and upper arms alone (gated with the
flight and the feet first): --seed 5 --tries 2000 --random 0.5 and --seed 6 --tries
2000 --random 0.2 from its best found 0.31 s flights from the hands that land on the
feet, but every one falls back (ends lying, 143 deg); 1500 tries around the shipped
numbers (--random 0.1 --sigma 0.05) rewarding the forearms touching at the take-off
found none.
"""

from __future__ import annotations

import argparse
import json
import random
import re
import sys
import tempfile
from pathlib import Path

import yaml

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from puppet.data.catalog import ROOT, setup_from_text  # noqa: E402
from puppet.session import Session  # noqa: E402
from puppet.testing import replay_log  # noqa: E402
from puppet.timeline.expectations import evaluate_all, parse_expectations  # noqa: E402
from puppet.timeline.log import record_events  # noqa: E402
from puppet.timeline.playback import play  # noqa: E402
from puppet.timeline.replay import SAMPLE_EVERY, Sampler  # noqa: E402
from puppet.timeline.script import ScriptSpec, compile_script  # noqa: E402

INTERFACE = ROOT / "interfaces" / "biped-floor.yaml"

# A parameter: (low, high, decimals, [where]); a place is a path into the interface
# ("i", ...) or the script ("s", ...); a path ending in "+-" writes [v, -v] there.
HS = "handstand"


def _pose(short: str, pose: str, **ranges) -> dict:
    """Parameters for a pose's joints, the same on both sides (waist and neck alone)."""
    out = {}
    for joint, (lo, hi) in ranges.items():
        names = [joint] if joint in ("waist", "neck") else [f"{joint}_near", f"{joint}_far"]
        out[f"{short}_{joint}"] = (lo, hi, 0, [("i", "poses", pose, "joints", n)
                                               for n in names])
    return out


def _world(short: str, pose: str, **ranges) -> dict:
    """The same for world targets ({world: A} or {world: A, hold: parent})."""
    out = _pose(short, pose, **ranges)
    for lo, hi, dec, places in out.values():
        places[:] = [place + ("world",) for place in places]
    return {f"{n}_world": v for n, v in out.items()}

FEATS = {
    "handstand": {
        "params": {
            "down_waist": (-40, 0, 0, [("i", "poses", "hands_down", "joints", "waist")]),
            "down_hip": (60, 130, 0, [("i", "poses", "hands_down", "joints", j)
                                      for j in ("hip_near", "hip_far")]),
            "down_knee": (-90, 0, 0, [("i", "poses", "hands_down", "joints", j)
                                      for j in ("knee_near", "knee_far")]),
            "down_ankle": (-20, 20, 0, [("i", "poses", "hands_down", "joints", j)
                                        for j in ("ankle_near", "ankle_far")]),
            "down_shoulder": (40, 120, 0, [("i", "poses", "hands_down", "joints", j)
                                           for j in ("shoulder_near", "shoulder_far")]),
            "over_waist": (-80, 0, 0, [("i", "poses", "hips_over", "joints", "waist")]),
            "over_hip": (80, 130, 0, [("i", "poses", "hips_over", "joints", j)
                                      for j in ("hip_near", "hip_far")]),
            "over_knee": (-40, 0, 0, [("i", "poses", "hips_over", "joints", j)
                                      for j in ("knee_near", "knee_far")]),
            "over_chest": (-170, -120, 0, [("i", "poses", "hips_over", "joints", j, "world")
                                           for j in ("shoulder_near", "shoulder_far")]),
            "hs_hip": (-30, 20, 0, [("i", "poses", HS, "joints", j)
                                    for j in ("hip_near", "hip_far")]),
            "hs_chest": (-200, -165, 0, [("i", "poses", HS, "joints", "shoulder_near",
                                          "world")]),
            "hs_far_arm": (130, 180, 0, [("i", "poses", HS, "joints", "shoulder_far")]),
            "t_down": (0.5, 1.6, 3, [("i", "sequences", "press", 0, "hold")]),
            "t_over": (0.2, 1.0, 3, [("i", "sequences", "press", 1, "hold")]),
            "gain_dx": (0, 30, 2, [("i", "states", HS, "maps", 0, "to", "+-")]),
            "gain_vx": (0, 40, 2, [("i", "states", HS, "maps", 1, "to", "+-")]),
            "t_up": (2.0, 3.5, 3, [("s", "events", 1, "t")]),
        },
    },
    "kip": {"interface": "biped-kip", "gate": [2, 3], "params": {
        "hip_torque": (250, 450, 0, [("i", "gains", j, "max_torque")
                                     for j in ("hip_near", "hip_far")]),
        **_pose("rock", "rock", waist=(-80, 0), hip=(90, 130), knee=(-150, 0),
                shoulder=(120, 180), elbow=(60, 150)),
        "rock_damp": (1, 30, 1, [("i", "poses", "rock", "damping", j) for j in (
            "hip_near", "hip_far", "knee_near", "knee_far", "waist")]),
        **_pose("snap", "snap", waist=(-20, 30), hip=(-30, 60), knee=(-90, 0),
                shoulder=(90, 180), elbow=(0, 60)),
        "snap_damp": (1, 30, 1, [("i", "poses", "snap", "damping", j) for j in (
            "hip_near", "hip_far", "knee_near", "knee_far", "waist")]),
        **_world("land", "kip_land", waist=(-70, 0), hip=(-70, 0), ankle=(-40, 0)),
        **_pose("land", "kip_land", knee=(-150, -60), shoulder=(0, 120)),
        "land_damp": (1, 50, 1, [("i", "poses", "kip_land", "damping", j) for j in (
            "hip_near", "hip_far", "knee_near", "knee_far")]),
        **{f"t_{n}": (lo, hi, 3, [("i", "sequences", "kip", k, "hold")])
           for k, (n, lo, hi) in enumerate((("rock", 0.2, 1.2), ("snap", 0.05, 0.5),
                                            ("land", 0.2, 1.2)))},
    }},
    "backflip": {"gate": True, "params": {
        **_world("set", "flip_set", waist=(-60, 0), hip=(-60, 0), ankle=(-40, 0)),
        **_pose("set", "flip_set", knee=(-140, -40), shoulder=(-60, 60)),
        **_world("jump", "flip_jump", waist=(-20, 40), hip=(-20, 40)),
        **_pose("jump", "flip_jump", knee=(-30, 0), ankle=(-45, 0), shoulder=(60, 180)),
        **_pose("tuck", "flip_tuck", waist=(-60, 0), hip=(80, 130), knee=(-150, -60),
                shoulder=(0, 120)),
        **_pose("land", "flip_land", waist=(-40, 10), hip=(0, 100), knee=(-100, 0),
                shoulder=(0, 120)),
        "jump_damp": (1, 20, 1, [("i", "poses", "flip_jump", "damping", j) for j in (
            "hip_near", "hip_far", "knee_near", "knee_far", "ankle_near", "ankle_far")]),
        **{f"t_{n}": (lo, hi, 3, [("i", "sequences", "backflip", k, "hold")])
           for k, (n, lo, hi) in enumerate((("set", 0.3, 1.2), ("jump", 0.08, 0.4),
                                            ("tuck", 0.15, 0.8), ("land", 0.1, 1.0)))},
    }},
}


def graded(feat: str, outcomes) -> float:
    """The feat's slope: the handstand's seconds on the hands (what balanced_on
    measures), a flip's turn in flight (turned ... in flight, per 100 deg), a kip's
    longest flight (per 0.1 s, to 0.3 s), how near upright its trunk ends (per 60 deg)
    and its head's lowest height over the last second (to 1.45 m)."""
    if feat == "kip":
        value = 0.0
        for o in outcomes:
            m = re.search(r"the longest ([0-9.]+) s", o.measured)
            if o.expectation.startswith("flight_phases") and m:
                value += min(float(m.group(1)), 0.3) * 10
            m = re.search(r"at most ([0-9.]+) deg from upright", o.measured)
            if o.expectation.startswith("tilt_at_end") and m:
                value += (180 - float(m.group(1))) / 60
            m = re.search(r"y = (-?[0-9.]+)\.\.", o.measured)
            if o.expectation.startswith("height_at_end") and m:
                value += min(float(m.group(1)), 1.45) * 2
        return value
    for o in outcomes:
        if o.expectation.startswith("balanced_on"):
            m = re.search(r"upside down: ([0-9.]+) s", o.measured)
            return float(m.group(1)) if m else 0.0
        if o.expectation.startswith("turned") and "in flight" in o.expectation:
            m = re.search(r"turned (-?[0-9.]+) deg", o.measured)
            return min(float(m.group(1)), 360.0) / 100 if m else 0.0
    return 0.0


def get(doc, path):
    for k in path:
        doc = doc[k]
    return doc


def put(docs: dict, place, value) -> None:
    where, *path = place
    if path[-1] == "+-":
        get(docs[where], path[:-2])[path[-2]] = [value, -value if value else 0.0]
    else:
        get(docs[where], path[:-1])[path[-1]] = value


def read(docs: dict, place):
    where, *path = place
    if path[-1] == "+-":
        return get(docs[where], path[:-1])[0]
    return get(docs[where], path)


def with_params(docs: dict, params: dict, p: dict) -> dict:
    out = json.loads(json.dumps(docs))
    for name, (lo, hi, dec, places) in params.items():
        v = round(p[name], dec) if dec else int(round(p[name]))
        for place in places:
            put(out, place, v)
    return out


def run(docs: dict, expect: list):
    """Play the script into a Session of the interface; the outcomes of ``expect``."""
    session = Session(setup_from_text(yaml.safe_dump(docs["i"], sort_keys=False),
                                      str(INTERFACE), docs["s"].get("scene"), None))
    spec = ScriptSpec.model_validate(docs["s"])
    sampler = Sampler(session)
    sampler(session)
    play(session, compile_script(spec, session.sim.dt),
         round(docs["s"]["seconds"] / session.sim.dt), SAMPLE_EVERY, sampler)
    return evaluate_all(parse_expectations(expect).items, sampler.trajectory(), "")


def score(feat: str, docs: dict, expect: list, shifts=(0.0,)) -> tuple[float, list]:
    """10 per expectation that holds plus the graded term, at the worst of the script
    played with its last key moved by each of ``shifts`` s (a person's timing)."""
    worst = None
    for by in shifts:
        moved = json.loads(json.dumps(docs))
        moved["s"]["events"][-1]["t"] = round(moved["s"]["events"][-1]["t"] + by, 3)
        outcomes = run(moved, expect)
        passed = sum(o.passed for o in outcomes)
        gate = FEATS[feat].get("gate")
        gate = [0] if gate is True else gate or []
        if not all(outcomes[k].passed for k in gate):
            # a flip: standing still passes the standing ones; a kip: only a flight
            # that ends on the feet counts
            passed = sum(outcomes[k].passed for k in gate)
        value = 10 * passed + graded(feat, outcomes)
        if worst is None or value < worst[0]:
            worst = (value, outcomes)
    return worst


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("feat", choices=sorted(FEATS))
    ap.add_argument("--tries", type=int, default=300)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--sigma", type=float, default=0.05)
    ap.add_argument("--random", type=float, default=0.3,
                    help="share of tries drawn fresh within the bounds")
    ap.add_argument("--shifts", type=float, nargs="*", default=[0.0],
                    help="also play the script's last key moved by these seconds; a try "
                         "scores its worst (e.g. --shifts -0.04 0 0.04)")
    args = ap.parse_args()
    global INTERFACE  # the feat's interface (biped-floor unless it names another)
    INTERFACE = ROOT / "interfaces" / f"{FEATS[args.feat].get('interface', 'biped-floor')}.yaml"
    params = FEATS[args.feat]["params"]
    script = ROOT / "assets" / "scripts" / f"biped-{args.feat}.yaml"
    expect_file = ROOT / "assets" / "logs" / f"biped-{args.feat}.expect.yaml"
    if not expect_file.is_file():  # a feat with no log yet: its target in tools/targets/
        expect_file = ROOT / "tools" / "targets" / f"biped-{args.feat}.expect.yaml"
    docs = {"i": yaml.safe_load(INTERFACE.read_text(encoding="utf-8")),
            "s": yaml.safe_load(script.read_text(encoding="utf-8"))}
    expect = yaml.safe_load(expect_file.read_text(encoding="utf-8"))["expect"]
    best_p = {n: read(docs, places[0]) for n, (_, _, _, places) in params.items()}
    best, outcomes = score(args.feat, with_params(docs, params, best_p), expect,
                           args.shifts)
    print(f"the files' own: {best:.2f}", flush=True)
    rng = random.Random(args.seed)
    for i in range(args.tries):
        if rng.random() < args.random:
            p = {n: rng.uniform(lo, hi) for n, (lo, hi, _, _) in params.items()}
        else:
            p = {n: min(hi, max(lo, best_p[n] + rng.gauss(0, args.sigma * (hi - lo))))
                 for n, (lo, hi, _, _) in params.items()}
        value, outs = score(args.feat, with_params(docs, params, p), expect, args.shifts)
        if value > best:
            best, best_p, outcomes = value, p, outs
            print(f"try {i}: {value:.2f}", flush=True)
    found = with_params(docs, params, best_p)
    print(yaml.safe_dump({n: read(found, places[0]) for n, (_, _, _, places)
                          in params.items()}, sort_keys=False))
    with tempfile.TemporaryDirectory() as tmp:
        iface = Path(tmp) / INTERFACE.name
        iface.write_text(yaml.safe_dump(found["i"], sort_keys=False), encoding="utf-8")
        s = Session(setup_from_text(iface.read_text(encoding="utf-8"), str(iface),
                                    found["s"].get("scene"), None))
        log = Path(tmp) / "try.jsonl"
        spec = ScriptSpec.model_validate(found["s"])
        record_events(s, compile_script(spec, s.sim.dt),
                      round(found["s"]["seconds"] / s.sim.dt), log)
        (Path(tmp) / "try.expect.yaml").write_text(expect_file.read_text(encoding="utf-8"),
                                                   encoding="utf-8")
        result = replay_log(log)
    for o in result.outcomes:
        print(o)
    return 1 if result.failed else 0


if __name__ == "__main__":
    sys.exit(main())
