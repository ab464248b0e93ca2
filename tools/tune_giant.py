"""Search the biped-gymnast giant swings (assets/scripts/biped-giant-swings.yaml).

    python tools/tune_giant.py [--tries 16] [--seed 1] [--seconds 60] [--turns 4] [--lift]
                               [--write assets/scripts/biped-giant-swings.yaml]

What a person does on interfaces/biped-gymnast.yaml (swing mode, hanging from the high
bar): watch the swing and sweep the mouse right and up (arms close, hips pike: the body
shortens) while the centre of mass rises, between ``lo`` and ``hi`` degrees from
hanging, and left and down (arms overhead, body stretched) while it falls. Shortening
under the bottom's high pull and stretching over the top's low one feeds the swing:
from a dead hang it grows swing by swing until it goes over the top, and then round.
With ``--lift`` the run starts with a spotter's lift instead (a Ctrl+drag of the pelvis
from the hang up in front of the bar to ``lift`` degrees, let go), and a try counts only
if the lift alone (the same script without its mouse sweeps) does not go round even
once: the turns are the pumping's.

The player below is that person: every control tick (1/60 s) it reads the centre of
mass's angle about the held bar and its turning rate, and when its choice changes it
writes a script entry (a mouse glide of ``glide`` s), played at once through the real
Session. So the script it writes replays to what it saw. Its numbers - the pike and
arch mouse points, the glide, the phase window, a reaction delay - are searched
(seeded random tries around the kept ones); each try is scored on the log's own
expectations (assets/logs/biped-giant-swings.expect.yaml: revolutions about the hand's
hold, both hands held throughout) by replaying the script through the same path
``puppet play --record`` takes. After ``--turns`` full turns the player stops pumping
(arms overhead, body straight) and the log runs on 3 s. The shipped log (seeded, so
the same script again):

    python tools/tune_giant.py --tries 16 --seconds 60 \
        --write assets/scripts/biped-giant-swings.yaml
    puppet play biped-gymnast --headless --input assets/scripts/biped-giant-swings.yaml \
        --record assets/logs/biped-giant-swings.jsonl
"""

from __future__ import annotations

import argparse
import math
import random
import sys
from pathlib import Path

import yaml

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from puppet.data.catalog import load_setup  # noqa: E402
from puppet.session import Session  # noqa: E402
from puppet.timeline.expectations import evaluate_all, load_expectations  # noqa: E402
from puppet.timeline.replay import Sampler  # noqa: E402
from puppet.timeline.script import ScriptSpec, compile_script  # noqa: E402
from tools.gestures import compile_entries  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
LOG = ROOT / "assets/logs/biped-giant-swings.jsonl"  # its sidecar .expect.yaml
INTERFACE = "biped-gymnast"
START = 0.5  # s hanging still before the first sweep
TICK = 8  # steps between the player's looks (60 Hz)
FIRST = {"pike_x": 0.71, "pike_y": 0.67, "arch_x": 0.2, "arch_y": 0.2, "glide": 0.08,
         "lo": 0.0, "hi": 180.0, "delay": 0.0, "lift": 105.0, "lift_time": 2.0}
BOUNDS = {"pike_x": (0.5, 0.8), "pike_y": (0.4, 0.8), "arch_x": (0.0, 0.35),
          "arch_y": (0.0, 0.4), "glide": (0.03, 0.15), "lo": (0.0, 60.0),
          "hi": (90.0, 180.0), "delay": (0.0, 0.1), "lift": (90.0, 115.0),
          "lift_time": (1.2, 3.0)}
PELVIS_R = 1.09  # m from the grip to the pelvis's centre, hanging straight
LIFT_HOLD = 0.3  # s


def lift_entries(p: dict, bar) -> list[dict]:
    """The spotter's lift: one Ctrl+drag of the pelvis from where it hangs to ``lift``
    degrees forward about the bar, in ``lift_time`` s (a straight pull: the held hands
    turn it into an arc), held ``LIFT_HOLD`` s there, then let go."""
    r = lambda v: round(v, 4)  # noqa: E731
    a = math.radians(p["lift"])
    return [{"t": START, "drag": {
        "link": "pelvis", "point": [0.0, 1.02],
        "start": [r(bar[0]), r(bar[1] - PELVIS_R)],
        "to": [r(bar[0] + PELVIS_R * math.sin(a)), r(bar[1] - PELVIS_R * math.cos(a))],
        "over": r(p["lift_time"]), "hold": LIFT_HOLD}}]


def _com_angle(session, bar) -> float:
    x, y = session.character.com()
    return math.atan2(x - bar[0], -(y - bar[1]))  # 0 hanging below, + forward (ccw)


