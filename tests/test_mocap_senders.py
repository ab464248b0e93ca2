"""Senders as people use them (issue 30), each through the real UDP path (a socket, the
source's server thread, the decoder, the mapping, the queue, a drain): a VMC sender of
rotations alone, a VMC frame spread over two bundles with one time, puppet channels
likewise, and the common MediaPipe-to-OSC bridge's messages (a leading count, picture
landmarks, mirrored, "no pose")."""

from __future__ import annotations

import socket
import time

import numpy as np
import pytest
from pythonosc.osc_bundle_builder import IMMEDIATELY, OscBundleBuilder

from puppet.commands.streams import source_for
from puppet.mocap import mediapipe_bridge, puppet_osc, unity, vmc
from puppet.mocap.bvh import read_bvh
from puppet.mocap.send import MIRROR, _matrices_to_quats, _world, encoder, load_bones

ANGLES = ("hip_near", "knee_near", "ankle_near", "hip_far", "knee_far", "ankle_far",
          "shoulder_near", "elbow_near", "shoulder_far", "elbow_far")


@pytest.fixture(scope="module")
def walk():
    return read_bvh("assets/mocap/cmu-131_01-walk.bvh")


@pytest.fixture(scope="module")
def table():
    return load_bones("assets/mocap/cmu-bones.yaml")


def _through_udp(fmt, frames, mapping=None):
    """Each item of ``frames`` (a list of datagrams: one frame) sent over loopback to a
    started source; after each, what one drain hands over (the channels, or None)."""
    source = source_for("udp://127.0.0.1:0", fmt, mapping, None)
    out = []
    with source, socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as sock:
        sent = 0
        for datagrams in frames:
            for dgram in datagrams:
                sock.sendto(dgram, (source.host, source.port))
                sent += 1
            deadline = time.monotonic() + 5.0  # (a datagram the system lost: go on)
            while source.decoder.counts.packets < sent and time.monotonic() < deadline:
                time.sleep(0.0005)
            events = source.drain()
            out.append(events[0]["values"] if events else None)
    return out, source


def _rms(a, b, names, frames=slice(None)):
    return {n: float(np.sqrt(np.mean([(x[n] - y[n]) ** 2 for x, y in zip(a[frames], b[frames])
                                      if x and y and n in x and n in y])))
            for n in names}


# -- VMC: rotations alone --------------------------------------------------------------------
PRIMARY = {"Spine": "Chest", "Chest": "UpperChest", "UpperChest": "Neck", "Neck": "Head"}
for _side in ("Left", "Right"):
    PRIMARY.update({f"{_side}UpperLeg": f"{_side}LowerLeg", f"{_side}LowerLeg": f"{_side}Foot",
                    f"{_side}Foot": f"{_side}Toes", f"{_side}Shoulder": f"{_side}UpperArm",
                    f"{_side}UpperArm": f"{_side}LowerArm", f"{_side}LowerArm": f"{_side}Hand"})


def _turn(a, b):
    """The least rotation taking direction a to direction b (3x3)."""
    a, b = a / np.linalg.norm(a), b / np.linalg.norm(b)
    v, c = np.cross(a, b), float(a @ b)
    if np.linalg.norm(v) < 1e-9:
        return np.eye(3)
    k = np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])
    return np.eye(3) + k + k @ k / (1.0 + c)


def rotation_only_frames(clip, table, frames):
    """The clip as a VRM-normalised rotation-only sender sends it: every bone's rotation
    turned so that the avatar's rest bone (assets/mocap/vmc-avatar.yaml, a T-pose)
    points where the clip's does, every position 0 0 0, one bundle a frame."""
    rot, _ = _world(clip, table)
    rest = np.zeros((len(clip.joints), 3))
    for i, j in enumerate(clip.joints):
        rest[i] = (rest[j.parent] if j.parent >= 0 else 0.0) + j.offset * table.unit
    index = {b: clip.index(j) for b, j in table.vmc.items()}
    avatar = vmc.avatar()
    world = {}
    for bone, i in index.items():
        child = PRIMARY.get(bone)
        turn = np.eye(3)
        if child in index and child in avatar:
            d_clip = rest[index[child]] - rest[i]
            if np.linalg.norm(d_clip) > 1e-6:
                turn = _turn(MIRROR @ np.asarray(avatar[child]), d_clip)
        world[bone] = rot[:, i] @ turn
    local = {}
    for bone in unity.BONES:
        if bone not in world:
            continue
        parent = unity.present_parent(bone, world)
        r = world[bone] if parent is None else np.swapaxes(world[parent], -1, -2) @ world[bone]
        local[bone] = _matrices_to_quats(MIRROR @ r @ MIRROR)
    return [[vmc.encode_frame(k * clip.frame_time,
                              {b: ((0.0, 0.0, 0.0), tuple(float(c) for c in q[k]))
                               for b, q in local.items()})] for k in frames]


def test_a_vmc_sender_of_rotations_alone_drives_the_avatars_bones(walk, table):
    """Positions from the rotations through the avatar's bone lengths: the joint angles
    are the full stream's (the directions are the clip's; the lengths the avatar's)."""
    frames = range(500, 740, 4)
    full = encoder(walk, "vmc", table)
    got, source = _through_udp("vmc", rotation_only_frames(walk, table, frames))
    want, _ = _through_udp("vmc", [[full(k, k * walk.frame_time)] for k in frames])
    assert source.decoder.counts.total_dropped == 0 and source.unmapped == 0
    assert all(g is not None for g in got)
    errors = _rms(got, want, ANGLES)
    assert max(errors.values()) < 3.0, errors
    assert source.decoder.rotation_only()


