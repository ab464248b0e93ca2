"""Build a biped-walk performance stride by stride from checkpoints, and write it as a
script: the walk (assets/scripts/biped-walk.yaml), with --march the march
(assets/scripts/biped-march.yaml), or with --mocap CLIP --arms the walk with the arms
from a performer (assets/scripts/biped-walk-mocap-arms.yaml).

    python tools/tune_walk.py [--finish 10.5] [--tries 32] [--seed 2] [--max-strides 60]
                              [--march [--parks 24]] [--interface biped-walk]
                              [--mocap CLIP [--mapping M] [--loop] [--arms [--max-rms 20]]]
                              [--write assets/scripts/biped-walk.yaml]

A walking stride is what a person does on interfaces/biped-walk.yaml: press space (the
legs swap), sweep the mouse up and right (where the new swing leg lifts to: thigh
forward, knee bent), then down, and wait for the next press. Its numbers: the period,
the lift's mouse position and glide time, when the mouse goes down and where. A
marching stride is the press alone (its period); the mouse is parked at t = 0.5 s,
where the best of ``--parks`` seeded tries of six even strides from standing went
furthest, and never moves again. From a checkpoint at the stride's start the search
tries the stride kept last (the first: a hand-made one), then seeded random strides
around it, each played through the real Session and looked at one stride further (the
same stride again), and keeps the one that gets furthest on the logs' own criteria
(assets/logs/biped-walk.expect.yaml, biped-march, biped-walk-mocap-arms): the pelvis
and chest never past 45 deg from upright, the pelvis never below 0.8 m and the head
never below 1.45 m (a fall or the splits). The kept stride is re-checked by playing the whole
script so far from the start (a try from a restored checkpoint can differ from that in
the last bits, and a walk is chaotic enough for the difference to grow); when none of
the best four passes, the search stops and says where (exit 1).

With ``--mocap CLIP`` every try also plays the clip's ``channels`` events (60 a second,
retargeted by ``--mapping M`` or the interface's ``tracking.mapping``, ``--loop`` to
play it over and over), merged with the script's events as ``puppet play --headless
--mocap`` merges them (at one step the script's first), so a kept stride is what the
recorded log does. ``--arms`` adds the ``a`` press at 0.1 s (biped-walk.yaml: ``track:
angles`` of the four arm joints; the legs stay on the mouse and space), and the
whole-script re-check then also asks the log's ``followed_channels``: each arm joint
within ``--max-rms`` degrees RMS of its channel from the first press on. The log:

    python tools/tune_walk.py --mocap cmu-01_01-jumps --mapping cmu-01 --arms --finish 18 \
        --write assets/scripts/biped-walk-mocap-arms.yaml
    puppet play biped-walk --headless --mocap cmu-01_01-jumps --mapping cmu-01 \
        --input assets/scripts/biped-walk-mocap-arms.yaml \
        --record assets/logs/biped-walk-mocap-arms.jsonl
"""

from __future__ import annotations

import argparse
import math
import random
import sys
from pathlib import Path

import yaml

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from puppet.physics.simulation import DEFAULT_DT  # noqa: E402
from puppet.session.playback import play  # noqa: E402
from puppet.timeline.script import ScriptSpec, compile_script  # noqa: E402
from tools.gestures import SessionRunner  # noqa: E402

START = 1.0  # s standing before the first press
FIRST = {"period": 0.5, "lx": 0.65, "ly": 0.65, "lift": 0.12, "reach_at": 0.22,
         "rx": 0.4, "ry": 0.05}
BOUNDS = {"period": (0.35, 0.7), "lx": (0.45, 0.9), "ly": (0.45, 1.0),
          "lift": (0.04, 0.2), "reach_at": (0.12, 0.4), "rx": (0.2, 0.7),
          "ry": (0.0, 0.35)}
TILT_MAX = 45.0  # deg, pelvis and chest (the log's never_fell and the brief)
PELVIS_MIN = 0.8  # m
HEAD_MIN = 1.45  # m
SAMPLE = 8


