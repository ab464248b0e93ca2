"""The fuzz harness: mutants of every shipped file kind and of logs, fed to the very
functions the CLI uses, each outcome classified.

A case must end in acceptance or a clean one-line DataError, within ``CASE_SECONDS``
of CPU time (not wall time: the suite holds on a busy machine) and ``CASE_MB``; an
accepted data file is also played for ``PLAY_SECONDS`` of simulated
time (scripted mouse moves and presses of every key it binds), which must not raise.
tests/test_fuzz.py drives it with hypothesis (seeded).
"""

from __future__ import annotations

import json
import os
import re
import resource
import signal
from collections import Counter
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import yaml

from puppet.commands.check import check_file
from puppet.data.catalog import ROOT, Setup, check_interface, find, load_setup
from puppet.data.characters import parse_character
from puppet.data.errors import DataError
from puppet.data.scenes import parse_scene
from puppet.data.yamlfile import load_file, load_text
from puppet.interface import events as ev
from puppet.session import Session
from puppet.session.playback import play
from puppet.timeline.log import read_log
from puppet.timeline.replay import replay
from puppet.timeline.script import check_links, compile_script, parse_script

# CPU seconds (this process's, user + system) one case may use: the work it does, which a
# busy machine does not stretch as it stretches the wall clock (issue 32: at a load of 8
# on 2 cores, cases that use well under a second of CPU took over 2 s of wall time).
# tools/mutation.sh gives more, for mutmut's trampolines.
CASE_SECONDS = float(os.environ.get("PUPPET_FUZZ_CASE_SECONDS", "2.0"))
# ... and a case that waits without using CPU (blocked on a read) is caught by the wall
# clock, at this many times the CPU bound (at least a minute): far above any load
WALL_FACTOR = 30.0
CASE_MB = 200  # resident memory one case may add
PLAY_SECONDS = 2.0  # simulated time an accepted mutant is played

KINDS = {  # kind -> (catalog folder, the shipped files)
    "character": sorted((ROOT / "characters").glob("*.yaml")),
    "interface": sorted((ROOT / "interfaces").glob("*.yaml")),
    "scene": sorted((ROOT / "assets" / "scenes").glob("*.yaml")),
    "script": sorted((ROOT / "assets" / "scripts").glob("*.yaml")),
    "expect": sorted((ROOT / "assets" / "logs").glob("*.expect.yaml")),
    "mapping": sorted((ROOT / "assets" / "mappings").glob("*.yaml")),
    "bones": sorted((ROOT / "assets" / "mocap").glob("*-bones.yaml")),  # bone tables
}
FOLDER = {"character": "characters", "interface": "interfaces", "scene": "scenes",
          "script": "scripts", "expect": "logs", "mapping": "mappings", "bones": "bones"}
LOGS = [ROOT / "assets" / "logs" / n for n in ("luxo-hop.jsonl", "luxo-keys-hops.jsonl",
                                               "cat-bound.jsonl")]
LOG_LINES = 40  # a log mutant keeps the header, this many events and the end line

NASTY_NUMBERS = [".nan", ".NaN", ".inf", "-.inf", "1.0e+308", "-1.0e+308", "1.0e+400",
                 "1.0e-320", "0", "-0.0", "-1", "1.0e+9", "-1.0e+9", "9" * 30, "0x7fffffff",
                 "1_000", "0o17", "1:30", "'3'", "true", "null", "~", "[]", "{}",
                 "!!float abc", "!!int 1x", "&a 1", "*a", "!!binary aGk=", "!!python/none ''",
                 "2001-12-14", "1e3", ".5", "+.inf", "1" + "0" * 400, "'-1'", "'1e400'"]
NASTY_WORDS = ["../../etc/passwd", "/etc/hosts", "../characters/luxo", "/dev/zero",
               "x" * 300, "luxo", "flat", "cat", "base", "ankle", "''", "\"\\0\"",
               "\"\\x07\"", "a b", "{a: *b}", "[&x a, *x, *x]", "!!str", "- ", ": ",
               "mouse.x", "contact.base", "ctrl+shift+q", "f1", "escape", "app:quit"]
