"""followed_channels: a joint's angle against the channel of its name, over a window."""

from __future__ import annotations

import math

import numpy as np
import pytest

from puppet.timeline.expectations import evaluate, parse_expectations
from puppet.timeline.replay import find_log, replay


@pytest.fixture(scope="module")
def walk():
    return replay(find_log("biped-mocap-walk"), trajectory=True).trajectory


def check(traj, entry):
    (e,) = parse_expectations([{"followed_channels": entry}]).items
    return evaluate(e, traj, "")


def test_it_passes_and_fails_on_its_bounds(walk):
    joints = ["hip_near", "knee_near"]
    assert check(walk, {"joints": joints, "from": 4.3, "until": 6.7, "max_rms": 10}).passed
    assert not check(walk, {"joints": joints, "from": 4.3, "until": 6.7, "max_rms": 2}).passed
    assert not check(walk, {"joints": joints, "from": 4.3, "until": 6.7, "min_rms": 30}).passed


def test_a_joint_whose_channel_never_came_fails(walk):
    traj = walk
    k = traj.joints.index("neck")
    saved = traj.joint_channel[:, k].copy()
    traj.joint_channel[:, k] = np.nan
    try:
        out = check(traj, {"joints": ["neck"], "max_rms": 90})
    finally:
        traj.joint_channel[:, k] = saved
    assert not out.passed and "no channel 'neck'" in out.measured


def test_angles_compare_round_the_circle(walk):
    """179 and -179 degrees are 2 apart, not 358."""
    traj = walk
    k = traj.joints.index("waist")
    angle, channel = traj.joint_angle[:, k].copy(), traj.joint_channel[:, k].copy()
    traj.joint_angle[:, k] = math.radians(179.0)
    traj.joint_channel[:, k] = math.radians(-179.0)
    try:
        out = check(traj, {"joints": ["waist"], "max_rms": 3})
    finally:
        traj.joint_angle[:, k], traj.joint_channel[:, k] = angle, channel
    assert out.passed, out.measured
