"""``puppet mocap info CLIP``: what a clip holds and the planar angles it would give."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from puppet.data.catalog import find, list_kind
from puppet.data.errors import DataError
from puppet.data.mappings import MappingSpec, load_mapping
from puppet.mocap.bvh import Clip, read_bvh
from puppet.mocap.retarget import retarget_clip


def matching_mappings(clip: Clip) -> list[tuple[str, MappingSpec]]:
    """The catalog's mappings whose every point the clip has."""
    names = set(clip.names)
    out = []
    for name, _ in list_kind("mapping"):
        try:
            mapping = load_mapping(find("mapping", name))
        except DataError:
            continue
        if mapping.point_names() <= names:
            out.append((name, mapping))
    return out


def _tree(clip: Clip) -> list[str]:
    lines = []
    depth = {}
    for i, j in enumerate(clip.joints):
        if j.end_site:
            continue
        d = 0 if j.parent < 0 else depth[j.parent] + 1
        depth[i] = d
        channels = " ".join(c[0] + c[1:].replace("position", "pos").replace("rotation", "rot")
                            for c in j.channels) or "no channels"
        lines.append(f"  {'  ' * d}{j.name}  ({channels})")
    return lines


def describe(clip_name: str, mapping_name: str | None = None) -> str:
    path = find("clip", clip_name)
    clip = read_bvh(path)
    joints = [j for j in clip.joints if not j.end_site]
    out = [f"{path}",
           f"  {len(joints)} joints, {len(clip.joints) - len(joints)} end sites, "
           f"{clip.motion.shape[1]} channels",
           f"  {clip.frames} frames at {clip.fps:.2f} fps: {clip.frames * clip.frame_time:.2f} s",
           "skeleton:"] + _tree(clip)
    if mapping_name is not None:
        mapping_path = find("mapping", mapping_name)
        chosen = [(Path(mapping_path).stem, load_mapping(mapping_path))]
    else:
        chosen = matching_mappings(clip)[:1]
        if not chosen:
            out.append("planar angles: no mapping of assets/mappings/ names all its joints "
                       "(write one, see docs/interfaces.md, 'Motion capture'; then "
                       "--mapping NAME)")
            return "\n".join(out)
    name, mapping = chosen[0]
    rc = retarget_clip(clip, mapping, str(path))
    out.append(f"planar channels through mapping '{name}' (degrees; m for .x .y):")
    out.append(f"  {'channel':16s} {'min':>8s} {'mean':>8s} {'max':>8s}")
    for channel, values in rc.channels.items():
        good = values[~np.isnan(values)]
        if len(good) == 0:
            out.append(f"  {channel:16s} {'never seen':>26s}")
            continue
        out.append(f"  {channel:16s} {good.min():8.2f} {good.mean():8.2f} {good.max():8.2f}")
    return "\n".join(out)
