"""Write characters/biped.yaml and characters/biped-small.yaml from one body table.

    .venv/bin/python tools/make_biped.py

The two files are the same figure at two sizes: every length, mass, inertia and gain
below is for the 1.75 m, 70 kg figure and is scaled for the small one (lengths by
height, masses by mass, inertias by m*L^2, stiffness and torque caps by m*L, damping
by m*L^1.5 so that each servo keeps its damping ratio). Edit the numbers here, run
this, and commit both files; a test checks that the files are what this writes.
"""

from __future__ import annotations

import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
H, M = 1.75, 70.0  # the table's figure: height m, mass kg

# Joint heights above the sole (m), standing straight, everything on x = 0.
ANKLE, KNEE, HIP, WAIST, SHOULDER, NECK = 0.068, 0.499, 0.928, 1.03, 1.432, 1.48
ELBOW, WRIST, EAR = SHOULDER - 0.3255, SHOULDER - 0.3255 - 0.2555, 1.63
HEEL, TOE, MT2 = -0.06, 0.206, (0.15, 0.01)  # sole from heel to toe 0.266 m

# Winter (2009) table 4.1 (Dempster's data): mass fraction of the body, centre of mass
# from the proximal end as a fraction of the segment, radius of gyration about it.
WINTER = {
    "foot": (0.0145, 0.50, 0.475),        # lateral malleolus - 2nd metatarsal head
    "shank": (0.0465, 0.433, 0.302),      # knee - medial malleolus ("leg")
    "thigh": (0.100, 0.433, 0.323),       # greater trochanter - knee
    "upper_arm": (0.028, 0.436, 0.322),   # shoulder - elbow
    "forearm": (0.022, 0.682, 0.468),     # elbow - ulnar styloid ("forearm and hand")
    "head": (0.081, 1.000, 0.495),        # C7-T1 - ear canal ("head and neck")
    "pelvis": (0.142, 0.105, None),       # L4-L5 - greater trochanter
    "chest": (0.355, 0.63, None),         # C7-T1 - L4-L5 ("thorax and abdomen")
}

# PD gains for the 70 kg figure: stiffness N*m/rad, damping N*m*s/rad, max torque N*m
# (the probe's gains that held a quiet stance, ../shared/docs/biped-notes.md).
GAINS = {
    "waist": (600, 30, 250), "neck": (80, 4, 40),
    "hip": (1000, 50, 250), "knee": (1000, 50, 250), "ankle": (800, 30, 200),
    "shoulder": (60, 3, 40), "elbow": (30, 1.5, 25),
}
LIMITS = {  # degrees, child relative to parent, + = counter-clockwise (facing +x)
    "waist": (-80, 30),      # - bends forward, + leans back
    "neck": (-50, 50),       # - chin down, + head back
    "hip": (-30, 130),       # + swings the thigh forward (flexion)
    "knee": (-150, 0),       # - bends the shin back; a knee never bends forward
    "ankle": (-45, 30),      # + toes up (dorsiflexion), - toes down
    "shoulder": (-60, 180),  # + raises the arm forward
    "elbow": (0, 150),       # + bends the forearm forward; an elbow never bends back
}
START = {  # degrees: a relaxed stance, near leg a little ahead, arms opposite
    "waist": 0, "neck": 0,
    "hip_near": 4, "knee_near": 0, "ankle_near": -4,
    "hip_far": -4, "knee_far": 0, "ankle_far": 4,
    "shoulder_near": -6, "elbow_near": 12, "shoulder_far": 6, "elbow_far": 12,
}
SKIN, SHIRT, TROUSERS, SHOES = (232, 188, 160), (70, 120, 190), (70, 76, 96), (60, 46, 40)
NEAR_SHIRT, NEAR_TROUSERS = (96, 150, 220), (96, 104, 128)


