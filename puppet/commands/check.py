"""``puppet check``: validate any data file, telling its kind from its folder or keys;
a log (``.jsonl``) as ``puppet replay`` reads it, a BVH clip as ``puppet mocap info``
does; a name as the other commands take one (``find_target``)."""

from __future__ import annotations

import argparse
import importlib
import sys
from pathlib import Path
from types import SimpleNamespace

from puppet.commands.options import EXIT_DATA_ERROR
from puppet.data.errors import DataError
from puppet.data.yamlfile import Located, load_file

# Each kind's models are imported when a file of that kind is checked: a character's
# check does not build the interface, scene and script models (process start).

KIND_BY_FOLDER = {"characters": "character", "interfaces": "interface", "scenes": "scene",
                  "scripts": "script", "mappings": "mapping", "tune": "tuning spec"}


YAML_EXTS = (".yaml", ".yml")
# kind -> (module, its parse function) for the kinds checked by parsing alone
_PARSERS = {"character": ("puppet.data.characters", "parse_character"),
            "scene": ("puppet.data.scenes", "parse_scene"),
            "script": ("puppet.timeline.script", "parse_script"),
            "mapping": ("puppet.data.mappings", "parse_mapping"),
            "humanoid rig": ("puppet.mocap.rigs", "parse_humanoid"),
            "vmc avatar": ("puppet.mocap.vmc", "parse_avatar")}
WHAT_CHECK_READS = ("puppet check reads .yaml data files (characters, interfaces, scenes, "
                    "scripts, mocap mappings, bone tables, logs' NAME.expect.yaml, tuning "
                    "specs), .jsonl logs, .bvh clips and .json motion libraries, or their names")


def find_target(name: str) -> Path:
    """``puppet check``'s argument as a file: a path as given, else a name looked up as
    the other commands look theirs up (catalog.find), in every kind's folder since the
    command does not say the kind: characters/, interfaces/, assets/scenes/,
    assets/scripts/, assets/logs/ (else recordings/, as replay looks), assets/mappings/,
    assets/mocap/. A name in two folders (a script and the log recorded from it) is
    refused, naming both. A name's file is returned as ``_shown`` names it, which its
    errors then carry."""
    p = Path(name)
    try:
        if p.is_dir():
            raise DataError(name, None, None, f"is a folder; {WHAT_CHECK_READS}")
        if p.is_file():
            return p
    except OSError:  # a name too long for the file system
        pass
    if len(p.parts) > 1 or p.suffix.lower() in YAML_EXTS + (".jsonl", ".bvh", ".json"):
        raise DataError(name, None, None, "no such file")
    from puppet.data import catalog

    found = []
    for kind in catalog.FOLDERS:
        if kind == "recording" and found and found[-1][0] == "log":
            continue  # replay's order (find_log): assets/logs/, else recordings/
        try:
            found.append((kind, catalog.find(kind, name)))
        except DataError:
            continue
    if len(found) == 1:
        return _shown(found[0][1])
    if found:
        named = [f"{catalog._a(kind)} ({_shown(path)})" for kind, path in found]
        which = ", ".join(named[:-1]) + " and " + named[-1]
        raise DataError(name, None, None, f"ambiguous name: {which}; give the path")
    folders = ", ".join(f"{sub}/" for sub, _ in catalog.FOLDERS.values())
    raise DataError(name, None, None, f"no such file, and no name of the catalog ({folders})")


def _shown(path: Path) -> Path:
    """A file found by name as check names it in every line about it (ok, its errors,
    its warnings, an ambiguous name's choices): relative to the current folder when it
    is inside it (interfaces/luxo-mouse.yaml, run in the checkout), else absolute; a
    path that opens the file from where the command runs either way."""
    try:
        return Path(path).relative_to(Path.cwd())
    except (ValueError, OSError):
        return Path(path)


def _read_log(path: Path):
    """read_log's Log; its refusal of a log cut mid-line names the command that reads
    the rest (``puppet replay --allow-truncated``: check has no such option)."""
    from puppet.timeline.log import TRUNCATED_HINT, read_log
    from puppet.timeline.replay import CHECK_TRUNCATED_HINT

    try:
        return read_log(path)
    except DataError as exc:
        if not exc.message.endswith(TRUNCATED_HINT):
            raise
        raise DataError(exc.path, exc.line, exc.col, exc.message[:-len(TRUNCATED_HINT)]
                        + CHECK_TRUNCATED_HINT) from None


def _has_expectations(log) -> bool:
    """Whether the log has expectations (its ``.expect.yaml`` or the header's): it is
    meant for ``puppet replay --check``. Invalid ones count: they are there to check."""
    from puppet.timeline.expectations import load_expectations

    try:
        return bool(load_expectations(log.path, log.header).items)
    except DataError:
        return True


