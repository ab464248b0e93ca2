"""Recognising a humanoid rig and building its mapping, so that a clip of a skeleton
puppet has never seen plays without a mapping file written by hand.

What ``assets/mocap/humanoid.yaml`` says is done in three moves:

1. **names**: each joint's name is split into words (``CC_Base_L_Thigh``: cc base l
   thigh), its side (left, l, right, r ...) and the words that say nothing (rig
   prefixes) are taken off; the ends of the limbs (ankle or foot, toe, wrist or hand)
   and the head are found by what is left. The rest is structure: the knee is the
   joint above the ankle, the hip the one above the knee (skipping helper joints -
   twist, roll, share bones - and joints at the same place); so for the elbow and
   shoulder; ``hips`` is the legs' common parent, ``chest`` the arms', ``spine`` the
   trunk joint halfway between, ``neck`` the head's parent.
2. **measures**, from the clip's frames: the up axis (the head above the feet), the
   unit (the performer's height: the common unit that makes it human - m, cm, mm,
   inches, CMU's), the handedness (the toes point the way the hips face), the floor
   (the lower toe joint's height with a foot down: where it is a quarter of the time
   or less; ``clearance`` is its height above that, less 2 cm), the feet's rest angle
   (ankle to toe while the foot is flat), the plane (``travel`` if the root goes one way,
   else ``facing``), the size (the figure's leg over the performer's).
3. **the mapping**: the file's template with the joints for the roles and the measured
   numbers, a ``MappingSpec`` like any other (``write_mapping`` writes it out as YAML
   that ``puppet check`` takes and that plays the same).

Nothing is assumed of a joint's position in the hierarchy beyond parent and child, of
the rest pose, or of the channels; the root's OFFSET drops out (the floor is measured
from the points as the clip gives them).
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Annotated

import numpy as np

from puppet.data.errors import DataError
from puppet.data.mappings import MappingSpec
from puppet.data.validate import Meta, Spec, validate
from puppet.data.yamlfile import load_file

HUMANOID = Path(__file__).resolve().parents[2] / "assets" / "mocap" / "humanoid.yaml"
UNITS = {"m": 1.0, "dm": 0.1, "cm": 0.01, "mm": 0.001, "inch": 0.0254, "foot": 0.3048,
         "CMU": 0.056444}  # the common units of a clip's lengths, metres each
HUMAN = 1.7  # m: the height a unit is chosen to come nearest (in ratio)
NEAR = 0.06  # of the performer's height: joints closer than this are at one place
TRAVEL = 1.0  # m: a clip whose root ends this far from its start, going one way, travels
BACK = 0.25  # ... going back along its way at most this share of it (the jumps clip: 1.2)
FLAT = 0.015  # m: a foot whose toe and ankle are both this near their usual low is flat
LOW = 20  # percentile: a point's usual low (a foot stands a good part of any clip)
CONTACT = 25  # percentile of the lower toe's height: where the toes are with a foot down
STANDING = 0.02  # m: the lower toe higher than that by more than this, the feet are off
Roles = Annotated[list[str], Meta(min_length=1)]


class RolesSpec(Spec, kw_only=True):
    ankle: Roles
    toe: Roles
    wrist: Roles
    head: Roles


class SidesSpec(Spec, kw_only=True):
    left: Roles
    right: Roles


class HumanoidSpec(Spec, kw_only=True):
    description: str = ""
    sides: SidesSpec
    silent: list[str]
    helpers: list[str]
    roles: RolesSpec
    character: str
    leg: Annotated[list[str], Meta(min_length=3, max_length=3)]
    mapping: MappingSpec


def parse_humanoid(located) -> HumanoidSpec:
    """The humanoid file (``puppet check`` reads it too): its template is a mapping
    whose points are roles, each one the roles the code finds."""
    spec = validate(located, HumanoidSpec)
    known = {f"{side}_{part}" for side in ("left", "right") for part in
             ("hip", "knee", "ankle", "toe", "shoulder", "elbow", "wrist")}
    known |= {"hips", "spine", "chest", "neck", "head"}
    for where, message in spec.mapping.problems():
        raise located.error(("mapping", *where), message)
    for name in sorted(spec.mapping.point_names() - known):
        raise located.error(("mapping",), f"the template reads '{name}', which is no role; "
                                          f"expected one of: {', '.join(sorted(known))}")
    return spec


def load_humanoid(path=HUMANOID) -> HumanoidSpec:
    return parse_humanoid(load_file(path))


_WORD = re.compile(r"[A-Z]+(?![a-z])|[A-Z]?[a-z]+|[0-9]+")


def words(name: str) -> list[str]:
    """A joint's name as lower-case words: ``LHipJoint`` -> l hip joint,
    ``CC_Base_L_Thigh`` -> cc base l thigh, ``mixamorig:LeftUpLeg`` -> mixamorig left
    up leg, ``thigh.L`` -> thigh l."""
    return [w.lower() for w in _WORD.findall(name)]


@dataclass
class Rig:
    """A recognised humanoid: role -> joint name, and what was measured."""

    joints: dict[str, str]  # role (left_knee, hips, ...) -> the clip's joint or End Site
    unit: float  # m per clip unit
    unit_name: str
    up: str  # the clip's up axis: y, -z ...
    handedness: str
    floor: float  # clip units along up
    feet: dict[str, float]  # side -> the foot's rest angle, deg
    plane: str
    size: float
    height: float  # m: the performer's height, head to feet
    mapping: MappingSpec
    notes: list[str] = field(default_factory=list)

    def summary(self) -> str:
        """One paragraph: what was recognised and measured."""
        j = self.joints
        return (f"a humanoid rig: hips {j['hips']}, legs {j['right_hip']} > "
                f"{j['right_knee']} > {j['right_ankle']} > {j['right_toe']}, arms "
                f"{j['right_shoulder']} > {j['right_elbow']} > {j['right_wrist']}, trunk "
                f"{j['spine']} > {j['neck']} > {j['head']}; unit {self.unit:g} m "
                f"({self.unit_name}: the performer is {self.height:.2f} m tall), up "
                f"{self.up}, {self.handedness}-handed, floor {self.floor:g}, feet's rest "
                f"{self.feet['right']:g} (right) {self.feet['left']:g} (left) deg, plane "
                f"{self.plane}, size {self.size:g}")


class NotHumanoid(DataError):
    """The clip's skeleton is not one this module can read as a human's (``missing``:
    what was not found)."""

    missing = ""


def recognise(clip, character=None, humanoid: HumanoidSpec | None = None) -> Rig:
    """The humanoid rig of a BVH ``clip`` and its mapping onto ``character`` (a
    CharacterSpec; default the humanoid file's, the biped). ``NotHumanoid`` (one
    line) if the names do not give the limbs' ends and the head."""
    from puppet.data.catalog import load_character_named

    h = humanoid or load_humanoid()
    if character is None:
        character, _ = load_character_named(h.character)
    names = clip.names
    parent = [j.parent for j in clip.joints]
    _, pos = clip.world_transforms()
    return _recognise(names, parent, pos, clip.frame_time, clip.path or "<clip>",
                      character, h)


