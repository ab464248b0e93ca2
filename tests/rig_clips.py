"""Test clips of rigs puppet has never seen, made from a shipped CMU clip: joints renamed
as another rig names them, lengths in another unit, the world turned to another up
axis, another frame rate, an extra root above the hips with an OFFSET, helper joints
inserted in a limb's chain. Every joint's rotation is written again (``R L R^T`` for
the turn, as Euler angles Z Y X), so the clip's points are the original's turned and
scaled."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from puppet.mocap.bvh import Clip

TURN = {"y": np.eye(3),  # the original's y up becomes ...
        "z": np.array([[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]]),
        "-z": np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]])}

# CMU 131's joint names (the walk) as other rigs name those joints
CC = {"Hips": "CC_Base_Hip", "LHipJoint": "CC_Base_L_Pelvis", "LeftHip": "CC_Base_L_Thigh",
      "LeftKnee": "CC_Base_L_Calf", "LeftAnkle": "CC_Base_L_Foot", "LeftToe": "CC_Base_L_ToeBase",
      "RHipJoint": "CC_Base_R_Pelvis", "RightHip": "CC_Base_R_Thigh",
      "RightKnee": "CC_Base_R_Calf", "RightAnkle": "CC_Base_R_Foot",
      "RightToe": "CC_Base_R_ToeBase", "lowerback": "CC_Base_Waist", "Chest": "CC_Base_Spine01",
      "Chest2": "CC_Base_Spine02", "lowerneck": "CC_Base_NeckTwist01",
      "Neck": "CC_Base_NeckTwist02", "Head": "CC_Base_Head", "LeftCollar": "CC_Base_L_Clavicle",
      "LeftShoulder": "CC_Base_L_Upperarm", "LeftElbow": "CC_Base_L_Forearm",
      "LeftWrist": "CC_Base_L_Hand", "lhand": "CC_Base_L_Mid1", "LFingers": "CC_Base_L_Mid2",
      "LThumb": "CC_Base_L_Thumb1", "RightCollar": "CC_Base_R_Clavicle",
      "RightShoulder": "CC_Base_R_Upperarm", "RightElbow": "CC_Base_R_Forearm",
      "RightWrist": "CC_Base_R_Hand", "rhand": "CC_Base_R_Mid1", "RFingers": "CC_Base_R_Mid2",
      "RThumb": "CC_Base_R_Thumb1"}


def _named(left: dict, rest: dict) -> dict:
    """A rename table from the left side's names (Left -> Right mirrored)."""
    out = dict(rest)
    for old, new in left.items():
        out[old] = new
        out[old.replace("Left", "Right").replace("LHip", "RHip").replace("lhand", "rhand")
            .replace("LFing", "RFing").replace("LThumb", "RThumb")] = (
            new.replace("Left", "Right").replace("L_", "R_").replace("left", "right"))
    return out


TRUNK = {"Hips": "Hips", "lowerback": "Spine", "Chest": "Chest", "Chest2": "UpperChest",
         "lowerneck": "NeckLower", "Neck": "Neck", "Head": "Head"}
UNITY = _named({"LHipJoint": "LeftHipHelper", "LeftHip": "LeftUpperLeg",
                "LeftKnee": "LeftLowerLeg", "LeftAnkle": "LeftFoot", "LeftToe": "LeftToes",
                "LeftCollar": "LeftShoulder", "LeftShoulder": "LeftUpperArm",
                "LeftElbow": "LeftLowerArm", "LeftWrist": "LeftHand", "lhand": "LeftPalm",
                "LFingers": "LeftMiddleProximal", "LThumb": "LeftThumbProximal"}, TRUNK)
SMPL = _named({"LHipJoint": "L_HipRoot", "LeftHip": "L_Hip", "LeftKnee": "L_Knee",
               "LeftAnkle": "L_Ankle", "LeftToe": "L_Foot", "LeftCollar": "L_Collar",
               "LeftShoulder": "L_Shoulder", "LeftElbow": "L_Elbow", "LeftWrist": "L_Wrist",
               "lhand": "L_Hand", "LFingers": "L_Fingers", "LThumb": "L_Thumb"},
              {"Hips": "Pelvis", "lowerback": "Spine1", "Chest": "Spine2", "Chest2": "Spine3",
               "lowerneck": "Neck", "Neck": "Neck2", "Head": "Head"})