def check_log(path: Path, warnings: list[str] | None = None) -> str:
    """A log as ``puppet replay`` reads it, without simulating: the header and every
    line, the files the header names, the expectations (its ``.expect.yaml`` or the
    header's) and the links they name, and the interface text of each reload event
    (which the replay would apply); the first problem is the replay's DataError. What a
    replay would warn about (the interface changed, no end line) goes to ``warnings``.

    A log with expectations is a test, run by ``puppet replay --check``: without its end
    line it is refused as that command refuses it (``require_end``: exit 2, not 'ok',
    which a check run before the replay in CI would pass). A log without expectations
    (a take the window recorded, then killed) plays in a plain replay: ok, with the
    warning that ``replay --check`` refuses it."""
    from puppet.data.catalog import parse_interface_text
    from puppet.timeline.expectations import load_expectations
    from puppet.timeline.replay import cut_warnings, require_end, setup_for_log

    log = _read_log(path)
    if log.end is None and _has_expectations(log):  # replay --check's first refusal
        require_end(log, False, for_check=True)
    setup, said = setup_for_log(log, for_check=True)
    said += cut_warnings(log, for_check=True)
    expectations = load_expectations(log.path, log.header)
    expectations.check_links([link.name for link in setup.character.links])
    expectations.check_scene(list(setup.scene.props), [g.name for g in setup.scene.ground])
    # what the replay's trajectory would know: every interface version's state and mode
    names = SimpleNamespace(state_names=dict.fromkeys(setup.interface.states),
                            mode_names=dict.fromkeys(setup.interface.modes))
    seen = set()
    for e in log.events:
        if e.event.get("type") != "reload" or e.event["text"] in seen:
            continue
        seen.add(e.event["text"])
        try:
            spec = parse_interface_text(e.event["text"], e.event.get("path")
                                        or str(setup.interface_path), setup.character,
                                        setup.character_path, setup.scene)[0]
        except DataError as exc:  # apply_log's words, at the event's line
            raise DataError(log.path, e.line, None, f"cannot apply this event: {exc}") from None
        names.state_names.update(dict.fromkeys(spec.states))
        names.mode_names.update(dict.fromkeys(spec.modes))
    # the states and modes named as the replay checks them (rc 2 there), and a window
    # that begins after the log's end (no sample in it: a sure failure)
    expectations.check_names(SimpleNamespace(state_names=list(names.state_names),
                                             mode_names=list(names.mode_names)))
    expectations.check_windows(log.last_step * float(log.header["dt"]))
    if warnings is not None:
        warnings += said + expectations.notes
    return "log"


def guess_kind(path: Path, located: Located) -> str:
    if path.name.endswith(".expect.yaml"):  # a log's sidecar (puppet replay --check)
        return "expectations"
    kind = KIND_BY_FOLDER.get(path.parent.name)
    if kind:
        return kind
    data = located.data if isinstance(located.data, dict) else {}
    if "stages" in data:  # (before script: a tuning spec may have fixed events)
        return "tuning spec"
    if "links" in data:
        return "character"
    if "ground" in data:
        return "scene"
    if "events" in data or "rules" in data:
        return "script"
    if "segments" in data:  # (before character: a mapping may name its character)
        return "mapping"
    if "sides" in data and "roles" in data:  # (before character: it names the figure's)
        return "humanoid rig"
    if "character" in data:
        return "interface"
    if "vmc" in data or "mediapipe" in data:
        return "bone table"
    if "bones" in data:
        return "vmc avatar"
    if "expect" in data:
        return "expectations"
    raise located.error((), "cannot tell what kind of file this is; expected a character "
                            "(links:), scene (ground:), interface (character:), script "
                            "(events: or rules:), mocap mapping (segments:), bone table (vmc:, "
                            "mediapipe:) or a log's expectations (expect:)")


def _check_script_names(path: Path, spec, located: Located) -> None:
    """A script naming its ``interface:``: the links its drags and pushes name, and its
    rules' sensors, states and modes, against that interface and its character (what
    ``puppet play --input`` refuses before playing), at their lines."""
    from puppet.data import catalog
    from puppet.timeline.script import check_links

    try:  # (one it cannot find is not checked: play names the interface to play on)
        where = catalog.find("interface", spec.interface, catalog.reference_folders(path))
    except DataError:
        return
    setup = catalog.load_setup(str(where))
    check_links(path, spec, [link.name for link in setup.character.links],
                setup.interface, setup.character, located)