# -- names and structure -------------------------------------------------------------
class _Names:
    def __init__(self, names, parent, h: HumanoidSpec):
        self.names, self.parent, self.h = names, parent, h
        self.side: list[str | None] = []
        self.core: list[str] = []
        self.helper: list[bool] = []
        left, right, silent = set(h.sides.left), set(h.sides.right), set(h.silent)
        for name in names:
            ws = words(name)
            side = None
            if any(w in left for w in ws):
                side = "left"
            elif any(w in right for w in ws):
                side = "right"
            rest = [w for w in ws if w not in left and w not in right and w not in silent]
            self.side.append(side)
            self.core.append("".join(rest))
            self.helper.append(any(w in h.helpers for w in rest)
                               or any(x in "".join(rest) for x in h.helpers if len(x) > 3))
        self.children: list[list[int]] = [[] for _ in names]
        for i, p in enumerate(parent):
            if p >= 0:
                self.children[p].append(i)

    def find(self, role: str, side: str | None, within: int | None = None) -> int | None:
        """The joint named for ``role`` (its names in preference order) on ``side``
        (None: any), among ``within``'s descendants if given; the one nearest the root
        when several are."""
        candidates = (range(len(self.names)) if within is None
                      else self.descendants(within))
        for word in getattr(self.h.roles, role):
            found = [i for i in candidates if self.core[i] == word and not self.helper[i]
                     and (side is None or self.side[i] == side)]
            if found:
                return min(found, key=self.depth)
        return None

    def depth(self, i: int) -> int:
        d = 0
        while self.parent[i] >= 0:
            i, d = self.parent[i], d + 1
        return d

    def descendants(self, i: int) -> list[int]:
        out, stack = [], list(self.children[i])
        while stack:
            j = stack.pop()
            out.append(j)
            stack.extend(self.children[j])
        return out

    def ancestors(self, i: int) -> list[int]:
        out = []
        while self.parent[i] >= 0:
            i = self.parent[i]
            out.append(i)
        return out

    def common(self, a: int, b: int) -> int:
        up = set([a, *self.ancestors(a)])
        for j in [b, *self.ancestors(b)]:
            if j in up:
                return j
        raise NotHumanoid("<clip>", None, None, "the limbs share no parent")


