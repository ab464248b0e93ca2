"""Retargeting: a mapping file turns a source's named 3-D points into the planar
figure's channels, for any rig (names, units, frame rate come from data, not code)."""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest

from puppet.data.errors import DataError
from puppet.data.mappings import parse_mapping
from puppet.data.yamlfile import load_text
from puppet.mocap.bvh import parse_bvh, read_bvh
from puppet.mocap.retarget import Retargeter, clip_points, load_mapping, retarget_clip

WALK = "assets/mocap/cmu-131_01-walk.bvh"
CMU = "assets/mappings/cmu-131.yaml"


def mapping_from(text: str, path: str = "test-mapping.yaml"):
    return parse_mapping(load_text(text, path))


def _emit_bvh(clip, rename, scale: float, every: int) -> str:
    """The clip as another rig would write it: joints renamed, lengths times
    ``scale`` (offsets and position channels), every ``every``-th frame."""
    joints = clip.joints
    kids: dict[int, list[int]] = {}
    for i, j in enumerate(joints):
        kids.setdefault(j.parent, []).append(i)
    lines = ["HIERARCHY"]

    def emit(i: int, depth: int) -> None:
        j, ind = joints[i], "  " * depth
        if j.end_site:
            lines.extend([f"{ind}End Site", f"{ind}{{",
                          f"{ind}  OFFSET {' '.join(f'{v * scale:.6f}' for v in j.offset)}",
                          f"{ind}}}"])
            return
        word = "ROOT" if j.parent < 0 else "JOINT"
        lines.extend([f"{ind}{word} {rename(j.name)}", f"{ind}{{",
                      f"{ind}  OFFSET {' '.join(f'{v * scale:.6f}' for v in j.offset)}",
                      f"{ind}  CHANNELS {len(j.channels)} {' '.join(j.channels)}"])
        for k in kids.get(i, []):
            emit(k, depth + 1)
        lines.append(f"{ind}}}")

    emit(0, 0)
    motion = clip.motion[::every].copy()
    for j in joints:
        for c, name in enumerate(j.channels):
            if name.endswith("position"):
                motion[:, j.first_channel + c] *= scale
    lines += ["MOTION", f"Frames: {len(motion)}", f"Frame Time: {clip.frame_time * every:.7f}"]
    lines += [" ".join(f"{v:.6f}" for v in row) for row in motion]
    return "\n".join(lines) + "\n"


def test_another_rig_needs_only_another_mapping_file():
    """Other joint names, centimetres instead of CMU units, 60 instead of 120 fps:
    the same performance through a mapping that names the new joints and unit gives
    the same channels, at the same moments."""
    clip = read_bvh(WALK)
    names = {"Hips": "pelvis_root", "LeftHip": "l_thigh", "RightHip": "r_thigh",
             "LeftKnee": "l_shin", "RightKnee": "r_shin", "LeftAnkle": "l_foot",
             "RightAnkle": "r_foot", "LeftToe": "l_toes", "RightToe": "r_toes",
             "Chest": "spine_1", "Chest2": "spine_2", "Neck": "neck_1", "Head": "head_1",
             "LeftShoulder": "l_upperarm", "RightShoulder": "r_upperarm",
             "LeftElbow": "l_forearm", "RightElbow": "r_forearm", "LeftWrist": "l_hand",
             "RightWrist": "r_hand"}
    cm_per_unit = 5.6444
    other = parse_bvh(_emit_bvh(clip, lambda n: names.get(n, "x_" + n), cm_per_unit, 2),
                      "other.bvh")
    assert round(other.fps) == 60
    text = Path(CMU).read_text(encoding="utf-8")
    for old, new in sorted(names.items(), key=lambda kv: -len(kv[0])):
        text = re.sub(rf"\b{old}\b", new, text)
    text = text.replace("unit: 0.056444", "unit: 0.01")
    # one plane for both (the take's last frame differs by a frame, and so would
    # 'travel' by a hair, which moves limbs seen nearly end-on)
    text = text.replace("plane: travel", "plane: [0, 0, 1]")
    cmu = load_mapping(CMU).model_copy(update={"plane": (0.0, 0.0, 1.0)})
    mine = retarget_clip(clip, cmu)
    theirs = retarget_clip(other, mapping_from(text))
    assert set(theirs.channels) == set(mine.channels)
    for name, values in theirs.channels.items():
        diff = values - mine.channels[name][::2]
        if name.endswith((".x", ".y")):  # metres
            assert np.nanmax(np.abs(diff)) < 1e-3, name
        else:  # degrees; where a limb is seen nearly end-on its angle holds from the
            # last frame that saw it, which the halved frame rate may make an earlier one
            diff = np.abs((diff + 180.0) % 360.0 - 180.0)
            assert np.nanpercentile(diff, 95) < 0.01 and np.nanmedian(diff) < 1e-4, name


