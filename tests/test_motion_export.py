"""``puppet replay LOG --export-motion OUT.bvh|.csv``: the performed motion for animators,
read back with puppet's BVH reader and compared with the replay's own trajectory."""

from __future__ import annotations

import csv
import math
from pathlib import Path

import numpy as np
import pytest

from puppet.commands import main
from puppet.data.catalog import load_setup
from puppet.data.characters import load_character
from puppet.data.errors import DataError
from puppet.mocap.bvh import read_bvh
from puppet.session import Session
from puppet.testing import replay_log
from puppet.timeline.log import read_log
from puppet.timeline.motion import planar_hierarchy, sample_motion, write_motion

ROOT = Path(__file__).resolve().parents[1]
BACKFLIP = ROOT / "assets" / "logs" / "luxo-backflip.jsonl"


@pytest.fixture(scope="module")
def flip():
    return sample_motion(BACKFLIP, 30.0)


@pytest.fixture(scope="module")
def flip_replay():
    return replay_log(BACKFLIP)  # samples every 4 steps; a 30 fps frame every 16


def test_bvh_reads_back_to_the_same_angles_within_a_hundredth_of_a_degree(flip, tmp_path):
    out = tmp_path / "flip.bvh"
    write_motion(flip, out)
    clip = read_bvh(out)
    assert [j.name for j in clip.joints if not j.end_site] == ["base", "lower_arm", "upper_arm"]
    assert clip.frames == flip.frames == 106  # 3.5 s at 30 fps, both ends
    assert clip.frame_time == pytest.approx(1 / 30, abs=1e-7)
    deg = np.degrees
    assert np.abs(clip.channel("base", "Zrotation") - deg(flip.root_angle)).max() < 0.01
    assert np.abs(clip.channel("lower_arm", "Zrotation") - deg(flip.joint_angle[:, 0])).max() < 0.01
    assert np.abs(clip.channel("upper_arm", "Zrotation") - deg(flip.joint_angle[:, 1])).max() < 0.01
    assert np.abs(clip.channel("base", "Xposition") - flip.root_xy[:, 0]).max() < 1e-5
    assert np.abs(clip.channel("base", "Yposition") - flip.root_xy[:, 1]).max() < 1e-5
    # a back flip: the root's angle accumulates to a full backward turn, no wrap-around
    # (a wrap would jump 360 deg; luxo-flip's opening whips the base round at up to
    # 3600 deg/s, about 120 deg between two frames)
    assert clip.channel("base", "Zrotation")[-1] > 330
    assert np.abs(np.diff(clip.channel("base", "Zrotation"))).max() < 180


def test_the_exported_angles_are_the_replays_link_angles(flip, flip_replay):
    traj = flip_replay.trajectory
    at = {int(s): i for i, s in enumerate(traj.step)}
    rows = [at[int(s)] for s in flip.step]
    base, lower, upper = (traj.index(n) for n in ("base", "lower_arm", "upper_arm"))
    assert flip.root_angle == pytest.approx(traj.angle[rows, base], abs=1e-12)
    assert flip.joint_angle[:, 0] == pytest.approx(
        traj.angle[rows, lower] - traj.angle[rows, base], abs=1e-12)
    assert flip.joint_angle[:, 1] == pytest.approx(
        traj.angle[rows, upper] - traj.angle[rows, lower], abs=1e-12)
    assert flip.final_hash == flip_replay.final_hash


def test_bvh_forward_kinematics_puts_the_joints_on_the_simulated_anchors(flip, flip_replay,
                                                                          tmp_path):
    out = tmp_path / "flip.bvh"
    write_motion(flip, out)
    clip = read_bvh(out)
    pos = clip.world_positions()
    traj = flip_replay.trajectory
    at = {int(s): i for i, s in enumerate(traj.step)}
    rows = [at[int(s)] for s in flip.step]
    session = Session(load_setup("luxo-mouse-strong"))  # bodies in a space: masses set
    character = session.character
    upper = traj.index("upper_arm")
    cog = character.bodies["upper_arm"].center_of_gravity
    knee = character.spec.joint("knee").anchor
    a = traj.angle[rows, upper]
    off = (knee[0] - cog.x, knee[1] - cog.y)  # the knee anchor, from the link's centre
    sim_knee = np.stack([traj.x[rows, upper] + np.cos(a) * off[0] - np.sin(a) * off[1],
                         traj.y[rows, upper] + np.sin(a) * off[0] + np.cos(a) * off[1]], 1)
    err = np.linalg.norm(pos[:, clip.index("upper_arm"), :2] - sim_knee, axis=1)
    # the hinges give a little under load (pymunk's pivot joints are solved iteratively):
    # 0.5 mm typically, 7 mm at the flip's hardest push and landing
    assert np.median(err) < 1e-3 and err.max() < 0.01
    assert np.abs(pos[:, :, 2]).max() == 0.0  # planar