def test_without_the_avatar_a_rotation_only_frame_would_be_a_heap(walk, table):
    """(what the avatar is for: every bone at its parent's place gives no channel)"""
    decoder = vmc.VmcDecoder()
    frame = decoder.feed(rotation_only_frames(walk, table, [500])[0][0])[0]
    assert len({tuple(np.round(p, 6)) for p in frame.points.values()}) > 15  # spread out
    assert frame.points["Head"][1] > frame.points["Hips"][1] > frame.points["LeftFoot"][1]


# -- one frame, several bundles ----------------------------------------------------------------
def _split(dgram: bytes) -> list[bytes]:
    """A one-bundle VMC frame as two bundles with the same /VMC/Ext/T (OK in the last)."""
    from puppet.mocap.osc import messages_of

    messages, _ = messages_of(dgram)
    time_message = next(m for m in messages if m.address == vmc.TIME)
    body = [m for m in messages if m.address not in (vmc.TIME, vmc.OK)]
    ok = next(m for m in messages if m.address == vmc.OK)
    half = len(body) // 2
    out = []
    for part in (body[:half], body[half:] + [ok]):
        builder = OscBundleBuilder(IMMEDIATELY)
        for m in part[:-1] if part[-1] is ok else part:
            builder.add_content(m)
        builder.add_content(time_message)
        if part[-1] is ok:
            builder.add_content(ok)
        out.append(builder.build().dgram)
    return out


def test_a_vmc_frame_spread_over_two_bundles_with_one_time_is_one_frame(walk, table):
    frames = range(500, 700, 4)
    encode = encoder(walk, "vmc", table)
    whole = [[encode(k, k * walk.frame_time)] for k in frames]
    split = [_split(d[0]) for d in whole]
    got, source = _through_udp("vmc", split)
    want, _ = _through_udp("vmc", whole)
    counts = source.decoder.counts
    assert counts.total_dropped == 0 and counts.dropped["stale"] == 0
    assert counts.continued == len(frames)  # each frame's second bundle went on with it
    assert max(_rms(got, want, ANGLES).values()) < 1e-6  # after both halves: the same


def test_puppet_channels_spread_over_two_messages_with_one_time(capsys):
    frames = [[puppet_osc.encode_frame(k / 60, {"a": float(k)}),
               puppet_osc.encode_frame(k / 60, {"b": -float(k)})] for k in range(30)]
    got, source = _through_udp("puppet", frames)
    assert got[-1] == {"a": 29.0, "b": -29.0}
    assert source.decoder.counts.continued == 30 and source.decoder.counts.total_dropped == 0
    again, source = _through_udp("puppet", [[puppet_osc.encode_frame(1.0, {"a": 1.0})] * 2])
    assert source.decoder.counts.dropped == {"stale": 1}  # the same time, nothing new


# -- the MediaPipe-to-OSC bridge -------------------------------------------------------------
def test_the_mediapipe_bridges_messages_drive_the_figure_as_world_landmarks_do(walk, table):
    """The walk filmed side-on as the bridge sends it (a count of 1, picture landmarks,
    mirrored), every fifth frame a "no pose": hips and knees within a few degrees of
    the world-landmark stream's over the walking part; no pose counted, not dropped."""
    frames = range(500, 760, 4)
    bridge, world = encoder(walk, "mediapipe-osc", table), encoder(walk, "mediapipe", table)
    sent = [[bridge(k, 0.0)] + ([mediapipe_bridge.encode_pose(None)] if i % 5 == 4 else [])
            for i, k in enumerate(frames)]
    got, source = _through_udp("mediapipe-osc", sent)
    want, _ = _through_udp("mediapipe", [[world(k, k * walk.frame_time)] for k in frames])
    counts = source.decoder.counts
    assert counts.total_dropped == 0 and counts.no_pose == len(frames) // 5
    assert counts.frames == len(frames) and "no pose" in source.status()
    errors = _rms(got, want, ("hip_near", "knee_near", "hip_far", "knee_far"))
    assert max(errors.values()) < 6.0, errors


def test_the_bridges_mirror_is_undone_and_its_older_form_read():
    """The bridge's left is the performer's right (its picture is a selfie view):
    unmirrored, the near knee is the performer's right; its older form (no count) reads
    the same; a count sent to the mediapipe format (world landmarks) says which format
    takes it."""
    right_knee = (0.62, 0.7, 0.0)
    points = {"right_knee": right_knee, "left_knee": (0.4, 0.7, 0.0)}
    for count in (True, False):
        d = mediapipe_bridge.MediaPipeBridgeDecoder()
        frame = d.feed(mediapipe_bridge.encode_pose(points, count=count))[0]
        assert frame.points["right_knee"] == pytest.approx(right_knee)
        assert frame.points["left_knee"] == pytest.approx((0.4, 0.7, 0.0))
    mirrored = mediapipe_bridge.encode_pose(points)
    unmirrored = mediapipe_bridge.MediaPipeBridgeDecoder(mirrored=False).feed(mirrored)[0]
    assert unmirrored.points["left_knee"] == pytest.approx((1 - 0.62, 0.7, 0.0))
    from puppet.mocap.mediapipe import MediaPipeDecoder

    d = MediaPipeDecoder()
    assert d.feed(mirrored) == [] and "--mocap-format mediapipe-osc" in d.counts.last_problem
