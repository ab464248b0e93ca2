"""The BVH reader (puppet/mocap/bvh.py): any skeleton, any channel order and count,
End Sites, frame times; forward kinematics; one-line errors; the planar writer."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from puppet.data.errors import DataError
from puppet.mocap.bvh import CMU_UNIT_METRES, PlanarJoint, parse_bvh, read_bvh, write_planar_bvh

ROOT = Path(__file__).resolve().parents[1]
WALK = ROOT / "assets" / "mocap" / "cmu-131_01-walk.bvh"
JUMPS = ROOT / "assets" / "mocap" / "cmu-01_01-jumps.bvh"

# A root that moves, an arm of two hinges about z (1 channel each, lengths 1 and 2) and
# a joint with 3 channels in X Y Z order, a second branch ending in an End Site.
SMALL = """HIERARCHY
ROOT pelvis
{
  OFFSET 0 0 0
  CHANNELS 6 Xposition Yposition Zposition Zrotation Yrotation Xrotation
  JOINT upper
  {
    OFFSET 0 1 0
    CHANNELS 1 Zrotation
    JOINT lower
    {
      OFFSET 0 1 0
      CHANNELS 1 Zrotation
      End Site
      {
        OFFSET 0 2 0
      }
    }
  }
  JOINT twist
  {
    OFFSET 1 0 0
    CHANNELS 3 Xrotation Yrotation Zrotation
    End Site
    {
      OFFSET 1 0 0
    }
  }
}
MOTION
Frames: 3
Frame Time: 0.04
0 0 0 0 0 0 0 0 0 0 0
1 2 3 0 0 0 90 0 0 0 0
0 0 0 90 0 0 0 90 0 90 90
"""


def test_small_hierarchy_names_channels_and_end_sites():
    clip = parse_bvh(SMALL, "small.bvh")
    assert clip.names == ["pelvis", "upper", "lower", "lower_end", "twist", "twist_end"]
    assert clip.frames == 3 and clip.frame_time == pytest.approx(0.04)
    assert clip.fps == pytest.approx(25.0)
    assert clip.joint("lower").channels == ("Zrotation",)
    assert clip.joint("twist").rotation_order == "XYZ"
    assert clip.joint("lower_end").end_site and clip.joint("lower_end").parent == 2
    assert clip.motion.shape == (3, 11)
    assert clip.channel("pelvis", "Yposition").tolist() == [0, 2, 0]
    assert clip.angles("twist")[2].tolist() == [0, 90, 90]


def test_forward_kinematics_of_a_planar_arm():
    pos = parse_bvh(SMALL).world_positions()
    i = parse_bvh(SMALL).index
    # frame 0: straight up the y axis
    assert pos[0, i("lower_end")] == pytest.approx([0, 4, 0])
    # frame 1: root moved to (1, 2, 3); upper turned 90 deg about z: the arm points -x
    assert pos[1, i("lower")] == pytest.approx([1 - 1, 2 + 1, 3])
    assert pos[1, i("lower_end")] == pytest.approx([1 - 3, 2 + 1, 3])
    # frame 2: root turned 90 deg about z, elbow a further 90: the forearm points -y
    assert pos[2, i("upper")] == pytest.approx([-1, 0, 0])
    assert pos[2, i("lower")] == pytest.approx([-2, 0, 0])
    assert pos[2, i("lower_end")] == pytest.approx([-2, -2, 0])


def test_rotation_channels_compose_in_the_order_they_are_listed():
    # twist at frame 2: Xrotation 0, Yrotation 90, Zrotation 90 -> Rx(0) Ry(90) Rz(90);
    # the end site's offset (1, 0, 0) goes to Ry(90) Rz(90) (1,0,0) = Ry(90) (0,1,0) = (0,1,0)
    clip = parse_bvh(SMALL)
    rot, pos = clip.world_transforms()
    twist, end = clip.index("twist"), clip.index("twist_end")
    root = rot[2, 0]  # root turned 90 about z
    local = np.linalg.solve(root, pos[2, end] - pos[2, twist])
    assert local == pytest.approx([0, 1, 0], abs=1e-12)
    # the same angles listed Z Y X give another direction: the order is really read
    zyx = SMALL.replace("CHANNELS 3 Xrotation Yrotation Zrotation",
                        "CHANNELS 3 Zrotation Yrotation Xrotation")
    clip2 = parse_bvh(zyx)  # now the numbers 0 90 90 mean z=0, y=90, x=90
    rot2, pos2 = clip2.world_transforms()
    local2 = np.linalg.solve(rot2[2, 0], pos2[2, end] - pos2[2, twist])
    assert local2 == pytest.approx([0, 0, -1], abs=1e-12)


def test_a_joint_may_have_no_channels_and_the_root_any_count():
    text = SMALL.replace("CHANNELS 6 Xposition Yposition Zposition Zrotation Yrotation "
                         "Xrotation", "CHANNELS 3 Yposition Xposition Zrotation")
    text = text.replace("    CHANNELS 3 Xrotation Yrotation Zrotation\n", "")
    rows = ["0 0 0 0 0", "2 1 0 90 0", "0 0 90 0 90"]
    text = text.split("Frame Time: 0.04\n")[0] + "Frame Time: 0.04\n" + "\n".join(rows) + "\n"
    clip = parse_bvh(text)
    assert clip.joint("twist").channels == ()
    assert clip.motion.shape == (3, 5)
    pos = clip.world_positions()
    assert pos[1, 0] == pytest.approx([1, 2, 0])  # Yposition first, then Xposition
    assert pos[1, clip.index("twist_end")] == pytest.approx([3, 2, 0])


def test_crlf_tabs_and_blank_lines_are_read():
    text = SMALL.replace("\n", "\r\n").replace("  ", "\t") + "\r\n\r\n"
    assert parse_bvh(text).motion.tolist() == parse_bvh(SMALL).motion.tolist()



def test_old_mac_line_ends_read_like_any_other():
    clip = parse_bvh(SMALL.replace("\n", "\r"))
    assert clip.motion.tolist() == parse_bvh(SMALL).motion.tolist()
    assert clip.names == parse_bvh(SMALL).names


def test_a_chain_as_deep_as_the_limit_reads_without_recursion():
    import sys

    from puppet.mocap.bvh import MAX_JOINTS

    depth = MAX_JOINTS - 1  # the root and a chain of joints to the limit
    chain = "".join(f"JOINT j{i}\n{{\nOFFSET 0 1 0\nCHANNELS 1 Zrotation\n"
                    for i in range(depth))
    text = ("HIERARCHY\nROOT r\n{\nOFFSET 0 0 0\n" + chain + "}\n" * (depth + 1)
            + f"MOTION\nFrames: 1\nFrame Time: 0.1\n{' '.join(['0.01'] * depth)}\n")
    limit = sys.getrecursionlimit()
    sys.setrecursionlimit(150)  # far below the depth: the reader must not recurse
    try:
        clip = parse_bvh(text)
    finally:
        sys.setrecursionlimit(limit)
    assert len(clip.joints) == depth + 1 and clip.joint(f"j{depth - 1}").parent == depth - 1
    assert clip.motion.shape == (1, depth)
    # each joint turns 0.01 degrees more than its parent: the chain curls to the left
    turns = np.radians(0.01 * np.arange(depth))
    end = [-np.sin(turns).sum(), np.cos(turns).sum(), 0]
    assert clip.world_positions()[0, -1] == pytest.approx(end, abs=1e-6)


def test_end_sites_are_named_uniquely():
    # two End Sites on one joint, and a joint already named like its End Site
    text = SMALL.replace("      End Site\n      {\n        OFFSET 0 2 0\n      }\n",
                         "      End Site\n      {\n        OFFSET 0 2 0\n      }\n"
                         "      End Site\n      {\n        OFFSET 0 3 0\n      }\n")
    text = text.replace("JOINT twist", "JOINT lower_end")
    clip = parse_bvh(text)
    assert clip.names == ["pelvis", "upper", "lower", "lower_end2", "lower_end3", "lower_end",
                          "lower_end_end"]
    assert clip.world_positions()[0, clip.index("lower_end3")] == pytest.approx([0, 5, 0])
    assert clip.joint("lower_end").channels == ("Xrotation", "Yrotation", "Zrotation")


# -- errors: one line, where, what was expected --------------------------------------
def _error(text: str) -> str:
    with pytest.raises(DataError) as info:
        parse_bvh(text, "bad.bvh")
    message = str(info.value)
    assert "\n" not in message
    return message


def _line_of(text: str, needle: str) -> int:
    return next(n for n, line in enumerate(text.splitlines(), 1)
                if needle in line.split() or needle == line.strip())


def test_a_frame_with_a_missing_value_names_its_line():
    lines = SMALL.splitlines()
    lines[-2] = "1 2 3 0 0 0 90 0 0 0"  # 10 values, 11 channels
    msg = _error("\n".join(lines) + "\n")
    assert msg.startswith(f"bad.bvh:{len(lines) - 1}:")
    assert "frame 2 has 10 values; expected 11" in msg


def test_a_word_among_the_numbers_names_its_line_and_column():
    text = SMALL.replace("1 2 3 0 0 0 90", "1 2 x3 0 0 0 90")
    line = _line_of(text, "x3")
    assert _error(text).startswith(f"bad.bvh:{line}:5: 'x3' in frame 2: expected a number")


def test_fewer_frames_than_announced():
    msg = _error(SMALL.replace("Frames: 3", "Frames: 4"))
    assert "the file ends after 3 frames; 'Frames: 4' expected 4" in msg


def test_more_frames_than_announced():
    text = SMALL.replace("Frames: 3", "Frames: 2")
    assert _error(text).startswith(f"bad.bvh:{len(text.splitlines())}:")


def test_an_unknown_channel_name():
    text = SMALL.replace("CHANNELS 1 Zrotation\n      End", "CHANNELS 1 Zrot\n      End")
    msg = _error(text)
    assert msg.startswith(f"bad.bvh:{_line_of(text, 'Zrot')}:18: 'Zrot': expected a channel "
                          "name, one of Xposition")
    assert msg.endswith("Yrotation, Zrotation")  # no hint about the count: a misspelling


def test_a_channel_count_that_does_not_match_the_names():
    text = SMALL.replace("CHANNELS 1 Zrotation\n      End", "CHANNELS 2 Zrotation\n      End")
    assert "'End': expected a channel name" in _error(text)


def test_a_missing_closing_brace():
    text = SMALL.replace("      }\n    }\n  }\n  JOINT twist", "      }\n    }\n  JOINT twist")
    msg = _error(text)
    assert "expected" in msg and msg.startswith("bad.bvh:")


def test_a_missing_offset_value():
    text = SMALL.replace("OFFSET 0 2 0", "OFFSET 0 2")
    line = _line_of(text, "OFFSET 0 2") + 1
    assert _error(text).startswith(f"bad.bvh:{line}:7: '}}': expected OFFSET z of lower_end")


def test_no_motion_section_and_no_hierarchy():
    assert "no MOTION section" in _error(SMALL.split("MOTION")[0])
    assert _error("ROOT x\n{\n}\n").startswith("bad.bvh:1:1: 'ROOT': expected 'HIERARCHY'")


def test_a_bad_frame_time_and_duplicate_names():
    assert "Frame Time: '0': expected seconds per frame" in _error(
        SMALL.replace("Frame Time: 0.04", "Frame Time: 0"))
    assert "a second joint with this name" in _error(SMALL.replace("JOINT twist", "JOINT upper"))



def test_numbers_are_written_as_bvh_writes_them():
    for word in ("1_000", "0x10", "١"):
        assert f"'{word}' in frame 2: expected a number" in _error(
            SMALL.replace("1 2 3 0 0 0 90", f"1 2 {word} 0 0 0 90"))
        assert f"'{word}': expected OFFSET y of upper, a number" in _error(
            SMALL.replace("OFFSET 0 1 0", f"OFFSET 0 {word} 0", 1))
    assert "frame 2 has a value that is not finite" in _error(
        SMALL.replace("1 2 3 0 0 0 90", "1 2 -inf 0 0 0 90"))
    assert "frame 3 has a value that is not finite" in _error(
        SMALL.replace("0 0 0 90 0 0 0 90", "0 0 0 1e999 0 0 0 90"))
    assert parse_bvh(SMALL.replace("1 2 3 0 0 0 90", "1 +2. .3e1 0 0 0 90")).motion[1, :3] \
        .tolist() == [1, 2, 3]


def test_counts_that_are_no_counts():
    huge = "9" * 5000  # more digits than Python's int() takes
    assert f"'{huge}': expected the number of channels, 0 to 6" in _error(
        SMALL.replace("CHANNELS 1", f"CHANNELS {huge}", 1))
    assert "'٣': expected the number of channels" in _error(
        SMALL.replace("CHANNELS 1", "CHANNELS ٣", 1))
    msg = _error(SMALL.replace("Frames: 3", f"Frames: {huge}"))
    assert f"Frames: '{'9' * 30}': expected a whole number of frames (at most 12" in msg
    assert len(msg) < 200
    assert "Frames: 999999999999 makes 999999999999 frames; a BVH clip may have at most" \
        in _error(SMALL.replace("Frames: 3", "Frames: 999999999999"))
    assert "the file ends after 3 frames; 'Frames: 5' expected 5" in _error(
        SMALL.replace("Frames: 3", "Frames: 5"))


def test_a_frame_time_whose_rate_overflows():
    msg = _error(SMALL.replace("Frame Time: 0.04", "Frame Time: 1e-320"))
    line = _line_of(SMALL, "Time:")
    assert msg.startswith(f"bad.bvh:{line}: Frame Time: '1e-320': expected")
    fast = parse_bvh(SMALL.replace("Frame Time: 0.04", "Frame Time: 1e-300"))
    assert fast.fps == pytest.approx(1e300)


def test_no_frames_at_all(recwarn):
    clip = parse_bvh(SMALL.split("Frames:")[0] + "Frames: 0\nFrame Time: 0.04\n")
    assert clip.motion.shape == (0, 11) and clip.world_positions().shape == (0, 6, 3)
    assert not recwarn.list  # (numpy warns of an empty table if it is asked to read one)


def test_errors_name_lines_that_are_there():
    assert _error("").startswith("bad.bvh:1: the hierarchy ends here; expected 'HIERARCHY'")
    head = SMALL.split("Frame Time:")[0]  # the file ends after its Frames line
    assert _error(head).startswith(f"bad.bvh:{head.count(chr(10)) + 1}:1: '': expected "
                                   "'Frame Time: SECONDS' here")
    head = SMALL.split("\n0 0 0 0")[0]  # and after its Frame Time, with no line end
    assert _error(head).startswith(f"bad.bvh:{head.count(chr(10)) + 1}: the file ends after 0")
    # a form feed or U+2028 is no line end: the lines after it keep their numbers
    text = SMALL.replace("OFFSET 0 1 0", "OFFSET 0\x0c1\u20280", 1).replace("Zrot", "Zrox", 1)
    assert _error(text).startswith(f"bad.bvh:{_line_of(SMALL, 'Zrotation')}:")


def test_an_unreadable_file(tmp_path):
    with pytest.raises(DataError, match="cannot read"):
        read_bvh(tmp_path / "none.bvh")


# -- the real clips (CMU, two namings of one skeleton) --------------------------------
@pytest.fixture(scope="module")
def walk():
    return read_bvh(WALK)


@pytest.fixture(scope="module")
def jumps():
    return read_bvh(JUMPS)


def test_the_two_cmu_clips_name_their_hips_differently(walk, jumps):
    assert (walk.frames, jumps.frames) == (994, 2752)
    assert walk.fps == pytest.approx(120, rel=1e-4) and jumps.fps == pytest.approx(120, rel=1e-4)
    assert "LeftHip" in walk.names and "LeftHip" not in jumps.names
    assert "LeftUpLeg" in jumps.names and "LeftUpLeg" not in walk.names
    assert sum(not j.end_site for j in walk.joints) == 31
    assert walk.motion.shape == (994, 96) and jumps.motion.shape == (2752, 96)
    # the walk clip lists its arm channels in another order than its legs
    assert walk.joint("LeftElbow").rotation_order == "ZXY"
    assert walk.joint("LeftKnee").rotation_order == "ZYX"


def test_walk_world_positions_match_an_independent_reader(walk):
    # Reference: bvhio 1.5.4 (PositionWorld after loadPose), times CMU's unit, for the
    # frames 0 and 400 (kneeling) of the walk clip; the wrist uses the Z X Y order.
    pos = walk.world_positions(CMU_UNIT_METRES)
    ref = {(0, "Head"): [0.30285737, 1.3552969, -1.8610419],
           (0, "LeftKnee"): [0.44522637, 0.46263355, -1.79035],
           (0, "LeftWrist"): [0.43060455, 0.99085504, -1.8431852],
           (400, "Head"): [1.094974, 0.89149195, -1.6487808],
           (400, "LeftWrist"): [0.7817986, 0.48278624, -1.7611852],
           (800, "LeftWrist"): [0.2481532, 0.7863852, 0.769692]}
    for (frame, name), xyz in ref.items():
        assert pos[frame, walk.index(name)] == pytest.approx(xyz, abs=1e-5), (frame, name)


def test_jumps_clip_forward_kinematics_is_a_person(jumps):
    pos = jumps.world_positions(CMU_UNIT_METRES)
    head, toe = jumps.index("Head_end"), jumps.index("LeftToeBase")
    assert 1.45 < pos[0, head, 1] < 1.9  # 1.54 m  # standing: the top of the head
    assert abs(pos[:, toe, 1].min()) < 0.1  # the feet reach the floor
    hips_y = pos[:, 0, 1]
    assert hips_y.max() - np.median(hips_y) > 0.2  # it jumps
    # bones keep their lengths in every frame
    knee, ankle = jumps.index("LeftLeg"), jumps.index("LeftFoot")
    bone = np.linalg.norm(pos[:, ankle] - pos[:, knee], axis=1)
    expected = np.linalg.norm(jumps.joint("LeftFoot").offset) * CMU_UNIT_METRES
    assert bone == pytest.approx(np.full_like(bone, expected), rel=1e-9)


# -- writing ---------------------------------------------------------------------------
def test_a_planar_clip_reads_back_to_its_angles(tmp_path):
    rng = np.random.default_rng(3)
    frames = 50
    joints = [PlanarJoint("base", None, (0, 0)),
              PlanarJoint("lower_arm", "base", (0.0, 0.03)),
              PlanarJoint("upper_arm", "lower_arm", (0.0, 0.2), end=(0.05, 0.2)),
              PlanarJoint("tail", "base", (-0.08, 0.0))]
    xy = rng.uniform(-3, 3, (frames, 2))
    angles = rng.uniform(-720, 720, (frames, 4))
    out = tmp_path / "planar.bvh"
    write_planar_bvh(out, joints, xy, angles, 1 / 30)
    clip = read_bvh(out)
    assert [j.name for j in clip.joints if not j.end_site] == ["base", "lower_arm",
                                                                 "upper_arm", "tail"]
    assert clip.frames == frames and clip.frame_time == pytest.approx(1 / 30, abs=1e-7)
    assert clip.channel("base", "Xposition") == pytest.approx(xy[:, 0], abs=1e-6)
    assert clip.channel("base", "Zrotation") == pytest.approx(angles[:, 0], abs=1e-5)
    for k, name in enumerate(["lower_arm", "upper_arm", "tail"], 1):
        assert clip.channel(name, "Zrotation") == pytest.approx(angles[:, k], abs=1e-5)
    # the forward kinematics is the planar one
    pos = clip.world_positions()
    a0, a1 = np.radians(angles[:, 0]), np.radians(angles[:, 0] + angles[:, 1])
    knee = xy + 0.03 * np.stack([-np.sin(a0), np.cos(a0)], 1) \
        + 0.2 * np.stack([-np.sin(a1), np.cos(a1)], 1)
    assert pos[:, clip.index("upper_arm"), :2] == pytest.approx(knee, abs=1e-5)
    assert np.abs(pos[:, :, 2]).max() < 1e-9
    assert math.isclose(clip.joint("upper_arm_end").offset[0], 0.05)


def test_messages_say_what_was_expected_where_the_file_stops_being_bvh():
    second_root = SMALL.replace("MOTION", "ROOT again\n{\n  OFFSET 0 0 0\n}\nMOTION")
    line = _line_of(second_root, "again")
    assert _error(second_root) == (f"bad.bvh:{line}:1: 'ROOT': expected MOTION after the root "
                                   "joint's closing '}' (one ROOT per file)")
    no_site = SMALL.replace("End Site", "End Zone", 1)
    assert _error(no_site).startswith(f"bad.bvh:{_line_of(no_site, 'Zone')}:11: 'Zone': "
                                      "expected 'Site' after 'End'")
    cut = SMALL[:SMALL.index("OFFSET 0 1 0") + len("OFFSET 0 1")]
    assert _error(cut) == (f"bad.bvh:{cut.count(chr(10)) + 1}: the hierarchy ends here; "
                           "expected OFFSET z of upper (a BVH file has HIERARCHY, ROOT ... "
                           "{ }, then MOTION)")
    assert "'{': expected the joint's name after JOINT" in _error(
        SMALL.replace("JOINT twist", "JOINT"))
    assert _error(SMALL.replace("JOINT twist", "JOIN twist")).startswith(
        f"bad.bvh:{_line_of(SMALL, 'twist')}:3: 'JOIN': expected JOINT, End Site or '}}' to "
        "close pelvis")


def test_a_repeated_name_and_a_missing_offset_are_told_apart():
    twice = SMALL.replace("JOINT twist", "JOINT upper")
    line = _line_of(SMALL, "twist")
    assert _error(twice) == (f"bad.bvh:{line}:9: 'upper': a second "
                             "joint with this name; expected unique joint names")
    no_offset = SMALL.replace("OFFSET 1 0 0\n    CHANNELS 3", "CHANNELS 3")
    assert _error(no_offset).endswith(": 'CHANNELS': expected 'OFFSET' (the first entry of "
                                      "twist: OFFSET x y z)")
