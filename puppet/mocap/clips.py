"""Open a clip for an interface: find the BVH file and the mapping, retarget."""

from __future__ import annotations

from pathlib import Path

from puppet.data.catalog import find
from puppet.data.errors import DataError
from puppet.data.mappings import MappingSpec, load_mapping
from puppet.mocap.bvh import read_bvh
from puppet.mocap.retarget import RetargetedClip, retarget_clip


def find_mapping(name: str | None, interface, interface_path=None) -> tuple[MappingSpec, Path]:
    """The mapping ``name`` (typed by the user: a path or a catalog name), else the one
    the interface's ``tracking.mapping`` names (a catalog name, or a file beside it)."""
    if name is None:
        tracking = interface.tracking
        if tracking is None or tracking.mapping is None:
            raise DataError(str(interface_path or interface.name), None, None,
                            "the interface names no mocap mapping (tracking.mapping); "
                            "expected one, or --mapping NAME")
        within = (Path(interface_path).resolve().parent,) if interface_path else ()
        path = find("mapping", tracking.mapping, within)
    else:
        path = find("mapping", name)
    return load_mapping(path), path


def open_clip(clip: str, mapping: MappingSpec) -> RetargetedClip:
    """A BVH clip (a path or a catalog name, assets/mocap/NAME.bvh) through ``mapping``."""
    path = find("clip", clip)
    return retarget_clip(read_bvh(path), mapping, str(path))
