"""Any humanoid rig without writing a mapping (issue 30): puppet mocap info, mapping and
play --mocap recognise a rig by its joint names and build the mapping - joints, unit,
up axis, handedness, floor, the feet's rest angle, plane, size - for rigs made in the
test from the shipped CMU clips (other names, centimetres, z up, 60 fps, an extra root
with an OFFSET, helper joints in a limb)."""

from __future__ import annotations

import numpy as np
import pytest
from rig_clips import CC, ROKOKO, SMPL, UNITY, write_rig

from puppet.commands import main
from puppet.data.catalog import find
from puppet.data.mappings import load_mapping, parse_mapping
from puppet.data.yamlfile import load_text
from puppet.mocap.bvh import CMU_UNIT_METRES, read_bvh
from puppet.mocap.mapping_text import mapping_yaml
from puppet.mocap.retarget import retarget_clip
from puppet.mocap.rigs import NotHumanoid, recognise, words

LIMBS = ("hip_near", "knee_near", "hip_far", "knee_far", "shoulder_near", "elbow_near",
         "shoulder_far", "elbow_far", "waist", "neck", "root.angle")


@pytest.fixture(scope="module")
def walk():
    return read_bvh("assets/mocap/cmu-131_01-walk.bvh")


@pytest.fixture(scope="module")
def walk_channels(walk):
    return retarget_clip(walk, load_mapping(find("mapping", "cmu-131"))).channels


@pytest.fixture(scope="module")
def cc_walk(walk, tmp_path_factory):
    """The walk as a character-creator rig: CC_Base_* names, centimetres, z up, 60 fps,
    a CC_Base_BoneRoot above the hips (whose OFFSET the position channels replace) and
    twist joints between thigh and calf."""
    path = tmp_path_factory.mktemp("rigs") / "cc-walk.bvh"
    return write_rig(walk, path, CC, scale=CMU_UNIT_METRES / 0.01, up="z", every=2,
                     extra_root="CC_Base_BoneRoot", root_offset=(0.0, 90.0, 0.0),
                     helpers={"CC_Base_L_ThighTwist01": "CC_Base_L_Calf",
                              "CC_Base_R_ThighTwist01": "CC_Base_R_Calf"})


def _rms(a, b) -> float:
    d = np.asarray(a) - np.asarray(b)
    return float(np.sqrt(np.nanmean(d * d)))


def test_a_joints_name_is_read_as_words():
    assert words("LHipJoint") == ["l", "hip", "joint"]
    assert words("CC_Base_L_Thigh") == ["cc", "base", "l", "thigh"]
    assert words("mixamorig:LeftUpLeg") == ["mixamorig", "left", "up", "leg"]
    assert words("thigh.L") == ["thigh", "l"]


@pytest.mark.parametrize("clip, mapping", [("cmu-131_01-walk", "cmu-131"),
                                           ("cmu-01_01-jumps", "cmu-01")])
def test_the_shipped_clips_are_recognised_as_their_hand_written_mappings_say(clip, mapping):
    """The same joints, unit, up, plane and (within 0.05) size as the hand-written
    mapping; the same channels but for the ankles (the feet's rest measured per foot:
    cmu-131's -14 is the two feet's mean) and the floor."""
    bvh = read_bvh(find("clip", clip))
    rig = recognise(bvh)
    hand = load_mapping(find("mapping", mapping))
    built = rig.mapping
    assert {n: (s.start, s.to) for n, s in built.segments.items()} == \
        {n: (s.start, s.to) for n, s in hand.segments.items()}
    assert built.effectors == hand.effectors and built.facing == hand.facing
    assert (built.source.unit, built.source.up, built.plane) == \
        (hand.source.unit, hand.source.up, hand.plane)
    assert abs(built.size - hand.size) < 0.05
    assert all(-20 < rest < -10 for rest in rig.feet.values()), rig.feet
    a, b = retarget_clip(bvh, built).channels, retarget_clip(bvh, hand).channels
    for name in LIMBS:
        assert _rms(a[name], b[name]) < 1e-9, name
    assert _rms(a["ankle_near"], b["ankle_near"]) < 5.0


def test_a_renamed_rig_in_centimetres_z_up_at_60_fps_is_mapped_without_a_mapping_file(
        cc_walk, walk_channels):
    rig = recognise(read_bvh(cc_walk))
    assert (rig.unit, rig.unit_name, rig.up, rig.handedness) == (0.01, "cm", "z", "right")
    assert rig.joints["right_knee"] == "CC_Base_R_Calf"  # above the foot, not the twist
    assert rig.joints["right_hip"] == "CC_Base_R_Thigh"
    assert rig.joints["right_elbow"] == "CC_Base_R_Forearm"
    assert rig.plane == "travel" and abs(rig.size - 1.07) < 0.02
    got = retarget_clip(read_bvh(cc_walk), rig.mapping).channels
    for name in LIMBS:  # every other frame of the walk, as cmu-131 retargets it
        assert _rms(got[name], walk_channels[name][::2]) < 1.0, name  # (5 decimals written)
    for name in ("ankle_near", "ankle_far"):
        assert _rms(got[name], walk_channels[name][::2]) < 4.0, name
    assert _rms(got["root.x"], walk_channels["root.x"][::2]) < 0.01


