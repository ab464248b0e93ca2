"""The OSC decoders (VMC, MediaPipe pose, puppet's channels address), the bone table
and the clip encoders of ``puppet mocap send``: what is sent decodes to what the clip
says, and every bad packet is dropped and counted by its reason."""

from __future__ import annotations

import math
import struct

import numpy as np
import pytest
from pythonosc.osc_bundle_builder import IMMEDIATELY, OscBundleBuilder
from pythonosc.osc_message_builder import OscMessageBuilder

from puppet.data.errors import DataError, UsageError
from puppet.mocap import mediapipe, puppet_osc, unity, vmc
from puppet.mocap.bvh import read_bvh
from puppet.mocap.formats import decoder, parse_udp
from puppet.mocap.send import encoder, load_bones, mediapipe_points, schedule, vmc_world

WALK = "assets/mocap/cmu-131_01-walk.bvh"
BONES = "assets/mocap/cmu-bones.yaml"


def msg(address, *args, types=None):
    b = OscMessageBuilder(address=address)
    for i, a in enumerate(args):
        b.add_arg(a, types[i] if types else None)
    return b.build()


def bundle(*messages):
    b = OscBundleBuilder(IMMEDIATELY)
    for m in messages:
        b.add_content(m)
    return b.build().dgram


IDENTITY = (0.0, 0.0, 0.0, 1.0)


def bone(name, p=(0.0, 0.0, 0.0), q=IDENTITY):
    return msg(vmc.BONE, name, *map(float, p), *map(float, q))


@pytest.fixture(scope="module")
def walk():
    return read_bvh(WALK), load_bones(BONES)


def test_vmc_sent_clip_decodes_to_the_clips_forward_kinematics(walk):
    clip, table = walk
    encode = encoder(clip, "vmc", table)
    world = vmc_world(clip, table)
    d = decoder("vmc")
    worst = 0.0
    frames = range(0, clip.frames, 9)
    for k in frames:
        out = d.feed(encode(k, k * clip.frame_time))
        assert len(out) == 1
        points = out[0].points
        assert set(points) == set(table.vmc)
        for name, p in points.items():
            worst = max(worst, float(np.max(np.abs(np.array(p) - world[name][k]))))
    assert worst < 2e-6  # float32 on the wire: ~1e-7 m per link, a few links deep
    assert d.counts.frames == len(frames) and d.counts.total_dropped == 0
    # the hips move forward over the walk and stand ~0.95 m up (metres, y up)
    hips = world["Hips"]
    assert 0.8 < hips[0, 1] < 1.1
    assert np.linalg.norm(hips[-1, [0, 2]] - hips[0, [0, 2]]) > 2.0


def test_another_rigs_names_need_only_another_bone_table():
    clip = read_bvh("assets/mocap/cmu-01_01-jumps.bvh")  # LeftUpLeg, not LeftHip
    table = load_bones("assets/mocap/cmu-01-bones.yaml")
    world = vmc_world(clip, table)
    vmc_enc, mp_enc = encoder(clip, "vmc", table), encoder(clip, "mediapipe", table)
    d, m = decoder("vmc"), decoder("mediapipe")
    points = mediapipe_points(clip, table)
    for k in range(0, clip.frames, 250):
        for name, p in d.feed(vmc_enc(k, k / 120))[0].points.items():
            assert np.allclose(p, world[name][k], atol=2e-6)
        frame = m.feed(mp_enc(k, k / 120))[0]
        assert len(frame.points) == len(table.mediapipe)
        for name, p in frame.points.items():
            assert np.allclose(p, points[name][k], atol=1e-6)
    assert d.counts.total_dropped == m.counts.total_dropped == 0


def test_vmc_frame_is_unity_left_handed_mirror_of_the_clip(walk):
    clip, table = walk
    world = vmc_world(clip, table)
    pos = clip.world_positions(table.unit)
    i = clip.index("LeftHip")
    assert np.allclose(world["LeftUpperLeg"][:, 0], -pos[:, i, 0])
    assert np.allclose(world["LeftUpperLeg"][:, 1:], pos[:, i, 1:])


