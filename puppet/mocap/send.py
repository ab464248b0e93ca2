"""``puppet mocap send``: stream a BVH clip over OSC in real time, as a live source would.

A *bone table* (``assets/mocap/cmu-bones.yaml``) says which BVH joint is which Unity
humanoid bone (VMC) and which MediaPipe landmark; it is data, so a clip from another
rig needs a new table, never new code. The frames sent reproduce the clip:

* ``vmc``: each listed bone's transform relative to its nearest listed ancestor
  (joints the table skips fold into their children), from ``Clip.world_transforms``,
  in metres and in Unity's left-handed Y-up frame (x mirrored), so a receiver's
  forward kinematics over the humanoid hierarchy gives the clip's joint positions;
* ``mediapipe``: the listed joints' world positions in metres in MediaPipe's world
  landmark axes (y down: a half turn about x), not re-centred on the hips, so a
  walk's travel is kept;
* ``mediapipe-osc``: as the common MediaPipe-to-OSC bridge sends a camera's pose: the
  landmarks normalised to a picture of the clip filmed side-on (``picture_points``),
  a leading count, mirrored as its selfie view is, no time;
* ``puppet``: the channels a mapping's Retargeter makes of the clip's joint
  positions, sent on puppet's own address (no mapping needed at the receiver).

The sender's time (``/VMC/Ext/T``, the first number of the others) is the clip time
played so far divided by the speed, going on across loops, so it never goes back.
"""

from __future__ import annotations

import socket
import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from puppet.data.errors import DataError
from puppet.data.yamlfile import load_file
from puppet.mocap import mediapipe, puppet_osc, unity, vmc
from puppet.mocap.bvh import MAX_NAME, Clip

MIRROR = np.diag([-1.0, 1.0, 1.0])  # right-handed -> Unity's left-handed (x mirrored)
Z_UP_TO_Y_UP = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]])
Y_DOWN = np.diag([1.0, -1.0, -1.0])  # Y-up -> MediaPipe's y-down world (a half turn)


@dataclass
class BoneTable:
    """Which BVH joint is which humanoid bone / landmark (see cmu-bones.yaml)."""

    path: str
    unit: float = 1.0
    up: str = "y"
    vmc: dict[str, str] = field(default_factory=dict)  # Unity bone -> BVH joint
    mediapipe: dict[str, str] = field(default_factory=dict)  # landmark -> BVH joint
    where: dict[tuple, tuple[int, int]] = field(default_factory=dict, repr=False)

    def error(self, loc: tuple, message: str) -> DataError:
        line, col = self.where.get(loc, (None, None))
        return DataError(self.path, line, col, message)


def load_bones(path: str | Path) -> BoneTable:
    """Read a bone table; a mistake is a one-line ``file:line:col`` DataError."""
    return parse_bones(load_file(path))


def parse_bones(doc) -> BoneTable:
    """A bone table from a loaded file (``puppet.data.yamlfile.Located``)."""
    path = doc.path
    data = doc.data
    if not isinstance(data, dict):
        raise doc.error((), "a bone table is a mapping with unit, up, vmc and mediapipe")
    known = {"description", "unit", "up", "vmc", "mediapipe"}
    for key in data:
        if key not in known:
            raise doc.error((key,), f"unknown key '{key}'; expected one of: "
                                    f"{', '.join(sorted(known))}", prefer_key=True)
    table = BoneTable(str(path))
    unit = data.get("unit", 1.0)
    if isinstance(unit, bool) or not isinstance(unit, (int, float)) or not 1e-6 <= unit <= 1e3:
        raise doc.error(("unit",), "unit must be metres per BVH unit, a number 1e-6..1000 "
                                   "(CMU: 0.056444)")
    table.unit = float(unit)
    up = data.get("up", "y")
    if up not in ("y", "z"):
        raise doc.error(("up",), f"up must be y or z (the clip's up axis), got {up!r}")
    table.up = up
    for part, names in (("vmc", unity.PARENTS), ("mediapipe", mediapipe.LANDMARKS)):
        section = data.get(part, {})
        if not isinstance(section, dict):
            raise doc.error((part,), f"{part} must map names to BVH joint names")
        for name, joint in section.items():
            if name not in names:
                what = "a Unity humanoid bone" if part == "vmc" else "a MediaPipe landmark"
                raise doc.error((part, name), f"'{name}' is not {what}", prefer_key=True)
            if not isinstance(joint, str) or not joint or len(joint) > MAX_NAME:
                raise doc.error((part, name), f"{part}.{name}: expected a BVH joint name "
                                              f"(1 to {MAX_NAME} characters)")
            getattr(table, part)[str(name)] = joint
            table.where[(part, name)] = doc.where((part, name)) or (None, None)
    return table


