"""Mocap mappings named on the command line: found by name or path, a wrong one named
with what there is; a clip no shipped mapping fits told how to write one."""

from __future__ import annotations

import pytest
from helpers import TWO_JOINT_BVH

from puppet.data.errors import DataError


def test_a_mapping_is_found_by_name_or_path_and_a_wrong_one_named():
    from puppet.mocap.clips import find_mapping

    spec, path = find_mapping("cmu-131", None)
    assert path.name == "cmu-131.yaml" and spec.point_names()
    spec2, path2 = find_mapping(str(path), None)
    assert path2 == path
    with pytest.raises(DataError) as info:
        find_mapping("cmu-999", None)
    assert "no mapping named 'cmu-999'" in str(info.value)


def test_info_on_a_clip_no_mapping_fits_says_how_to_write_one(tmp_path):
    from puppet.mocap.info import describe

    bvh = tmp_path / "odd.bvh"
    bvh.write_text(TWO_JOINT_BVH)
    text = describe(str(bvh))
    assert ("planar angles: no mapping of assets/mappings/ names all its joints, and it is "
            "no humanoid rig puppet recognises (no joint named for the left ankle (or "
            "foot)") in text
    assert "write a mapping (docs/interfaces.md, 'Motion capture'), then --mapping NAME" in text
