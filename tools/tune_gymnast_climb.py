"""Search the gymnast's ladder climb (assets/scripts/biped-gymnast-climb-bound.yaml)
phase by phase from checkpoints, and check the script on its log's own expectations.

    python tools/tune_gymnast_climb.py bound [--write]

The performance is what a person at the mouse does: q and w open the hands, e brings
them to the rung at 1.8 m, z and x grip it rigidly (the forearms keep their angle to the
rung); 2 picks the bound mapping. Then phases, each a let-go of the limbs
that move (z / x for a hand, a / s for a foot; a foot still on the floor is only armed),
one stroke of the mouse and, a moment later, the same keys again (armed: each limb
catches the first rung that comes within 5 cm of it).

The bound pattern: the feet together with the mouse up (legs gather, arms pull the
body up to the hands), then the hands together with the mouse down (legs push the body
up on the rigid feet, arms reach up); three rounds, and the feet twice more. (A trot
climb - the diagonal mapping moves one arm with the other side's leg, so the limbs that
hold would be the pushing leg and the pulling arm - is not searched yet.) A foot aims
for the rung four under the hands (1.2 m: the stretch that reaches the next rung; three
for the last stroke, as the hands' fourth rung was out of reach), a hand for the rung
above: strokes that land there rank first.

Every phase starts with a checkpoint (an ``action: checkpoint`` entry of the script,
so the recorded log is the searched run bit for bit); each candidate stroke - mouse x
(the waist) and y at the end, its duration, and when the keys come again - is played
from that checkpoint. A stroke counts if the limbs moved each hold a rung above the one
they left and every limb holds at the end of the phase; they rank by how near the
moved limbs land to the rungs aimed for, then by the height of the centre of mass.
Depth first: the best stroke of a phase is kept, and the next (up to ``KEEP``) tried
if the phases after it find nothing. The grid is fixed, so the search is deterministic
(about 3 minutes on a loaded machine). The script is then recorded as a log in a
temporary folder and replayed with its ``.expect.yaml`` sidecar (exit 1 if an
expectation fails); --write writes the script.
"""

from __future__ import annotations

import argparse
import itertools
import sys
import tempfile
from pathlib import Path

import yaml

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from puppet.data.catalog import ROOT, load_setup  # noqa: E402
from puppet.interface import events as ev  # noqa: E402
from puppet.session import Session  # noqa: E402
from puppet.testing import record_script, replay_log  # noqa: E402
from puppet.timeline.playback import play  # noqa: E402
from puppet.timeline.script import ScriptSpec, compile_script  # noqa: E402

INTERFACE, SCENE = "biped-gymnast", "ladder"
KEY = {"hand_near": "z", "hand_far": "x", "foot_near": "a", "foot_far": "s"}
SETTLE = 0.8  # s after a stroke before the phase is judged (and the next begins)
START = [  # hands to the rung at 1.8 m, gripped rigidly
    {"t": 0.0, "key": "q"}, {"t": 0.0, "key": "w"}, {"t": 0.0, "key": "e"},
    {"t": 0.2, "key": "z"}, {"t": 0.2, "key": "x"}]
# pattern -> (mode key, mouse y at the start of the rounds, phases: (limbs, y targets,
# rungs from the feet up to the hands a foot aims for))
PATTERNS = {
    "bound": ("2", 0.0, [(("foot_near", "foot_far"), (0.8, 0.9, 1.0), 4),
                         (("hand_near", "hand_far"), (0.0, 0.2, 0.3, 0.4), 4)] * 3
              + [(("foot_near", "foot_far"), (0.8, 0.9, 1.0), 4),
                 (("foot_near", "foot_far"), (0.8, 0.9, 1.0), 3)]),
}
XS = (0.2, 0.4, 0.6, 0.8)  # mouse x: the waist, 20 deg back .. 60 forward
DURATIONS = (0.6, 1.0, 1.4)  # s the stroke takes
REARM = (0.15, 0.35)  # s after the let-go the keys come again
HAND_XS = (0.6, 0.7, 0.8, 0.9, 1.0)  # the waist bent forward: the body leans to the rungs
HAND_REARM = (0.35, 0.6)  # later: clear of the rung the hands left
KEEP = 3  # strokes of a phase tried before going back to the phase before


def rung(sim, name: str) -> int:
    """The number of the rung ``name`` holds (0: none)."""
    held = sim.grasps.get(name)
    if held is None or held[1] is None:
        return 0
    point = sim.props[held[1]].nearest(sim.grasp_point(name))[2]
    return int(point[4:]) if point else 0


def goal(limb: str, before: dict, gap: int) -> int:
    """The rung a moving limb aims for: a hand one above the highest hand, a foot
    ``gap`` rungs under the highest
    hand."""
    hands = max(before["hand_near"], before["hand_far"])
    if limb.startswith("hand"):
        return hands + 1
    return hands - gap


def script(entries: list[dict], seconds: float) -> ScriptSpec:
    return ScriptSpec(interface=INTERFACE, scene=SCENE, seconds=seconds, events=entries)


