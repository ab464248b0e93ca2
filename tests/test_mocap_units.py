"""A wrong unit is said, not silent: a BVH in metres read at the CMU unit (a mapping's
source.unit, a bone table's unit) is an 8 cm performer; info, send and play --mocap
each say so in one line on stderr. The shipped clips at their units say nothing."""

from __future__ import annotations

import re
import socket
from pathlib import Path

import pytest

from puppet.commands import main
from puppet.mocap.bvh import CMU_UNIT_METRES, read_bvh
from puppet.mocap.info import performer_height

WALK = "assets/mocap/cmu-131_01-walk.bvh"


def _metres_walk(tmp_path, frames: int = 60) -> str:
    """The walk's first ``frames`` frames, its lengths in metres (offsets and the root's
    positions times the CMU unit), as a BVH exported in metres would be."""
    hierarchy, motion = Path(WALK).read_text().split("MOTION\n", 1)

    def scaled(m):
        return "OFFSET " + " ".join(f"{float(v) * CMU_UNIT_METRES:.6f}" for v in m.group(1).split())
    hierarchy = re.sub(r"OFFSET ([-0-9.e ]+)", scaled, hierarchy)
    lines = motion.splitlines()
    rows = []
    for line in lines[2:2 + frames]:
        values = line.split()
        values[:3] = [f"{float(v) * CMU_UNIT_METRES:.6f}" for v in values[:3]]  # X Y Z position
        rows.append(" ".join(values))
    path = tmp_path / "walk-metres.bvh"
    path.write_text(hierarchy + "MOTION\n" + f"Frames: {frames}\n" + lines[1] + "\n"
                    + "\n".join(rows) + "\n")
    return str(path)


def test_the_metres_clip_is_the_walk_shrunk_by_the_cmu_unit(tmp_path):
    walk, metres = read_bvh(WALK), read_bvh(_metres_walk(tmp_path, frames=994))
    assert performer_height(metres, 1.0, "y") == pytest.approx(
        performer_height(walk, CMU_UNIT_METRES, "y"), rel=1e-4)
    assert 1.2 < performer_height(walk, CMU_UNIT_METRES, "y") < 2.0


def test_info_says_a_performer_far_from_human_size_is_a_unit_question(tmp_path, capsys):
    assert main(["mocap", "info", _metres_walk(tmp_path), "--mapping", "cmu-131"]) == 0
    err = capsys.readouterr().err
    assert err.count("\n") == 1, err
    assert err.startswith("puppet mocap info: warning: the performer is 0.08 m tall: "
                          "is the unit right? (head to feet 1.4")
    assert "x 0.056444 m, the mapping's source.unit in " in err and "cmu-131.yaml" in err


@pytest.mark.parametrize("clip", ["cmu-131_01-walk", "cmu-01_01-jumps"])
def test_the_shipped_clips_are_human_size_and_say_nothing(clip, capsys):
    assert main(["mocap", "info", clip]) == 0
    assert capsys.readouterr().err == ""


def test_send_says_it_at_the_bone_tables_unit(tmp_path, capsys):
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as sink:  # somewhere to send
        sink.bind(("127.0.0.1", 0))
        port = sink.getsockname()[1]
        assert main(["mocap", "send", _metres_walk(tmp_path, frames=12), "-q", "--speed", "10",
                     "--to", f"udp://127.0.0.1:{port}"]) == 0
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "the performer is 0.08 m tall: is the unit right?" in err
    assert "the bone table's unit in " in err and "cmu-bones.yaml" in err


def test_play_mocap_says_it_at_the_mappings_unit(tmp_path, capsys):
    main(["play", "biped-mocap", "--headless", "--seconds", "0.05", "--mocap",
          _metres_walk(tmp_path)])
    err = capsys.readouterr().err
    assert err.startswith("puppet play: warning: the performer is 0.08 m tall: is the unit "
                          "right?"), err
    assert "the mapping's source.unit in " in err
