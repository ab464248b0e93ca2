"""``puppet check``: validate any data file, telling its kind from its folder or keys."""

from __future__ import annotations

from pathlib import Path

from puppet.data.errors import DataError
from puppet.data.yamlfile import Located, load_file

# Each kind's models are imported when a file of that kind is checked: a character's
# check does not build the interface, scene and script models (process start).

KIND_BY_FOLDER = {"characters": "character", "interfaces": "interface", "scenes": "scene",
                  "scripts": "script", "mappings": "mapping"}


def guess_kind(path: Path, located: Located) -> str:
    if path.name.endswith(".expect.yaml"):  # a log's sidecar (puppet replay --check)
        return "expectations"
    kind = KIND_BY_FOLDER.get(path.parent.name)
    if kind:
        return kind
    data = located.data if isinstance(located.data, dict) else {}
    if "links" in data:
        return "character"
    if "ground" in data:
        return "scene"
    if "events" in data:
        return "script"
    if "character" in data:
        return "interface"
    if "segments" in data:
        return "mapping"
    if "vmc" in data or "mediapipe" in data:
        return "bone table"
    if "expect" in data:
        return "expectations"
    raise located.error((), "cannot tell what kind of file this is; expected a character "
                            "(links:), scene (ground:), interface (character:), script "
                            "(events:), mocap mapping (segments:), bone table (vmc:, "
                            "mediapipe:) or a log's expectations (expect:)")


def check_file(path: str | Path, warnings: list[str] | None = None) -> str:
    """Validate one file; return its kind. Raises DataError on the first problem;
    ``warnings`` collects what is valid but probably not meant (two maps on a joint)."""
    path = Path(path)
    located = load_file(path)
    kind = guess_kind(path, located)
    if kind == "character":
        from puppet.data.characters import parse_character

        parse_character(located)
        return kind
    if kind == "scene":
        from puppet.data.scenes import parse_scene

        parse_scene(located)
        return kind
    if kind == "script":
        from puppet.timeline.script import parse_script

        parse_script(located)
        return kind
    if kind == "mapping":
        from puppet.data.mappings import parse_mapping

        parse_mapping(located)
        return kind
    if kind == "expectations":  # their states and modes are checked when a log replays
        from puppet.data.validate import validate
        from puppet.timeline.expectations import ExpectFile

        validate(located, ExpectFile)
        return kind
    if kind == "bone table":  # puppet mocap send's: BVH joints as bones, landmarks
        from puppet.mocap.send import parse_bones

        parse_bones(located)
        return kind
    from puppet.data import catalog
    from puppet.data.scenes import parse_scene

    spec, character, _ = catalog.check_interface(located)
    if warnings is not None:
        from puppet.data.interface_refs import map_conflicts

        warnings += map_conflicts(spec, located)
    try:
        scene_path = catalog.find("scene", spec.scene, catalog.reference_folders(path))
    except DataError as exc:
        raise located.error(("scene",), exc.message) from None
    # props named by reaches and grasps must be in the scene, as play checks
    from puppet.data.interface_refs import check_scene_refs

    check_scene_refs(spec, parse_scene(load_file(scene_path)), located, scene_path.stem)
    if spec.tracking is not None and spec.tracking.mapping is not None:
        from puppet.data.mappings import load_mapping
        from puppet.data.tracking import mapping_problem

        try:
            mapping = load_mapping(catalog.find("mapping", spec.tracking.mapping,
                                                catalog.reference_folders(path)))
        except DataError as exc:
            raise located.error(("tracking", "mapping"), exc.message) from None
        problem = mapping_problem(spec.tracking, mapping, [j.name for j in character.actuated])
        if problem:
            raise located.error(("tracking", "mapping"), problem)
    return kind