def _joint_index(clip: Clip, table: BoneTable, part: str, name: str, joint: str) -> int:
    try:
        return clip.index(joint)
    except KeyError as exc:
        raise table.error((part, name), f"{part}.{name}: {exc.args[0]}") from None


def _matrices_to_quats(m: np.ndarray) -> np.ndarray:
    """(..., 3, 3) rotation matrices -> (..., 4) unit quaternions (x, y, z, w)."""
    m00, m11, m22 = m[..., 0, 0], m[..., 1, 1], m[..., 2, 2]
    out = np.empty(m.shape[:-2] + (4,))
    w = np.sqrt(np.maximum(0.0, 1.0 + m00 + m11 + m22)) / 2.0
    x = np.sqrt(np.maximum(0.0, 1.0 + m00 - m11 - m22)) / 2.0
    y = np.sqrt(np.maximum(0.0, 1.0 - m00 + m11 - m22)) / 2.0
    z = np.sqrt(np.maximum(0.0, 1.0 - m00 - m11 + m22)) / 2.0
    x = np.copysign(x, m[..., 2, 1] - m[..., 1, 2])
    y = np.copysign(y, m[..., 0, 2] - m[..., 2, 0])
    z = np.copysign(z, m[..., 1, 0] - m[..., 0, 1])
    out[..., 0], out[..., 1], out[..., 2], out[..., 3] = x, y, z, w
    return out / np.linalg.norm(out, axis=-1, keepdims=True)


def _world(clip: Clip, table: BoneTable) -> tuple[np.ndarray, np.ndarray]:
    """World rotations and positions (metres) with Y up, right-handed."""
    rot, pos = clip.world_transforms()
    pos = pos * table.unit
    if table.up == "z":
        rot = Z_UP_TO_Y_UP @ rot
        pos = pos @ Z_UP_TO_Y_UP.T
    return rot, pos


def vmc_bones(clip: Clip, table: BoneTable) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """Unity bone -> ((frames, 3) local positions, (frames, 4) local rotations), in
    Unity's frame, each relative to its nearest listed ancestor."""
    if not table.vmc:
        raise table.error((), "the bone table lists no vmc bones")
    index = {bone: _joint_index(clip, table, "vmc", bone, j) for bone, j in table.vmc.items()}
    by_joint = {i: bone for bone, i in index.items()}
    if len(by_joint) != len(index):
        raise table.error(("vmc",), "two vmc bones name the same BVH joint")
    rot, pos = _world(clip, table)
    out = {}
    for bone in unity.BONES:  # parents first
        if bone not in index:
            continue
        i = index[bone]
        parent = clip.joints[i].parent  # the nearest listed BVH ancestor
        while parent >= 0 and parent not in by_joint:
            parent = clip.joints[parent].parent
        expected = unity.present_parent(bone, index)
        got = by_joint.get(parent)
        if got != expected:
            raise table.error(("vmc", bone), f"vmc.{bone}: its nearest listed BVH ancestor "
                                             f"is {got or 'none'} but in Unity's hierarchy "
                                             f"it is {expected or 'none'}; list the joints "
                                             f"so that both agree")
        if parent < 0:
            local_r, local_p = rot[:, i], pos[:, i]
        else:
            pr_t = np.swapaxes(rot[:, parent], -1, -2)
            local_r = pr_t @ rot[:, i]
            local_p = np.einsum("fab,fb->fa", pr_t, pos[:, i] - pos[:, parent])
        out[bone] = (local_p @ MIRROR.T, _matrices_to_quats(MIRROR @ local_r @ MIRROR))
    return out


def vmc_world(clip: Clip, table: BoneTable) -> dict[str, np.ndarray]:
    """The listed bones' world positions (frames, 3) in Unity's frame: what a
    receiver's forward kinematics should find."""
    _, pos = _world(clip, table)
    return {bone: pos[:, clip.index(j)] @ MIRROR.T for bone, j in table.vmc.items()}


def mediapipe_points(clip: Clip, table: BoneTable) -> dict[str, np.ndarray]:
    """Landmark -> (frames, 3) positions in metres, MediaPipe's world axes (y down)."""
    if not table.mediapipe:
        raise table.error((), "the bone table lists no mediapipe landmarks")
    _, pos = _world(clip, table)
    return {name: pos[:, _joint_index(clip, table, "mediapipe", name, j)] @ Y_DOWN.T
            for name, j in table.mediapipe.items()}


PICTURE_HEIGHT = 2.2  # m a side-on picture of the clip is high (mediapipe-image's unit)
PICTURE_ASPECT = 4.0 / 3.0  # its width over its height (mediapipe-image's x scale)
PICTURE_TOP = 2.0  # m above the clip's lowest point: the picture's top edge