def test_mediapipe_sent_clip_decodes_to_the_clips_points_y_down(walk):
    clip, table = walk
    encode = encoder(clip, "mediapipe", table)
    points = mediapipe_points(clip, table)
    d = decoder("mediapipe")
    for k in (0, 400, 993):
        frame = d.feed(encode(k, k / 120))[0]
        assert set(frame.points) == set(table.mediapipe)  # the rest sent invisible
        for name, p in frame.points.items():
            assert np.allclose(p, points[name][k], atol=1e-6)
    head, ankle = points["nose"][0], points["left_ankle"][0]
    assert head[1] < ankle[1]  # y down


def test_a_vmc_frame_ends_with_ok_or_with_its_bundle():
    d = decoder("vmc")
    assert d.feed(bone("Hips", (0, 1, 0)).dgram) == []  # loose messages: wait for OK
    assert d.feed(bone("Spine", (0, 0.1, 0)).dgram) == []
    frames = d.feed(msg(vmc.OK, 1).dgram)
    assert len(frames) == 1 and frames[0].points["Spine"] == pytest.approx((0, 1.1, 0))
    frames = d.feed(bundle(bone("Hips", (0, 2, 0))))  # a bundle without OK: its end
    assert frames[0].points == {"Hips": (0, 2, 0), "Spine": pytest.approx((0, 2.1, 0))}
    assert d.feed(msg(vmc.OK, 1).dgram) == []  # nothing new: no frame


def test_vmc_root_and_rotations_compose_down_the_hierarchy():
    d = decoder("vmc")
    quarter = (0.0, 0.0, math.sin(math.pi / 4), math.cos(math.pi / 4))  # 90 deg about z
    root = msg(vmc.ROOT, "root", 1.0, 0.0, 0.0, *quarter)
    frames = d.feed(bundle(root, bone("Hips", (0, 1, 0)), bone("LeftUpperLeg", (0.1, 0, 0)),
                           bone("LeftFoot", (0, -0.5, 0))))  # LowerLeg absent: Foot on UpperLeg
    p = frames[0].points
    assert p["Hips"] == pytest.approx((0.0, 0.0, 0.0), abs=1e-6)
    assert p["LeftUpperLeg"] == pytest.approx((0.0, 0.1, 0.0), abs=1e-6)
    assert p["LeftFoot"] == pytest.approx((0.5, 0.1, 0.0), abs=1e-6)
    assert unity.present_parent("LeftFoot", {"Hips", "LeftUpperLeg"}) == "LeftUpperLeg"
    assert len(unity.PARENTS) == 55


def test_vmc_time_going_back_is_dropped_a_restart_is_not():
    d = decoder("vmc")
    t = lambda s: msg(vmc.TIME, float(s))  # noqa: E731
    assert d.feed(bundle(bone("Hips"), t(10.0)))
    assert d.feed(bundle(bone("Hips", (0, 1, 0)), t(9.9))) == []
    assert d.feed(bundle(bone("Hips"), t(10.0))) == []  # the same time, nothing new
    assert d.counts.dropped == {"out_of_order": 1, "stale": 1}
    # the same time with new bones: the frame's next bundle, not stale
    assert d.feed(bundle(bone("Spine", (0, 0.5, 0)), t(10.0)))[0].points["Spine"] == (0, 0.5, 0)
    assert d.counts.continued == 1 and d.counts.dropped["stale"] == 1
    # the dropped frames' bones were not kept
    assert d.feed(bundle(bone("Hips", (0, 3, 0)), t(10.1)))[0].points["Hips"] == (0, 3, 0)
    assert d.feed(bundle(bone("Hips"), t(0.5)))  # far back: the sender started again
    assert d.counts.restarts == 1