NASTY_JSON = ["NaN", "Infinity", "-Infinity", "1e400", "1e308", "-1e308", "1e30",
              "1000000000000", "-1", "0", "0.5", "true", "false", "null", '""', '"x"',
              "[]", "{}", '{"type": {}}', "[" * 200 + "]" * 200, '"' + "k" * 5000 + '"',
              '"../../etc/passwd"', '"/etc/hosts"', '"rewind"', '"reset"', "1.5",
              "123456789012345678901234567890", "[" * 100000 + "]" * 100000,
              "9" * 5000]

NUMBER = re.compile(r"(?<![\w.])-?\d+(\.\d+)?(e[+-]?\d+)?(?![\w.])")
SCALAR = re.compile(r"(?<=: )[^\s\[\]{},#][^\n\[\]{},#]*")


@dataclass
class Result:
    outcome: str  # "accepted", "refused", or a failure: "uncaught", "hang", "memory",
    # "accepted-then-crash", "multi-line", "library words" (the validation library's own
    # wording in the message, not puppet's)
    detail: str = ""


# msgspec's (and pydantic's) phrases, which a message in puppet's words never holds
LIBRARY_WORDS = re.compile(r"Expected `|Object (contains|missing)|Invalid (enum )?value|"
                           r" - at `\$|msgspec|pydantic|Input should|validation error")
STATS: Counter = Counter()  # (kind, outcome) -> cases, printed by conftest at the end


class Hang(Exception):
    pass


@contextmanager
def time_limit(seconds: float, wall: float | None = None):
    """Raise ``Hang`` in the block once it has used ``seconds`` of CPU time (a profiling
    timer: user + system time of this process), or ``wall`` seconds of wall time
    (default ``WALL_FACTOR`` times ``seconds``, at least 60: a case blocked, using no CPU)."""
    wall = max(60.0, WALL_FACTOR * seconds) if wall is None else wall

    def on_cpu(signum, frame):
        raise Hang(f"more than {seconds} s of CPU time")

    def on_wall(signum, frame):
        raise Hang(f"more than {wall} s of wall time (blocked?)")

    old_prof = signal.signal(signal.SIGPROF, on_cpu)
    old_alrm = signal.signal(signal.SIGALRM, on_wall)
    signal.setitimer(signal.ITIMER_PROF, seconds)
    signal.setitimer(signal.ITIMER_REAL, wall)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_PROF, 0)
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGPROF, old_prof)
        signal.signal(signal.SIGALRM, old_alrm)


def _rss_mb() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024  # peak, kB on Linux


# -- mutations of text -----------------------------------------------------------------
def mutate_text(text: str, ops: list[tuple[int, int, int]]) -> str:
    """Apply ``ops`` (operation, where, what: three integers drawn by hypothesis)."""
    for op, where, what in ops:
        lines = text.split("\n")
        kind = op % 9
        if kind == 0:  # a number becomes a nasty one
            spots = list(NUMBER.finditer(text))
            if spots:
                m = spots[where % len(spots)]
                text = text[:m.start()] + NASTY_NUMBERS[what % len(NASTY_NUMBERS)] + text[m.end():]
        elif kind == 1:  # a scalar value becomes a nasty word or number
            spots = list(SCALAR.finditer(text))
            if spots:
                m = spots[where % len(spots)]
                pool = NASTY_WORDS + NASTY_NUMBERS
                text = text[:m.start()] + pool[what % len(pool)] + text[m.end():]
        elif kind == 2:  # delete a line
            if lines:
                del lines[where % len(lines)]
                text = "\n".join(lines)
        elif kind == 3:  # duplicate a line
            if lines:
                i = where % len(lines)
                lines.insert(i, lines[i])
                text = "\n".join(lines)
        elif kind == 4:  # delete a span of characters
            if text:
                i = where % len(text)
                text = text[:i] + text[i + 1 + what % 12:]
        elif kind == 5:  # insert a character
            i = where % (len(text) + 1)
            chars = "[]{},:-#&*!|>'\"\t\x00\x07 \n\\%@`?0.e9"
            text = text[:i] + chars[what % len(chars)] + text[i:]
        elif kind == 6:  # re-indent a line
            if lines:
                i = where % len(lines)
                lines[i] = " " * (what % 7) + lines[i].lstrip()
                text = "\n".join(lines)
        elif kind == 7:  # nesting or an alias bomb in front of a value
            spots = list(SCALAR.finditer(text))
            if spots:
                m = spots[where % len(spots)]
                deep = ("[" * (what % 3000) + "]" * (what % 3000) if what % 2
                        else "&a [x, x, x, x, x, x, x, x, x]")
                text = text[:m.start()] + deep + text[m.end():]
        else:  # swap two lines
            if len(lines) > 1:
                i, j = where % len(lines), what % len(lines)
                lines[i], lines[j] = lines[j], lines[i]
                text = "\n".join(lines)
    return text


