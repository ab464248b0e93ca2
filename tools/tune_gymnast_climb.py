"""Search the gymnast's ladder climbs (assets/scripts/biped-gymnast-climb-bound.yaml,
-trot.yaml) phase by phase from checkpoints, and check a script on its log's own
expectations.

    python tools/tune_gymnast_climb.py bound|trot [--write]

The performance is what a person at the mouse does: q and w open the hands, e brings
them to the rung at 1.8 m, z and x grip it rigidly (the forearms keep their angle to the
rung); 2 picks the bound mapping. Then phases, each a let-go of the limbs
that move (z / x for a hand, a / s for a foot; a foot still on the floor is only armed),
one stroke of the mouse and, a moment later, the same keys again (armed: each limb
catches the first rung that comes within 5 cm of it).

The bound pattern: d brings the hands to the rung at 1.5 m (rung 5); then the feet
together with the mouse up (legs gather, arms pull the body up to the hands), then the
hands together with the mouse down (legs push the body up on the rigid feet, arms
reach up); four rounds, and the feet twice more. A foot aims for the rung above its own
(from the floor: four under the hands, the stretch that reaches the next rung), a hand
for the rung above its own: strokes that land there rank first. (Started from rung 6
with e, the hands' fourth rung, rung 10, is out of reach from rung 9: the body falls
back off the feet as both hands let go.)

The trot pattern: both feet onto rung 2 as in the bound, then 3 (the trot mapping) and
the diagonal pairs by turns, four rounds - the near hand and the far foot with the
mouse up (the far arm pulls and the near leg pushes), the far hand and the near foot
with it down. A trot stroke may be preloaded: the mouse first to the stroke's far end
(PRELOAD s, every limb still holding), then the let-go; both kinds are tried.

Every phase starts with a checkpoint (an ``action: checkpoint`` entry of the script,
so the recorded log is the searched run bit for bit); each candidate stroke - mouse x
(the waist) and y at the end, its duration, and when the keys come again - is played
from that checkpoint. A stroke counts if the limbs moved each hold a rung above the one
they left and every limb holds at the end of the phase; they rank by how near the
moved limbs land to the rungs aimed for, then by the height of the centre of mass.
Depth first: the best stroke of a phase is kept, and the next (up to ``KEEP[pattern]``) tried
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
from puppet.session.playback import play  # noqa: E402
from puppet.testing import record_script, replay_log  # noqa: E402
from puppet.timeline.script import ScriptSpec, compile_script  # noqa: E402
from tools.ladder_rungs import rung  # noqa: E402

INTERFACE, SCENE = "biped-gymnast", "ladder"
KEY = {"hand_near": "z", "hand_far": "x", "foot_near": "a", "foot_far": "s"}
SETTLE = 0.8  # s after a stroke before the phase is judged (and the next begins)


def start(pose: str) -> list[dict]:
    """The hands to the rung of the pose key (e: 1.8 m, d: 1.5 m), gripped rigidly."""
    return [{"t": 0.0, "key": "q"}, {"t": 0.0, "key": "w"}, {"t": 0.0, "key": pose},
            {"t": 0.2, "key": "z"}, {"t": 0.2, "key": "x"}]


FEET, HANDS = ("foot_near", "foot_far"), ("hand_near", "hand_far")
UP, DOWN = (0.8, 0.9, 1.0), (0.0, 0.2, 0.3, 0.4)  # mouse y targets of a stroke
# pattern -> (mode key, pose key, mouse y at the start of the rounds, phases: (limbs,
# y targets, rungs from the feet up to the hands a foot aims for), what it does)
PATTERNS = {
    "bound": ("2", "d", 0.0, [(FEET, UP, 4), (HANDS, DOWN, 4, 0.0)] * 4
              + [(FEET, UP, 4), (FEET, UP, 3)],
              "both feet together, then both hands together, four rounds, and the feet "
              "twice more"),
    "trot": ("2", "e", 0.0, [(FEET, UP, 4), "3"]
             + [(("hand_near", "foot_far"), UP, 4, 1.0),
                (("hand_far", "foot_near"), DOWN, 4, 0.0)] * 4,
             "both feet onto the rungs in the bound mapping, then 3 and the diagonal pairs "
             "by turns - near hand and far foot with the mouse up, far hand and near foot "
             "with it down - four rounds"),
}
XS = (0.2, 0.4, 0.6, 0.8)  # mouse x: the waist, 20 deg back .. 60 forward
DURATIONS = (0.6, 1.0, 1.4)  # s the stroke takes
REARM = (0.15, 0.35)  # s after the let-go the keys come again
HAND_XS = (0.6, 0.7, 0.8, 0.9, 1.0)  # the waist bent forward: the body leans to the rungs
HAND_REARM = (0.35, 0.6)  # later: clear of the rung the hands left
PRELOAD = 0.4  # s the mouse takes to the stroke's far end before a trot let-go
KEEP = {"bound": 2, "trot": 3}  # strokes of a phase tried before going back to the phase before


def goal(limb: str, before: dict, gap: int) -> int:
    """The rung a moving limb aims for: the rung above its own; a foot still on the
    floor, ``gap`` rungs under the highest hand."""
    if before[limb] or limb.startswith("hand"):
        return before[limb] + 1
    return max(before["hand_near"], before["hand_far"]) - gap


def script(entries: list[dict], seconds: float) -> ScriptSpec:
    return ScriptSpec.model_validate({"interface": INTERFACE, "scene": SCENE,
                                      "seconds": seconds, "events": entries})


def stroke(t0: float, limbs, held: dict, x: float, y: float, duration: float,
           rearm: dict, pre: float | None = None) -> list[dict]:
    """A phase's entries: a checkpoint, (if ``pre``) the mouse to (x, pre) in PRELOAD s
    while every limb still holds, the let-go of the held limbs that move, the mouse
    stroke, and each moving limb's key again ``rearm[limb]`` s later."""
    out = [{"t": round(t0, 4), "action": "checkpoint"}]
    if pre is not None:
        out.append({"t": round(t0 + 0.01, 4), "mouse": [x, pre], "over": PRELOAD})
        t0 += PRELOAD + 0.05
    for limb in limbs:
        if held[limb]:
            out.append({"t": round(t0 + 0.01, 4), "key": KEY[limb]})  # let go
    out.append({"t": round(t0 + 0.01, 4), "mouse": [x, y], "over": duration})
    for limb in sorted(limbs, key=lambda n: rearm[n]):
        out.append({"t": round(t0 + 0.01 + rearm[limb], 4), "key": KEY[limb]})  # armed
    return out