def test_vmc_bad_messages_are_dropped_and_counted_by_reason_the_rest_kept():
    d = decoder("vmc")
    nan = float("nan")
    frames = d.feed(bundle(
        bone("Hips", (0, 1, 0)),
        bone("Spine", (nan, 0, 0)),  # not finite
        bone("Chest", (500, 0, 0)),  # out of range
        bone("Neck", q=(0, 0, 0, 0)),  # no rotation
        bone("Tail"),  # not a humanoid bone
        msg(vmc.BONE, "Head", 1.0, 2.0),  # too few arguments
        msg(vmc.BONE, 7, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0),  # name not a string
        msg("/VMC/Ext/Blend/Val", "A", 1.0),  # valid VMC, not used
        msg("/avatar/parameters/x", 1.0),  # not VMC
    ))
    assert frames[0].points == {"Hips": (0, 1, 0)}
    c = d.counts
    assert c.dropped == {"not_finite": 1, "out_of_range": 2, "bad_arguments": 3,
                         "unknown_address": 1}
    assert c.ignored == 1 and c.accepted == 1 and c.messages == 9
    assert d.feed(b"\x00\x01garbage") == [] and c.dropped["malformed"] == 1
    assert d.feed(b"#bundle\x00" + b"\xff" * 11) == [] and c.dropped["malformed"] == 2
    assert "dropped" in c.drops_text() and "3 bad_arguments" in c.drops_text()


def test_mediapipe_low_visibility_leaves_a_point_out_and_bad_packets_drop():
    d = decoder("mediapipe")
    values = []
    for i in range(33):
        values += [0.1 * i, 0.2, 0.3, 0.9 if i != 23 else 0.2]
    frame = d.feed(msg(mediapipe.ADDRESS, *values).dgram)[0]
    assert "left_hip" not in frame.points and len(frame.points) == 32
    assert frame.points["right_hip"] == pytest.approx((2.4, 0.2, 0.3), rel=1e-6)
    assert frame.time is None
    timed = d.feed(msg(mediapipe.ADDRESS, 1.5, *values).dgram)[0]
    assert timed.time == 1.5
    assert d.feed(msg(mediapipe.ADDRESS, 1.4, *values).dgram) == []  # back in time
    assert d.feed(msg(mediapipe.ADDRESS, *values[:-1]).dgram) == []  # 131 numbers
    bad = list(values)
    bad[3] = 1.5  # visibility beyond 0..1
    assert d.feed(msg(mediapipe.ADDRESS, *bad).dgram) == []
    bad[3] = float("inf")
    assert d.feed(msg(mediapipe.ADDRESS, *bad).dgram) == []
    assert d.feed(msg("/mediapipe/hands", *values).dgram) == []
    assert d.counts.dropped == {"out_of_order": 1, "bad_arguments": 1, "out_of_range": 1,
                                "not_finite": 1, "unknown_address": 1}


def test_puppet_channels_address_needs_no_mapping():
    d = decoder("puppet")
    frame = d.feed(puppet_osc.encode_frame(2.0, {"lean": 0.25, "arm.x": -1.0}))[0]
    assert frame.channels == {"lean": 0.25, "arm.x": -1.0} and frame.time == 2.0
    assert d.feed(msg(puppet_osc.ADDRESS, "lean", 0.5).dgram)[0].channels == {"lean": 0.5}
    for args, reason in [(("mocap.fresh", 1.0), "bad_arguments"),  # puppet's own
                         (("9lives", 1.0), "bad_arguments"),
                         (("lean", "x"), "bad_arguments"),
                         (("lean", 2e6), "out_of_range"),
                         ((), "bad_arguments"),
                         (("lean", float("nan")), "not_finite")]:
        before = d.counts.dropped[reason]
        assert d.feed(msg(puppet_osc.ADDRESS, *args).dgram) == []
        assert d.counts.dropped[reason] == before + 1, args
    ints = msg(puppet_osc.ADDRESS, "lean", 1, types="si").dgram  # an int is a number
    assert d.feed(ints)[0].channels == {"lean": 1.0}


def test_nested_bundles_are_read_in_order():
    inner = OscBundleBuilder(IMMEDIATELY)
    inner.add_content(bone("Hips", (0, 1, 0)))
    outer = OscBundleBuilder(IMMEDIATELY)
    outer.add_content(inner.build())
    outer.add_content(bone("Spine", (0, 1, 0)))
    d = decoder("vmc")
    assert d.feed(outer.build().dgram)[0].points["Spine"] == (0, 2, 0)


