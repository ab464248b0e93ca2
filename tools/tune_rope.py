"""Find the pumping rhythm of the gymnast's swing on the rope
(assets/scripts/biped-rope-swing.yaml).

    python tools/tune_rope.py [--from 0.6] [--to 1.8] [--step 0.05] [--seconds 30]
                              [--write assets/scripts/biped-rope-swing.yaml]

interfaces/biped-gymnast.yaml on the `rope` scene (six dynamic links hanging from a
pivot 4.4 m up; the figure holds the lower ones), in swing mode. What a person does to
get a rope swinging from a still hang: sweep the mouse right and up (arms close, hips
pike: the legs swing forward) and back left and down (arms overhead, body stretched)
in the rope's own rhythm, the same sweep every half period. The rhythm is the one
number: this tool plays every half period from ``--from`` to ``--to`` s (a sweep of
0.1 s at each), scores each on the log's own expectations
(assets/logs/biped-rope-swing.expect.yaml, replayed as ``puppet play --record`` does)
and keeps the passing one that swings widest at the end; the same script without its
sweeps (the mouse parked, hanging still) must fail them. The tools/tune_giant.py
player (which reads the swing's phase and pumps on it) does not get going here: from a
still hang the centre of mass stays within 2 deg of straight under the pivot, so it has
no phase to read.
"""

from __future__ import annotations

import argparse
import re
import sys
from pathlib import Path

import yaml

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from puppet.data.catalog import load_setup  # noqa: E402
from puppet.session import Session  # noqa: E402
from puppet.session.playback import play  # noqa: E402
from puppet.timeline.expectations import evaluate_all, load_expectations  # noqa: E402
from puppet.timeline.replay import SAMPLE_EVERY, Sampler  # noqa: E402
from puppet.timeline.script import ScriptSpec, compile_script  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
LOG = ROOT / "assets/logs/biped-rope-swing.jsonl"  # its sidecar .expect.yaml
INTERFACE, SCENE = "biped-gymnast", "rope"
PIKE, ARCH = (0.71, 0.67), (0.2, 0.2)  # the giant swings' mouse points (swing mode)
START, GLIDE = 0.5, 0.1  # s: the first sweep; each sweep's glide


def script(half: float, seconds: float, sweeps: bool = True) -> dict:
    events = [{"t": 0.0, "mouse": list(ARCH)}]
    t, k = START, 0
    while sweeps and t < seconds - GLIDE:
        events.append({"t": round(t, 3), "mouse": list(PIKE if k % 2 == 0 else ARCH),
                       "over": GLIDE})
        t, k = t + half, k + 1
    return {"seconds": seconds, "events": events}


def score(s: dict) -> list:
    """The log's expectations on the script played through the Session."""
    spec = ScriptSpec.model_validate({"interface": INTERFACE, "scene": SCENE, **s})
    session = Session(load_setup(INTERFACE, SCENE))
    sampler = Sampler(session)
    sampler(session)
    play(session, compile_script(spec, session.sim.dt), round(spec.seconds / session.sim.dt),
         SAMPLE_EVERY, sampler)
    return evaluate_all(load_expectations(LOG, {}).items, sampler.trajectory(),
                        session.sim.state_hash())


def late_swing(outcomes) -> float:
    """The smaller side of the last swung window's extremes (deg)."""
    found = 0.0
    for o in outcomes:
        m = re.match(r"(-?[0-9.]+)\.\.(-?[0-9.]+) deg", o.measured)
        if o.expectation.startswith("swung") and m:
            found = min(-float(m.group(1)), float(m.group(2)))
    return found


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--from", dest="lo", type=float, default=0.6)
    ap.add_argument("--to", dest="hi", type=float, default=1.8)
    ap.add_argument("--step", type=float, default=0.05)
    ap.add_argument("--seconds", type=float, default=30.0)
    ap.add_argument("--write", type=Path)
    args = ap.parse_args()
    still = score(script(1.0, args.seconds, sweeps=False))
    print(f"hanging still: {late_swing(still):.1f} deg, "
          f"{'passes (wrong)' if all(o.passed for o in still) else 'fails'}")
    best = None
    n = round((args.hi - args.lo) / args.step)
    for k in range(n + 1):
        half = round(args.lo + k * args.step, 3)
        outcomes = score(script(half, args.seconds))
        ok = all(o.passed for o in outcomes)
        print(f"half period {half:.2f} s: {late_swing(outcomes):.1f} deg at the end, "
              f"{'passes' if ok else 'fails'}", flush=True)
        if ok and (best is None or late_swing(outcomes) > late_swing(best[1])):
            best = (half, outcomes)
    if best is None or all(o.passed for o in still):
        return 1
    half, outcomes = best
    for o in outcomes:
        print(o)
    print(f"half period: {half} s")
    if args.write:
        head = {"description": "The gymnast swinging on the rope: from a still hang the "
                               "mouse (swing mode) sweeps right and up (arms close, hips "
                               f"pike) and back left and down every {half:g} s, the rope's "
                               "own rhythm, pumping the swing up; hands on the rope "
                               "throughout. The rhythm found by tools/tune_rope.py.",
                "interface": INTERFACE, "scene": SCENE}
        args.write.write_text(yaml.safe_dump({**head, **script(half, args.seconds)},
                                             sort_keys=False, default_flow_style=None,
                                             width=100))
        print("wrote", args.write)
    return 0


if __name__ == "__main__":
    sys.exit(main())