def test_a_stream_frame_by_frame_gives_the_clip_channels():
    """The live path (one frame at a time, as a network source calls it) and the clip
    path (vectorised) are one computation."""
    clip = read_bvh(WALK)
    mapping = load_mapping(CMU)
    whole = retarget_clip(clip, mapping)
    forward = Retargeter(mapping).clip(clip_points(clip, mapping.point_names()),
                                       clip.frame_time)
    # a stream cannot know where the whole take goes: give the plane the clip found
    travel = clip_points(clip, ["LeftHip", "RightHip"])
    d = (travel["LeftHip"][-1] + travel["RightHip"][-1]
         - travel["LeftHip"][0] - travel["RightHip"][0])
    fixed = mapping.model_copy(update={"plane": (float(d[0]), 0.0, float(d[2]))})
    live = Retargeter(fixed)
    pts = clip_points(clip, live.point_names)
    for k in range(clip.frames):
        got = live.channels({n: p[k] for n, p in pts.items()})
        seen = {n for n, v in whole.channels.items() if not np.isnan(v[k])}
        assert set(got) == seen, k  # the same channels, none missing from the stream
        for name, value in got.items():
            assert value == pytest.approx(whole.channels[name][k], abs=1e-6), (name, k)
    assert forward.channels.keys() == whole.channels.keys()


def test_the_signs_are_the_figures():
    """A performer facing +z in a right-handed, y-up frame, the thigh 30 deg forward,
    the knee bent 45 deg, the trunk upright: hip +30, knee -45, like the figure's."""
    mapping = mapping_from("""
root: {point: hip, floor: 0}
plane: [0, 0, 1]
segments:
  trunk: {from: hip, to: neck, rest: up}
  thigh: {from: hip, to: knee}
  shank: {from: knee, to: ankle}
channels:
  hip_near: {segment: thigh, relative_to: trunk}
  knee_near: {segment: shank, relative_to: thigh}
  root.angle: {segment: trunk}
""")
    a, b = math.radians(30), math.radians(30 - 45)
    hip = np.array([0.1, 0.9, 0.0])
    knee = hip + 0.4 * np.array([0.0, -math.cos(a), math.sin(a)])
    ankle = knee + 0.4 * np.array([0.0, -math.cos(b), math.sin(b)])
    points = {"hip": hip, "neck": hip + [0, 0.5, 0], "knee": knee, "ankle": ankle}
    got = Retargeter(mapping).channels(points)
    assert got["hip_near"] == pytest.approx(30.0)
    assert got["knee_near"] == pytest.approx(-45.0)
    assert got["root.angle"] == pytest.approx(0.0, abs=1e-9)
    assert got["root.y"] == pytest.approx(0.9)
    # the same body in a left-handed frame (Unity's: z mirrored) says the same
    lefty = mapping.model_copy(update={"source": mapping.source.model_copy(
        update={"handedness": "left"}), "plane": (0.0, 0.0, -1.0)})
    mirrored = {n: p * [1, 1, -1] for n, p in points.items()}
    assert Retargeter(lefty).channels(mirrored)["hip_near"] == pytest.approx(30.0)


def test_a_segment_seen_end_on_holds_its_last_angle():
    mapping = mapping_from("""
root: {point: shoulder, floor: 0}
plane: [1, 0, 0]
segments:
  arm: {from: shoulder, to: hand}
channels:
  shoulder_near: {segment: arm}
""")
    rt = Retargeter(mapping)
    s = np.zeros(3)
    assert rt.channels({"shoulder": s, "hand": [0.3, -0.3, 0]})["shoulder_near"] \
        == pytest.approx(45.0)
    # the arm straight out sideways (along z): no angle in the plane, the last one held
    assert rt.channels({"shoulder": s, "hand": [0.01, 0.0, 0.5]})["shoulder_near"] \
        == pytest.approx(45.0)