def test_csv_has_a_header_row_and_one_row_per_frame(flip, tmp_path):
    out = tmp_path / "flip.csv"
    write_motion(flip, out)
    with open(out, newline="") as f:
        rows = list(csv.reader(f))
    assert rows[0] == ["frame", "time_s", "root_x_m", "root_y_m", "root_angle_deg",
                       "ankle_deg", "knee_deg"]
    table = np.array(rows[1:], dtype=float)
    assert table.shape == (flip.frames, 7)
    assert table[:, 0].tolist() == list(range(flip.frames))
    assert np.diff(table[:, 1]) == pytest.approx(np.full(flip.frames - 1, 1 / 30), abs=1e-6)
    assert np.abs(table[:, 4] - np.degrees(flip.root_angle)).max() < 1e-5
    assert np.abs(table[:, 6] - np.degrees(flip.joint_angle[:, 1])).max() < 1e-5


def test_a_frame_rate_that_does_not_divide_the_step_takes_the_nearest_steps():
    motion = sample_motion(BACKFLIP, 25.0, until_step=480)
    dt = 1 / 480
    assert motion.frames == 26  # 0 .. 1 s
    assert np.abs(motion.t - np.arange(26) / 25).max() <= dt / 2 + 1e-12


def test_the_cats_tree_is_one_bvh_joint_per_link(tmp_path):
    spec = load_setup("cat-trot").character
    joints = planar_hierarchy(spec)
    assert sorted(j.name for j in joints) == sorted(link.name for link in spec.links)
    assert joints[0].name == spec.root and joints[0].parent is None
    leaves = {j.name for j in joints} - {j.parent for j in joints}
    assert all(j.end is not None for j in joints if j.name in leaves)
    log = read_log(ROOT / "assets" / "logs" / "cat-trot.jsonl")
    motion = sample_motion(log, 10.0, until_step=round(2.0 / log.header["dt"]))  # its step
    out = tmp_path / "cat.bvh"
    write_motion(motion, out)
    clip = read_bvh(out)
    assert clip.frames == 21  # 0 .. 2 s at 10 fps
    for k, j in enumerate(spec.joints):
        got = clip.channel(j.child, "Zrotation")
        assert np.abs(got - np.degrees(motion.joint_angle[:, k])).max() < 0.01, j.name


def test_cli_writes_bvh_and_csv_and_refuses_other_files(tmp_path, capsys):
    out = tmp_path / "hop.bvh"
    assert main(["replay", "luxo-hop", "--export-motion", str(out), "--fps", "24"]) == 0
    assert "same end as recorded" in capsys.readouterr().out
    assert read_bvh(out).frame_time == pytest.approx(1 / 24, abs=1e-7)
    assert main(["replay", "luxo-hop", "--export-motion", str(tmp_path / "hop.csv")]) == 0
    assert math.isfinite(read_bvh(out).motion.sum())


def test_export_into_a_new_folder_creates_it_as_video_and_plot_do(tmp_path, capsys):
    out = tmp_path / "new" / "deeper" / "hop.csv"
    assert main(["replay", "luxo-hop", "--until-step", "120", "--export-motion",
                 str(out)]) == 0
    said = capsys.readouterr().out
    assert said.startswith(f"wrote {out}: 8 frames at 30 fps"), said  # 0.25 s at dt 1/480
    with out.open(newline="") as f:
        rows = list(csv.reader(f))
    assert rows[0][:2] == ["frame", "time_s"] and len(rows) == 1 + 8