def stride_entries(t0: float, p: dict) -> tuple[list[dict], float]:
    r = lambda v: round(v, 3)  # noqa: E731
    # every glide ends inside its stride (a stride tried alone is cut at its end)
    reach_t = t0 + 0.02 + min(max(p["lift"], p["reach_at"] * p["period"]),
                              p["period"] - 0.15)
    return [
        {"t": r(t0), "key": "space", "hold": 0.05},
        {"t": r(t0 + 0.02), "mouse": [r(p["lx"]), r(p["ly"])], "over": r(p["lift"])},
        {"t": r(reach_t), "mouse": [r(p["rx"]), r(p["ry"])], "over": 0.1},
    ], r(t0 + p["period"])


def _y(body) -> float:
    return body.local_to_world(body.center_of_gravity).y


def tilt(angle: float) -> float:
    return abs(math.degrees(math.remainder(angle, 2 * math.pi)))


SCENE = "biped-track"
IFACE = "biped-walk"
MARCH = False  # --march: the mouse parked before START, strides are only swap presses
MARCH_BOUNDS = {"period": (0.3, 0.8)}
PARK_BOUNDS = {"mx": (0.2, 0.8), "my": (0.2, 0.9)}
CLIP: list = []  # --mocap: the clip's (step, channels event) pairs, for the whole search
ARMS_AT = 0.1  # s: --arms presses a (track: angles, the arm joints) at this time
ARMS_KEY = "a"
ARM_JOINTS = ("shoulder_near", "elbow_near", "shoulder_far", "elbow_far")
MAX_RMS = math.inf  # --arms: each arm joint within this of its channel (deg RMS)


def clip_events(interface: str, scene: str, clip: str, mapping: str | None, loop: bool,
                seconds: float) -> list:
    """The (step, channels event) pairs ``puppet play --mocap CLIP [--mapping M]
    [--loop]`` adds to a run of ``seconds`` (the same ClipSource, mapping and dt)."""
    from puppet.data.catalog import load_setup
    from puppet.mocap.clip_source import ClipSource
    from puppet.mocap.clips import find_mapping, open_clip

    setup = load_setup(interface, scene)
    spec, _ = find_mapping(mapping, setup.interface, setup.interface_path)
    return ClipSource(open_clip(clip, spec), name=Path(clip).stem,
                      loop=loop).events(DEFAULT_DT, seconds)


def merged(script_pairs: list, start: int, until: int) -> list:
    """The script's pairs and the clip's events from step ``start`` to before ``until``
    in the order ``puppet play`` applies them: by step, the script's first at a step
    (a stable sort of script + clip, as the command does)."""
    if not CLIP:
        return script_pairs
    window = [e for e in CLIP if start <= e[0] < until]
    return sorted(list(script_pairs) + window, key=lambda e: e[0])


def march_entries(t0: float, p: dict) -> tuple[list[dict], float]:
    return [{"t": round(t0, 3), "key": "space", "hold": 0.05}], round(t0 + p["period"], 3)


