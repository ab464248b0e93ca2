"""The stability check in words: what ``puppet check CHARACTER`` prints about a body.

Lines of the report (what the body does) and warnings (what will trouble a designer:
it falls, a joint oscillates, a joint is locked by its damping, a joint cannot carry
its load), each warning saying what to change. The measurements are ``stability``'s.
"""

from __future__ import annotations

import math

from puppet.data.characters import CharacterSpec
from puppet.physics.stability import (
    NUDGE_AT,
    SAG_DEG,
    SECONDS,
    SWING_DEG,
    TAIL,
    TIP_DEG,
    TOPPLE_MARGIN,
    TRACK_LAM,
    Stability,
    stability,
)

CAPPED_SHARE = 0.2  # of the run at its torque limit: the joint is too weak
GIVE_DEG = 3.0  # deg a loaded joint gives under its weight (torque / stiffness): too soft
GIVE_SHARE = 0.25  # ... when it carries at least this share of the body
NEAR_EDGE = 0.25  # of the support's length: a centre of mass this near an edge tips over it


def _g(x: float) -> str:
    """A number as a designer writes it: 3 significant figures, no trailing zeros."""
    return f"{x:.3g}" if abs(x) < 1000 else f"{x:.0f}"


def _fall(run, what: str) -> str:
    return f"{what} falls at {run.fell_at:.2f} s: {run.why}"


def report(s: Stability) -> tuple[list[str], list[str]]:
    """(report lines, warnings) for ``s``; the lines are indented for the ok line."""
    lines, warnings = [], []
    q = s.quiet
    floor = ", ".join(s.touching) or "nothing"
    if s.stands:
        lines.append(f"stands: held its start pose {SECONDS:g} s (simulated) on a flat floor; "
                     f"root turned {abs(q.tilt):.1f} deg, centre of mass "
                     f"{q.com_start[1]:.3f} -> {q.com_end[1]:.3f} m high; on the floor: "
                     f"{floor}")
    else:
        warnings.append(_fall(q, "with its targets held (its start pose) on a flat floor, "
                                 "it") + "; see docs/characters.md (Will it stand?)")
    sank = [n for n in s.touching if n not in s.touching_start]
    if s.stands and sank:
        warnings.append(f"it sinks onto {', '.join(sank)}: on the floor at the end, not at "
                        "the start (stiffer joints above them, or a start pose that "
                        "rests on them)")
    if s.stands and abs(q.tilt) > TIP_DEG:
        way = "backward" if q.tilt > 0 else "forward"
        warnings.append(f"it tips {q.tilt:+.0f} deg ({way}) while held (the root link's "
                        "angle): the start pose does not rest on its support as drawn"
                        + _over(s, q.tilt > 0))
    n = s.nudged
    nudge = f"nudged {s.nudge:.2g} m/s forward at {NUDGE_AT:g} s"
    if s.stands and n.fell_at is not None:
        warnings.append(_fall(n, f"{nudge}, it") + ": it stands only while nothing "
                        "touches it (stiffer hips, knees or ankles, or a wider stance)")
    elif s.stands:
        still = (f"still again by {n.settled_at:.1f} s" if n.settled_at is not None
                 and n.settled_at < SECONDS - 0.1 else "still moving at the end")
        lines.append(f"{nudge}: stands, {still}")
    for j in s.oscillating:
        warnings.append(f"joint '{j.name}' oscillates: +-{j.swing:.1g} deg at {j.hz:.2g} Hz "
                        f"over the last {TAIL:g} s with nothing driving it; raise its damping "
                        f"(up to {_g(j.track_damping)}, past which the engine locks it) or "
                        "lower its stiffness")
    for j in s.locked:
        warnings.append(f"joint '{j.name}': damping locks it against the light link "
                        f"'{j.light}' ({j.light_moment:.2g} kg*m^2): the engine keeps "
                        f"e^-{j.lam:.1f} of its speed each step, so it follows a new target "
                        f"in about {_seconds(j.follow)}, not damping/stiffness; damping "
                        f"{_g(j.track_damping)} or less tracks (docs/characters.md, "
                        "Damping that locks)")
    weak = [j for j in s.joints if j.capped > CAPPED_SHARE]
    for j in weak:
        warnings.append(f"joint '{j.name}' is at its torque limit {j.capped:.0%} of the "
                        "time: raise its max_torque")
    for load in s.loads:
        both = " + ".join(load.joints)
        if load.topple > 0 and load.stiffness < TOPPLE_MARGIN * load.topple:
            warnings.append(f"{both} carr{'y' if len(load.joints) > 1 else 'ies'} "
                            f"{load.mass:.3g} kg standing on it: stiffness "
                            f"{_g(load.stiffness)} N*m/rad against m*g*h = "
                            f"{_g(load.topple)}; give it {TOPPLE_MARGIN:g}-3 times that "
                            f"({_g(2 * load.topple)})")
        bend = math.degrees(load.torque / load.stiffness) if load.stiffness > 0 else 90.0
        if bend > GIVE_DEG and load.mass >= GIVE_SHARE * s.mass:  # the weight bends it:
            # the pose moves, and the body's balance with it (a tail's sag is cosmetic)
            warnings.append(f"{both} give{'' if len(load.joints) > 1 else 's'} about "
                            f"{bend:.0f} deg under the {load.mass:.3g} kg "
                            f"{'they carry' if len(load.joints) > 1 else 'it carries'} "
                            f"(its weight pulls with {_g(load.torque)} N*m, stiffness "
                            f"{_g(load.stiffness)} N*m/rad: torque / stiffness radians); for "
                            f"{GIVE_DEG - 1:g} deg or less, stiffness "
                            f"{_g(load.torque / math.radians(GIVE_DEG - 1))}")
        if load.torque > load.max_torque:
            warnings.append(f"{both} cannot hold the {load.mass:.3g} kg it carries: its "
                            f"weight pulls with {_g(load.torque)} N*m, max_torque "
                            f"{_g(load.max_torque)}")
    if not s.stands:
        sag = [j for j in s.joints if abs(j.sag) >= SAG_DEG]
        if sag:
            lines.append("at the end, far from their targets: " + ", ".join(
                f"{j.name} {j.sag:+.0f} deg" for j in sag))
    if s.stands:
        quiet = [f"none oscillates (+-{SWING_DEG:g} deg)" if not s.oscillating else "",
                 "none is locked by its damping" if not s.locked else "",
                 "none reaches its torque limit" if not weak else ""]
        sag = [j for j in s.joints if abs(j.sag) >= SAG_DEG]
        said = [t for t in quiet if t]
        if sag:
            said.append("sagging from their targets: " + ", ".join(
                f"{j.name} {j.sag:+.1f} deg" for j in sag))
        lines.append("joints: " + "; ".join(said) if said else "joints: see the warnings")
        slow = max(s.joints, key=lambda j: j.follow, default=None)
        if slow is not None and not s.locked and slow.follow >= 0.005:
            ceiling = (f" (its damping is past the {_g(slow.track_damping)} up to which the "
                       "engine lets it track freely)" if slow.lam > TRACK_LAM else "")
            lines.append(f"slowest to follow a new target: {slow.name}, about "
                         f"{_seconds(slow.follow)}{ceiling}")
    said = balance_line(s)
    if said:
        lines.append(said)
    for load in sorted(s.loads, key=lambda x: -x.mass)[:3]:
        ratio = (f", {load.stiffness / load.topple:.2g}x its m*g*h {_g(load.topple)}"
                 if load.topple > 0 else " (it hangs below the hinge)")
        verb = "carry" if len(load.joints) > 1 else "carries"
        lines.append(f"load at the start: {' + '.join(load.joints)} {verb} {load.mass:.3g} "
                     f"kg: stiffness {_g(load.stiffness)} N*m/rad{ratio}; "
                     f"{_g(load.torque)} of {_g(load.max_torque)} N*m to hold it")
    return lines, warnings


