"""Play the monkey bars of interfaces/biped-bars.yaml as a person watching the figure
would, write the key presses as a script and check it on the log's own expectations.

    python tools/play_bars.py [--leads 0.3 0.45 0.6] [--write]

The performer is closed-loop on what is on screen, with the keys a person has: it
waits for the mount (both hands on the first bar, knees up), pulls up on the near arm
(`w`) and sends the far hand to the next bar (`d`); every time the reaching hand has
caught its bar it swaps the arms (space), lets go with the rear hand (`x`) so the body
swings forward under the new bar, pulls up (`w`) as the shoulder passes under that
bar (the bottom of the swing: pumping, as on a playground swing) and presses `d` as
the forward swing slows, when the shoulder's forward speed drops below ``lead`` m/s
(so the hand arrives near the top of the swing). After the last bar it lets go with
the rear hand and hangs. The presses are exact steps; they are written as a script
(assets/scripts/biped-monkey-bars.yaml with --write), recorded as a log in a
temporary folder and replayed with assets/logs/biped-monkey-bars.expect.yaml. A
``lead`` passes or fails as a whole; the best is the one that passes and finishes
first. Deterministic: the same interface gives the same script.

The shipped script is now played by watching (rules on the same cues: the body
under the support hand, the forward swing slowing; see its comments), so that a
playtest's tries follow the swing; ``--write`` would replace it with a timed one.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import yaml

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from puppet.data.catalog import ROOT, load_setup  # noqa: E402
from puppet.interface import events as ev  # noqa: E402
from puppet.session import Session  # noqa: E402
from puppet.testing import replay_script_text  # noqa: E402

INTERFACE = ROOT / "interfaces" / "biped-bars.yaml"
SCRIPT = ROOT / "assets" / "scripts" / "biped-monkey-bars.yaml"
EXPECT = ROOT / "assets" / "logs" / "biped-monkey-bars.expect.yaml"
BARS = 7
SHOULDER = (0.0, 1.432)  # the shoulders' hinge on the chest, model frame
HANG = 3.0  # s hanging from the last bar at the end


def perform(lead: float, start: float = 3.0, patience: float = 2.0):
    """Play the bars; return (the presses [(t, key)], the last bar held, end time)."""
    s = Session(load_setup(str(INTERFACE), None))
    c, dt, sim = s.character, s.sim.dt, s.sim
    presses: list[tuple[float, str]] = []

    def press(key: str) -> None:
        presses.append((round(s.steps * dt, 6), key))
        s.handle(ev.key(key, True))
        s.handle(ev.key(key, False))

    def wait(seconds: float) -> None:
        s.advance(max(1, round(seconds / dt)))

    def holds(chain: str) -> str | None:
        if chain not in sim.grasps:
            return None
        prop = sim.grasps[chain][1]
        return sim.props[prop].nearest(sim.grasp_point(chain))[2] if prop else None

    def shoulder_x() -> float:
        return c.bodies["chest"].local_to_world(SHOULDER)[0]

    wait(start)
    support, bar = "hand_near", 1
    press("w")
    wait(0.5)
    press("d")
    while True:
        reach = "hand_far" if support == "hand_near" else "hand_near"
        t0 = s.time
        while s.time - t0 < patience and holds(reach) != f"bar{bar + 1}":
            wait(1 / 120)
        if holds(reach) != f"bar{bar + 1}":
            return presses, bar, s.time
        bar += 1
        wait(0.3)
        press("space")
        support = reach
        press("x")  # the rear hand lets go: the body swings forward under the new bar
        if bar == BARS:
            wait(HANG)
            return presses, bar, s.time
        under = sim.grasp_point(support)[0]
        t0 = s.time
        while s.time - t0 < patience and shoulder_x() < under:
            wait(1 / 120)
        press("w")  # pull up at the bottom of the swing
        t0, last = s.time, shoulder_x()
        while s.time - t0 < patience:
            wait(1 / 120)
            x = shoulder_x()
            speed, last = (x - last) * 120, x
            if speed <= lead:
                break
        press("d")


def script_text(presses, seconds: float, lead: float) -> str:
    head = {"description": "The human figure crosses the seven monkey bars hand over hand: "
                           "mounted from the platform, it pulls up on the support arm at the "
                           "bottom of each swing and reaches for the next bar as the swing "
                           "slows; after the last bar it hangs from one hand. Written by "
                           f"tools/play_bars.py (lead {lead:g} m/s).",
            "interface": "biped-bars", "scene": "monkey-bars", "seconds": round(seconds, 3)}
    lines = [yaml.safe_dump(head, sort_keys=False, width=100).rstrip(), "events:"]
    lines += [f"  - {{t: {t:.6g}, key: {'space' if k == 'space' else k}}}" for t, k in presses]
    return "\n".join(lines) + "\n"


def check(text: str):
    """The script ``text`` played and judged by the shipped log's expectations."""
    return replay_script_text(text, INTERFACE, EXPECT)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--leads", type=float, nargs="+", default=[0.3, 0.45, 0.6])
    ap.add_argument("--write", action="store_true", help=f"write {SCRIPT.relative_to(ROOT)}")
    args = ap.parse_args()
    best = None
    for lead in args.leads:
        presses, bar, end = perform(lead)
        text = script_text(presses, end, lead)
        result = check(text)
        failed = [str(o) for o in result.outcomes if not o.passed]
        print(f"lead {lead:g}: bar {bar} at {end:.2f} s, "
              + ("passes" if not failed else f"fails: {failed[0]}"), flush=True)
        if not failed and (best is None or end < best[0]):
            best = (end, lead, text, result)
    if best is None:
        return 1
    for o in best[3].outcomes:
        print(o)
    if args.write:
        SCRIPT.write_text(best[2], encoding="utf-8")
        print(f"wrote {SCRIPT.relative_to(ROOT)} (lead {best[1]:g})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