def test_mapping_mistakes_are_one_line_errors_at_their_place():
    with pytest.raises(DataError) as err:
        mapping_from("root: {point: Hips}\nsegments:\n  a: {from: Hips, to: Knee}\n"
                     "channels:\n  hip: {segment: b}\n")
    assert "test-mapping.yaml:" in str(err.value) and "segment 'b'" in str(err.value)
    assert "\n" not in str(err.value)
    with pytest.raises(DataError, match="facing"):
        mapping_from("root: {point: Hips}\nplane: facing\nsegments:\n"
                     "  a: {from: Hips, to: Knee}\n")
    with pytest.raises(DataError, match=r"source_unit|1e-6\.\.1000"):
        mapping_from("root: {point: Hips}\nsource: {unit: 0}\nsegments:\n"
                     "  a: {from: Hips, to: Knee}\n")


def test_a_clip_without_the_mapped_joints_is_refused_by_name():
    clip = read_bvh("assets/mocap/cmu-01_01-jumps.bvh")  # LeftUpLeg..., not LeftHip
    with pytest.raises(DataError, match="no point named .*LeftHip"):
        retarget_clip(clip, load_mapping(CMU))


def test_the_shipped_walk_retargets_to_a_walk():
    """The CMU walk through cmu-131: about 2.8 m forward, the hips about the figure's
    height, the knees bending and straightening as steps do."""
    rc = retarget_clip(read_bvh(WALK), load_mapping(CMU))
    assert 2.5 < rc.channels["root.x"][-1] < 3.1
    walk = (rc.times > 4.3) & (rc.times < 6.7)
    assert 0.8 < np.median(rc.channels["root.y"][walk]) < 0.95
    for knee in ("knee_near", "knee_far"):
        k = rc.channels[knee][walk]
        assert k.max() > -10 and k.min() < -60  # straight in stance, bent in swing
    assert rc.at(-1.0) == rc.at(0.0) and rc.at(99.0) == rc.at(rc.duration)


def test_a_stream_faces_the_way_the_hips_say():
    """plane: travel or facing, a stream: forward is where the performer faces (from
    the hips), so walking toward -x drives the figure forward, hips still positive."""
    mapping = load_mapping(CMU)
    rt = Retargeter(mapping)
    clip = read_bvh(WALK)
    pts = clip_points(clip, rt.point_names)
    turned = {n: p * [-1, 1, -1] for n, p in pts.items()}  # the take turned round (z)
    first = {n: p[600] for n, p in pts.items()}
    got = rt.channels(first)
    rt2 = Retargeter(mapping)
    got2 = rt2.channels({n: p[600] for n, p in turned.items()})
    assert got2["hip_near"] == pytest.approx(got["hip_near"], abs=1e-6)
    assert got2["knee_far"] == pytest.approx(got["knee_far"], abs=1e-6)


def test_a_clip_with_no_frames_is_a_one_line_error():
    text = Path(WALK).read_text(encoding="utf-8")
    head = text[:text.index("MOTION")]
    empty = parse_bvh(head + "MOTION\nFrames: 0\nFrame Time: 0.008333\n", "empty.bvh")
    with pytest.raises(DataError, match="no frames") as err:
        retarget_clip(empty, load_mapping(CMU), "empty.bvh")
    assert str(err.value).startswith("empty.bvh") and "\n" not in str(err.value)


def test_a_mapping_without_facing_points_for_its_plane_is_refused():
    with pytest.raises(DataError, match="needs 'facing"):
        mapping_from("root: {point: Hips}\nplane: travel\nsegments:\n"
                     "  a: {from: Hips, to: Knee}\n")
    mapping_from("root: {point: Hips}\nplane: [1, 0, 0]\nsegments:\n"
                 "  a: {from: Hips, to: Knee}\n")  # a given plane needs none


