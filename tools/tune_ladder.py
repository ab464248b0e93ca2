"""Search the IK ladder climb (assets/scripts/biped-ladder-climb.yaml) limb by limb from
checkpoints, and check the script on the log's own expectations.

    python tools/tune_ladder.py [--write] [--partial SCRIPT] [--rounds N] [--prefix SCRIPT]

The climb is the state machine's order, four rounds of the near hand, the far hand,
the near foot and the far foot, less the far foot's last turn (with the hands on the
top rung a foot above rung 7 puts the hips above the hands: the body falls back off its
feet). A hand's turn is g (two rungs up: rung 4 from the floor, then 6, 8, 10; a
candidate landing elsewhere does not count); a foot's, t (one rung up; from the floor,
rung 2) or g (two). Every turn is a phase that starts with a checkpoint (an ``action:
checkpoint`` entry of the script, so the recorded log is the searched run bit for
bit); each candidate is played from that checkpoint: optionally a posture key first (h
push with the legs, n bend them, u pull with the arms, y push with them) 0.3 or 0.7 s
before the limb's key, and optionally one (h, y, u) 0.5 or 0.9 s after it; the phase
ends 1.8 s after the limb's key. A candidate counts if every limb that held still holds
at the end of the phase and the moving limb holds a rung above the one it left; they
rank by how the body stands - the share of the phase's samples (every 1/20 s) with the
chest within 25 deg of upright, the pelvis within 0.35 m of the rungs' x and both feet
below the pelvis (what the log's mostly_within expectations measure), from the third
round on plus the same at the phase's last sample (the next phase starts there) - then
by the rung the limb reached. Depth first: the best candidate of a phase is kept, the
next (up to KEEP) tried if the phases after it find nothing (the first candidate of
the first phase leads to a dead end in the first two rounds: the search comes back
to the second). The grid is fixed, so the search is deterministic (about ten minutes
on a loaded machine). The script is then recorded as a log in a temporary folder and
replayed with assets/logs/biped-ladder-climb.expect.yaml (exit 1 if it fails); --write
writes it over the script. --partial writes the furthest climb found so far as the
search goes, --rounds and --prefix (start after a script's phases) are for trials.
"""

from __future__ import annotations

import argparse
import itertools
import math
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

INTERFACE, SCENE = "biped-ladder", "ladder"
NAME = "biped-ladder-climb"
LIMBS = ("hand_near", "hand_far", "foot_near", "foot_far")  # the state machine's order
ROUNDS = 4
# the far foot's last turn is left out: with the hands on the top rung, a foot above
# rung 7 puts the hips above the hands, and the body falls back off its feet
LAST = 15
LADDER_X = 0.45  # m: the rungs' x (assets/scenes/ladder.yaml)
PRE = (None, "h", "n", "u", "y")  # a posture key before the limb's (None: none)
PRE_GAP = (0.3, 0.7)  # s from it to the limb's key
POST = (None, "h", "y", "u")  # a posture key after the limb's
POST_GAP = (0.5, 0.9)  # s after the limb's key
PHASE = 1.8  # s from the limb's key to the end of its phase (the reach ends at 1.5-1.6 s)
SETTLE = 2.0  # s after the last phase (the log ends there)
KEEP = 2  # candidates of a phase tried before going back to the phase before
SAMPLE = 1 / 20  # s between posture samples
END_FROM = 2  # from this round (0: the first) a phase's last sample counts too


def posture(character) -> tuple[bool, bool, bool]:
    """(chest within 25 deg of upright, pelvis within 0.35 m of the rungs' x, both feet
    below the pelvis): what the log's mostly_within expectations measure."""
    chest = abs(math.degrees(math.remainder(character.bodies["chest"].angle, 2 * math.pi)))
    px, py = character.link_position("pelvis")
    feet = max(character.link_position(f)[1] for f in ("foot_near", "foot_far"))
    return chest <= 25.0, abs(px - LADDER_X) <= 0.35, feet < py


def script(entries: list[dict], seconds: float) -> ScriptSpec:
    return ScriptSpec.model_validate({"interface": INTERFACE, "scene": SCENE,
                                      "seconds": seconds, "events": entries})


def keys_of(limb: str) -> tuple[str, ...]:
    return ("g",) if limb.startswith("hand") else ("t", "g")


def rows(t0: float, limb: str):
    """(entries, end) of each candidate of a phase starting at ``t0``."""
    for key, pre, pre_gap, post, post_gap in itertools.product(
            keys_of(limb), PRE, PRE_GAP, POST, POST_GAP):
        if (pre is None and pre_gap != PRE_GAP[0]) or (post is None and post_gap != POST_GAP[0]):
            continue
        out = [{"t": round(t0, 4), "action": "checkpoint"}]
        at = t0 + 0.01
        if pre is not None:
            out.append({"t": round(at, 4), "key": pre})
            at += pre_gap
        out.append({"t": round(at, 4), "key": key})
        if post is not None:
            out.append({"t": round(at + post_gap, 4), "key": post})
        yield out, round(at + PHASE, 4)