def mutate_data(data, path: list[int], value):
    """Replace the value found by following ``path`` (indices into each level's keys or
    items, wrapping) with ``value``; returns the mutated copy."""
    data = json.loads(json.dumps(data))
    parent, key, node = None, None, data
    for step in path:
        if isinstance(node, dict) and node:
            parent, key = node, list(node)[step % len(node)]
        elif isinstance(node, list) and node:
            parent, key = node, step % len(node)
        else:
            break
        node = parent[key]
    if parent is None:
        return value
    parent[key] = value
    return data


# -- running one case ------------------------------------------------------------------
def _keys_of(spec) -> list[str]:
    keys = [k.key for k in spec.keys] + [g.key for g in spec.gestures]
    for state in spec.states.values():
        keys += [k.key for k in state.keys]
    return keys


def _input_events(spec, dt: float) -> list[tuple[int, dict]]:
    """Mouse sweeps and a press of every bound key, over PLAY_SECONDS."""
    events, n = [], round(PLAY_SECONDS / dt)
    for i in range(0, n, 24):
        u = i / n
        events.append((i, ev.mouse(abs(1 - 2 * u), u)))
    for j, key in enumerate(_keys_of(spec) if spec is not None else []):
        at = (j * 37) % n
        events += [(at, ev.key(key, True)), (min(n - 1, at + 60), ev.key(key, False))]
    events.sort(key=lambda e: e[0])
    return events


def play_setup(setup: Setup, events=None) -> None:
    session = Session(setup)
    dt = session.sim.dt
    if events is None:
        events = _input_events(setup.interface, dt)
    play(session, events, round(PLAY_SECONDS / dt))
    session.sim.state_hash()


def _accepted(kind: str, path: Path) -> None:
    """Play an accepted data file for PLAY_SECONDS."""
    if kind == "interface":
        play_setup(load_setup(str(path)))
    elif kind == "character":
        base = load_setup("cat-trot" if "cat" in path.read_text() else "luxo-mouse")
        character = parse_character(load_file(path))
        located = load_file(find("interface", "luxo-mouse"))
        spec = base.interface
        try:  # the interface's references must still fit; else no play
            spec, character, _ = check_interface(located, character, path)
        except DataError:
            spec = spec.model_copy(update={"maps": [], "keys": [], "gains": {},
                                           "poses": {}, "sequences": {}, "states": {},
                                           "modes": {}, "chains": {}, "gestures": []})
        play_setup(Setup(spec, character, base.scene, base.interface_path, path,
                         base.scene_path))
    elif kind == "scene":
        base = load_setup("luxo-mouse")
        scene = parse_scene(load_file(path))
        play_setup(Setup(base.interface, base.character, scene, base.interface_path,
                         base.character_path, path))
    elif kind == "mapping":  # retarget the walk clip through it
        from puppet.data.mappings import load_mapping
        from puppet.mocap.bvh import read_bvh
        from puppet.mocap.retarget import retarget_clip

        mapping = load_mapping(path)
        try:
            clip = retarget_clip(read_bvh(ROOT / "assets" / "mocap" / "cmu-131_01-walk.bvh"),
                                 mapping)
        except DataError as exc:  # valid, but not for this clip: said in one line
            assert "\n" not in str(exc), str(exc)
            return
        for values in clip.channels.values():
            assert not np.isinf(values).any()
    elif kind == "bones":  # stream the walk clip through it, as mocap send does
        from puppet.mocap.bvh import read_bvh
        from puppet.mocap.send import encoder, load_bones

        clip = read_bvh(ROOT / "assets" / "mocap" / "cmu-131_01-walk.bvh")
        table = load_bones(path)
        for fmt in ("vmc", "mediapipe"):
            try:
                encode = encoder(clip, fmt, table)
            except DataError as exc:  # valid, but not for this clip: said in one line
                assert "\n" not in str(exc), str(exc)
                continue
            for k in range(0, clip.frames, 97):
                assert isinstance(encode(k, k * clip.frame_time), bytes)
    elif kind == "script":
        spec = parse_script(load_file(path))
        setup = load_setup("luxo-keys")
        try:
            check_links(path, spec, [link.name for link in setup.character.links])
        except DataError as exc:  # valid, but for another character: said in one line
            assert "\n" not in str(exc), str(exc)
            return
        dt = 1 / 480
        play_setup(setup, [e for e in compile_script(spec, dt)
                           if e[0] < round(PLAY_SECONDS / dt)])