def test_a_wrong_export_name_is_a_usage_error_before_the_replay(tmp_path, capsys,
                                                                monkeypatch):
    import puppet.timeline.motion as motion

    def no_replay(*args, **kwargs):
        raise AssertionError("replayed before the output name was checked")

    monkeypatch.setattr(motion, "sample_motion", no_replay)
    cases = [(tmp_path / "hop.fbx", "'.fbx'; give a file name ending in .bvh or .csv"),
             (tmp_path / "hop", "no extension; give a file name ending in .bvh or .csv"),
             (tmp_path, "is a folder; give a file name ending in .bvh or .csv")]
    for out, words in cases:
        assert main(["replay", "luxo-hop", "--export-motion", str(out)]) == 2
        err = capsys.readouterr().err
        assert err == f"puppet replay: --export-motion {out}: {words}\n", err
    assert main(["replay", "luxo-hop", "luxo-kip", "--export-motion", "x.csv"]) == 2
    assert capsys.readouterr().err == "puppet replay: --export-motion takes one log\n"
    long = tmp_path / ("a" * 300 + ".csv")  # more than a file name may hold
    assert main(["replay", "luxo-hop", "--export-motion", str(long)]) == 2
    err = capsys.readouterr().err
    assert err.startswith("puppet replay: --export-motion /") and err.endswith(
        "...: File name too long\n") and err.count("\n") == 1, err
    assert list(tmp_path.iterdir()) == []


def test_an_export_that_cannot_be_written_is_one_line(tmp_path, capsys, monkeypatch):
    import puppet.timeline.motion as motion

    def full(*args, **kwargs):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(motion, "write_planar_bvh", full)
    out = tmp_path / "hop.bvh"
    assert main(["replay", "luxo-hop", "--until-step", "10", "--export-motion", str(out)]) == 2
    assert capsys.readouterr().err == (f"puppet replay: --export-motion {out}: cannot write: "
                                       f"No space left on device\n")


HOP_LOG = Path(__file__).resolve().parents[1] / "assets" / "logs" / "luxo-hop.jsonl"


def _hop_at(step: int) -> Session:
    from puppet.timeline.log import read_log
    from puppet.timeline.replay import LogFeeder, new_session, setup_for_log

    log = read_log(HOP_LOG)
    s = new_session(log, setup_for_log(log, False)[0])
    feeder = LogFeeder(s, log)
    feeder.advance(step)
    return s


BOXES = """
name: boxes
description: a base and a leaf link that is a rotated box (test character)
links:
  - name: base
    mass: 5.0
    shapes: [{type: box, center: [0.0, 0.05], size: [0.4, 0.1]}]
  - name: flap
    mass: 1.0
    shapes:
      - {type: box, center: [0.0, 0.3], size: [0.1, 0.4], angle: 30}
      - {type: segment, a: [0.0, 0.1], b: [0.02, 0.15], radius: 0.01}   # a short one last
joints:
  - {name: hinge, parent: base, child: flap, anchor: [0.0, 0.1], limits: [-80, 80],
     pd: {stiffness: 40, damping: 1.0, max_torque: 60}}
"""


def _corners(cx, cy, w, h, deg):
    a = math.radians(deg)
    return [(cx + math.cos(a) * x - math.sin(a) * y, cy + math.sin(a) * x + math.cos(a) * y)
            for x, y in ((-w / 2, -h / 2), (w / 2, -h / 2), (w / 2, h / 2), (-w / 2, h / 2))]


ONE = """
name: one
description: a single box and no joints (test character)
links:
  - name: block
    mass: 2.0
    shapes: [{type: box, center: [0.1, 0.2], size: [0.2, 0.1]}]
"""


def test_a_replays_joint_angles_are_the_angles_reached_not_the_targets():
    from puppet.timeline.replay import replay

    traj = replay(HOP_LOG, until_step=600).trajectory
    s = _hop_at(600)
    knee = list(s.character.servos).index("knee")
    assert traj.joint_angle[-1, knee] == s.character.servos["knee"].angle
    assert abs(traj.joint_angle[:, knee] - traj.joint_target[:, knee]).max() > 0.01


def test_motion_sampled_at_less_than_one_frame_a_second():
    from puppet.timeline.motion import sample_motion

    motion = sample_motion(HOP_LOG, 0.5)  # a frame every 2 s of the 4.5 s hop
    assert motion.t.tolist() == [0.0, 2.0, 4.0]
    with pytest.raises(ValueError, match="fps must be positive"):
        sample_motion(HOP_LOG, 0.0)


