"""Find data files by name: characters, interfaces, scenes, scripts, logs and recordings.

Names resolve to ``<root>/<folder>/<name>.yaml``; a path to an existing file is
taken as is. The root is the checkout (or ``$PUPPET_HOME``).
"""

from __future__ import annotations

import hashlib
import os
from dataclasses import dataclass
from pathlib import Path

from puppet.data.characters import CharacterSpec, parse_character
from puppet.data.errors import DataError
from puppet.data.interfaces import InterfaceSpec, check_against_character, parse_interface
from puppet.data.scenes import SceneSpec, parse_scene
from puppet.data.yamlfile import Located, load_file, load_text, read_text

ROOT = Path(os.environ.get("PUPPET_HOME") or Path(__file__).resolve().parents[2])

FOLDERS = {
    "character": ("characters", ".yaml"),
    "interface": ("interfaces", ".yaml"),
    "scene": ("assets/scenes", ".yaml"),
    "script": ("assets/scripts", ".yaml"),
    "log": ("assets/logs", ".jsonl"),
    "recording": ("recordings", ".jsonl"),  # the window's own logs (not shipped)
}


def folder(kind: str) -> Path:
    return ROOT / FOLDERS[kind][0]


def find(kind: str, name: str) -> Path:
    """Path of the ``kind`` file called ``name`` (or ``name`` itself if it is a file)."""
    as_path = Path(name)
    if as_path.suffix and as_path.is_file():
        return as_path
    sub, ext = FOLDERS[kind]
    if as_path.is_dir():
        raise DataError(str(name), None, None, f"is a folder; expected {_a(kind)} name or a "
                                               f"{ext} file")
    if len(as_path.parts) > 1 or as_path.suffix == ext:  # a path, not a name: say so
        raise DataError(str(name), None, None, f"no such file (expected {_a(kind)} name, "
                                               f"e.g. '{_first(kind)}', or a {ext} file)")
    candidate = ROOT / sub / (name if name.endswith(ext) else name + ext)
    if candidate.is_file():
        return candidate
    known = ", ".join(n for n, _ in list_kind(kind)) or "none"
    raise DataError(str(name), None, None, f"no {kind} named '{name}'; known: {known}")


def _a(word: str) -> str:
    return f"{'an' if word[0] in 'aeiou' else 'a'} {word}"


def _first(kind: str) -> str:
    items = list_kind(kind)
    return items[0][0] if items else "NAME"


def list_kind(kind: str) -> list[tuple[str, str]]:
    """(name, one-line description) of every file of a kind, sorted by name."""
    sub, ext = FOLDERS[kind]
    out = []
    for path in sorted((ROOT / sub).glob("*" + ext)):
        out.append((path.stem, describe(path)))
    return out


def describe(path: Path) -> str:
    """A file's one-line description, without validating it."""
    try:
        if path.suffix == ".jsonl":
            import json

            with path.open(encoding="utf-8") as fh:
                header = json.loads(fh.readline() or "{}")
            text = header.get("description") or f"log of {header.get('interface', '?')}"
        else:
            data = load_file(path).data
            text = data.get("description", "") if isinstance(data, dict) else ""
    except (DataError, ValueError, OSError):
        return "(unreadable)"
    return " ".join(str(text).split())


def file_hash(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()[:16]


@dataclass
class Setup:
    """Everything a session needs, validated together."""

    interface: InterfaceSpec
    character: CharacterSpec
    scene: SceneSpec
    interface_path: Path
    character_path: Path
    scene_path: Path
    warnings: tuple[str, ...] = ()  # valid, but probably not meant (puppet check's)


def load_character_named(name: str) -> tuple[CharacterSpec, Path]:
    path = find("character", name)
    return parse_character(load_file(path)), path


def load_scene_named(name: str) -> tuple[SceneSpec, Path]:
    path = find("scene", name)
    return parse_scene(load_file(path)), path


def parse_interface_text(text: str, path: str | Path, character: CharacterSpec | None = None,
                         character_path: str | Path | None = None,
                         scene: SceneSpec | None = None
                         ) -> tuple[InterfaceSpec, Located, CharacterSpec, Path | None]:
    """Parse and validate an interface's YAML ``text`` as the file ``path`` (error
    messages name it): the checks ``puppet check`` makes, including the references to
    its character. With ``character`` (a running session's, for a hot reload or a
    replayed reload event) the text must name that character, and no file is read;
    without, the character is found by name and loaded.

    With ``scene`` (the running session's), the props its reaches and grasps name
    must be in that scene.

    Returns (spec, located, character spec, character path or None)."""
    located = load_text(text, str(path))
    spec, character, character_path = check_interface(located, character, character_path)
    if scene is not None:
        from puppet.data.interface_refs import check_scene_refs

        check_scene_refs(spec, scene, located, scene.name)
    return spec, located, character, (Path(character_path) if character_path else None)


def check_interface(located: Located, character: CharacterSpec | None = None,
                    character_path: str | Path | None = None
                    ) -> tuple[InterfaceSpec, CharacterSpec, str | Path | None]:
    """Validate a parsed interface file and its references to its character (found by
    name and loaded, unless a running session's ``character`` is given: then the file
    must name that one). Returns (spec, character spec, character path)."""
    spec = parse_interface(located)
    if character is None:
        try:
            character_path = find("character", spec.character)
        except DataError as exc:
            raise located.error(("character",), exc.message) from None
        character = parse_character(load_file(character_path))
    else:
        running = Path(character_path).stem if character_path is not None else character.name
        if Path(spec.character).stem != running:
            raise located.error(("character",), f"character '{spec.character}' is not the "
                                                f"running session's '{running}'; a reload "
                                                "cannot change the character (restart instead)")
    check_against_character(spec, character, located)
    return spec, character, character_path


def setup_from_text(text: str, interface_path: str | Path, scene: str | None = None) -> Setup:
    """A Setup from an interface's text (the file need not hold that text any more:
    a log that embeds the interface replays it)."""
    spec, located, character, character_path = parse_interface_text(text, interface_path)
    try:
        scene_path = find("scene", scene or spec.scene)
    except DataError as exc:
        if scene is not None:
            raise
        raise located.error(("scene",), exc.message) from None
    scene_spec = parse_scene(load_file(scene_path))
    from puppet.data.interface_refs import check_scene_refs

    check_scene_refs(spec, scene_spec, located, scene_path.stem)
    from puppet.data.interface_refs import map_conflicts

    return Setup(spec, character, scene_spec, Path(interface_path), character_path, scene_path,
                 tuple(map_conflicts(spec, located)))


def load_setup(interface: str, scene: str | None = None) -> Setup:
    """Load an interface by name or path, its character and a scene (its default if None)."""
    interface_path = find("interface", interface)
    return setup_from_text(read_text(interface_path), interface_path, scene)
