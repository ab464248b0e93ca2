"""``puppet mocap info CLIP``: what a clip holds and the planar angles it would give."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from puppet.data.catalog import find
from puppet.data.mappings import MappingSpec, load_mapping
from puppet.mocap.bvh import Clip, read_bvh
from puppet.mocap.retarget import retarget_clip


def matching_mappings(clip: Clip) -> list[tuple[str, MappingSpec]]:
    """The catalog's mappings whose every point the clip has."""
    from puppet.mocap.clips import shipped_mappings  # (clips imports this module)

    names = set(clip.names)
    return [(name, mapping) for name, mapping in shipped_mappings()
            if mapping.point_names() <= names]


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


HUMAN_HEIGHT = (0.5, 3.0)  # metres: a performer's head-to-feet outside this is a wrong unit


def performer_height(clip: Clip, unit: float, up: str) -> float:
    """The performer's height in metres: head to feet (the extent of every joint and
    End Site along ``up``: "y", "-z"...), the median over the clip's frames (a crouch
    or a jump moves few of them), times ``unit`` (metres per BVH unit)."""
    _, pos = clip.world_transforms()
    along = pos[..., "xyz".index(up[-1])]
    return float(np.median(along.max(axis=1) - along.min(axis=1))) * unit


def height_note(clip: Clip, unit: float, up: str, where: str) -> str | None:
    """One line when the performer is far from human size at ``unit`` (a clip in
    metres read as centimetres: a 10 cm performer), naming where the unit is set
    (``where``); None when the height is human."""
    height = performer_height(clip, unit, up)
    if HUMAN_HEIGHT[0] <= height <= HUMAN_HEIGHT[1]:
        return None
    return (f"the performer is {height:.2f} m tall: is the unit right? (head to feet "
            f"{height / unit:.4g} clip units x {unit:g} m, {where}; a human is "
            f"{HUMAN_HEIGHT[0]:g}..{HUMAN_HEIGHT[1]:g} m)")


def mapping_unit_note(clip: Clip, mapping: MappingSpec, mapping_path) -> str | None:
    """``height_note`` at a mapping's unit (its ``source: {unit, up}``)."""
    return height_note(clip, mapping.source.unit, mapping.source.up,
                       f"the mapping's source.unit in {mapping_path}")


def describe(clip_name: str, mapping_name: str | None = None,
             notes: list[str] | None = None) -> str:
    """What ``puppet mocap info`` prints; ``notes`` gets what goes to stderr (a
    performer far from human size at the mapping's unit)."""
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
        mapping_path = find("mapping", chosen[0][0]) if chosen else None
        if not chosen:  # a rig no mapping names: recognised as a humanoid, if it is one
            from puppet.mocap.rigs import NotHumanoid, recognise

            try:
                rig = recognise(clip)
            except NotHumanoid as exc:
                out.append(f"planar angles: no mapping of assets/mappings/ names all its "
                           f"joints, and it is no humanoid rig puppet recognises (no joint "
                           f"named for {exc.missing}); write a mapping (docs/interfaces.md, "
                           f"'Motion capture'), then --mapping NAME")
                return "\n".join(out)
            out.append(f"recognised {rig.summary()}")
            out.append(f"  (puppet mocap mapping {clip_name} writes this mapping out, "
                       f"for editing)")
            chosen = [(rig.mapping.name, rig.mapping)]
            mapping_path = f"the rig recognised in {path}"
    name, mapping = chosen[0]
    note = mapping_unit_note(clip, mapping, mapping_path)
    if note and notes is not None:
        notes.append(note)
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