class _Apart:
    """How far apart two joints are, the median over (up to 200 of) the clip's frames:
    no rest pose is assumed (some rigs' is none a body takes)."""

    def __init__(self, pos: np.ndarray):
        self.pos = pos[:: max(1, len(pos) // 200)]
        self.cache: dict[tuple[int, int], float] = {}

    def __call__(self, i: int, j: int) -> float:
        key = (min(i, j), max(i, j))
        if key not in self.cache:
            self.cache[key] = float(np.median(np.linalg.norm(self.pos[:, i] - self.pos[:, j],
                                                             axis=1)))
        return self.cache[key]


def _above(n: _Names, apart: _Apart, i: int, gap: float) -> int | None:
    """The first joint above ``i`` that is no helper and is at least ``gap`` away."""
    for j in n.ancestors(i):
        if not n.helper[j] and apart(i, j) >= gap:
            return j
    return None


def _roles(n: _Names, apart: _Apart, size: float, where: str) -> dict[str, int]:
    gap = NEAR * size
    out: dict[str, int] = {}
    missing = []
    for side in ("left", "right"):
        ankle = n.find("ankle", side)
        wrist = n.find("wrist", side)
        if ankle is None or wrist is None:
            what = "ankle (or foot)" if ankle is None else "wrist (or hand)"
            missing.append(f"the {side} {what}")
            continue
        toe = n.find("toe", side, within=ankle)
        if toe is None:  # the foot's end: its farthest descendant (an End Site)
            below = n.descendants(ankle)
            if not below:
                missing.append(f"the {side} toe (no joint or End Site below "
                               f"{n.names[ankle]})")
                continue
            toe = max(below, key=lambda j: apart(j, ankle))
        knee = _above(n, apart, ankle, gap)
        hip = _above(n, apart, knee, gap) if knee is not None else None
        elbow = _above(n, apart, wrist, gap)
        shoulder = _above(n, apart, elbow, gap) if elbow is not None else None
        if None in (knee, hip, elbow, shoulder):
            missing.append(f"the {side} {'leg' if None in (knee, hip) else 'arm'}'s joints "
                           f"above {n.names[ankle if None in (knee, hip) else wrist]}")
            continue
        out.update({f"{side}_ankle": ankle, f"{side}_toe": toe, f"{side}_knee": knee,
                    f"{side}_hip": hip, f"{side}_wrist": wrist, f"{side}_elbow": elbow,
                    f"{side}_shoulder": shoulder})
    head = n.find("head", None)
    if head is None:
        missing.append("the head")
    if missing:
        error = NotHumanoid(where, None, None,
                            f"not a humanoid rig puppet can read: no joint named for "
                            f"{', '.join(missing)} (assets/mocap/humanoid.yaml says which "
                            f"names mean what); expected a skeleton with legs, arms and a "
                            f"head, or a mapping file (--mapping)")
        error.missing = ", ".join(missing)
        raise error
    hips = n.common(out["left_hip"], out["right_hip"])
    chest = n.common(out["left_shoulder"], out["right_shoulder"])
    neck = n.parent[head] if n.parent[head] >= 0 else chest
    for j in n.ancestors(head):  # the head's parent, at a distance from the head
        if apart(j, head) >= 0.5 * gap:
            neck = j
            break
    base = n.common(hips, chest)  # (the hips themselves, or a root both hang from)
    path = []  # the trunk's joints from the chest down, short of its base
    j = chest
    while j != base and j >= 0:
        path.append(j)
        j = n.parent[j]
    half = 0.5 * apart(chest, hips)
    spine = min(path, key=lambda j: abs(apart(j, hips) - half)) if path else chest
    if spine == neck:
        spine = chest
    out.update(hips=hips, chest=chest, spine=spine, neck=neck, head=head)
    return out


# -- measures ------------------------------------------------------------------------
def _up(pos: np.ndarray, idx: dict[str, int]) -> tuple[str, np.ndarray]:
    feet = (pos[:, idx["left_ankle"]] + pos[:, idx["right_ankle"]]) / 2
    rise = np.median(pos[:, idx["head"]] - feet, axis=0)
    axis = int(np.argmax(np.abs(rise)))
    sign = 1.0 if rise[axis] > 0 else -1.0
    up = np.zeros(3)
    up[axis] = sign
    return ("" if sign > 0 else "-") + "xyz"[axis], up


def _unit(height_units: float) -> tuple[str, float]:
    name = min(UNITS, key=lambda u: abs(math.log(max(height_units * UNITS[u], 1e-9) / HUMAN)))
    return name, UNITS[name]


def _handedness(pos, idx, up) -> str:
    """right if the toes point the way a right-handed reading of the hips faces."""
    across = pos[:, idx["left_hip"]] - pos[:, idx["right_hip"]]
    facing = np.cross(across, up)
    toes = sum(pos[:, idx[f"{s}_toe"]] - pos[:, idx[f"{s}_ankle"]] for s in ("left", "right"))
    along = np.sum(facing * toes, axis=1)
    return "right" if np.median(along) >= 0 else "left"


def _feet(pos, idx, up, unit: float, floor: float) -> dict[str, float]:
    """side -> the ankle-to-toe angle below the horizontal while the foot is flat
    (toe and ankle both within FLAT m of their usual low), deg, to 0.1."""
    out = {}
    for side in ("left", "right"):
        toe, ankle = pos[:, idx[f"{side}_toe"]], pos[:, idx[f"{side}_ankle"]]
        ht, ha = toe @ up, ankle @ up
        flat = (ht <= np.percentile(ht, LOW) + FLAT / unit) & \
               (ha <= np.percentile(ha, LOW) + FLAT / unit)
        d = toe[flat] - ankle[flat] if flat.any() else toe - ankle
        rise = d @ up
        run = np.linalg.norm(d - rise[:, None] * up, axis=1)
        out[side] = round(float(np.degrees(np.median(np.arctan2(rise, run)))), 1)
    return out


def _plane(pos, idx, up, unit: float) -> str:
    """``travel`` if the root ends ``TRAVEL`` m from its start and hardly goes back
    along that way (less than ``BACK`` of it), else ``facing``."""
    root = (pos[:, idx["left_hip"]] + pos[:, idx["right_hip"]]) / 2
    flat = root - (root @ up)[:, None] * up
    flat = flat[:: max(1, len(flat) // 100)]
    way = flat[-1] - flat[0]
    net = float(np.linalg.norm(way))
    if net * unit < TRAVEL:
        return "facing"
    steps = np.diff(flat, axis=0) @ (way / net)
    back = -float(np.sum(steps[steps < 0]))
    return "travel" if back <= BACK * net else "facing"


def _figure_leg(character, joints: list[str]) -> float | None:
    anchors = {j.name: j.anchor for j in character.joints}
    if not all(j in anchors for j in joints):
        return None
    a, b, c = (np.asarray(anchors[j], float) for j in joints)
    return float(np.linalg.norm(a - b) + np.linalg.norm(b - c))


def _recognise(names, parent, pos, frame_time, where, character, h) -> Rig:
    n = _Names(names, parent, h)
    apart = _Apart(pos)
    extent = np.median(np.max(pos, axis=1) - np.min(pos, axis=1), axis=0)  # the body, (3,)
    idx = _roles(n, apart, float(np.max(extent)) or 1.0, where)  # (its longest extent)
    up_name, up = _up(pos, idx)
    along = pos @ up
    height_units = float(np.median(along.max(axis=1) - along.min(axis=1)))
    unit_name, unit = _unit(height_units)
    handedness = _handedness(pos, idx, up)
    toes = np.minimum(along[:, idx["left_toe"]], along[:, idx["right_toe"]])
    floor = float(np.percentile(toes, CONTACT))  # the toe joints' level with a foot down
    standing = STANDING
    feet = _feet(pos, idx, up, unit, floor)
    plane = _plane(pos, idx, up, unit)
    hip, knee, ankle = (pos[:, idx[f"right_{k}"]] for k in ("hip", "knee", "ankle"))
    leg = float(np.median(np.linalg.norm(hip - knee, axis=1)
                          + np.linalg.norm(knee - ankle, axis=1))) * unit
    figure = _figure_leg(character, h.leg)
    size = round(figure / leg, 3) if figure and leg > 0 else 1.0
    joints = {role: names[i] for role, i in idx.items()}
    floor = round(floor, 4)
    mapping = _build(h.mapping, joints, unit, up_name, handedness, floor, feet, plane, size,
                     standing, character.name, Path(where).stem)
    return Rig(joints, unit, unit_name, up_name, handedness, floor, feet, plane, size,
               height_units * unit, mapping)


def _build(template: MappingSpec, joints: dict[str, str], unit, up, handedness, floor, feet,
           plane, size, standing, character: str, clip: str) -> MappingSpec:
    """The template with the clip's joints for its roles and the measured numbers."""
    import msgspec

    data = msgspec.to_builtins(template)
    point = joints.__getitem__

    data["name"] = f"{clip}-humanoid"
    data["character"] = character
    data["description"] = f"{clip}'s rig, recognised as a humanoid (puppet mocap mapping)"
    data["source"] = {"up": up, "unit": unit, "handedness": handedness}
    data["plane"] = plane
    data["size"] = size
    data["facing"] = {k: point(v) for k, v in data["facing"].items() if v is not None}
    data["root"] = {"point": [point(p) for p in data["root"]["point"]], "floor": floor}
    for seg in data["segments"].values():
        seg["from"], seg["to"] = point(seg["from"]), point(seg["to"])
    for name, seg in template.segments.items():
        side = next((s for s in ("left", "right") if seg.to == f"{s}_toe"), None)
        if side is not None:
            data["segments"][name]["rest"] = feet[side]
    data["effectors"] = {k: point(v) for k, v in data["effectors"].items()}
    if data.get("clearance"):
        data["clearance"] = {"points": [point(p) for p in data["clearance"]["points"]],
                             "standing": standing}
    com: dict[str, float] = {}
    for role, w in data["com"].items():  # two roles on one joint (a short trunk) add up
        com[point(role)] = round(com.get(point(role), 0.0) + w, 6)
    data["com"] = com
    return MappingSpec.model_validate(data)