class Walker(SessionRunner):
    def __init__(self):
        super().__init__(IFACE, SCENE)

    def pairs(self, entries, mouse_from):
        spec = ScriptSpec.model_validate({"events": [{"t": 0.0, "mouse": list(mouse_from)}]
                                          + list(entries)})
        return compile_script(spec, self.dt)[1:]

    def run(self, entries, until: float, mouse_from, arms_from: float | None = None) -> dict:
        """Play ``entries`` (and the clip's events, with --mocap) to ``until`` s and
        judge it; ``arms_from``: also the arm joints' RMS from their channels (deg)
        over the samples from that time on that have a channel (``rms``: the worst)."""
        s, c = self.session, self.session.character
        rt = s.runtime
        worst = {"tilt": 0.0, "pelvis": 9.0, "head": 9.0}
        sq = {j: [0.0, 0] for j in ARM_JOINTS}

        def sample(sess):
            worst["tilt"] = max(worst["tilt"], tilt(c.bodies["pelvis"].angle),
                                tilt(c.bodies["chest"].angle))
            worst["pelvis"] = min(worst["pelvis"], _y(c.bodies["pelvis"]))
            worst["head"] = min(worst["head"], _y(c.bodies["head"]))
            if arms_from is not None and sess.time >= arms_from - 1e-9:
                for j, acc in sq.items():
                    if j in rt.channels:  # the log's followed_channels, the same sum
                        d = math.remainder(c.joint_angle(j) - math.radians(rt.channels[j]),
                                           2 * math.pi)
                        acc[0] += math.degrees(d) ** 2
                        acc[1] += 1

        end = round(until / self.dt)
        play(s, merged(self.pairs(entries, mouse_from), s.steps, end), end, SAMPLE, sample)
        ok = (worst["tilt"] < TILT_MAX and worst["pelvis"] > PELVIS_MIN
              and worst["head"] > HEAD_MIN and s.blowups == 0)
        out = {"ok": ok, "x": c.com()[0], **worst}
        if arms_from is not None:
            rms = {j: math.sqrt(a / n) if n else math.inf for j, (a, n) in sq.items()}
            out["rms"] = max(rms.values())
            out["ok"] = ok and out["rms"] <= MAX_RMS
        return out



