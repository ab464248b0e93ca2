"""Open a clip for an interface: find the BVH file and the mapping, retarget."""

from __future__ import annotations

from pathlib import Path

from puppet.data.catalog import find, list_kind
from puppet.data.errors import DataError
from puppet.data.mappings import (
    MappingSpec,
    channel_error,
    channel_problem,
    interface_reads,
    load_mapping,
)
from puppet.mocap.bvh import read_bvh
from puppet.mocap.retarget import RetargetedClip, retarget_clip


def shipped_mappings() -> list[tuple[str, MappingSpec]]:
    """(name, spec) of every mapping in the catalog that loads (a broken one is
    ``puppet check``'s business, not a suggestion's)."""
    out = []
    for name, _ in list_kind("mapping"):
        try:
            out.append((name, load_mapping(find("mapping", name))))
        except DataError:
            continue
    return out


def fitting_mappings(character) -> list[str]:
    """The shipped mappings (names) whose every channel the character (a CharacterSpec)
    can take: each a joint of it or its root angle."""
    joints = [j.name for j in character.joints]
    return [name for name, mapping in shipped_mappings()
            if channel_problem(mapping, joints, character.name) is None]


def find_mapping(name: str | None, interface, interface_path=None,
                 character=None) -> tuple[MappingSpec, Path]:
    """The mapping ``name`` (typed by the user: a path or a catalog name), else the one
    the interface's ``tracking.mapping`` names (a catalog name, or a file beside it).
    With ``character`` (the CharacterSpec it plays on), a channel of the mapping that
    is no joint of it (nor read by the interface) is a DataError at the channel's line,
    and so is a mapping none of whose channels is one: it would drive nothing."""
    if name is None:
        tracking = interface.tracking
        if tracking is None or tracking.mapping is None:
            fits = fitting_mappings(character) if character is not None else None
            if fits == []:
                hint = (f"no mapping of assets/mappings/ fits {character.name} (none "
                        f"makes channels of its joints: "
                        f"{', '.join(j.name for j in character.joints)}); expected a "
                        f"mapping written for it (docs/interfaces.md, section 15.1)")
            elif fits:
                hint = (f"expected one, or --mapping NAME ({', '.join(fits)} "
                        f"fit{'s' if len(fits) == 1 else ''} {character.name})")
            else:
                hint = "expected one, or --mapping NAME"
            raise DataError(str(interface_path or interface.name), None, None,
                            f"the interface names no mocap mapping (tracking.mapping)"
                            f"{', and ' if fits == [] else '; '}{hint}")
        within = (Path(interface_path).resolve().parent,) if interface_path else ()
        path = find("mapping", tracking.mapping, within)
    else:
        path = find("mapping", name)
    mapping = load_mapping(path)
    if character is not None:
        error = channel_error(path, mapping, [j.name for j in character.joints],
                              character.name, interface_reads(interface))
        if error is not None:
            raise error
    return mapping, path


def choose_mapping(clip: str, name: str | None, interface, interface_path,
                   character) -> tuple[MappingSpec, str, str | None]:
    """The mapping a clip (a path or a catalog name) plays through on ``interface``:
    ``--mapping NAME`` if given; else the interface's ``tracking.mapping`` if the clip
    has every joint it names; else the shipped mapping that names them all (the one
    ``puppet mocap info`` picks) if it fits the character; else the clip's rig
    recognised as a humanoid (``puppet.mocap.rigs``). Returns (the mapping, where it
    came from, a note saying which was taken when it was not the interface's)."""
    if name is not None or interface.tracking is None or interface.tracking.mapping is None:
        mapping, path = find_mapping(name, interface, interface_path, character)
        return mapping, str(path), None
    mapping, path = find_mapping(None, interface, interface_path, character)
    clip_path = find("clip", clip)
    bvh = read_bvh(clip_path)
    if mapping.point_names() <= set(bvh.names):
        return mapping, str(path), None
    from puppet.mocap.info import matching_mappings
    from puppet.mocap.rigs import NotHumanoid, recognise

    joints = [j.name for j in character.joints]
    stem = Path(clip_path).stem
    for other, spec in matching_mappings(bvh):
        if channel_problem(spec, joints, character.name) is None:
            return spec, str(find("mapping", other)), (
                f"{stem}: mapping '{mapping.name}' (the interface's) names joints the clip "
                f"has not; playing it through '{other}', which names them all")
    try:
        rig = recognise(bvh, character)
    except NotHumanoid as exc:
        try:
            retarget_clip(bvh, mapping, str(clip_path))
        except DataError as missing:
            raise DataError(missing.path, missing.line, missing.col,
                            f"{missing.message}; and {exc.message}") from None
        raise
    return rig.mapping, f"the rig recognised in {clip_path}", (
        f"{stem}: no mapping names its joints; recognised {rig.summary()} (puppet mocap "
        f"mapping {clip} writes the mapping out)")


def open_clip(clip: str, mapping: MappingSpec) -> RetargetedClip:
    """A BVH clip (a path or a catalog name, assets/mocap/NAME.bvh) through ``mapping``."""
    path = find("clip", clip)
    bvh = read_bvh(path)
    if not mapping.point_names() <= set(bvh.names):
        from puppet.mocap.info import matching_mappings

        fits = matching_mappings(bvh)[:1]  # the one mocap info picks
        try:
            return retarget_clip(bvh, mapping, str(path))
        except DataError as exc:
            if not fits:
                raise
            name = fits[0][0]
            raise DataError(exc.path, exc.line, exc.col,
                            f"{exc.message}; expected a mapping that names its joints: "
                            f"--mapping {name} (shipped) names them all, the one "
                            f"'puppet mocap info' picks") from None
    return retarget_clip(bvh, mapping, str(path))