def _over(s: Stability, backward: bool) -> str:
    """What the start pose's balance says about a tip ``backward`` (else forward): its
    centre of mass outside what it stands on, or near that edge."""
    if s.balance is None or s.balance[1] is None:
        return ""
    x, (left, right) = s.balance
    off = s.off_support
    if off != 0.0:
        return (f"; its centre of mass starts {abs(off) * 100:.1f} cm "
                f"{'ahead of' if off > 0 else 'behind'} what it stands on (x {left:.3g}.."
                f"{right:.3g} m): move the feet under it")
    edge = x - left if backward else right - x
    if edge > NEAR_EDGE * (right - left):
        return ""  # well inside: the tip is the joints' (a warning of its own says which)
    return (f"; its centre of mass starts {edge * 100:.1f} cm from the "
            f"{'back' if backward else 'front'} edge of what it stands on (x {left:.3g}.."
            f"{right:.3g} m): move the feet {'back' if backward else 'forward'} "
            f"under it, or the mass {'forward' if backward else 'back'}")


def balance_line(s: Stability) -> str | None:
    """Where the start pose's centre of mass is over what it stands on."""
    if s.balance is None or s.balance[1] is None:
        return None
    x, (left, right) = s.balance
    if s.off_support:
        where = (f"{abs(s.off_support) * 100:.1f} cm "
                 f"{'ahead of' if s.off_support > 0 else 'behind'} it")
    else:
        where = (f"{(x - left) * 100:.1f} cm from its back edge, {(right - x) * 100:.1f} "
                 "cm from its front edge")
    return (f"balance at the start: centre of mass at x {x:.3g} m, what it stands on from "
            f"{left:.3g} to {right:.3g} m: {where}")


def _seconds(t: float) -> str:
    if t == float("inf"):
        return "never (no stiffness)"
    return f"{t:.2g} s" if t < 100 else f"{t:.0f} s"


def character_report(spec: CharacterSpec) -> tuple[list[str], list[str]]:
    """(report lines, warnings) of ``spec``'s stability check."""
    return report(stability(spec))