def body_table(h: float, m: float) -> dict:
    """Per link: mass kg, centre of mass (x, y) m, inertia kg*m^2, at height h, mass m."""
    s = h / H

    def seg(name, top, bottom, x=0.0):
        frac, com, rg = WINTER[name]
        length = abs(top - bottom)
        mass = frac * M
        return mass, (x, top - com * length), mass * (rg * length) ** 2

    foot_len = ((MT2[0] - 0.0) ** 2 + (MT2[1] - ANKLE) ** 2) ** 0.5
    links = {
        "pelvis": (WINTER["pelvis"][0] * M, (0.0, WAIST - 0.105 * (WAIST - HIP)),
                   WINTER["pelvis"][0] * M * (0.19 ** 2 + 0.17 ** 2) / 12),
        "chest": (WINTER["chest"][0] * M, (0.0, NECK - 0.63 * (NECK - WAIST)),
                  WINTER["chest"][0] * M * (0.21 ** 2 + 0.47 ** 2) / 12),
        "head": seg("head", EAR, NECK),
        "upper_arm": seg("upper_arm", SHOULDER, ELBOW),
        "forearm": seg("forearm", ELBOW, WRIST),
        "thigh": seg("thigh", HIP, KNEE),
        "shank": seg("shank", KNEE, ANKLE),
        "foot": (WINTER["foot"][0] * M, (MT2[0] / 2, (ANKLE + MT2[1]) / 2 + 0.005),
                 WINTER["foot"][0] * M * (WINTER["foot"][2] * foot_len) ** 2),
    }
    # the head's centre of mass is at the ear canal (fraction 1.0 of C7-T1 to ear)
    mass, _, inertia = links["head"]
    links["head"] = (mass, (0.0, EAR), inertia)
    f_m, f_i = m / M, (m / M) * s * s
    return {k: (mass * f_m, (c[0] * s, c[1] * s), inertia * f_i)
            for k, (mass, c, inertia) in links.items()}


def fmt(v: float) -> str:
    text = f"{v:.5f}".rstrip("0").rstrip(".")
    return "0" if text in ("-0", "") else text


def pt(x: float, y: float, s: float) -> str:
    return f"[{fmt(x * s)}, {fmt(y * s)}]"