def test_a_mapping_check_error_points_at_the_field_without_a_dump():
    """A channel naming an undefined segment is an error at that channel's line, with a
    did-you-mean, not at 1:1 with the whole file quoted; so is a plane without facing."""
    text = ("name: hop-m\nroot: {point: Hips}\nplane: [1, 0, 0]\nsegments:\n"
            "  thigh_near: {from: Hips, to: Knee}\n  shank_near: {from: Knee, to: Ankle}\n"
            "channels:\n  knee_near: {segment: shank_near, relative_to: thigh_nar}\n")
    with pytest.raises(DataError) as err:
        mapping_from(text, "e3.yaml")
    message = str(err.value)
    assert message.startswith("e3.yaml:8:"), message
    assert "did you mean 'thigh_near'?" in message and "(got" not in message
    with pytest.raises(DataError) as err:
        mapping_from("root: {point: Hips}\nsegments:\n  a: {from: Hips, to: Knee}\n"
                     "plane: facing\n", "e4.yaml")
    assert str(err.value).startswith("e4.yaml:4:") and "(got" not in str(err.value)


def _walk_points(names):
    from puppet.mocap.bvh import read_bvh
    from puppet.mocap.retarget import clip_points

    clip = read_bvh(WALK)
    return clip, clip_points(clip, names)


def test_a_looped_clip_carries_root_x_on_by_its_lap_not_from_zero():
    """The clip's root starts 1.5 m out and goes 1 m in its 2 s: each lap adds
    end - start (1 m), not where it ends (2.5 m)."""
    from puppet.mocap.clip_source import LAP_CHANNEL, ClipSource
    from puppet.mocap.retarget import RetargetedClip

    t = np.arange(61) / 30.0
    clip = RetargetedClip(times=t, channels={LAP_CHANNEL: 1.5 + 0.5 * t, "hip": np.sin(t)})
    source = ClipSource(clip, loop=True)
    assert source.values_at(1.0)[LAP_CHANNEL] == pytest.approx(2.0)
    assert source.values_at(5.0)[LAP_CHANNEL] == pytest.approx(2.0 + 2 * 1.0)


def test_a_left_handed_z_up_source_retargets_as_the_right_handed_y_up_one():
    """The walk's points rewritten as a left-handed, z-up rig writes them: (x, y, z)
    -> (-x, -z, y). With a mapping saying so, the same channels come out."""
    from puppet.mocap.retarget import Retargeter, load_mapping

    mapping = load_mapping("assets/mappings/cmu-131.yaml").model_copy(
        update={"plane": (0.0, 0.0, 1.0)})
    clip, pts = _walk_points(mapping.point_names())
    mine = Retargeter(mapping).clip(pts, clip.frame_time)
    other = {n: np.stack([-p[:, 0], -p[:, 2], p[:, 1]], axis=1) for n, p in pts.items()}
    source = mapping.source.model_copy(update={"up": "z", "handedness": "left"})
    theirs_map = mapping.model_copy(update={"source": source, "plane": (0.0, -1.0, 0.0)})
    theirs = Retargeter(theirs_map).clip(other, clip.frame_time)
    assert set(theirs.channels) == set(mine.channels)
    for name, values in theirs.channels.items():
        ok = ~np.isnan(values)
        assert np.abs(values[ok] - mine.channels[name][ok]).max() < 1e-6, name


def test_a_take_that_stands_still_faces_the_way_its_hips_say():
    """plane: travel, but the root does not move: the facing points give the plane
    (their first frame), the same as plane: facing for a take that never turns."""
    from puppet.mocap.retarget import Retargeter, load_mapping

    travel = load_mapping("assets/mappings/cmu-131.yaml")
    assert travel.plane == "travel" and travel.facing
    clip, pts = _walk_points(travel.point_names())
    still = {n: np.repeat(p[:1], 30, axis=0) for n, p in pts.items()}
    a = Retargeter(travel).clip(still, clip.frame_time)
    b = Retargeter(travel.model_copy(update={"plane": "facing"})).clip(still,
                                                                       clip.frame_time)
    assert a.channels.keys() == b.channels.keys()
    for name in a.channels:
        assert np.array_equal(a.channels[name], b.channels[name], equal_nan=True), name


def test_facing_directions_missing_at_the_start_take_the_first_good_one():
    from puppet.mocap.retarget import _filled

    nan = [np.nan] * 3
    forward = np.array([nan, nan, [1.0, 0, 0], nan, [0, 0, 1.0], nan])
    got = _filled(forward)
    assert got.tolist() == [[1, 0, 0], [1, 0, 0], [1, 0, 0], [1, 0, 0], [0, 0, 1],
                            [0, 0, 1]]