ROKOKO = _named({"LHipJoint": "LeftHipJoint", "LeftHip": "LeftThigh", "LeftKnee": "LeftShin",
                 "LeftAnkle": "LeftFoot", "LeftToe": "LeftToe", "LeftCollar": "LeftShoulder",
                 "LeftShoulder": "LeftArm", "LeftElbow": "LeftForeArm", "LeftWrist": "LeftHand",
                 "lhand": "LeftHandPalm", "LFingers": "LeftFingers", "LThumb": "LeftThumb"},
                {"Hips": "Hips", "lowerback": "Spine1", "Chest": "Spine2", "Chest2": "Spine4",
                 "lowerneck": "Neck", "Neck": "Neck1", "Head": "Head"})


def _zyx(m: np.ndarray) -> np.ndarray:
    """(frames, 3, 3) rotations as Z, Y, X angles in degrees: m = Rz Ry Rx."""
    y = np.arcsin(np.clip(-m[:, 2, 0], -1.0, 1.0))
    z = np.arctan2(m[:, 1, 0], m[:, 0, 0])
    x = np.arctan2(m[:, 2, 1], m[:, 2, 2])
    return np.degrees(np.stack([z, y, x], axis=1))


def write_rig(clip: Clip, path: Path, rename: dict, scale: float = 1.0, up: str = "y",
              every: int = 1, extra_root: str | None = None,
              root_offset: tuple = (0.0, 0.0, 0.0), helpers: dict | None = None) -> Path:
    """``clip`` written as another rig (see the module). ``helpers``: new name -> the
    (new) name of the joint it is inserted above, at that joint's parent's place."""
    turn = TURN[up]
    frames = np.arange(0, clip.frames, every)
    names = [rename.get(j.name, j.name) for j in clip.joints]
    kids: dict[int, list[int]] = {}
    for i, j in enumerate(clip.joints):
        kids.setdefault(j.parent, []).append(i)
    above = {v: k for k, v in (helpers or {}).items()}
    lines = ["HIERARCHY"]
    columns: list[np.ndarray] = []
    zero = np.zeros((len(frames), 3))

    def vec(v) -> str:
        return " ".join(f"{x:.6f}" for x in v)

    def joint(i: int, depth: int, root: bool) -> None:
        j = clip.joints[i]
        pad = "  " * depth
        if j.end_site:
            lines.extend([f"{pad}End Site", f"{pad}{{",
                          f"{pad}  OFFSET {vec(turn @ j.offset * scale)}", f"{pad}}}"])
            return
        if names[i] in above:  # a helper joint first, where this joint's parent is
            lines.extend([f"{pad}JOINT {above[names[i]]}", f"{pad}{{", f"{pad}  OFFSET 0 0 0",
                          f"{pad}  CHANNELS 3 Zrotation Yrotation Xrotation"])
            columns.append(zero)
            pad, depth = pad + "  ", depth + 1
        local = clip.local_rotations(i)[frames]
        angles = np.unwrap(_zyx(turn @ local @ turn.T), period=360.0, axis=0)
        if root:
            lines.extend([f"{pad}{'ROOT' if extra_root is None else 'JOINT'} {names[i]}",
                          f"{pad}{{", f"{pad}  OFFSET {vec(np.asarray(root_offset) * scale)}",
                          f"{pad}  CHANNELS 6 Xposition Yposition Zposition Zrotation "
                          f"Yrotation Xrotation"])
            moves = clip.local_translations(i)[frames] @ turn.T * scale
            columns.append(moves)
        else:
            lines.extend([f"{pad}JOINT {names[i]}", f"{pad}{{",
                          f"{pad}  OFFSET {vec(turn @ j.offset * scale)}",
                          f"{pad}  CHANNELS 3 Zrotation Yrotation Xrotation"])
        columns.append(angles)
        for k in kids.get(i, []):
            joint(k, depth + 1, False)
        lines.append(f"{pad}}}")
        if names[i] in above:
            lines.append(f"{'  ' * (depth - 1)}}}")

    if extra_root is not None:  # a root at the floor that never moves, the hips below it
        lines.extend([f"ROOT {extra_root}", "{", "  OFFSET 0 0 0",
                      "  CHANNELS 6 Xposition Yposition Zposition Zrotation Yrotation "
                      "Xrotation"])
        columns += [zero, zero]
        joint(0, 1, True)
        lines.append("}")
    else:
        joint(0, 0, True)
    table = np.concatenate(columns, axis=1)
    lines += ["MOTION", f"Frames: {len(frames)}", f"Frame Time: {clip.frame_time * every:.7f}"]
    lines += [" ".join(f"{v:.5f}" for v in row) for row in table]
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path
