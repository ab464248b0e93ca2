"""A BVH file has limits, as a YAML data file has (issue 32): bytes (checked before it is
read), joints, a joint name's length, frames, the motion table's values and the joint
positions playing it computes; a wrong frame count is found before any number is
converted; every refusal is one line, ``file:line: what, what was expected``."""

import numpy as np
import pytest
from test_mocap_bvh import SMALL, WALK

from puppet.commands.check import check_file
from puppet.data.errors import DataError
from puppet.mocap import bvh
from puppet.mocap.bvh import MAX_BYTES, MAX_JOINT_FRAMES, MAX_JOINTS, MAX_NAME, parse_bvh, read_bvh


def _refused(path_or_text, fragment: str, reader=None) -> DataError:
    with pytest.raises(DataError) as info:
        if reader is None:
            parse_bvh(path_or_text, "bad.bvh")
        else:
            reader(path_or_text)
    assert fragment in info.value.message, str(info.value)
    assert "\n" not in str(info.value)
    return info.value


def test_a_frame_with_inf_then_a_word_is_a_one_line_error():
    """'inf abc': the number check stopped at inf (a word float() reads), so 'abc'
    reached float() and raised a ValueError with a traceback."""
    lines = SMALL.splitlines()
    at = len(lines) - 1  # the last frame
    lines[at] = "0 0 0 inf abc 0 0 0 0 0 0"
    error = _refused("\n".join(lines) + "\n", "'abc' in frame 3: expected a number")
    assert (error.line, error.col) == (at + 1, lines[at].index("abc") + 1)
    lines[at] = "0 0 0 -inf 1 nan 0 0 0 0 0"  # only words float() reads: not finite
    _refused("\n".join(lines) + "\n", "frame 3 has a value that is not finite")


def test_a_file_too_big_is_refused_before_it_is_read(tmp_path, monkeypatch):
    path = tmp_path / "huge.bvh"
    head = SMALL.encode()
    with open(path, "wb") as fh:  # 35 MB, sparse: no disk used
        fh.write(head)
        fh.truncate(35_000_000)
    reads = []
    real_open = open

    def watching(file, mode="r", *args, **kwargs):
        handle = real_open(file, mode, *args, **kwargs)
        if str(file) == str(path):
            real_read = handle.read
            handle.read = lambda *a: reads.append(a) or real_read(*a)
        return handle

    monkeypatch.setattr("builtins.open", watching)
    error = _refused(path, f"a BVH file may be at most {MAX_BYTES // 1_000_000} MB",
                     read_bvh)
    assert "35.0 MB" in error.message and error.path == str(path)
    assert reads == []  # refused on its size, not a byte read


def test_a_wrong_frame_count_is_found_before_the_numbers_are_read(monkeypatch):
    """A big table whose 'Frames:' is wrong: refused on its line count, without
    converting the numbers (numpy's reader, then the slow one, did it all first)."""
    lines = SMALL.splitlines()
    frame = lines[-1]
    many = "\n".join(lines[:-3] + [frame] * 20000) + "\n"
    monkeypatch.setattr(np, "loadtxt", lambda *a, **k: pytest.fail("numbers read"))
    monkeypatch.setattr(bvh, "_motion_slow", lambda *a, **k: pytest.fail("numbers read"))
    error = _refused(many, "more frames than 'Frames: 3' says")
    assert error.line == len(lines) - 3 + 4  # the fourth frame's line
    _refused(many.replace("Frames: 3", "Frames: 30000"),
             "the file ends after 20000 frames; 'Frames: 30000' expected 30000")


def _star(joints: int, frames: int = 1) -> str:
    """A root with ``joints - 1`` children, one rotation channel each."""
    kids = "".join(f"JOINT j{i}\n{{\nOFFSET 0 1 0\nCHANNELS 1 Zrotation\n}}\n"
                   for i in range(joints - 1))
    row = " ".join(["0"] * (joints + 2))
    return ("HIERARCHY\nROOT r\n{\nOFFSET 0 0 0\nCHANNELS 3 Xposition Yposition Zrotation\n"
            + kids + "}\nMOTION\n" + f"Frames: {frames}\nFrame Time: 0.01\n"
            + (row + "\n") * frames)


def test_a_rig_of_thousands_of_joints_is_refused_by_check(tmp_path):
    """2,030 joints passed ``puppet check`` and took 424 MB to play 3 s."""
    assert len(parse_bvh(_star(MAX_JOINTS)).joints) == MAX_JOINTS  # the limit reads
    path = tmp_path / "rig.bvh"
    path.write_text(_star(2030))
    error = _refused(path, f"a BVH file may have at most {MAX_JOINTS} joints and End Sites",
                     check_file)
    assert error.line is not None and error.path == str(path)


def test_a_joint_name_has_a_length_limit():
    error = _refused(SMALL.replace("JOINT upper", "JOINT " + "u" * 5000),
                     f"a joint name of 5000 characters; expected at most {MAX_NAME}")
    assert len(str(error)) < 200


def test_frames_times_joints_is_bounded():
    frames = MAX_JOINT_FRAMES // 100 + 1  # a 100-joint rig: one frame too many
    text = _star(100, 1).replace("Frames: 1", f"Frames: {frames}")
    _refused(text, f"joint positions (frames x joints and End Sites); a BVH clip may have "
                   f"at most {MAX_JOINT_FRAMES}")


def test_playing_a_clip_computes_only_the_joints_the_mapping_reads():
    """The retargeting reads a few points: their chains' transforms, not every
    joint's (a big rig's memory), the same positions as the whole forward kinematics."""
    clip = read_bvh(WALK)
    names = ["LeftAnkle", "RightAnkle", "Head", "no-such-joint"]
    some = clip.positions_of(names, scale=0.5)
    every = clip.world_positions(0.5)
    assert set(some) == set(names[:3])
    for name, xyz in some.items():
        assert np.array_equal(xyz, every[:, clip.index(name)])


def test_a_mapping_lists_at_most_so_many_points(tmp_path):
    import yaml

    from puppet.data.mappings import MAX_POINTS, load_mapping

    data = yaml.safe_load((WALK.parents[1] / "mappings" / "cmu-131.yaml").read_text())
    data["segments"] = {f"s{i}": {"from": "LeftHip", "to": "LeftKnee"}
                        for i in range(MAX_POINTS + 1)}
    path = tmp_path / "big.yaml"
    path.write_text(yaml.safe_dump(data))
    error = _refused(path, f"expected at most {MAX_POINTS} item(s)", load_mapping)
    assert error.line is not None


def test_a_bone_tables_joint_names_are_bounded(tmp_path):
    from puppet.mocap.send import load_bones

    text = (WALK.parent / "cmu-bones.yaml").read_text()
    path = tmp_path / "bones.yaml"
    path.write_text(text.replace("Hips: Hips", "Hips: " + "h" * 5000, 1))
    _refused(path, f"vmc.Hips: expected a BVH joint name (1 to {MAX_NAME} characters)",
             load_bones)