def test_deeply_nested_bundles_are_malformed_not_a_crash():
    dgram = bone("Hips").dgram
    for _ in range(3000):
        dgram = b"#bundle\x00" + b"\x00" * 7 + b"\x01" + struct.pack(">i", len(dgram)) + dgram
    d = decoder("vmc")
    d.feed(dgram)
    assert d.counts.packets == 1 and (d.counts.frames == 1 or d.counts.dropped["malformed"])


def test_bone_table_mistakes_are_one_line_errors_with_a_position(tmp_path, walk):
    clip, _ = walk
    cases = {
        "vmc:\n  Tail: Hips\n": (2, "'Tail' is not a Unity humanoid bone"),
        "mediapipe:\n  belly: Hips\n": (2, "'belly' is not a MediaPipe landmark"),
        "unit: -1\n": (1, "unit must be metres"),
        "up: x\n": (1, "up must be y or z"),
        "colour: red\n": (1, "unknown key 'colour'"),
    }
    for text, (line, words) in cases.items():
        path = tmp_path / "bones.yaml"
        path.write_text(text)
        with pytest.raises(DataError) as err:
            load_bones(path)
        assert f"bones.yaml:{line}:" in str(err.value) and words in str(err.value)
        assert "\n" not in str(err.value)
    # names the clip does not have, and a table whose ancestors disagree with Unity's
    path = tmp_path / "bones.yaml"
    path.write_text("vmc:\n  Hips: Hips\n  LeftUpperLeg: LeftUpLeg\n")
    with pytest.raises(DataError, match=r"bones.yaml:3:.*no joint 'LeftUpLeg'"):
        encoder(clip, "vmc", load_bones(path))
    path.write_text("vmc:\n  Hips: Hips\n  LeftLowerLeg: LeftKnee\n  Spine: LeftHip\n")
    with pytest.raises(DataError, match=r"bones.yaml:3:\d+: vmc.LeftLowerLeg: its nearest "
                                        r"listed BVH ancestor is Spine but in Unity's "
                                        r"hierarchy it is Hips"):
        encoder(clip, "vmc", load_bones(path))


def test_the_send_schedule_keeps_time_going_forward_across_loops():
    times = [t for _, (f, t) in zip(range(7), schedule(3, 0.5, 2.0, loop=True))]
    assert times == [0.0, 0.25, 0.5, 0.75, 1.0, 1.25, 1.5]
    assert [f for f, _ in schedule(3, 0.5, 1.0, loop=False)] == [0, 1, 2]


def test_udp_addresses():
    assert parse_udp("--mocap", "udp://127.0.0.1:39539") == ("127.0.0.1", 39539)
    assert parse_udp("--mocap", "udp://:4000") == ("127.0.0.1", 4000)
    assert parse_udp("--mocap", "udp://0.0.0.0", 39539) == ("0.0.0.0", 39539)
    assert parse_udp("--mocap", "udp://[::1]:5000") == ("::1", 5000)
    for bad, words in [("tcp://1.2.3.4:5", "only udp"), ("udp://host.lan:5", "not an IP"),
                       ("udp://1.2.3.4:99999", "1..65535"), ("udp://1.2.3.4:x", "1..65535")]:
        with pytest.raises(UsageError, match=words):
            parse_udp("--mocap", bad)


def test_puppet_check_knows_bone_tables(tmp_path):
    from puppet.commands.check import check_file

    assert check_file(BONES) == "bone table"
    assert check_file("assets/mocap/cmu-01-bones.yaml") == "bone table"
    bad = tmp_path / "rig.yaml"
    bad.write_text("unit: 0.01\nmediapipe:\n  left_hip: LHip\n  tail: Tail\n")
    with pytest.raises(DataError, match=r"rig.yaml:4:3: 'tail' is not a MediaPipe landmark"):
        check_file(bad)
