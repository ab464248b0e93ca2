"""Unity's humanoid skeleton (HumanBodyBones) and forward kinematics in Unity's frame.

The VMC protocol sends each bone's *local* transform (position and rotation in its
parent's frame) in Unity's left-handed, Y-up frame, in metres. ``PARENTS`` is the
humanoid hierarchy (Unity's ``HumanBodyBones`` names, parents before children).
Optional bones (UpperChest, Neck, Shoulders, Toes, fingers...) may be absent from an
avatar: a bone's parent is then its nearest ancestor that is present, as in the
avatar's own transform hierarchy.

Quaternions are (x, y, z, w), as Unity and VMC write them; the rotation matrix of a
quaternion is the usual one (Unity's handedness changes which way a positive angle
looks, not the algebra), so ``world = parent_world * local`` composes as anywhere.
"""

from __future__ import annotations

import math

Quat = tuple[float, float, float, float]
Vec = tuple[float, float, float]

_FINGERS = ("Thumb", "Index", "Middle", "Ring", "Little")
_PHALANGES = ("Proximal", "Intermediate", "Distal")


def _table() -> dict[str, str | None]:
    parents: dict[str, str | None] = {
        "Hips": None,
        "LeftUpperLeg": "Hips", "RightUpperLeg": "Hips",
        "LeftLowerLeg": "LeftUpperLeg", "RightLowerLeg": "RightUpperLeg",
        "LeftFoot": "LeftLowerLeg", "RightFoot": "RightLowerLeg",
        "LeftToes": "LeftFoot", "RightToes": "RightFoot",
        "Spine": "Hips", "Chest": "Spine", "UpperChest": "Chest",
        "Neck": "UpperChest", "Head": "Neck",
        "LeftEye": "Head", "RightEye": "Head", "Jaw": "Head",
        "LeftShoulder": "UpperChest", "RightShoulder": "UpperChest",
        "LeftUpperArm": "LeftShoulder", "RightUpperArm": "RightShoulder",
        "LeftLowerArm": "LeftUpperArm", "RightLowerArm": "RightUpperArm",
        "LeftHand": "LeftLowerArm", "RightHand": "RightLowerArm",
    }
    for side in ("Left", "Right"):
        for finger in _FINGERS:
            parent = f"{side}Hand"
            for phalanx in _PHALANGES:
                name = f"{side}{finger}{phalanx}"
                parents[name] = parent
                parent = name
    return parents


PARENTS: dict[str, str | None] = _table()  # 55 bones, parents first
BONES = tuple(PARENTS)


def present_parent(bone: str, present) -> str | None:
    """``bone``'s nearest ancestor in ``present`` (a set of names), or None."""
    parent = PARENTS[bone]
    while parent is not None and parent not in present:
        parent = PARENTS[parent]
    return parent


def normalised(q: Quat) -> Quat:
    n = math.sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3])
    return (q[0] / n, q[1] / n, q[2] / n, q[3] / n)


def multiply(a: Quat, b: Quat) -> Quat:
    """The rotation ``a`` after ``b`` (a * b)."""
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    return (aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw,
            aw * bw - ax * bx - ay * by - az * bz)


def rotate(q: Quat, v: Vec) -> Vec:
    """``v`` rotated by the unit quaternion ``q``."""
    x, y, z, w = q
    # t = 2 * cross(q.xyz, v); v' = v + w t + cross(q.xyz, t)
    tx = 2.0 * (y * v[2] - z * v[1])
    ty = 2.0 * (z * v[0] - x * v[2])
    tz = 2.0 * (x * v[1] - y * v[0])
    return (v[0] + w * tx + (y * tz - z * ty),
            v[1] + w * ty + (z * tx - x * tz),
            v[2] + w * tz + (x * ty - y * tx))


def world_positions(root: tuple[Vec, Quat], local: dict[str, tuple[Vec, Quat]]
                    ) -> dict[str, Vec]:
    """World positions of the bones in ``local`` (bone -> local position, unit
    rotation), each placed in its nearest present ancestor's frame, the topmost in
    the ``root`` transform's."""
    world: dict[str, tuple[Vec, Quat]] = {}
    for bone in BONES:
        if bone not in local:
            continue
        parent = present_parent(bone, local)
        pp, pq = root if parent is None else world[parent]
        lp, lq = local[bone]
        r = rotate(pq, lp)
        world[bone] = ((pp[0] + r[0], pp[1] + r[1], pp[2] + r[2]), multiply(pq, lq))
    return {bone: pq[0] for bone, pq in world.items()}