def score(o_stride, o_look, x0):
    if not (o_stride["ok"] and o_look["ok"]):
        return -10.0 + o_stride["x"] - x0
    return (o_stride["x"] - x0) + 0.5 * (o_look["x"] - o_stride["x"]) \
        - 0.01 * max(0.0, o_look["tilt"] - 15.0)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("--finish", type=float, default=10.5)
    ap.add_argument("--tries", type=int, default=32)
    ap.add_argument("--seed", type=int, default=2)
    ap.add_argument("--max-strides", type=int, default=60)
    ap.add_argument("--write", default="")
    ap.add_argument("--march", action="store_true",
                    help="the march: mouse parked before the first press, then only "
                         "swap presses, on biped-terrain")
    ap.add_argument("--parks", type=int, default=24,
                    help="--march: parked mouse positions tried (6 even strides each)")
    ap.add_argument("--interface", default="biped-walk")
    ap.add_argument("--mocap", metavar="CLIP", default=None,
                    help="play this clip's channels along (as puppet play --mocap)")
    ap.add_argument("--mapping", default=None, help="--mocap: the clip's mapping")
    ap.add_argument("--loop", action="store_true", help="--mocap: play it over and over")
    ap.add_argument("--arms", action="store_true",
                    help="--mocap: press a at 0.1 s (the arms follow the clip)")
    ap.add_argument("--max-rms", type=float, default=20.0,
                    help="--arms: each arm joint within this many deg RMS of its "
                         "channel from the first press on (the log's followed_channels)")
    a = ap.parse_args(argv)
    global SCENE, MARCH, IFACE, MAX_RMS
    if (a.mapping or a.loop or a.arms) and not a.mocap:
        ap.error("--mapping, --loop and --arms go with --mocap (the clip they are for)")
    # the module's settings, all of them for this call (main can be called again)
    IFACE, SCENE, MARCH = a.interface, "biped-terrain" if a.march else "biped-track", a.march
    MAX_RMS = a.max_rms if a.arms else math.inf
    CLIP[:] = []
    if a.mocap:  # the clip's events for as long as the longest search could run
        horizon = START + (a.max_strides + 1) * max(BOUNDS["period"][1],
                                                    MARCH_BOUNDS["period"][1])
        CLIP[:] = clip_events(IFACE, SCENE, a.mocap, a.mapping, a.loop, horizon)
    arms_from = START if a.arms else None  # followed_channels from the first press
    rng = random.Random(a.seed)
    entries_of, bounds, first = stride_entries, BOUNDS, dict(FIRST)
    park = [0.5, 0.2]
    if a.march:
        entries_of, bounds, first = march_entries, MARCH_BOUNDS, {"period": 0.55}
        best_park = None
        for _ in range(a.parks):  # where to park the mouse: 6 even strides from standing
            q = [round(rng.uniform(*PARK_BOUNDS["mx"]), 3),
                 round(rng.uniform(*PARK_BOUNDS["my"]), 3)]
            per = round(rng.uniform(*MARCH_BOUNDS["period"]), 3)
            evs = [{"t": 0.5, "mouse": q}]
            for k in range(6):
                evs += march_entries(START + k * per, {"period": per})[0]
            o = Walker().run(evs, START + 6 * per, (0.5, 0.2))
            sc = o["x"] - (0 if o["ok"] else 10)
            if best_park is None or sc > best_park[0]:
                best_park = (sc, q, per)
        _, park, per = best_park
        first = {"period": per}
        print(f"mouse parked at {park}, period {per}", flush=True)
    w = Walker()
    events: list[dict] = [{"t": 0.5 if a.march else 0.2, "mouse": park}]
    if a.arms:
        events.insert(0, {"t": ARMS_AT, "key": ARMS_KEY, "hold": 0.05})
    w.run(events, START, (0.5, 0.2))
    t, last, mouse = START, first, tuple(park)
    x = w.session.character.com()[0]
    for k in range(a.max_strides):
        events.append({"t": t, "action": "checkpoint"})
        w.checkpoint()
        tried = []
        for i in range(a.tries):
            if i == 0:
                p = dict(last)
            else:
                spread = 0.35 if i < a.tries // 2 else 0.12
                p = {n: min(hi, max(lo, last[n] + rng.gauss(0, spread * (hi - lo))))
                     for n, (lo, hi) in bounds.items()}
            ents, t1 = entries_of(t, p)
            look, t2 = entries_of(t1, p)
            o1 = w.run(ents, t1, mouse)
            o2 = w.run(look, t2, mouse if a.march else (p["rx"], p["ry"]))
            w.back()
            tried.append((score(o1, o2, x), i, p, ents, t1))
        tried.sort(key=lambda item: (-item[0], item[1]))
        # The kept stride is checked by playing the whole script so far from the start,
        # as the recorded log will (a try from a restored checkpoint can differ from it
        # in the last bits, and a walk is chaotic enough for that to grow).
        kept = None
        for sc, _, p, ents, t1 in tried[:4]:
            if sc < -5:
                break
            fresh = Walker()
            o1 = fresh.run(events + ents, t1, (0.5, 0.2), arms_from)
            if o1["ok"]:
                kept = (sc, p, ents, t1, o1, fresh)
                break
        if kept is None:
            print(f"stride {k + 1}: nothing passes from x {x:.2f}")
            break
        sc, p, ents, t1, o1, w = kept
        events += ents
        t, last, x = t1, p, o1["x"]
        mouse = mouse if a.march else (p["rx"], p["ry"])
        arms = f" arms {o1['rms']:.1f} deg RMS" if "rms" in o1 else ""
        print(f"stride {k + 1}: t {t:.2f} x {x:.2f} tilt {o1['tilt']:.1f} "
              f"pelvis {o1['pelvis']:.2f}{arms}", flush=True)
        if x > a.finish:
            break
    if a.write:
        what = ("The march: the mouse parked before the first press, then only swap "
                "presses (space), over rough ground, stride by stride from checkpoints."
                if a.march else "The human figure walks on the mouse and the swap key "
                "(space), stride by stride from checkpoints.")
        if a.mocap:
            play_with = " ".join(["--mocap", a.mocap] + (["--mapping", a.mapping]
                                 if a.mapping else []) + (["--loop"] if a.loop else []))
            what += ((f" The arms from a performer: {ARMS_KEY} at {ARMS_AT} s makes them "
                      "follow the clip (track: angles)" if a.arms else
                      " The clip's channels play along") + f"; play with {play_with}.")
        Path(a.write).write_text(yaml.safe_dump({
            "description": what, "interface": "biped-walk", "scene": SCENE,
            "seconds": round(t, 2), "events": events}, sort_keys=False))
    return 0 if x > a.finish else 1


if __name__ == "__main__":
    sys.exit(main())