def character_text(name: str, h: float, m: float, description: str, extra_notes: str,
                   view_height: float) -> str:
    s = h / H
    table = body_table(h, m)
    k_scale = (m / M) * s          # stiffness and torque ~ m g L
    c_scale = (m / M) * s ** 1.5   # damping ~ sqrt(k * I): same damping ratio
    out = ["# Written by tools/make_biped.py: edit the numbers there and run it.",
           f"name: {name}", f"description: {description}", "notes: >"]
    notes = (
        f"A planar human, {h:g} m and {m:g} kg, thirteen links: pelvis (the root) and "
        "chest joined at the waist (L4-L5), head with neck, upper arm and forearm "
        "with hand, thigh, shank and foot on each side. Source: D. A. Winter, "
        "Biomechanics and Motor Control of Human Movement, 4th ed. (Wiley 2009), "
        "table 4.1 (Dempster's cadaver data): segment mass as a fraction of body mass "
        "/ centre of mass from the proximal joint as a fraction of the segment / "
        "radius of gyration about it: foot 0.0145 / 0.50 / 0.475 (lateral malleolus "
        "to 2nd metatarsal head), leg (shank) 0.0465 / 0.433 / 0.302, thigh 0.100 / "
        "0.433 / 0.323, upper arm 0.028 / 0.436 / 0.322, forearm and hand 0.022 / "
        "0.682 / 0.468 (elbow to ulnar styloid), head and neck 0.081 / 1.00 / 0.495 "
        "(C7-T1 to ear canal), pelvis 0.142 / 0.105 (L4-L5 to greater trochanter), "
        "thorax and abdomen 0.355 / 0.63 (C7-T1 to L4-L5). Segment lengths from "
        "Winter's figure 4.1 (fractions of height H): ankle 0.039 H, knee 0.285 H, "
        "hip 0.530 H, shoulder 0.818 H, upper arm 0.186 H, forearm 0.146 H, hand "
        "0.108 H, foot 0.152 H long. For 1.75 m, 70 kg: thigh 7.0 kg 0.429 m, shank "
        "3.26 kg 0.431 m, foot 1.02 kg 0.266 m long, upper arm 1.96 kg 0.326 m, "
        "forearm and hand 1.54 kg 0.256 m + hand, head and neck 5.67 kg, pelvis "
        "9.94 kg, chest 24.85 kg; joint heights ankle 0.068, knee 0.499, hip 0.928, "
        "waist 1.03, shoulder 1.432, neck 1.48 m. Each link's centre of mass and "
        "inertia are given explicitly from the table (the shapes only collide); "
        "pelvis and chest, for which the table gives no radius of gyration, take "
        "the inertia of their drawn boxes. Model frame: metres, y up, facing +x, "
        "origin on the ground under the hips, all joints 0 = standing straight with "
        "the arms hanging. Positive joint angles turn the child counter-clockwise: "
        "hip + swings the thigh forward, knee - bends it (never forward), ankle + "
        "lifts the toes, waist - bends forward, shoulder + raises the arm forward, "
        "elbow + bends it (never back), neck + tilts the head back. Near limbs (layer "
        "near, lighter) are drawn in front, far limbs (layer far, darker) behind; "
        "they share hinge points and do not collide with each other. Feet touch the "
        "ground at the heel and at the toe (a flat sole). Gains: the probe's "
        "standing gains (hip and knee 1000 N*m/rad, ankle 800, waist 600; "
        "../shared/docs/biped-notes.md); at 0.5x they collapse, at 3x the body "
        "rocks as a plank. The solver runs 40 iterations with 0.1 mm collision "
        "slop for this figure (the engine's 20 and 0.5 mm let it sway about 5x "
        "more)." + extra_notes)
    out += ["  " + line for line in _wrap(notes, 86)]
    out += [f"view_height: {fmt(view_height)}",
            "solver: {iterations: 40, collision_slop: 0.0001}", "links:"]

    def link(name, mass_key, shapes, color, layer=None, friction=0.9, desc=None):
        mass, com, inertia = table[mass_key]
        lines = [f"  - name: {name}"]
        if desc:
            lines.append(f"    description: \"{desc}\"")
        lines += [f"    mass: {fmt(mass)}", f"    center_of_mass: {pt(*com, 1)}",
                  f"    inertia: {fmt(inertia)}", f"    friction: {fmt(friction)}"]
        if layer:
            lines.append(f"    layer: {layer}")
        lines.append(f"    color: [{color[0]}, {color[1]}, {color[2]}]")
        lines.append("    shapes:")
        lines += [f"      - {sh}" for sh in shapes]
        return lines

    def seg(a, b, r):
        return f"{{type: segment, a: {pt(*a, s)}, b: {pt(*b, s)}, radius: {fmt(r * s)}}}"

    def box(c, w, hgt, r):
        return (f"{{type: box, center: {pt(*c, s)}, size: [{fmt(w * s)}, {fmt(hgt * s)}], "
                f"radius: {fmt(r * s)}}}")

    r = 0.01  # the sole's rounding: points sit r inside, so the sole is at y = 0
    foot = ("{type: polygon, points: [" + ", ".join(pt(x, y, s) for x, y in (
        (HEEL + r, r), (TOE - r, r), (TOE - r, 0.025), (0.05, ANKLE + 0.02),
        (-0.03, ANKLE + 0.02), (HEEL + r, 0.045))) + f"], radius: {fmt(r * s)}}}")
    out += link("pelvis", "pelvis", [box((0.0, 0.965), 0.19, 0.17, 0.02)], TROUSERS,
                desc="pelvis and hips; the root link")
    out += link("chest", "chest", [box((0.0, 1.265), 0.21, 0.47, 0.03)], SHIRT,
                desc="abdomen and thorax, up to the shoulders")
    out += link("head", "head", [seg((0.0, NECK), (0.01, 1.56), 0.045),
                                 f"{{type: circle, center: {pt(0.015, 1.64, s)}, "
                                 f"radius: {fmt(0.1 * s)}}}",
                                 "{type: polygon, points: [" + ", ".join(
                                     pt(x, y, s) for x, y in ((0.105, 1.655), (0.14, 1.615),
                                                              (0.105, 1.6))) + "]}"],
                SKIN, desc="head and neck; the nose shows which way it faces")
    for side in ("near", "far"):
        shirt = NEAR_SHIRT if side == "near" else SHIRT
        trousers = NEAR_TROUSERS if side == "near" else TROUSERS
        out += link(f"upper_arm_{side}", "upper_arm", [seg((0, SHOULDER), (0, ELBOW), 0.045)],
                    shirt, side)
        out += link(f"forearm_{side}", "forearm",
                    [seg((0, ELBOW), (0, WRIST), 0.035), seg((0, WRIST), (0.01, 0.69), 0.03)],
                    SKIN if side == "near" else (200, 160, 136), side,
                    desc="forearm and hand" if side == "near" else None)
        out += link(f"thigh_{side}", "thigh", [seg((0, HIP), (0, KNEE), 0.065)], trousers, side)
        out += link(f"shank_{side}", "shank", [seg((0, KNEE), (0, ANKLE + 0.01), 0.048)],
                    trousers, side)
        out += link(f"foot_{side}", "foot", [foot], SHOES, side, friction=1.0,
                    desc="a flat sole, heel to toe" if side == "near" else None)
    out.append("joints:")

    def joint(name, kind, parent, child, anchor, desc=None):
        k, c, t = GAINS[kind]
        lo, hi = LIMITS[kind]
        lines = [f"  - name: {name}"]
        if desc:
            lines.append(f"    description: \"{desc}\"")
        lines += [f"    parent: {parent}", f"    child: {child}",
                  f"    anchor: {pt(*anchor, s)}", f"    limits: [{lo}, {hi}]",
                  f"    pd: {{stiffness: {fmt(k * k_scale)}, damping: {fmt(c * c_scale)}, "
                  f"max_torque: {fmt(t * k_scale)}}}"]
        return lines

    out += joint("waist", "waist", "pelvis", "chest", (0, WAIST),
                 "pelvis - chest; - bends forward, + leans back")
    out += joint("neck", "neck", "chest", "head", (0, NECK), "+ tilts the head back")
    for side in ("near", "far"):
        out += joint(f"hip_{side}", "hip", "pelvis", f"thigh_{side}", (0, HIP),
                     "+ swings the thigh forward" if side == "near" else None)
        out += joint(f"knee_{side}", "knee", f"thigh_{side}", f"shank_{side}", (0, KNEE),
                     "- bends the knee; 0 is straight" if side == "near" else None)
        out += joint(f"ankle_{side}", "ankle", f"shank_{side}", f"foot_{side}", (0, ANKLE),
                     "+ lifts the toes" if side == "near" else None)
    for side in ("near", "far"):
        out += joint(f"shoulder_{side}", "shoulder", "chest", f"upper_arm_{side}",
                     (0, SHOULDER), "+ raises the arm forward" if side == "near" else None)
        out += joint(f"elbow_{side}", "elbow", f"upper_arm_{side}", f"forearm_{side}",
                     (0, ELBOW), "+ bends the elbow; 0 is straight" if side == "near" else None)
    out += ["start:", "  angle: 0", "  joints:"]
    out += [f"    {k}: {fmt(v)}" for k, v in START.items()]
    return "\n".join(out) + "\n"