def picture_points(clip: Clip, table: BoneTable) -> dict[str, np.ndarray]:
    """Landmark -> (frames, 3) normalised picture landmarks of the clip filmed side-on
    (the camera looking across the way the clip travels, the performer's right side
    to it: x the way it travels, in picture widths, 0.5 at the middle of its travel; y
    down from the top edge, in picture heights; z the depth across, in widths), as the
    MediaPipe-to-OSC bridge's tracker would see them before its selfie flip."""
    if not table.mediapipe:
        raise table.error((), "the bone table lists no mediapipe landmarks")
    _, pos = _world(clip, table)
    hips = pos[:, [_joint_index(clip, table, "mediapipe", n, table.mediapipe[n])
                   for n in ("left_hip", "right_hip")]].mean(axis=1)
    way = hips[-1] - hips[0]
    way[1] = 0.0
    if np.linalg.norm(way) < 0.05:
        way = np.array([0.0, 0.0, 1.0])
    way /= np.linalg.norm(way)
    across = np.cross(way, [0.0, 1.0, 0.0])  # to the performer's right
    middle = 0.5 * (np.min(hips @ way) + np.max(hips @ way))
    top = float(np.min(pos[..., 1])) + PICTURE_TOP
    width = PICTURE_HEIGHT * PICTURE_ASPECT
    out = {}
    for name, joint in table.mediapipe.items():
        p = pos[:, _joint_index(clip, table, "mediapipe", name, joint)]
        out[name] = np.stack([0.5 + (p @ way - middle) / width, (top - p[:, 1]) / PICTURE_HEIGHT,
                              -(p @ across) / width], axis=1)
    return out


def encoder(clip: Clip, fmt: str, table: BoneTable | None = None,
            retargeter=None) -> Callable[[int, float], bytes]:
    """``encode(frame, time) -> datagram`` for one of the clip's frames."""
    if fmt == "vmc":
        bones = vmc_bones(clip, table)
        f32 = {b: (p.astype(np.float32).astype(float), q.astype(np.float32).astype(float))
               for b, (p, q) in bones.items()}

        def encode(k: int, t: float) -> bytes:
            return vmc.encode_frame(t, {b: (tuple(p[k]), tuple(q[k]))
                                        for b, (p, q) in f32.items()})
        return encode
    if fmt == "mediapipe":
        points = mediapipe_points(clip, table)

        def encode(k: int, t: float) -> bytes:
            return mediapipe.encode_frame(t, {n: tuple(p[k]) for n, p in points.items()})
        return encode
    if fmt == "mediapipe-osc":  # as the bridge sends it: a count, mirrored, no time
        from puppet.mocap.mediapipe_bridge import encode_pose

        points = picture_points(clip, table)

        def encode(k: int, t: float) -> bytes:
            return encode_pose({n: tuple(p[k]) for n, p in points.items()})
        return encode
    if fmt == "puppet":
        names = [n for n in retargeter.point_names if n in clip.names]
        _, pos = clip.world_transforms()  # the mapping says the clip's unit and axes
        cols = [clip.index(n) for n in names]

        def encode(k: int, t: float) -> bytes:
            values = retargeter.channels({n: pos[k, c] for n, c in zip(names, cols)})
            return puppet_osc.encode_frame(t, values)
        return encode
    raise ValueError(fmt)


def schedule(frames: int, frame_time: float, speed: float, loop: bool) -> Iterator[tuple[int, float]]:
    """(clip frame, send time in seconds from the start) for every frame sent."""
    k = 0
    while True:
        for f in range(frames):
            yield f, k * frame_time / speed
            k += 1
        if not loop:
            return


def stream(encode: Callable[[int, float], bytes], frames: int, frame_time: float,
           address: tuple[str, int], speed: float = 1.0, loop: bool = False,
           stop=None, on_sent: Callable[[int], None] | None = None,
           clock: Callable[[], float] = time.perf_counter) -> int:
    """Send the frames in real time (each at its time from the start, scaled by
    ``speed``); returns how many were sent. ``stop``: a ``threading.Event`` that ends
    the stream early."""
    sent = 0
    with socket.socket(socket.AF_INET6 if ":" in address[0] else socket.AF_INET,
                       socket.SOCK_DGRAM) as sock:
        start = clock()
        for f, t in schedule(frames, frame_time, speed, loop):
            if stop is not None and stop.is_set():
                break
            wait = start + t - clock()
            if wait > 0:
                if stop is not None:
                    if stop.wait(wait):
                        break
                else:
                    time.sleep(wait)
            try:
                sock.sendto(encode(f, t), address)
            except OSError:  # nobody listening yet (ICMP refused): UDP goes on
                pass
            sent += 1
            if on_sent is not None:
                on_sent(sent)
    return sent