def perform(p: dict, turns: float, seconds: float) -> tuple[dict, int]:
    """Play the player with numbers ``p`` through a live Session; the script entries it
    wrote (a dict as the YAML file) and its end step."""
    session = Session(load_setup(INTERFACE))
    dt = session.sim.dt
    bar = session.sim.grasp_point("hand_near") or (0.0, 2.8)
    r = lambda v: round(v, 4)  # noqa: E731
    entries: list[dict] = []
    pending: list = []
    mouse = (p["arch_x"], p["arch_y"])
    entries.append({"t": 0.0, "mouse": [r(mouse[0]), r(mouse[1])]})
    if p["lift"] > 0:
        entries += lift_entries(p, bar)
    pending += compile_entries(entries, dt, mouse)
    pending.sort(key=lambda pair: pair[0])
    free = START + (p["lift_time"] + LIFT_HOLD + 0.05 if p["lift"] > 0 else 0.0)
    end = round(seconds / dt)
    prev = _com_angle(session, bar)
    unwrapped, top, w = 0.0, 0.0, 0.0
    choice, want, since = "arch", "arch", 0
    stopped_at = None
    while session.steps < end:
        while pending and pending[0][0] <= session.steps:
            session.handle(pending.pop(0)[1])
        session.advance(TICK)
        a = _com_angle(session, bar)
        d = math.remainder(a - prev, 2 * math.pi)
        prev = a
        unwrapped += d
        w = d / (TICK * dt)
        top = max(top, abs(unwrapped))
        t = session.steps * dt
        if stopped_at is None and top >= turns * 2 * math.pi:
            stopped_at = t
        if t < free:
            continue
        phase = math.degrees(math.remainder(a, 2 * math.pi))
        pike = phase * w > 0 and p["lo"] <= abs(phase) <= p["hi"]  # rising: shorten
        if stopped_at is not None:
            pike = False
        new = "pike" if pike else "arch"
        if new != want:
            want, since = new, session.steps
        if want != choice and (session.steps - since) * dt >= p["delay"] - 1e-9:
            choice = want
            target = (p["pike_x"], p["pike_y"]) if pike else (p["arch_x"], p["arch_y"])
            entry = {"t": r(session.steps * dt), "mouse": [r(target[0]), r(target[1])],
                     "over": r(p["glide"])}
            entries.append(entry)
            pending += compile_entries([entry], dt, mouse)
            pending.sort(key=lambda pair: pair[0])
            mouse = target
        if stopped_at is not None and t > stopped_at + 3.0:
            break
    return {"seconds": r(session.steps * dt), "events": entries}, session.steps


def score(script: dict) -> tuple[float, list]:
    """Replay the script as ``puppet play --record`` would and evaluate the log's
    expectations: (the revolutions measured, the outcomes)."""
    spec = ScriptSpec.model_validate({"interface": INTERFACE, **script})
    session = Session(load_setup(INTERFACE))
    pairs = compile_script(spec, session.sim.dt)
    sampler = Sampler(session)
    from puppet.session.playback import play

    sampler(session)
    play(session, pairs, round(spec.seconds / session.sim.dt), 4, sampler)
    expect = load_expectations(LOG, {})
    outcomes = evaluate_all(expect.items, sampler.trajectory(), session.sim.state_hash())
    turns = next((float(o.measured.split()[0]) for o in outcomes
                  if o.expectation.startswith("revolutions")), 0.0)
    return turns, outcomes


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--tries", type=int, default=16)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--turns", type=float, default=4.0, help="full turns before stopping")
    ap.add_argument("--seconds", type=float, default=60.0, help="at most")
    ap.add_argument("--lift", action="store_true",
                    help="start with the spotter's lift (else from a dead hang)")
    ap.add_argument("--write", type=Path)
    args = ap.parse_args()
    rng = random.Random(args.seed)
    best = None
    first = dict(FIRST) if args.lift else {**FIRST, "lift": 0.0, "lo": 0.0}
    bounds = dict(BOUNDS) if args.lift else {n: b for n, b in BOUNDS.items()
                                              if n not in ("lift", "lift_time")}
    p = dict(first)
    for k in range(args.tries):
        if k:
            base = best[2] if best else first
            p = {**base, **{n: min(hi, max(lo, base[n] + rng.gauss(0, 0.15 * (hi - lo))))
                            for n, (lo, hi) in bounds.items()}}
        script, _ = perform(p, args.turns, args.seconds)
        turns, outcomes = score(script)
        # the control: the same script without its mouse sweeps (the lift alone, or
        # hanging still) must not go round even once,
        # so the turns are the pumping's
        alone = {"seconds": script["seconds"],
                 "events": [e for e in script["events"] if "mouse" not in e or e["t"] == 0.0]}
        lift_turns, _ = score(alone)
        ok = all(o.passed for o in outcomes) and lift_turns < 1.0
        print(f"  without its mouse sweeps: {lift_turns:.2f} turns", flush=True)
        print(f"try {k}: {turns:.2f} turns in {script['seconds']:.1f} s, "
              f"{'passes' if ok else 'fails'}", flush=True)
        # the shortest passing run; else the most turns
        key = (ok, turns if not ok else -script["seconds"])
        if best is None or key > best[0]:
            best = (key, script, p, outcomes)
    key, script, p, outcomes = best
    for o in outcomes:
        print(o)
    print("numbers:", {n: round(v, 3) for n, v in p.items()})
    if not key[0]:
        return 1
    if args.write:
        how = ("a spotter's lift (Ctrl+drag of the pelvis) swings the hanging figure up in "
               "front, then " if args.lift else "from a dead hang, ")
        head = {"description": "Giant swings on the high bar: " + how + "the mouse (swing "
                               "mode) pikes the body on each rising half of the swing and "
                               "stretches it as it falls, pumping it up and over the top and "
                               "round the bar; played by tools/tune_giant.py's player.",
                "interface": INTERFACE, "scene": "highbar"}
        args.write.write_text(yaml.safe_dump({**head, **script}, sort_keys=False,
                                             default_flow_style=None, width=100))
        print("wrote", args.write)
    return 0


if __name__ == "__main__":
    sys.exit(main())
