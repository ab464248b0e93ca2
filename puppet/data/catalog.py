"""Find data files by name: characters, interfaces, scenes, scripts, logs and recordings.

Names resolve to ``<root>/<folder>/<name>.yaml``; the root is the checkout (or
``$PUPPET_HOME``). What a name may reach depends on who wrote it:

- a name or path the user typed on the command line: any existing file, else a
  catalog name;
- a name inside a file (an interface's ``character:`` / ``scene:``, a log header's
  ``interface`` / ``character`` / ``scene``): a catalog name, or a file of that kind's
  extension directly in one of the folders the user named on the command line (the
  folders of the files given there: ``puppet play DIR/x.yaml`` trusts ``DIR``,
  ``puppet replay DIR/x.jsonl`` trusts ``DIR``): beside that file, not in a folder
  under it, not hidden (``.name``), also after resolving symbolic links. An absolute
  path into the catalog's own folder is that catalog file. Anything else is refused
  by its spelling alone, without looking at the disk, so a file someone sends you
  cannot read yours, nor tell whether one exists (``Folders.found`` lists what such
  names did reach: a log's replay quotes nothing of those files, see
  ``puppet.timeline.replay.setup_for_log``).
"""

from __future__ import annotations

import os
import re
from dataclasses import dataclass
from pathlib import Path

from puppet.data.characters import CharacterSpec, parse_character
from puppet.data.errors import DataError, did_you_mean
from puppet.data.interface_refs import check_scene_refs, map_conflicts
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
    "mapping": ("assets/mappings", ".yaml"),  # mocap retargeting
    "clip": ("assets/mocap", ".bvh"),  # motion capture
    "library": ("assets/mocap", ".json"),  # a motion library (puppet mocap library)
}


def folder(kind: str) -> Path:
    return ROOT / FOLDERS[kind][0]


_PLAIN_NAME = re.compile(r"[A-Za-z0-9_][A-Za-z0-9_.-]{0,199}")
MAX_NAME = 4096


SHORT_PATH = 80  # characters of a path a one-line message shows


def short_path(path) -> str:
    """A path (or name) as a one-line message shows it: at most ``SHORT_PATH``
    characters, a longer one cut with '...' (a name too long for the file system)."""
    text = str(path)
    return text if len(text) <= SHORT_PATH else text[:SHORT_PATH - 3] + "..."


class Folders(tuple):
    """The folders names written in a file may reach besides the catalog (resolved),
    and ``found``: the files such names reached there (not catalog files), in order."""

    def __new__(cls, folders=()):
        self = super().__new__(cls, (Path(f).resolve() for f in folders))
        self.found = []
        return self


def _beside(name: str, ext: str, catalog: Path, within) -> Path | None:
    """The file a name written in a file reaches: directly in the catalog folder or in
    one of ``within`` (a bare file name is looked for in each of ``within``; an
    absolute path must be one of these folders' files), with ``ext``, not hidden, and
    still so once symbolic links are resolved. None: refused, decided from the name's
    spelling (and the links of the folder's own entry), never from whether a file
    exists elsewhere. A path that is allowed but names no file is returned as is."""
    folders = [catalog.resolve(), *(Path(f).resolve() for f in within)]
    written = Path(name)
    if written.is_absolute():
        if ".." in written.parts:
            return None
        spelled = {str(f): f for f in folders}
        spelled.update({str(Path(os.path.abspath(f))): Path(f).resolve()
                        for f in [catalog, *within]})
        base = spelled.get(str(written.parent))
        if base is None:
            return None
        bases = [base]
    elif len(written.parts) == 1:
        bases = folders[1:]
    else:  # a folder under the trusted one ('sub/x.yaml', '../x.yaml')
        return None
    leaf = written.name
    if leaf.startswith(".") or not leaf.endswith(ext) or leaf == ext:
        return None
    missing = None
    for base in bases:
        candidate = base / leaf
        try:
            resolved = candidate.resolve()
        except (OSError, RuntimeError):  # a symlink loop
            return None
        if (resolved.parent not in folders or resolved.name.startswith(".")
                or resolved.suffix != ext):
            return None  # a link beside the trusted file that leads elsewhere
        try:
            if resolved.is_file():
                return resolved
        except OSError:
            pass
        missing = missing or candidate
    return missing


def in_catalog(path) -> bool:
    """Whether ``path`` is a file directly in one of the catalog's folders."""
    try:
        parent = Path(path).resolve().parent
    except (OSError, RuntimeError):
        return False
    return any(parent == (ROOT / sub).resolve() for sub, _ in FOLDERS.values())