@pytest.mark.parametrize("rename, expect", [
    (UNITY, {"right_hip": "RightUpperLeg", "right_knee": "RightLowerLeg",
             "right_ankle": "RightFoot", "right_toe": "RightToes",
             "right_shoulder": "RightUpperArm", "right_wrist": "RightHand", "head": "Head"}),
    (SMPL, {"right_hip": "R_Hip", "right_knee": "R_Knee", "right_ankle": "R_Ankle",
            "right_toe": "R_Foot", "right_shoulder": "R_Shoulder", "right_elbow": "R_Elbow",
            "right_wrist": "R_Wrist", "hips": "Pelvis"}),
    (ROKOKO, {"right_hip": "RightThigh", "right_knee": "RightShin", "right_ankle": "RightFoot",
              "right_toe": "RightToe", "right_shoulder": "RightArm",
              "right_elbow": "RightForeArm", "right_wrist": "RightHand"}),
], ids=["unity-vrm", "smpl", "rokoko"])
def test_other_rigs_names_are_recognised(walk, tmp_path, rename, expect):
    path = write_rig(walk, tmp_path / "rig.bvh", rename, scale=CMU_UNIT_METRES, every=6)
    rig = recognise(read_bvh(path))
    assert {k: rig.joints[k] for k in expect} == expect
    assert rig.unit == 1.0 and rig.up == "y"


def test_mixamo_names_in_metres(tmp_path):
    jumps = read_bvh("assets/mocap/cmu-01_01-jumps.bvh")
    rename = {j.name: f"mixamorig:{j.name}" for j in jumps.joints if not j.end_site}
    path = write_rig(jumps, tmp_path / "mixamo.bvh", rename, scale=CMU_UNIT_METRES, every=8)
    rig = recognise(read_bvh(path))
    assert rig.joints["right_knee"] == "mixamorig:RightLeg" and rig.unit == 1.0
    text = mapping_yaml(rig.mapping)  # a name with a colon is quoted: the file reads back
    assert '"mixamorig:RightLeg"' in text
    assert parse_mapping(load_text(text, "mixamo.yaml")) == rig.mapping


def test_a_skeleton_with_no_limbs_is_said_to_be_no_humanoid(tmp_path, capsys):
    from helpers import TWO_JOINT_BVH

    path = tmp_path / "odd.bvh"
    path.write_text(TWO_JOINT_BVH)
    with pytest.raises(NotHumanoid) as info:
        recognise(read_bvh(path))
    assert "no joint named for the left ankle (or foot)" in str(info.value)
    assert main(["mocap", "mapping", str(path)]) == 2
    err = capsys.readouterr().err
    assert "not a humanoid rig puppet can read" in err and err.count("\n") == 1


def test_mocap_mapping_writes_a_file_check_takes_that_plays_the_same(cc_walk, tmp_path,
                                                                     capsys):
    assert main(["mocap", "mapping", str(cc_walk)]) == 0
    text = capsys.readouterr().out
    assert text.startswith("# Built by 'puppet mocap mapping")
    mine = tmp_path / "my.yaml"
    mine.write_text(text, encoding="utf-8")
    assert main(["check", str(mine)]) == 0
    assert load_mapping(mine) == recognise(read_bvh(cc_walk)).mapping  # the same, exactly
    hashes = []
    for extra in ([], ["--mapping", str(mine)]):
        assert main(["play", "biped-mocap", "--headless", "--seconds", "1.5", "--mocap",
                     str(cc_walk), *extra]) == 0
        out = capsys.readouterr()
        hashes.append(out.out.split("state=")[1].split()[0])
        if not extra:
            assert "no mapping names its joints; recognised a humanoid rig" in out.err
    assert hashes[0] == hashes[1]


def test_play_follows_the_renamed_rig_within_a_few_degrees(cc_walk, tmp_path, capsys):
    """biped-mocap with the character-creator walk and no mapping: KD control follows
    hips and knees within 10 degrees RMS over the walking part, as the CMU clip's own
    log does (biped-mocap-walk: 4 to 8), and the figure stays up."""
    from puppet.testing import replay_log

    log = tmp_path / "cc-walk.jsonl"
    assert main(["play", "biped-mocap", "--headless", "--mocap", str(cc_walk),
                 "--seconds", "7", "--record", str(log)]) == 0
    capsys.readouterr()
    (tmp_path / "cc-walk.expect.yaml").write_text(
        "expect:\n"
        "  - never_fell: true\n"
        "  - followed_channels: {joints: [hip_near, knee_near, hip_far, knee_far], "
        "from: 4.3, until: 6.7, max_rms: 10}\n", encoding="utf-8")
    result = replay_log(log)
    assert not result.failed, [str(f) for f in result.failed]


def test_play_picks_the_shipped_mapping_that_names_the_clips_joints(capsys):
    """biped-mocap's mapping is cmu-131; the jumps clip names its joints as cmu-01
    does: it plays through cmu-01 (the one mocap info picks), saying so."""
    assert main(["play", "biped-mocap", "--headless", "--seconds", "0.2", "--mocap",
                 "cmu-01_01-jumps"]) == 0
    err = capsys.readouterr().err
    assert ("mapping 'cmu-131' (the interface's) names joints the clip has not; playing it "
            "through 'cmu-01'") in err


def test_info_describes_a_rig_no_mapping_names(cc_walk, capsys):
    assert main(["mocap", "info", str(cc_walk)]) == 0
    out = capsys.readouterr().out
    assert "recognised a humanoid rig: hips CC_Base_Hip, legs CC_Base_R_Thigh > " in out
    assert "unit 0.01 m (cm: the performer is" in out and "up z" in out
    assert "planar channels through mapping 'cc-walk-humanoid'" in out
