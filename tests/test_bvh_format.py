"""BVH files: a broken one says what goes where (the MOTION header, its lines), and the
planar writer nests each joint under its parent."""

from __future__ import annotations

from pathlib import Path

import pytest
from helpers import TWO_JOINT_BVH as BVH

from puppet.data.errors import DataError

ROOT = Path(__file__).resolve().parents[1]


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