def find(kind: str, name: str, within=None) -> Path:
    """Path of the ``kind`` file called ``name``.

    ``within=None``: ``name`` was typed by the user: an existing file path is taken as
    is, else it is a catalog name. ``within`` (folders): ``name`` was written in a file:
    a catalog name, or a file with the kind's extension directly in the catalog folder
    or in one of ``within`` (``_beside``; a ``Folders`` records what it reached).
    Anything else is a DataError, and is not read."""
    sub, ext = FOLDERS[kind]
    shown = short_path(name)
    if not isinstance(name, str) or not name or len(name) > MAX_NAME or "\x00" in name:
        raise DataError(shown, None, None, f"not a {kind} name")
    if within is None:
        as_path = Path(name)
        try:
            if as_path.suffix and as_path.is_file():
                return as_path
            if as_path.is_dir():
                raise DataError(shown, None, None, f"is a folder; expected {_a(kind)} name "
                                                   f"or a {ext} file")
        except OSError:  # e.g. a name too long for the file system
            pass
        if len(as_path.parts) > 1 or as_path.suffix == ext:  # a path, not a name: say so
            raise DataError(shown, None, None, f"no such file (expected {_a(kind)} name, "
                                               f"e.g. '{_first(kind)}', or a {ext} file)")
    catalog = ROOT / sub
    plain = _PLAIN_NAME.fullmatch(name) is not None
    if plain:
        candidate = catalog / (name if name.endswith(ext) else name + ext)
        if candidate.is_file():
            return candidate
    if within is not None:
        reached = _beside(name + ext if plain and not name.endswith(ext) else name, ext,
                          catalog, within)
        if reached is None:
            places = ", ".join(str(f) for f in within) or "none"
            raise DataError(shown, None, None,
                            f"'{shown}' is neither a {kind} of the catalog ({sub}/NAME{ext}) "
                            f"nor a {ext} file beside the file that names it, in a folder "
                            f"named on the command line ({places}; not in a folder under "
                            f"it, not hidden); it was not read")
        try:
            exists = reached.is_file()
        except OSError:  # a name too long for the file system
            exists = False
        if exists:
            if reached.parent != catalog.resolve() and hasattr(within, "found"):
                within.found.append(reached)
            return reached
    names = [n for n, _ in list_kind(kind)]
    hint = did_you_mean(name, names)  # "; did you mean 'luxo-mouse'?"
    raise DataError(shown, None, None, f"no {kind} named '{shown}'{hint}"
                                       f"{' Known' if hint else '; known'}: "
                                       f"{', '.join(names) or 'none'}")


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
        elif path.suffix == ".json":  # a motion library
            import json

            data = json.loads(path.read_text(encoding="utf-8"))
            text = data.get("description", "") if isinstance(data, dict) else ""
        else:
            data = load_file(path).data
            text = data.get("description", "") if isinstance(data, dict) else ""
    except (DataError, ValueError, OSError):
        return "(unreadable)"
    return " ".join(str(text).split())


def file_hash(path: Path) -> str:
    import hashlib  # here: OpenSSL's start-up is ~5 ms that a check does not need

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
                         scene: SceneSpec | None = None, within=None
                         ) -> tuple[InterfaceSpec, Located, CharacterSpec, Path | None]:
    """Parse and validate an interface's YAML ``text`` as the file ``path`` (error
    messages name it): the checks ``puppet check`` makes, including the references to
    its character. With ``character`` (a running session's, for a hot reload or a
    replayed reload event) the text must name that character, and no file is read;
    without, the character is found by name and loaded (``within``: see
    ``check_interface``).

    With ``scene`` (the running session's), the props its reaches and grasps name
    must be in that scene.

    Returns (spec, located, character spec, character path or None)."""
    located = load_text(text, str(path))
    spec, character, character_path = check_interface(located, character, character_path,
                                                      within)
    if scene is not None:
        check_scene_refs(spec, scene, located, scene.name)
    return spec, located, character, (Path(character_path) if character_path else None)


def reference_folders(interface_path: str | Path, within=None) -> tuple:
    """The folders an interface's ``character:`` and ``scene:`` may name files in:
    ``within`` if given (the folders named on the command line), else the interface
    file's own folder (the user named that file)."""
    if within is None:
        return (Path(interface_path).parent,)
    return within if isinstance(within, Folders) else tuple(within)  # (what it found)


def check_interface(located: Located, character: CharacterSpec | None = None,
                    character_path: str | Path | None = None, within=None
                    ) -> tuple[InterfaceSpec, CharacterSpec, str | Path | None]:
    """Validate a parsed interface file and its references to its character (found by
    name and loaded, unless a running session's ``character`` is given: then the file
    must name that one). The character is a catalog name or a file inside
    ``reference_folders(located.path, within)``. Returns (spec, character spec,
    character path)."""
    spec = parse_interface(located)
    if character is None:
        try:
            character_path = find("character", spec.character,
                                  reference_folders(located.path, within))
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


def setup_from_text(text: str, interface_path: str | Path, scene: str | None = None,
                    within=None) -> Setup:
    """A Setup from an interface's text (the file need not hold that text any more:
    a log that embeds the interface replays it). ``within=None``: the interface file
    and ``scene`` were named by the user; else (folders) ``scene`` and the interface's
    own names must be catalog names or files inside those folders."""
    spec, located, character, character_path = parse_interface_text(
        text, interface_path, within=within)
    folders = reference_folders(interface_path, within)
    try:
        scene_path = find("scene", scene, within) if scene else find("scene", spec.scene,
                                                                     folders)
    except DataError as exc:
        if scene is not None:
            raise
        raise located.error(("scene",), exc.message) from None
    scene_spec = parse_scene(load_file(scene_path))
    check_scene_refs(spec, scene_spec, located, scene_path.stem)
    return Setup(spec, character, scene_spec, Path(interface_path), character_path, scene_path,
                 tuple(map_conflicts(spec, located)))


def load_setup(interface: str, scene: str | None = None, within=None) -> Setup:
    """Load an interface by name or path, its character and a scene (its default if None).
    ``within=None``: ``interface`` and ``scene`` are what the user typed (any path);
    else (folders) they were written in a file: see ``find``."""
    interface_path = find("interface", interface, within)
    return setup_from_text(read_text(interface_path), interface_path, scene, within)
