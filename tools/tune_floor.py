"""Search the floor feats of interfaces/biped-floor.yaml (and the wall flip of
interfaces/biped-wall.yaml) on their logs' own expectations and print the numbers found
(to paste into the interface and the script).

    python tools/tune_floor.py FEAT [--tries 300] [--seed 1] [--sigma 0.05] [--random 0.3]
                               [--only PREFIX ...] [--start JSON] [--verbose]
    FEAT: handstand, backflip, kip, wall-flip

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

    puppet play biped-floor --headless --input biped-handstand \
        --record assets/logs/biped-handstand.jsonl

records the log (the same end hash as the tool's replay).

The back flip (assets/logs/biped-backflip): a gated score (the other expectations
count only once the turn in flight, the feet-first touch-down and never_fell hold, or
standing still or sitting after the flip would win) plus a landing slope: 20 times the
share of the time after the flight spent on the feet alone (nothing else touching, the
pelvis within 60 deg of upright, the feet less than 0.5 m apart). The take-off pose's
leg damping is searched too (the character's 50 N*m*s/rad brake legs straightening at
10-15 rad/s), and so are the landing poses' stiffness and damping. How the shipped
numbers were found: three runs of an earlier version of this search (--seed 4, 5, 6)
gave a flip that turned 326 deg and landed but sat down; from there
``--only land absorb rise landed t_absorb t_straighten t_tuck`` runs and then
``--seed 5 --random 0 --sigma 0.05`` over everything gave a landing that rolled on; a
hand grid over the tuck (hips 120 instead of 80: a tighter tuck spins faster) and the
opening (t_tuck 0.43, land hips 30, knees -70) found a landing on the feet that stays
on them, and ``--seed 8 --random 0.2 --sigma 0.06 --only land absorb rise landed
t_absorb t_straighten t_tuck tuck`` from it (try 503) stood it up. It then fell once the
standing pose's low damping (inherited from the flip) met a longer run, so the
interface got flip_stood (the character's leg gains back, 2.0 s into the stand-up,
chosen by hand among 1.5-2.5 s) and the script runs 8 s. ``--tries 0`` replays the
files' numbers and passes. ``--start JSON`` starts from printed numbers, ``--only``
searches a part, ``--verbose`` prints the numbers at each improvement.

The wall flip (assets/logs/biped-wall-flip, interfaces/biped-wall.yaml): gated on the
first three expectations (the foot on the wall before the flight, the turn in flight,
the flight beginning from the wall foot), with the turn and the same landing slope
once the first two hold. Gated on the wall touch alone, a search found a jump back
with no flip; gated on the touch and the turn, it stalled near 156 deg from a pushing
pose of its own. Started instead from the floor flip's take-off, tuck and landing with
the arms back (the arms swung forward hit the wall), ``--seed 3 --random 0.3 --sigma
0.1`` reached 319 deg, but the flight began from the floor foot after a hop back; with
``took_off: {links: [foot_near]}`` in the expectations, ``--seed 4 --random 0.2
--sigma 0.08 --start`` (that best) found the shipped numbers at try 587: 309 deg, the
flight from the wall foot, feet first, never on its back. None of about 600 more tries
stood it up after the landing (it folds forward onto hands and knees).

The kip (interfaces/biped-kip.yaml, its own interface: the figure starts lying on its
back) searches the rock, snap and landing poses (joint targets), their damping, the
three holds, the hips' torque, the rising state's ankle-map gains and the standing
pose's knees and ankles. Only a flight that looks like a kip counts (a gate on
flight_phases, first_touch, the chest's angle_within, took_off and turned: feet first,
off the hands, the trunk never face down, turning forward), the landing slope counts
once the first seven hold, and the graded term is the flight (to 0.3 s), the chest's
most forward angle (to -45 deg), how near upright the trunk ends, the head's height
and both feet's share of the last second on the floor. ``--sweep FROM TO STEP`` plays
the files' numbers with k at each moment and counts the ones that pass every
expectation; ``--shifts ... --mean`` scores a try's mean over shifted presses.

How the shipped numbers were found, each run started from the best before it (the
first from the kip that took off from the head, earlier shipped): ``--seed 11`` and
``--seed 12`` found backward rolls and hops that passed a gate without ``turned``
(it was added), ``--seed 13 --tries 3000 --random 0.4 --sigma 0.08`` a push from the
hands that landed with the feet 0.7 m ahead of the body (the landing pose then held
the pelvis in the world: in the air that throws the legs forward, so it became joint
targets); ``--seed 14 --random 0.2 --sigma 0.06`` (try 115) a kip that stood 1 s and
fell back; ``--seed 16 --random 0.1 --sigma 0.05 --only land t_land rise`` one that
stood on one foot; ``--seed 17 --random 0.1 --sigma 0.05 --only land t_land rise
stand`` (try 222, with the feet's graded term) passed every expectation, but only at
3 of 40 press times (``--sweep 0.5 2.45 0.05``). From it ``--seed 19 --random 0
--sigma 0.02 --shifts -0.6 -0.3 0 0.3 0.6 --mean`` (try 286: the mean over k at 0.7,
1.0, 1.3, 1.6 and 1.9 s); with got_up's lay_seconds lowered to 0.1 (the rock passes
through lying: the last stretch on the back before the kick is 0.15 s; the first
angle_within already proves the start on the back) it passed at 22 of 40, standing
with a foot not flat at most of the others; ``--seed 20 --sigma 0.015`` (the same
shifts, 450 tries) found nothing better, and a hand grid over the standing pose's
ankles (world -8..0) and the rising dx gain (40, 45.18, 50) at 20 press times gave
-6 and 45.18: 32 of 40. Those are the shipped numbers (``--tries 0`` replays them).
The 50 ms grid flatters them (its moments behave alike; why is not measured): at 10 ms
(``--sweep 0.7 2.45 0.01``) 42 of 176 pass, and ``--seed 21 --sigma 0.02 --shifts 0
0.002 0.006 0.011 0.302 -0.296 0.607 -0.493 --mean`` (150 tries, mixed phases) raised
its own mean but not that count (38). They were recorded with

    puppet play biped-kip --headless --input biped-kip --record assets/logs/biped-kip.jsonl

The runs before ``--seed 17`` used earlier versions of this feat (fewer parameters,
gates and graded terms), and ``--seed 19`` scored got_up with lay_seconds 0.2, so
those do not replay exactly from this file.
"""