def run_case(kind: str, fn, play_fn=None) -> Result:
    """Run ``fn`` (raises DataError or returns); if it accepts, ``play_fn``."""
    before = _rss_mb()
    try:
        with time_limit(CASE_SECONDS):
            try:
                fn()
            except DataError as exc:
                text = str(exc)
                result = (Result("multi-line", text) if len(text.splitlines()) != 1
                          else Result("library words", text) if LIBRARY_WORDS.search(text)
                          else Result("refused", text))
            else:
                result = Result("accepted")
                if play_fn is not None:
                    try:
                        play_fn()
                    except Hang:
                        raise
                    except Exception as exc:  # noqa: BLE001 - that is the finding
                        result = Result("accepted-then-crash", f"{type(exc).__name__}: {exc}")
    except Hang as exc:
        result = Result("hang", str(exc))
    except Exception as exc:  # noqa: BLE001
        result = Result("uncaught", f"{type(exc).__name__}: {exc}"[:500])
    if _rss_mb() - before > CASE_MB:
        result = Result("memory", f"peak memory grew by {_rss_mb() - before:.0f} MB")
    if not kind.startswith("self-test"):
        STATS[(kind, result.outcome)] += 1
    return result


def data_case(kind: str, text: str, tmp: Path, src: Path) -> Result:
    """``text``: a mutant of the shipped file ``src``, written under ``tmp``."""
    folder = tmp / FOLDER[kind]
    folder.mkdir(parents=True, exist_ok=True)
    if kind == "expect":  # what `puppet replay --check` does with a sidecar
        log = folder / src.name.replace(".expect.yaml", ".jsonl")
        if not log.exists():
            lines = src.with_name(log.name).read_text(encoding="utf-8").splitlines()
            log.write_text("\n".join(lines[:1 + LOG_LINES]) + "\n", encoding="utf-8")
        path = folder / src.name
        path.write_text(text, encoding="utf-8", errors="surrogatepass")
        return run_case(kind, lambda: replay(log, until_step=round(PLAY_SECONDS * 480)))
    path = folder / f"m-{kind}.yaml"
    path.write_text(text, encoding="utf-8", errors="surrogatepass")
    return run_case(kind, lambda: check_file(path), lambda: _accepted(kind, path))


def log_lines(which: int) -> list[str]:
    lines = LOGS[which % len(LOGS)].read_text(encoding="utf-8").splitlines()
    return lines[:1 + LOG_LINES] + [lines[-1]]


def log_case(lines: list[str], tmp: Path) -> Result:
    tmp.mkdir(parents=True, exist_ok=True)
    path = tmp / "m.jsonl"
    path.write_text("\n".join(lines) + "\n", encoding="utf-8", errors="surrogatepass")

    def accepted():
        replay(path, until_step=round(PLAY_SECONDS * 480))

    return run_case("log", lambda: read_log(path), accepted)


def yaml_text_of(data) -> str:
    return yaml.safe_dump(data, sort_keys=False, allow_unicode=True)


def located_data(path: Path):
    return load_text(path.read_text(encoding="utf-8"), str(path)).data