def stroke(t0: float, limbs, held: dict, x: float, y: float, duration: float,
           rearm: float) -> list[dict]:
    out = [{"t": round(t0, 4), "action": "checkpoint"}]
    for limb in limbs:
        if held[limb]:
            out.append({"t": round(t0 + 0.01, 4), "key": KEY[limb]})  # let go
    out.append({"t": round(t0 + 0.01, 4), "mouse": [x, y], "over": duration})
    for limb in limbs:
        out.append({"t": round(t0 + 0.01 + rearm, 4), "key": KEY[limb]})  # armed again
    return out


def ranked(pattern: str, entries: list[dict], t: float, limbs, ys, gap: int) -> list[tuple]:
    """The strokes of phase ``limbs`` that work from the end of ``entries`` (at ``t``),
    best first: (value, row, end, rungs held after)."""
    s = Session(load_setup(INTERFACE, SCENE))
    dt = s.sim.dt
    play(s, compile_script(script(entries, t), dt), round(t / dt))
    before = {n: rung(s.sim, n) for n in KEY}
    held = {n: n in s.sim.grasps for n in KEY}
    s.handle(ev.action("checkpoint"))  # what the phase's first entry does, at step t
    out = []
    hands = limbs[0].startswith("hand")  # a hand stroke: wider, later re-grips
    grid = itertools.product(HAND_XS if hands else XS, ys, DURATIONS,
                             HAND_REARM if hands else REARM)
    for x, y, duration, rearm in grid:
        row = stroke(t, limbs, held, x, y, duration, rearm)
        end = round(t + 0.01 + duration + SETTLE, 4)
        s.restore_checkpoint()
        play(s, [e for e in compile_script(script(entries + row, end), dt)
                 if e[0] > round(t / dt)], round(end / dt))
        now = {n: rung(s.sim, n) for n in KEY}
        if not all(now[n] > before[n] for n in limbs) or not all(now.values()):
            continue
        miss = sum(abs(now[n] - goal(n, before, gap)) for n in limbs)
        out.append(((-miss, round(s.character.com()[1], 6)), row, end, now))
    out.sort(key=lambda c: c[0], reverse=True)
    return out


def search(pattern: str) -> tuple[list[dict], float]:
    """Depth first over the phases: each phase's strokes best first, the next
    ``KEEP`` tried if the phases after it find nothing."""
    mode, y0, phases = PATTERNS[pattern]
    start = START + [{"t": 1.2, "key": mode}, {"t": 1.2, "mouse": [0.5, y0], "over": 0.5}]

    def go(entries, t, number):
        if number == len(phases):
            return entries, t
        limbs, ys, gap = phases[number]
        for value, row, end, now in ranked(pattern, entries, t, limbs, ys, gap)[:KEEP]:
            print(f"{'  ' * number}phase {number} ({', '.join(limbs)}): "
                  f"{[e for e in row if 'mouse' in e][0]} -> {now}, com y {value[1]:.2f}",
                  flush=True)
            found = go(entries + row, end, number + 1)
            if found is not None:
                return found
        return None

    found = go(start, 2.2, 0)
    if found is None:
        raise SystemExit("no climb found")
    return found[0], round(found[1] + 1.0, 4)


def write_script(pattern: str, entries: list[dict], seconds: float, path: Path) -> None:
    what = "both feet together, then both hands together, three rounds, and the feet twice more"
    text = {"description": f"The gymnast climbs the ladder in the {pattern} pattern ({what}): "
                           "hands gripping rigidly (z, x), feet rigid (a, s), each regrasp a "
                           "let-go, one mouse stroke and the key again; found phase by phase "
                           "from checkpoints by tools/tune_gymnast_climb.py.",
            "interface": INTERFACE, "scene": SCENE, "seconds": seconds, "events": entries}
    path.write_text(yaml.safe_dump(text, sort_keys=False, width=100), encoding="utf-8")


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("pattern", choices=sorted(PATTERNS))
    parser.add_argument("--write", action="store_true", help="write the script")
    args = parser.parse_args()
    name = f"biped-gymnast-climb-{args.pattern}"
    entries, seconds = search(args.pattern)
    out = ROOT / "assets" / "scripts" / f"{name}.yaml"
    with tempfile.TemporaryDirectory() as tmp:
        path = out if args.write else Path(tmp) / f"{name}.yaml"
        write_script(args.pattern, entries, seconds, path)
        expect = ROOT / "assets" / "logs" / f"{name}.expect.yaml"
        if not expect.exists():
            print(f"{expect.name} missing: not checked")
            return 0
        log = record_script(str(path), Path(tmp) / f"{name}.jsonl")
        result = replay_log(log, expect=yaml.safe_load(expect.read_text())["expect"])
        for o in result.outcomes:
            print(("  ok   " if o.passed else "  FAIL ") + f"{o.expectation}: {o.measured}")
        return 0 if all(o.passed for o in result.outcomes) else 1


if __name__ == "__main__":
    sys.exit(main())