def check_file(path: str | Path, warnings: list[str] | None = None,
               report: list[str] | None = None) -> str:
    """Validate one file; return its kind. Raises DataError on the first problem;
    ``warnings`` collects what is valid but probably not meant (two maps on a joint).
    ``report``: for a character, collects the stability check's lines (its problems go
    to ``warnings``): the start pose held on a flat floor, ``puppet.physics.stability``."""
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix == ".jsonl":
        return check_log(path, warnings)
    if suffix == ".bvh":  # as puppet mocap info reads it
        from puppet.mocap.bvh import read_bvh

        read_bvh(path)
        return "mocap clip"
    if suffix == ".json":  # a motion library, as tracking.reaction.library reads it
        from puppet.data.motion_library import load_library

        load_library(path)
        return "motion library"
    if suffix not in YAML_EXTS:
        got = f"'{path.suffix}' files" if path.suffix else "a file with no extension"
        raise DataError(str(path), None, None, f"cannot check {got}; {WHAT_CHECK_READS}")
    located = load_file(path)
    kind = guess_kind(path, located)
    if kind in _PARSERS:  # (imported when asked: check reads only its file's kind)
        module, parse = _PARSERS[kind]
        spec = getattr(importlib.import_module(module), parse)(located)
        if kind == "script" and spec.interface:  # its rules' names, as play checks them
            _check_script_names(path, spec, located)
        if kind == "character" and report is not None:
            from puppet.physics.stability_report import character_report

            lines, problems = character_report(spec)
            report += lines
            if warnings is not None:
                warnings += [f"{path}: warning: {w}" for w in problems]
        return kind
    if kind == "expectations":  # their states and modes: checking the log checks them
        from puppet.timeline.expectations import validate_expect_file

        if not validate_expect_file(located).expect and warnings is not None:
            warnings.append(f"{path}: warning: 'expect' is an empty list: no expectation "
                            "is checked")
        return kind
    if kind == "tuning spec":  # puppet tune's (docs/tuning.md)
        from puppet.timeline.tuning import load_tune_spec

        load_tune_spec(path)
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
        from puppet.physics.holds import hold_warnings

        warnings += map_conflicts(spec, located)
        warnings += hold_warnings(spec, character, located)
    try:
        scene_path = catalog.find("scene", spec.scene, catalog.reference_folders(path))
    except DataError as exc:
        raise located.error(("scene",), exc.message) from None
    # props named by reaches and grasps must be in the scene, as play checks
    from puppet.data.interface_refs import check_scene_refs

    check_scene_refs(spec, parse_scene(load_file(scene_path)), located, scene_path.stem)
    if spec.tracking is not None and spec.tracking.mapping is not None:
        from puppet.data.mappings import channel_error, interface_reads, load_mapping
        from puppet.data.tracking import interface_mapping_problem

        try:
            mapping_path = catalog.find("mapping", spec.tracking.mapping,
                                        catalog.reference_folders(path))
            mapping = load_mapping(mapping_path)
        except DataError as exc:
            raise located.error(("tracking", "mapping"), exc.message) from None
        error = channel_error(mapping_path, mapping, [j.name for j in character.joints],
                              spec.character, interface_reads(spec))
        if error is not None:  # a channel no joint of this character (as play says)
            raise located.error(("tracking", "mapping"), str(error))
        problem = interface_mapping_problem(spec, character, mapping)
        if problem:
            raise located.error(("tracking", "mapping"), problem)
    return kind


def register(subparsers) -> None:
    """``puppet check FILE...``."""
    check = subparsers.add_parser("check", help="validate data files, logs and clips (exit 0 "
                                                "valid, 2 invalid)",
                                  description="Validate files as the app loads them: YAML data "
                                              "files (.yaml: characters, interfaces, scenes, "
                                              "scripts, mocap mappings, bone tables and logs' "
                                              "expectations, NAME.expect.yaml), each told by its "
                                              "folder, name or keys; input logs (.jsonl) as "
                                              "replay reads them (header, every line, the files "
                                              "it names, its expectations; one with expectations "
                                              "needs its end line, as replay --check does), "
                                              "without simulating; "
                                              "BVH clips (.bvh) as mocap info reads them. A name "
                                              "is looked up in every catalog folder (a name in "
                                              "two, such as a script and its log, is refused: "
                                              "give the path). A valid file prints 'FILE: ok "
                                              "(KIND)'; an invalid one a line 'puppet check: "
                                              "FILE:LINE:COL: what is wrong, what was expected'. "
                                              "Exit 0 if all are valid, else 2.")
    check.add_argument("files", nargs="+", metavar="FILE",
                       help="YAML data file(s), logs (.jsonl) or BVH clips (.bvh) to "
                            "validate: paths (characters/luxo.yaml) or names (luxo-mouse, "
                            "cmu-131_01-walk)")
    check.add_argument("-q", "--quiet", action="store_true", help="print errors only")
    check.add_argument("--no-stability", action="store_true",
                       help="characters: skip the stability check (the start pose held "
                            "5 s on a flat floor, and nudged: does it stand, which joints "
                            "oscillate, sag or are locked by their damping)")
    check.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    failed = 0
    for name in args.files:
        try:
            warnings: list[str] = []
            # a path as given, or a name: then the file's path, the same in the ok line
            path = find_target(name)  # as in its errors and warnings (_shown)
            report: list[str] | None = None if args.no_stability else []
            kind = check_file(path, warnings, report)
            for w in warnings:
                print(w, file=sys.stderr)
            if not args.quiet:  # a name says which file it was
                print(f"{name if path == Path(name) else path}: ok ({kind})")
                for line in report or ():  # a character's stability check
                    print(f"  {line}")
        except DataError as exc:
            print(f"puppet check: {exc}", file=sys.stderr)
            failed += 1
    return EXIT_DATA_ERROR if failed else 0
