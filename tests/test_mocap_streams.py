"""Live OSC streams: what a source drops and counts (a lost stream, out-of-range
numbers and times), its floor, and the humanoid forward kinematics of VMC bones."""

from __future__ import annotations

import numpy as np
import pytest


def test_a_stream_that_stops_is_counted_lost_once():
    from puppet.mocap.puppet_osc import encode_frame
    from puppet.mocap.source import OscSource

    source = OscSource("puppet", port=0)
    source.receive(encode_frame(0.0, {"hip": 0.1}), arrival=10.0)
    assert source.drain(wall=10.01) and source.lost_count == 0
    for wall in (10.5, 11.0, 12.0):  # nothing more arrives
        source.drain(wall=wall)
    assert source.lost_count == 1
    source.receive(encode_frame(0.1, {"hip": 0.2}), arrival=12.1)
    source.drain(wall=12.11)
    source.drain(wall=13.0)
    assert source.lost_count == 2


def test_a_number_too_large_for_a_float_is_dropped_as_out_of_range():
    from puppet.mocap.osc import Drop, number

    with pytest.raises(Drop) as info:
        number(10 ** 400, "hip")
    assert info.value.reason == "out_of_range" and "too large" in info.value.detail
    with pytest.raises(Drop) as info:
        number(float("nan"), "hip")
    assert info.value.reason == "not_finite"


def test_unitys_hands_hang_from_the_forearms():
    from puppet.mocap.unity import PARENTS

    assert PARENTS["LeftHand"] == "LeftLowerArm" and PARENTS["RightHand"] == "RightLowerArm"


def test_a_time_out_of_range_is_dropped_as_out_of_range_with_its_detail():
    from puppet.mocap.osc import MAX_TIME, Drop, frame_time

    assert frame_time(1.5) == 1.5
    with pytest.raises(Drop) as info:
        frame_time(-1.0, "t")
    assert info.value.reason == "out_of_range"
    assert str(info.value) == info.value.detail == f"t: -1 s is not 0..{MAX_TIME:g}"
    bare = Drop("malformed")
    assert str(bare) == bare.detail == "malformed"


def test_a_stream_with_floor_lowest_measures_the_root_from_the_lowest_point_seen():
    from puppet.mocap.retarget import Retargeter, load_mapping

    mapping = load_mapping("assets/mappings/mediapipe-pose.yaml")
    assert mapping.root.floor == "lowest"
    live = Retargeter(mapping)
    names = live.point_names
    up = np.array([0.0, -1.0, 0.0])  # mediapipe's up is -y

    def frame(drop: float):
        pts = {n: np.array([0.0, -1.0, 0.0]) for n in names}  # 1 unit up
        for n, side in (("left_hip", -0.1), ("right_hip", 0.1)):  # side by side
            pts[n] = np.array([0.0, -1.0 - drop, side])
        pts[sorted(names)[0]] = np.array([0.0, 0.2, 0.0])  # a point 0.2 below the origin
        return pts

    a = live.channels(frame(0.0))
    hips = float(frame(0.0)["left_hip"] @ up)
    lowest = min(float(p @ up) for p in frame(0.0).values())
    assert a["root.y"] == pytest.approx((hips - lowest) * live.metres)
