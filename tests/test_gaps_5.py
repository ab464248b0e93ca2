"""Behaviours a fresh seeded mutation run of issue 17 (seed 77) found no listed test
looking at, each tested as the feature reads: the centre of mass over the support, the
pulls coming back after a push, messages of a broken BVH file, the BVH writer's
nesting, the project's default files, a live mapping the stream cannot feed, OSC
times and drops, a stream's floor, the ground's top, revolutions either way, a tilt at
its bound, what expectations say of themselves, a log header's puppet version."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
from helpers import TWO_JOINT_BVH as BVH

from puppet.data.catalog import load_setup
from puppet.data.errors import DataError, UsageError
from puppet.interface.conditions import reader
from puppet.session import Session

ROOT = Path(__file__).resolve().parents[1]


# -- sensors ---------------------------------------------------------------------------------
def test_com_dx_support_is_the_offset_from_the_middle_of_the_feet():
    s = Session(load_setup("biped-stand"))
    s.advance(240)
    c = s.character
    lo, hi = c.support_extent()
    got = reader("com.dx.support", c)()
    assert got == pytest.approx(c.com()[0] - 0.5 * (lo + hi), abs=1e-12)
    assert abs(got) < 0.1 and hi - lo > 0.1  # standing: over the middle of the feet
    s.sim.character.bodies["pelvis"].position = (0.0, 5.0)  # nothing touches
    for b in s.character.bodies.values():
        b.position = (b.position.x, b.position.y + 3.0)
    s.advance(1)
    assert reader("com.dx.support", c)() == 0.0


# -- tracking: the pulls come back after a push ------------------------------------------------
def test_after_a_push_the_pulls_come_back_from_their_weight_to_full_over_recover():
    s = Session(load_setup("biped-mocap"))
    tracker = s.runtime.tracker
    small = tracker.spec.reaction.small
    dt = s.sim.dt
    tracker.reaction = ("small", 0)
    assert tracker._weight(0) == pytest.approx(small.weight)
    half = round((small.hold + small.recover / 2) / dt)
    assert tracker._weight(half) == pytest.approx(small.weight + (1 - small.weight) / 2,
                                                  abs=0.01)
    assert tracker._weight(round((small.hold + small.recover) / dt) + 1) == 1.0
    assert tracker.reaction is None


# -- BVH ---------------------------------------------------------------------------------------


@pytest.mark.parametrize("old, new, want", [
    ("Frames: 2", "Frame count 2", "expected 'Frames: N' here"),
    ("Frame Time: 0.1", "Frametime 0.1", "expected 'Frame Time: SECONDS' here"),
])
def test_a_bvh_motion_header_line_misnamed_says_what_goes_there(old, new, want):
    from puppet.mocap.bvh import parse_bvh

    with pytest.raises(DataError) as info:
        parse_bvh(BVH.replace(old, new), "odd.bvh")
    assert want in str(info.value) and "\n" not in str(info.value)


def test_a_bvh_without_its_motion_part_says_what_should_follow():
    from puppet.mocap.bvh import parse_bvh

    with pytest.raises(DataError) as info:
        parse_bvh(BVH.split("MOTION")[0], "cut.bvh")
    assert "then 'Frames: N', 'Frame Time: SECONDS' and the frames" in str(info.value)


def test_the_planar_bvh_writer_indents_each_joint_under_its_parent(tmp_path):
    from puppet.timeline.motion import sample_motion, write_motion

    motion = sample_motion(ROOT / "assets" / "logs" / "luxo-hop.jsonl", 10.0, until_step=240)
    out = tmp_path / "hop.bvh"
    write_motion(motion, out)
    lines = out.read_text().splitlines()
    depth = {ln.strip().split()[1]: len(ln) - len(ln.lstrip("\t"))
             for ln in lines if ln.strip().startswith(("ROOT", "JOINT"))}
    assert depth == {"base": 0, "lower_arm": 1, "upper_arm": 2}  # a tab a level


# -- the mocap commands ------------------------------------------------------------------------
def test_a_default_file_is_found_from_any_folder(tmp_path, monkeypatch):
    from puppet.commands.mocap import DEFAULT_BONES, _project_file

    monkeypatch.chdir(tmp_path)
    got = _project_file(DEFAULT_BONES)
    assert got.is_absolute() and got.is_file() and got == ROOT / DEFAULT_BONES
    assert _project_file("no/such/file.yaml") == Path("no/such/file.yaml")


def test_a_live_mapping_that_reads_points_the_stream_never_sends_is_refused():
    from puppet.commands.streams import source_for

    with pytest.raises(UsageError) as info:
        source_for("udp://127.0.0.1:0", "vmc", "cmu-131")
    msg = str(info.value)
    assert "reads points a vmc stream never sends" in msg and "Unity humanoid bone names" in msg
    source = source_for("udp://127.0.0.1:0", "vmc", None)  # the shipped vmc-humanoid
    assert source.retargeter is not None


def test_the_listen_help_says_where_the_take_comes_from(capsys):
    from puppet.commands import main

    with pytest.raises(SystemExit):
        main(["mocap", "listen", "--help"])
    out = " ".join(capsys.readouterr().out.split())
    assert "network)" in out


# -- OSC ---------------------------------------------------------------------------------------
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


# -- the ground --------------------------------------------------------------------------------
def test_the_grounds_top_is_its_line_plus_half_its_thickness():
    s = Session(load_setup("biped-stand"))
    ground = s.setup.scene.ground[0]
    assert s.sim.ground_surface(1.0) == pytest.approx(ground.points[0][1] + ground.thickness / 2)


# -- expectations ------------------------------------------------------------------------------
def _evaluate(item, traj):
    from puppet.timeline.expectations import evaluate, parse_expectations

    e, = parse_expectations([item]).items
    return evaluate(e, traj, ""), e


def test_revolutions_either_way_counts_a_backward_turn_once():
    from types import SimpleNamespace

    a = np.linspace(0, 2 * math.pi * 1.5, 200) - math.pi / 2
    com = np.stack([np.cos(a), np.sin(a)], 1)
    traj = SimpleNamespace(t=np.arange(200) * 0.1, com=com, held=[()] * 200)
    got, _ = _evaluate({"revolutions": {"about": [0.0, 0.0], "min": 1, "direction": "either"}},
                       traj)
    assert got.passed and got.measured.startswith("1.50 turns in a row backward")


def test_a_tilt_exactly_at_its_bound_passes():
    from types import SimpleNamespace

    traj = SimpleNamespace(t=np.arange(3) * 0.1, names=["base"],
                           angle=np.radians(np.array([[0.0], [30.0], [-30.0]])),
                           index=lambda n: 0)
    got, _ = _evaluate({"tilt_never_above": {"links": ["base"], "max": 30}}, traj)
    assert got.passed, got
    upright = SimpleNamespace(t=traj.t, names=["base"], angle=np.zeros((3, 1)),
                              index=lambda n: 0)
    got, _ = _evaluate({"tilt_at_end": {"links": ["base"], "max": 0, "held": 0.1}}, upright)
    assert got.passed and got.measured == "base at most 0.0 deg from upright over the last 0.1 s"


def test_what_holding_expectations_say_of_themselves():
    from puppet.timeline.expectations import parse_expectations

    said = [e.describe() for e in parse_expectations([
        {"held": {"chains": ["a", "b"], "prop": "bar"}},
        {"held": {"chains": ["a"], "from": 1.0, "until": 2.0}},
        {"always_holding": {"chains": ["a", "b"]}},
        {"always_holding": {"chains": ["a"], "from": 3.0}},
        {"stayed_in_state": {"state": "up", "until": 4.0}},
    ]).items]
    assert said == ["held a, b on bar", "held a from 1.0 s until 2.0 s",
                    "always_holding one of a, b", "always_holding one of a from 3.0 s",
                    "stayed_in_state up until 4.0 s"]


def test_a_got_up_over_two_samples_reads_their_spacing():
    from types import SimpleNamespace

    traj = SimpleNamespace(t=np.array([0.0, 0.5]), root_angle=np.radians([90.0, 0.0]),
                           contact=np.ones((2, 1), dtype=bool))
    got, _ = _evaluate({"got_up": {"lay_seconds": 0.4, "within_seconds": 1.0}}, traj)
    assert got.passed, got


# -- a log's header ----------------------------------------------------------------------------
@pytest.mark.parametrize("key", ["description", "puppet", "interface_hash"])
def test_a_header_text_field_that_is_not_text_is_named(tmp_path, key):
    from puppet.timeline.log import read_log

    lines = (ROOT / "assets" / "logs" / "luxo-hop.jsonl").read_text().splitlines()
    h = json.loads(lines[0])
    h[key] = 5
    path = tmp_path / "h.jsonl"
    path.write_text("\n".join([json.dumps(h)] + lines[1:]) + "\n")
    with pytest.raises(DataError) as info:
        read_log(path)
    assert str(info.value).startswith(f"{path}:1:") and key in str(info.value)


# -- more of the fresh sample's survivors -------------------------------------------------------
def test_a_listen_duration_is_more_than_zero_and_at_most_a_day():
    import argparse

    from puppet.commands.mocap import _duration

    assert _duration("60") == 60.0 and _duration("86400") == 86400.0
    for bad in ("0", "-1", "86401", "soon"):
        with pytest.raises(argparse.ArgumentTypeError):
            _duration(bad)


def test_listen_listens_on_the_port_it_is_given(capsys):
    import socket

    from puppet.commands import main

    for _ in range(5):  # a free port, probed; another process may take it before the bind
        with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as probe:
            probe.bind(("127.0.0.1", 0))
            port = probe.getsockname()[1]
        code = main(["mocap", "listen", "--format", "puppet", "--port", str(port),
                     "--seconds", "0.1"])
        out, err = capsys.readouterr()
        if code == 0 or "cannot listen" not in err:
            break
    assert code == 0, err
    assert f"listening for puppet on udp://127.0.0.1:{port}" in out


def test_listen_on_port_0_says_the_port_the_system_chose(capsys):
    from puppet.commands import main

    assert main(["mocap", "listen", "--format", "puppet", "--port", "0",
                 "--seconds", "0.1"]) == 0
    line = capsys.readouterr().out.splitlines()[0]
    assert line.startswith("listening for puppet on udp://127.0.0.1:")
    assert int(line.split(":")[2].split(";")[0]) > 0


def test_the_latency_measure_reports_transit_and_waiting_times():
    from puppet.commands.bench.latency import measure_latency

    got = measure_latency(0.3)
    assert got["transit_median_ms"] >= 0 and got["transit_p99_ms"] >= got["transit_median_ms"]
    assert got["frames"] > 0


def test_regrasps_exactly_the_minimum_pass():
    from types import SimpleNamespace

    rows = [(("l", "bars", "b1", 0, 0),), (("l", "bars", "b1", 0, 0), ("r", "bars", "b2", 0, 0)),
            (("r", "bars", "b2", 0, 0), ("l", "bars", "b3", 0, 0))]
    traj = SimpleNamespace(t=np.arange(3) * 0.1, held=rows,
                           prop_points={"bars": ["b1", "b2", "b3"]})
    got, _ = _evaluate({"regrasps": {"chains": ["l", "r"], "prop": "bars", "min": 2}}, traj)
    assert got.passed and got.measured.startswith("2 progressing grasps")


def test_a_checkpoint_interval_of_zero_means_the_default():
    from puppet.session.history import CHECKPOINT_EVERY, History

    dt = 1 / 480
    assert History(dt, 0).checkpoint_every == History(dt, CHECKPOINT_EVERY).checkpoint_every
    assert History(dt, 0).checkpoint_every > 1


def test_a_script_pushing_a_link_the_character_lacks_is_named_at_its_line(tmp_path):
    from puppet.timeline.script import check_links, load_script

    path = tmp_path / "s.yaml"
    path.write_text("events:\n  - {t: 0.5, push: {link: tail, impulse: [1, 0]}}\n")
    with pytest.raises(DataError) as info:
        check_links(path, load_script(path), ["base", "lower_arm", "upper_arm"])
    msg = str(info.value)
    assert msg.startswith(f"{path}:2:") and "tail" in msg and "\n" not in msg


def test_what_the_leap_and_seat_expectations_say_of_themselves():
    from puppet.timeline.expectations import parse_expectations

    said = [e.describe() for e in parse_expectations([
        {"on_ground": {"links": ["thigh_near"], "min_seconds": 1, "min_root_angle": 30,
                       "max_root_angle": 80}},
        {"first_touch": {"links": ["foot_near", "foot_far"], "min_x": 1.0}},
        {"first_touch": {"links": ["foot_near"]}},
    ]).items]
    assert said == ["on_ground thigh_near min 1 s, root at least 30 and at most 80 deg (signed)",
                    "first_touch foot_near, foot_far only, each at x >= 1 m",
                    "first_touch foot_near only"]


def test_listen_prints_the_channels_that_arrive(capsys, monkeypatch):
    import socket
    import threading
    import time

    from helpers import ListenedPort

    from puppet.commands import main
    from puppet.mocap.puppet_osc import encode_frame

    listened = ListenedPort(monkeypatch)  # port 0: the system picks a free one
    codes = []
    listener = threading.Thread(target=lambda: codes.append(main(
        ["mocap", "listen", "--format", "puppet", "--port", "0", "--seconds", "0.6"])))
    listener.start()
    port = listened.wait()
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as send:  # a stream, until it
        k = 0                                                        # has listened 0.6 s
        while listener.is_alive() and k < 3000:
            send.sendto(encode_frame(k / 60, {"hip": 0.125}), ("127.0.0.1", port))
            k += 1
            time.sleep(0.01)
    listener.join(5)
    assert codes == [0]
    assert "  channels: hip=0.125" in capsys.readouterr().out