@pytest.mark.parametrize("interface", ["luxo-mouse", "cat-trot", "biped-walk"])
def test_a_limb_without_children_ends_at_its_farthest_point_in_the_hierarchy(interface):
    from puppet.timeline.motion import planar_hierarchy

    spec = load_setup(interface).character
    anchors = {j.child: tuple(j.anchor) for j in spec.joints}
    ends = {j.name: j.end for j in planar_hierarchy(spec) if j.end is not None}
    assert ends
    for name, end in ends.items():
        ax, ay = anchors.get(name, (0.0, 0.0))
        points = []
        for s in next(lk for lk in spec.links if lk.name == name).shapes:
            points += ([tuple(s.center)] if s.type == "circle" else
                       [tuple(s.a), tuple(s.b)] if s.type == "segment" else
                       [tuple(p) for p in s.points])
        reach = max(math.dist(p, (ax, ay)) for p in points)
        assert math.hypot(*end) == pytest.approx(reach), name
        assert any(math.dist(p, (ax + end[0], ay + end[1])) < 1e-9 for p in points), name


def test_a_motion_export_cut_short_makes_no_claim_about_the_end(tmp_path, capsys):
    import argparse

    from puppet.timeline.motion import export_motion_command

    out = tmp_path / "hop.csv"
    common = dict(logs=[str(HOP_LOG)], export_motion=str(out), fps=30.0,
                  allow_truncated=False, as_recorded=False)
    assert export_motion_command(argparse.Namespace(until_step=480, **common)) == 0
    said = capsys.readouterr().out
    assert said.startswith(f"wrote {out}: 31 frames at 30 fps") and "recorded" not in said
    assert export_motion_command(argparse.Namespace(until_step=None, **common)) == 0
    assert "(same end as recorded)" in capsys.readouterr().out


def test_the_bvh_offsets_add_up_to_every_joints_anchor_on_the_cat():
    """Each joint's offset is from its parent's anchor: summed from the root, they put
    every joint on its anchor (the cat's knees hang off hips that are not at x = 0)."""
    from puppet.timeline.motion import planar_hierarchy

    spec = load_setup("cat-trot").character
    joints = {j.name: j for j in planar_hierarchy(spec)}
    anchor = {j.child: tuple(j.anchor) for j in spec.joints}
    for name, j in joints.items():
        if j.parent is None:
            continue
        x = y = 0.0
        k = j
        while k.parent is not None:
            x, y = x + k.offset[0], y + k.offset[1]
            k = joints[k.parent]
        assert (x, y) == pytest.approx(anchor[name], abs=1e-12), name
    assert any(abs(anchor[j.parent][0]) > 0.05 for j in joints.values()
               if j.parent in anchor)  # some offsets are from an off-centre parent


def test_a_box_ended_leaf_ends_at_its_farthest_rotated_corner(tmp_path):
    """Of all its shapes' points: here a rotated box's corner, not the short segment
    listed after it."""
    from puppet.timeline.motion import planar_hierarchy

    (tmp_path / "boxes.yaml").write_text(BOXES)
    spec = load_character(tmp_path / "boxes.yaml")
    flap = next(j for j in planar_hierarchy(spec) if j.name == "flap")
    far = max(_corners(0.0, 0.3, 0.1, 0.4, 30), key=lambda p: math.dist(p, (0.0, 0.1)))
    assert flap.end == pytest.approx((far[0], far[1] - 0.1), abs=1e-12)


def test_a_lone_root_link_ends_at_its_farthest_point_from_the_origin(tmp_path):
    from puppet.timeline.motion import planar_hierarchy

    (tmp_path / "one.yaml").write_text(ONE)
    try:
        spec = load_character(tmp_path / "one.yaml")
    except DataError as exc:  # a character needs a joint: nothing to test then
        pytest.skip(str(exc))
    (root,) = planar_hierarchy(spec)
    far = max(_corners(0.1, 0.2, 0.2, 0.1, 0), key=lambda p: math.hypot(*p))
    assert root.end == pytest.approx(far, abs=1e-12)