def grid(limbs, ys):
    """(x, y, duration, rearm per limb) of a phase's strokes: hands wider and later."""
    hands = [n for n in limbs if n.startswith("hand")]
    feet = [n for n in limbs if n.startswith("foot")]
    for x, y, duration, hand, foot in itertools.product(
            HAND_XS if hands else XS, ys, DURATIONS, HAND_REARM if hands else (None,),
            REARM if feet else (None,)):
        yield x, y, duration, {**{n: hand for n in hands}, **{n: foot for n in feet}}


def ranked(pattern: str, entries: list[dict], t: float, limbs, ys, gap: int,
           pre: float | None = None) -> list[tuple]:
    """The strokes of phase ``limbs`` that work from the end of ``entries`` (at ``t``),
    best first: (value, row, end, rungs held after)."""
    s = Session(load_setup(INTERFACE, SCENE))
    dt = s.sim.dt
    play(s, compile_script(script(entries, t), dt), round(t / dt))
    before = {n: rung(s.sim, n) for n in KEY}
    held = {n: n in s.sim.grasps for n in KEY}
    s.handle(ev.action("checkpoint"))  # what the phase's first entry does, at step t
    out = []
    for (x, y, duration, rearm), first in itertools.product(grid(limbs, ys), {None, pre}):
        row = stroke(t, limbs, held, x, y, duration, rearm, first)
        end = round(t + 0.01 + duration + SETTLE + (0 if first is None else PRELOAD + 0.05), 4)
        s.restore_checkpoint()
        play(s, [e for e in compile_script(script(entries + row, end), dt)
                 if e[0] > round(t / dt)], round(end / dt))
        now = {n: rung(s.sim, n) for n in KEY}
        if not all(now[n] > before[n] for n in limbs) or not all(
                now[n] for n in KEY if before[n] or n in limbs):  # all that held hold
            continue
        miss = sum(abs(now[n] - goal(n, before, gap)) for n in limbs)
        out.append(((-miss, round(s.character.com()[1], 6)), row, end, now))
    out.sort(key=lambda c: c[0], reverse=True)
    return out


def search(pattern: str) -> tuple[list[dict], float]:
    """Depth first over the phases: each phase's strokes best first, the next
    ``KEEP[pattern]`` tried if the phases after it find nothing."""
    mode, pose, y0, phases, _ = PATTERNS[pattern]
    first = start(pose) + [{"t": 1.2, "key": mode},
                           {"t": 1.2, "mouse": [0.5, y0], "over": 0.5}]

    def go(entries, t, number):
        if number == len(phases):
            return entries, t
        if isinstance(phases[number], str):  # a mode key between two phases
            return go(entries + [{"t": round(t, 4), "key": phases[number]}],
                      round(t + 0.01, 4), number + 1)
        limbs, ys, gap, *pre = phases[number]
        for value, row, end, now in ranked(pattern, entries, t, limbs, ys, gap,
                                           *pre)[:KEEP[pattern]]:
            print(f"{'  ' * number}phase {number} ({', '.join(limbs)}): "
                  f"{[e for e in row if 'mouse' in e][0]} -> {now}, com y {value[1]:.2f}",
                  flush=True)
            found = go(entries + row, end, number + 1)
            if found is not None:
                return found
        return None

    found = go(first, 2.2, 0)
    if found is None:
        raise SystemExit("no climb found")
    return found[0], round(found[1] + 1.0, 4)


def write_script(pattern: str, entries: list[dict], seconds: float, path: Path) -> None:
    what = PATTERNS[pattern][4]
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
