"""Clean channels (issue 30): angles continuous (no flips through +-180), a live stream
filtered (the 1-euro filter, its lag measured), outliers dropped and counted."""

from __future__ import annotations

import math
import random

import numpy as np
import pytest

from puppet.commands.streams import source_for
from puppet.data.catalog import find, load_setup
from puppet.mocap import puppet_osc
from puppet.mocap.bvh import read_bvh
from puppet.mocap.retarget import TURN_LIMIT, _continued, load_mapping, retarget_clip
from puppet.mocap.smoothing import StreamFilter


@pytest.fixture(scope="module")
def walk_channels():
    clip = read_bvh("assets/mocap/cmu-131_01-walk.bvh")
    return clip, retarget_clip(clip, load_mapping(find("mapping", "cmu-131")))


def test_an_angle_wobbling_across_180_is_continued_not_flipped():
    wobble = [179.0, -179.0, 178.0, -178.0, 170.0]
    prev, joint, world = None, [], []
    for w in wobble:
        prev = _continued(prev, w, False)
        joint.append(prev)
    assert joint == [179.0, 181.0, 178.0, 182.0, 170.0]
    prev = None
    for w in [170.0, -170.0, -90.0, 0.0, 90.0, 170.0, -170.0]:  # a somersault: the world's
        prev = _continued(prev, w, True)
        world.append(prev)
    assert world == [170.0, 190.0, 270.0, 360.0, 450.0, 530.0, 550.0]
    # a joint never drifts a turn: past TURN_LIMIT it goes a turn back
    past = TURN_LIMIT + 5.0 - 360.0  # TURN_LIMIT + 5, a turn back
    assert _continued(TURN_LIMIT - 1.0, past, False) == past
    assert _continued(TURN_LIMIT - 1.0, past, True) == TURN_LIMIT + 5.0


def test_the_walks_ankles_no_longer_flip_through_180(walk_channels):
    """The CMU walk's crouch: with angles kept in -180..180 the ankles flipped by a turn
    three times (frames 348, 391, 402) and the near shoulder four; continuous, the
    ankles never jump by a turn and the arm (seen end-on, its projection spinning)
    only where it passes 225 degrees."""
    clip, rc = walk_channels
    flips = {}
    for name, values in rc.channels.items():
        step = np.abs(np.diff(values))
        flips[name] = int(np.sum(step[~np.isnan(step)] > 300.0))
    assert flips["ankle_near"] == flips["ankle_far"] == 0
    assert rc.channels["ankle_near"].min() < -180.0  # it went past -180, continuously
    assert sum(flips.values()) <= 3, flips
    assert all(np.nanmax(np.abs(v)) <= TURN_LIMIT for n, v in rc.channels.items()
               if n not in ("root.x", "root.y", "clearance") and "." not in n[1:-2])


def test_the_filter_smooths_a_still_performer_and_follows_a_moving_one(walk_channels):
    rng = random.Random(5)
    f = StreamFilter()
    still = [f.apply({"knee_near": -20.0 + rng.gauss(0.0, 1.0)}, k / 60)["knee_near"]
             for k in range(600)]
    assert np.std(still[60:]) < 0.5  # 1 degree of jitter becomes less than half of one
    clip, rc = walk_channels  # the walk at 120 Hz: the lag, by the best shift
    names = ["hip_near", "knee_near", "hip_far", "knee_far", "elbow_far", "root.x"]
    f = StreamFilter()
    t = np.arange(clip.frames) * clip.frame_time
    out = {n: [] for n in names}
    for k in range(clip.frames):
        v = f.apply({n: float(rc.channels[n][k]) for n in names}, t[k])
        for n in names:
            out[n].append(v[n])
    lags = []
    for n in names:
        raw, got = rc.channels[n], np.array(out[n])
        shifts = np.arange(0.0, 0.08, 0.001)
        errors = [np.sqrt(np.mean((got - np.interp(t - s, t, raw)) ** 2)) for s in shifts]
        lags.append(shifts[int(np.argmin(errors))])
    assert min(lags) >= 0.008 and max(lags) <= 0.025, lags  # the docs say 12-19 ms
    assert f.lag(0.0) == pytest.approx(1 / (2 * math.pi * 4.0))


def test_a_live_stream_is_judged_then_filtered_and_its_outliers_counted(walk_channels):
    """The walk's channels as a puppet stream at 120 Hz with a spike every 50 frames
    (one channel thrown 120 degrees back for one frame): each spike is dropped (too_fast),
    the rest filtered; the channels handed on stay within a few degrees of the clip."""
    clip, rc = walk_channels
    source = source_for("udp://127.0.0.1:0", "puppet", None, load_setup("biped-mocap"))
    names = ["hip_near", "knee_near", "hip_far", "knee_far"]
    errors = []
    for k in range(600):
        values = {n: float(rc.channels[n][k]) for n in names}
        if k % 50 == 25:
            values["knee_far"] -= 120.0
        t = k * clip.frame_time
        assert source.receive(puppet_osc.encode_frame(t, values), arrival=t) == 1
        got = source.drain(wall=t)[0]["values"]
        if k % 50 != 25:
            errors += [abs(got[n] - values[n]) for n in names]
        else:
            assert "knee_far" not in got  # dropped: the runtime keeps its last value
    assert source.guard.tally.dropped == {"too_fast": 12}, source.guard.tally.first_detail
    # the filter's lag at the walk's speeds (a held end-on angle let go is a step: 31)
    assert np.sqrt(np.mean(np.square(errors))) < 4.0 and np.percentile(errors, 95) < 6.0
    assert "judged: 12 dropped (12 too_fast)" in source.hud_line(now=t)


def test_a_mappings_filter_is_data():
    from puppet.data.mappings import FilterSpec

    spec = load_mapping(find("mapping", "mediapipe-pose"))
    assert spec.filter == FilterSpec()  # the defaults: 4 Hz, 0.02
    f = StreamFilter(0.0, 0.0)  # cutoff 0: no filter
    assert f.apply({"a": 1.0}, 0.0) == {"a": 1.0} and f.apply({"a": 5.0}, 0.01) == {"a": 5.0}
