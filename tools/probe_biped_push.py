"""How hard a push on the chest the standing human figure survives, targets held.

    .venv/bin/python tools/probe_biped_push.py [--character biped]

For each ankle setting (the character's own, and softer or less damped ones) it finds
by bisection the largest horizontal impulse (N*s) at the chest's centre of mass,
backward and forward, after which the figure still stands 4 s later (pelvis and chest
within 45 deg of upright, both feet touching). A number for a balance controller to
beat; nothing is shipped from here.
"""

from __future__ import annotations

import argparse
import math

from puppet.data.catalog import load_character_named, load_scene_named
from puppet.physics.simulation import Simulation

SETTINGS = {  # name: ankle (stiffness factor, damping N*m*s/rad or None = the file's)
    "as in the file": (1.0, None),
    "stiff ankle x2": (2.0, None),
    "soft ankle x0.5": (0.5, None),
    "ankle damping 4": (1.0, 4.0),
    "soft x0.5, damping 4": (0.5, 4.0),
}


def stands_after(character: str, impulse: float, stiffness: float, damping) -> bool:
    spec, _ = load_character_named(character)
    for joint in spec.joints:
        if joint.name.startswith("ankle") and joint.pd is not None:
            joint.pd.stiffness *= stiffness
            if damping is not None:
                joint.pd.damping = damping
    scene, _ = load_scene_named("flat")
    sim = Simulation(spec, scene)
    c = sim.character
    sim.step(480)
    chest = c.bodies["chest"]
    chest.apply_impulse_at_local_point((impulse, 0.0), chest.center_of_gravity)
    sim.step(4 * 480)
    upright = all(abs(math.degrees(math.remainder(c.bodies[n].angle, 2 * math.pi))) < 45
                  for n in ("pelvis", "chest"))
    return upright and c.in_contact("foot_near") and c.in_contact("foot_far")


def largest(character: str, sign: float, stiffness: float, damping, top: float = 80.0) -> float:
    lo, hi = 0.0, top
    if stands_after(character, sign * hi, stiffness, damping):
        return hi
    for _ in range(9):
        mid = (lo + hi) / 2
        if stands_after(character, sign * mid, stiffness, damping):
            lo = mid
        else:
            hi = mid
    return lo


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--character", default="biped")
    args = parser.parse_args()
    print(f"{args.character}: largest chest impulse survived (N*s), 4 s after the push")
    for name, (stiffness, damping) in SETTINGS.items():
        back = largest(args.character, -1.0, stiffness, damping)
        fwd = largest(args.character, 1.0, stiffness, damping)
        print(f"  {name:22s} backward {back:5.1f}   forward {fwd:5.1f}", flush=True)


if __name__ == "__main__":
    main()