def ranked(entries: list[dict], t: float, limb: str, end_too: bool) -> list[tuple]:
    """The candidates of ``limb``'s phase that work from the end of ``entries`` (at
    ``t``), best first: (value, row, end, rungs held after)."""
    s = Session(load_setup(INTERFACE, SCENE))
    dt = s.sim.dt
    play(s, compile_script(script(entries, t), dt), round(t / dt))
    before = {n: rung(s.sim, n) for n in LIMBS}
    s.handle(ev.action("checkpoint"))  # what the phase's first entry does, at step t
    every = max(1, round(SAMPLE / dt))
    out = []
    for row, end in rows(t, limb):
        s.restore_checkpoint()
        seen = []
        play(s, [e for e in compile_script(script(entries + row, end), dt)
                 if e[0] > round(t / dt)], round(end / dt), every=every,
             on_tick=lambda s, seen=seen: seen.append(posture(s.character)))
        now = {n: rung(s.sim, n) for n in LIMBS}
        if not all(now[n] for n in LIMBS if before[n]) or now[limb] <= before[limb]:
            continue
        if limb.startswith("hand") and now[limb] != (before[limb] + 2 if before[limb] else 4):
            continue  # a hand two rungs up (from the floor: rung 4)
        # the share of the phase's samples standing well, and (from round END_FROM on)
        # how it ends: the next phase starts from there
        value = sum(sum(p) for p in seen) / (3 * max(1, len(seen)))
        if end_too:
            value += sum(posture(s.character)) / 3
        out.append(((round(value, 3), now[limb]), row, end, now))
    out.sort(key=lambda c: c[0], reverse=True)
    return out


def search(partial: Path | None = None, rounds: int = ROUNDS,
           prefix: Path | None = None) -> tuple[list[dict], float]:
    phases = [limb for _ in range(rounds) for limb in LIMBS][:LAST]
    deepest = [-1]

    def go(entries, t, number):
        if partial is not None and number > deepest[0]:  # the furthest climb so far
            deepest[0] = number
            write_script(entries, round(t + SETTLE, 4), partial)
        if number == len(phases):
            return entries, t
        limb = phases[number]
        for value, row, end, now in ranked(entries, t, limb,
                                             number >= END_FROM * len(LIMBS))[:KEEP]:
            keys = " ".join(e["key"] for e in row if "key" in e)
            print(f"{'  ' * number}phase {number} ({limb}): {keys} -> {now}, "
                  f"posture {value[0]:.2f}", flush=True)
            found = go(entries + row, end, number + 1)
            if found is not None:
                return found
        return None

    first, t0, number = [], 0.5, 0
    if prefix is not None:  # a script's phases taken as they are (a trial from there)
        spec = yaml.safe_load(prefix.read_text())
        first, t0 = spec["events"], spec["seconds"] - SETTLE
        number = sum(1 for e in first if e.get("key") in ("g", "t"))
    found = go(first, round(t0, 4), number)
    if found is None:
        raise SystemExit("no climb found")
    return found[0], round(found[1] + SETTLE, 4)


def write_script(entries: list[dict], seconds: float, path: Path) -> None:
    text = {"description": "The human figure climbs the ladder with hands and feet, every "
                           "limb regrasping in the order the state machine keeps (near "
                           "hand, far hand, near foot, far foot), four rounds: the hands "
                           "two rungs at a time from rung 4 to rung 10, the feet from the "
                           "floor, each turn with the posture keys (h, n, u, y) before or "
                           "after it that tools/tune_ladder.py found, phase by phase from "
                           "checkpoints, standing up to the ladder.",
            "interface": INTERFACE, "scene": SCENE, "seconds": seconds, "events": entries}
    path.write_text(yaml.safe_dump(text, sort_keys=False, width=100), encoding="utf-8")


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--write", action="store_true", help="write the script")
    parser.add_argument("--partial", type=Path, help="write the furthest climb found so "
                                                     "far to this script, as the search goes")
    parser.add_argument("--rounds", type=int, default=ROUNDS,
                        help=f"rounds of the four limbs (default {ROUNDS}; fewer: a trial)")
    parser.add_argument("--interface", default=INTERFACE, help="an interface to try")
    parser.add_argument("--prefix", type=Path, help="start after this script's phases")
    args = parser.parse_args()
    globals()["INTERFACE"] = args.interface
    entries, seconds = search(args.partial, args.rounds, args.prefix)
    out = ROOT / "assets" / "scripts" / f"{NAME}.yaml"
    with tempfile.TemporaryDirectory() as tmp:
        path = out if args.write else Path(tmp) / f"{NAME}.yaml"
        write_script(entries, seconds, path)
        expect = ROOT / "assets" / "logs" / f"{NAME}.expect.yaml"
        log = record_script(str(path), Path(tmp) / f"{NAME}.jsonl")
        result = replay_log(log, expect=yaml.safe_load(expect.read_text())["expect"])
        for o in result.outcomes:
            print(("  ok   " if o.passed else "  FAIL ") + f"{o.expectation}: {o.measured}")
        return 0 if all(o.passed for o in result.outcomes) else 1


if __name__ == "__main__":
    sys.exit(main())