def _wrap(text: str, width: int) -> list[str]:
    lines, cur = [], ""
    for word in text.split():
        if cur and len(cur) + 1 + len(word) > width:
            lines.append(cur)
            cur = word
        else:
            cur = f"{cur} {word}" if cur else word
    return lines + [cur]


def files() -> dict[Path, str]:
    s = 1.0 / H
    return {
        ROOT / "characters" / "biped.yaml": character_text(
            "biped", H, M,
            "A planar human, 1.75 m and 70 kg (Winter's anthropometric table); stands "
            "with its targets held.", "", 2.4),
        ROOT / "characters" / "biped-small.yaml": character_text(
            "biped-small", 1.0, 20.0,
            "The paper's smaller, lighter human for the long jump, 1.0 m and 20 kg, with the "
            "proportions of biped.yaml.",
            f" This is the small figure: lengths x{s:.3f}, masses x{20 / M:.3f}, inertias "
            f"x{20 / M * s * s:.4f}, stiffness and torque caps x{20 / M * s:.3f} (m*g*L), "
            f"damping x{20 / M * s ** 1.5:.3f} (the same damping ratio).",
            2.4 * s),
    }


def main(argv: list[str]) -> int:
    for path, text in files().items():
        path.write_text(text)
        print(f"wrote {path.relative_to(ROOT)}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