from __future__ import annotations

import argparse
import json
import random
import re
import sys
import tempfile
from pathlib import Path

import numpy as np
import yaml

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from puppet.data.catalog import ROOT, setup_from_text  # noqa: E402
from puppet.session import Session  # noqa: E402
from puppet.session.playback import play  # noqa: E402
from puppet.testing import replay_log  # noqa: E402
from puppet.timeline.expectations import _longest_run, evaluate_all, parse_expectations  # noqa: E402
from puppet.timeline.log import record_events  # noqa: E402
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
    for *_, places in out.values():
        places[:] = [place + ("world",) for place in places]
    return {f"{n}_world": v for n, v in out.items()}

def _side(short: str, pose: str, world: bool = False, **ranges) -> dict:
    """Parameters for single joints (one side's: hip_near, knee_far ...)."""
    return {f"{short}_{j}" + ("_world" if world else ""):
            (lo, hi, 0, [("i", "poses", pose, "joints", j) + (("world",) if world else ())])
            for j, (lo, hi) in ranges.items()}


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
    "kip": {"interface": ROOT / "interfaces" / "biped-kip.yaml", "gate": [2, 3, 4, 5, 6],
            "landing_slope": True, "turn_gate": 7,
            "params": {
        "hip_torque": (250, 450, 0, [("i", "gains", j, "max_torque")
                                     for j in ("hip_near", "hip_far")]),
        **_pose("rock", "rock", waist=(-80, 0), neck=(-50, 50), hip=(90, 130),
                knee=(-150, -40), shoulder=(120, 180), elbow=(40, 150)),
        "rock_damp": (1, 30, 1, [("i", "poses", "rock", "damping", j) for j in (
            "hip_near", "hip_far", "knee_near", "knee_far", "waist")]),
        **_pose("snap", "snap", waist=(-30, 30), neck=(-50, 50), hip=(-30, 60),
                knee=(-130, 0), shoulder=(90, 180), elbow=(0, 90)),
        "snap_damp": (1, 30, 1, [("i", "poses", "snap", "damping", j) for j in (
            "hip_near", "hip_far", "knee_near", "knee_far", "waist")]),
        **_pose("land", "kip_land", waist=(-40, 30), hip=(20, 130), knee=(-150, -40),
                ankle=(-30, 30), shoulder=(-40, 150)),
        "land_damp": (1, 50, 1, [("i", "poses", "kip_land", "damping", j) for j in (
            "hip_near", "hip_far", "knee_near", "knee_far")]),
        **{f"t_{n}": (lo, hi, 3, [("i", "sequences", "kip", k, "hold")])
           for k, (n, lo, hi) in enumerate((("rock", 0.2, 1.2), ("snap", 0.05, 0.5),
                                            ("land", 0.1, 1.2)))},
        # the stand after the landing: the rising state's ankle maps' gains
        "rise_dx": (0, 60, 2, [("i", "states", "rising", "maps", k, "to", "+-")
                               for k in (0, 1)]),
        "rise_vx": (0, 50, 2, [("i", "states", "rising", "maps", 2, "to", "+-")]),
        **_pose("stand", "standing", knee=(-30, 0)),
        **_world("stand", "standing", ankle=(-15, 10)),
    }},
    "backflip": {"gate": 3, "landing_slope": True, "params": {
        **_world("set", "flip_set", waist=(-60, 0), hip=(-60, 0), ankle=(-40, 0)),
        **_pose("set", "flip_set", knee=(-140, -40), shoulder=(-60, 60)),
        **_world("jump", "flip_jump", waist=(-20, 40), hip=(-20, 40)),
        **_pose("jump", "flip_jump", knee=(-30, 0), ankle=(-45, 0), shoulder=(60, 180)),
        **_pose("tuck", "flip_tuck", waist=(-60, 0), hip=(80, 130), knee=(-150, -60),
                shoulder=(0, 120)),
        **_pose("land", "flip_land", waist=(-40, 10), hip=(0, 120), knee=(-100, 0),
                ankle=(-30, 30), shoulder=(0, 150)),
        **_world("absorb", "flip_absorb", waist=(-70, 0), hip=(-70, 0), ankle=(-40, 0)),
        **_pose("absorb", "flip_absorb", knee=(-140, -40), shoulder=(0, 150)),
        **_world("rise", "flip_straighten", waist=(-40, 0), hip=(-40, 0), ankle=(-25, 0)),
        **_pose("rise", "flip_straighten", knee=(-90, -10)),
        **{f"{st}_{inp}": (0, 40, 2, [("i", "states", f"flip_{st}", "maps", k, "to", "+-")])
           for st in ("landed", "rise") for k, inp in enumerate(("dx", "vx"))},
        "land_damp": (2, 80, 1, [("i", "poses", "flip_land", "damping", j) for j in (
            "hip_near", "hip_far", "knee_near", "knee_far")]),
        "land_stiff": (100, 1500, 0, [("i", "poses", "flip_land", "stiffness", j) for j in (
            "hip_near", "hip_far", "knee_near", "knee_far")]),
        "absorb_stiff": (100, 1500, 0, [("i", "poses", "flip_absorb", "stiffness", j)
                                        for j in ("hip_near", "hip_far", "knee_near",
                                                  "knee_far")]),
        "absorb_damp": (2, 80, 1, [("i", "poses", "flip_absorb", "damping", j) for j in (
            "hip_near", "hip_far", "knee_near", "knee_far")]),
        "absorb_ankle_damp": (1, 60, 1, [("i", "poses", "flip_absorb", "damping", j)
                                         for j in ("ankle_near", "ankle_far")]),
        "rise_damp": (2, 80, 1, [("i", "poses", "flip_straighten", "damping", j) for j in (
            "hip_near", "hip_far", "knee_near", "knee_far")]),
        "rise_ankle_damp": (1, 60, 1, [("i", "poses", "flip_straighten", "damping", j)
                                       for j in ("ankle_near", "ankle_far")]),
        "t_absorb": (0.1, 1.5, 3, [("i", "states", "flip_landed", "transitions", 0, "after")]),
        "t_straighten": (0.2, 1.2, 3, [("i", "sequences", "flip_stand", 0, "hold")]),
        "t_stood": (0.3, 3.0, 3, [("i", "states", "flip_rise", "transitions", 0, "after")]),
        "jump_damp": (1, 20, 1, [("i", "poses", "flip_jump", "damping", j) for j in (
            "hip_near", "hip_far", "knee_near", "knee_far", "ankle_near", "ankle_far")]),
        **{f"t_{n}": (lo, hi, 3, [("i", "sequences", "backflip", k, "hold")])
           for k, (n, lo, hi) in enumerate((("set", 0.3, 1.2), ("jump", 0.08, 0.4),
                                            ("tuck", 0.15, 0.8)))},
    }},
    "wall-flip": {"gate": 3, "turn_gate": 2, "landing_slope": True,
                  "interface": ROOT / "interfaces" / "biped-wall.yaml",
                  "params": {
        **_side("step", "wall_step", hip_near=(40, 130), knee_near=(-130, -20),
                ankle_near=(-20, 30)),
        **_world("step", "wall_step", waist=(-70, 0)),
        **_side("step", "wall_step", world=True, hip_far=(-60, 0), ankle_far=(-40, 0)),
        **_side("step", "wall_step", knee_far=(-140, -40)),
        **_pose("step", "wall_step", shoulder=(-60, 90)),
        **_world("push", "wall_push", waist=(0, 50)),
        **_side("push", "wall_push", hip_near=(0, 120), knee_near=(-60, 0),
                ankle_near=(-45, 30), knee_far=(-30, 0), ankle_far=(-45, 0)),
        **_side("push", "wall_push", world=True, hip_far=(-20, 40)),
        **_pose("push", "wall_push", shoulder=(60, 180)),
        "push_damp": (1, 20, 1, [("i", "poses", "wall_push", "damping", j) for j in (
            "hip_near", "hip_far", "knee_near", "knee_far", "ankle_near", "ankle_far")]),
        **_pose("tuck", "wall_tuck", waist=(-60, 0), hip=(60, 130), knee=(-150, -60),
                shoulder=(0, 120)),
        **_pose("land", "wall_land", waist=(-40, 10), hip=(0, 120), knee=(-100, 0),
                ankle=(-30, 30), shoulder=(0, 150)),
        **_world("absorb", "wall_absorb", waist=(-70, 0), hip=(-70, 0), ankle=(-40, 0)),
        **_pose("absorb", "wall_absorb", knee=(-140, -40), shoulder=(0, 150)),
        **_world("rise", "wall_straighten", waist=(-40, 0), hip=(-40, 0), ankle=(-25, 0)),
        **_pose("rise", "wall_straighten", knee=(-90, -10)),
        **{f"{st}_{inp}": (0, 40, 2, [("i", "states", st, "maps", k, "to", "+-")])
           for st in ("landed", "rising") for k, inp in enumerate(("dx", "vx"))},
        "land_damp": (2, 80, 1, [("i", "poses", "wall_land", "damping", j) for j in (
            "hip_near", "hip_far", "knee_near", "knee_far")]),
        "t_absorb": (0.1, 1.5, 3, [("i", "states", "landed", "transitions", 0, "after")]),
        "t_straighten": (0.2, 1.2, 3, [("i", "sequences", "stand_up", 0, "hold")]),
        **{f"t_{n}": (lo, hi, 3, [("i", "sequences", "wallflip", k, "hold")])
           for k, (n, lo, hi) in enumerate((("step", 0.2, 1.0), ("push", 0.08, 0.4),
                                            ("tuck", 0.15, 0.8)))},
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
            m = re.search(r"chest (-?[0-9]+)\.\.", o.measured)
            if o.expectation.startswith("angle_within chest") and m:
                value += (min(float(m.group(1)), -45) + 180) / 45  # less face-down
            m = re.search(r"the longest ([0-9.]+) s", o.measured)
            if o.expectation.startswith("flight_phases") and m:
                value += min(float(m.group(1)), 0.3) * 10
            m = re.search(r"at most ([0-9.]+) deg from upright", o.measured)
            if o.expectation.startswith("tilt_at_end") and m:
                value += (180 - float(m.group(1))) / 60
            m = re.search(r"y = (-?[0-9.]+)\.\.", o.measured)
            if o.expectation.startswith("height_at_end") and m:
                value += min(float(m.group(1)), 1.45) * 2
            m = re.search(r"touching at ([0-9]+)%", o.measured)
            if o.expectation.startswith("touching_at_end") and m:
                value += float(m.group(1)) / 20  # both feet down
        return value
    for o in outcomes:
        if o.expectation.startswith("balanced_on"):
            m = re.search(r"upside down: ([0-9.]+) s", o.measured)
            return float(m.group(1)) if m else 0.0
    value = 0.0
    for o in outcomes:
        if o.expectation.startswith("turned") and "in flight" in o.expectation:
            m = re.search(r"turned (-?[0-9.]+) deg", o.measured)
            value += min(float(m.group(1)), 360.0) / 100 if m else 0.0
        elif o.expectation.startswith("never_fell") and not o.passed:
            m = re.search(r"largest tilt on the ground ([0-9.]+) deg", o.measured)
            value += (180 - float(m.group(1))) / 90 if m else 0.0  # less of a fall
        elif o.expectation.startswith("tilt_at_end") and not o.passed:
            m = re.search(r"at most ([0-9.]+) deg", o.measured)
            value += (180 - float(m.group(1))) / 90 if m else 0.0  # nearer upright
        elif o.expectation.startswith("height_at_end"):
            m = re.search(r"y = (-?[0-9.]+)\.\.", o.measured)
            value += 2 * float(m.group(1)) if m else 0.0  # the lowest head, higher
    return value


def on_feet_after_flight(tr) -> float:
    """A landing's slope: the share of the time after the longest flight that passed
    before anything but the feet touched, the pelvis tipped 60 deg from upright or the
    feet came more than 0.5 m apart (a split)."""
    free = ~tr.contact.any(axis=1)
    length, first, last = _longest_run(free, tr.t)
    if length <= 0 or last + 1 >= len(tr.t):
        return 0.0
    feet = [tr.index(n) for n in ("foot_near", "foot_far")]
    others = np.delete(tr.contact, feet, axis=1).any(axis=1)
    tilt = np.degrees(np.abs(np.remainder(tr.angle[:, tr.index("pelvis")] + np.pi,
                                          2 * np.pi) - np.pi))
    apart = np.abs(tr.x[:, feet[0]] - tr.x[:, feet[1]]) > 0.5
    bad = (others | (tilt > 60) | apart)[last + 1:]
    return float(np.argmax(bad) if bad.any() else len(bad)) / len(bad)


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
    for name, (_, _, dec, places) in params.items():
        v = round(p[name], dec) if dec else int(round(p[name]))
        for place in places:
            put(out, place, v)
    return out


def run(docs: dict, expect: list, traj: bool = False, interface: Path = INTERFACE):
    """Play the script into a Session of the interface; the outcomes of ``expect``
    (``traj``: and the sampled trajectory)."""
    session = Session(setup_from_text(yaml.safe_dump(docs["i"], sort_keys=False),
                                      str(interface), docs["s"].get("scene"), None))
    spec = ScriptSpec.model_validate(docs["s"])
    sampler = Sampler(session)
    sampler(session)
    play(session, compile_script(spec, session.sim.dt),
         round(docs["s"]["seconds"] / session.sim.dt), SAMPLE_EVERY, sampler)
    tr = sampler.trajectory()
    outcomes = evaluate_all(parse_expectations(expect).items, tr, "")
    return (outcomes, tr) if traj else outcomes


def score(feat: str, docs: dict, expect: list, shifts=(0.0,),
          mean: bool = False) -> tuple[float, list]:
    """10 per expectation that holds plus the graded term, at the worst of the script
    played with its last key moved by each of ``shifts`` s (a person's timing; ``mean``:
    their mean, with the worst one's outcomes)."""
    worst, total = None, 0.0
    for by in shifts:
        moved = json.loads(json.dumps(docs))
        moved["s"]["events"][-1]["t"] = round(moved["s"]["events"][-1]["t"] + by, 3)
        outcomes, tr = run(moved, expect, traj=True,
                           interface=FEATS[feat].get("interface", INTERFACE))
        passed = sum(o.passed for o in outcomes)
        gate = FEATS[feat].get("gate", 0)  # a count of leading ones, or their indices
        gate = list(range(gate)) if isinstance(gate, int) else list(gate)
        if gate and not all(outcomes[k].passed for k in gate):
            # a flip: standing still (or sitting after it) passes the standing ones; a
            # kip: only a flight that ends on the feet counts
            passed = sum(outcomes[k].passed for k in gate)
        value = 10 * passed + graded(feat, outcomes)
        turn = FEATS[feat].get("turn_gate", 1)  # the leading ones that make it a flip
        if FEATS[feat].get("landing_slope") and all(o.passed for o in outcomes[:turn]):
            value += 20 * on_feet_after_flight(tr)
        total += value
        if worst is None or value < worst[0]:
            worst = (value, outcomes)
    return (total / len(shifts), worst[1]) if mean else worst


def sweep(feat: str, docs: dict, expect: list, start: float, stop: float,
          step: float) -> int:
    """Play the feat with its last key at each moment start..stop; print the moments
    that pass every expectation and, for the others, the first expectation that fails."""
    stood = []
    count = int(round((stop - start) / step)) + 1
    for k in range(count):
        at = round(start + k * step, 3)
        moved = json.loads(json.dumps(docs))
        moved["s"]["events"][-1]["t"] = at
        outcomes = run(moved, expect, interface=FEATS[feat].get("interface", INTERFACE))
        failed = [o.expectation.split(":")[0] for o in outcomes if not o.passed]
        print(f"{at:.3f} s: " + ("passes" if not failed else "fails " + "; ".join(failed)),
              flush=True)
        if not failed:
            stood.append(at)
    print(f"{len(stood)} of {count} pass: {', '.join(f'{t:g}' for t in stood)}")
    return 0


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
    ap.add_argument("--only", nargs="*", default=None,
                    help="search only the parameters whose names start with these (the "
                         "others keep the files' numbers), e.g. --only land absorb rise")
    ap.add_argument("--verbose", action="store_true",
                    help="print the numbers at each improvement")
    ap.add_argument("--start", default=None,
                    help="a JSON object of numbers to start from instead of the files' "
                         "(what --verbose printed)")
    ap.add_argument("--mean", action="store_true",
                    help="with --shifts: score the mean over the shifts, not the worst")
    ap.add_argument("--sweep", type=float, nargs=3, default=None,
                    metavar=("FROM", "TO", "STEP"),
                    help="instead of a search: play the files' numbers (or --start) with "
                         "the script's last key at each moment FROM..TO s, STEP apart, and "
                         "print which pass every expectation (a person's timing)")
    args = ap.parse_args()
    params = FEATS[args.feat]["params"]
    if args.only is not None:
        params = {n: v for n, v in params.items() if n.startswith(tuple(args.only))}
    script = ROOT / "assets" / "scripts" / f"biped-{args.feat}.yaml"
    expect_file = ROOT / "assets" / "logs" / f"biped-{args.feat}.expect.yaml"
    if not expect_file.is_file():  # a feat with no log yet: its target in tools/targets/
        expect_file = ROOT / "tools" / "targets" / f"biped-{args.feat}.expect.yaml"
    interface = FEATS[args.feat].get("interface", INTERFACE)  # biped-floor unless named
    docs = {"i": yaml.safe_load(interface.read_text(encoding="utf-8")),
            "s": yaml.safe_load(script.read_text(encoding="utf-8"))}
    expect = yaml.safe_load(expect_file.read_text(encoding="utf-8"))["expect"]
    if args.start:  # write them into the files' documents: a fixed one stays so too
        docs = with_params(docs, FEATS[args.feat]["params"], {
            **{n: read(docs, pl[0]) for n, (_, _, _, pl) in FEATS[args.feat]["params"].items()},
            **json.loads(args.start)})
    if args.sweep:
        return sweep(args.feat, docs, expect, *args.sweep)
    best_p = {n: read(docs, places[0]) for n, (_, _, _, places) in params.items()}
    best, outcomes = score(args.feat, with_params(docs, params, best_p), expect,
                           args.shifts, args.mean)
    print(f"the files' own: {best:.2f}", flush=True)
    rng = random.Random(args.seed)
    for i in range(args.tries):
        if rng.random() < args.random:
            p = {n: rng.uniform(lo, hi) for n, (lo, hi, _, _) in params.items()}
        else:
            p = {n: min(hi, max(lo, best_p[n] + rng.gauss(0, args.sigma * (hi - lo))))
                 for n, (lo, hi, _, _) in params.items()}
        value, _ = score(args.feat, with_params(docs, params, p), expect, args.shifts,
                            args.mean)
        if value > best:
            best, best_p = value, p
            print(f"try {i}: {value:.2f}", flush=True)
            if args.verbose:
                found = with_params(docs, params, best_p)
                print(json.dumps({n: read(found, places[0]) for n, (_, _, _, places)
                                  in params.items()}), flush=True)
    found = with_params(docs, params, best_p)
    print(yaml.safe_dump({n: read(found, places[0]) for n, (_, _, _, places)
                          in params.items()}, sort_keys=False))
    with tempfile.TemporaryDirectory() as tmp:
        iface = Path(tmp) / interface.name
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
