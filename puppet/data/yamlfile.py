"""Safe YAML loading that remembers where every key and value came from.

Validation errors must name file:line:col, so we read the YAML *event* stream of the
safe parser (no tags that run code) and build plain Python data plus a map from each
data path (tuple of keys/indices) to its source position. PyYAML's C parser
(libyaml, ``yaml.CSafeLoader``) is used when it is installed: it reads the same files
about ten times faster and keeps the same marks; the pure-Python parser is the
fallback, and the one whose message a syntax error reports (so both give the very same
one-line error).

Hardening, for files written by anyone: a file is at most ``MAX_BYTES``, nested at
most ``MAX_DEPTH`` levels, holds no anchors or aliases (a few hundred bytes of aliases
expand to gigabytes) and no control characters; every failure is one DataError with
its line and column. The data is built with an explicit stack, never by recursion.
"""

from __future__ import annotations

import os
import re
import stat
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import yaml

from puppet.data.errors import DataError
from puppet.data.yaml_errors import plain_words

Position = tuple[int, int]  # 1-based line, column
MAX_BYTES = 2_000_000  # a data file's largest size (the shipped ones are under 10 kB)
MAX_DEPTH = 48  # deepest nesting of maps and lists (the shipped ones reach 8)
PURE_LOADER = yaml.SafeLoader
C_LOADER = getattr(yaml, "CSafeLoader", None)  # None: PyYAML built without libyaml
_SCALARS = yaml.constructor.SafeConstructor()
_RESOLVER = yaml.resolver.Resolver()


@dataclass
class Located:
    """Plain data from a YAML file and the source position of every path in it."""

    path: str
    data: Any
    value_pos: dict[tuple, Position] = field(default_factory=dict)
    key_pos: dict[tuple, Position] = field(default_factory=dict)
    # the YAML text it was read from (None: data built in code), for messages that
    # quote what was written (``key: 0x1F`` was written 0x1F, not 31)
    text: str | None = field(default=None, repr=False, compare=False)

    def where(self, loc: tuple, prefer_key: bool = False) -> Position | None:
        """Position of the deepest known prefix of ``loc``."""
        loc = tuple(loc)
        while True:
            if prefer_key and loc in self.key_pos:
                return self.key_pos[loc]
            if loc in self.value_pos:
                return self.value_pos[loc]
            if not loc:
                return None
            loc = loc[:-1]

    def error(self, loc: tuple, message: str, prefer_key: bool = False) -> DataError:
        pos = self.where(loc, prefer_key)
        line, col = pos if pos else (None, None)
        return DataError(self.path, line, col, message)


_TAG = "tag:yaml.org,2002:"
_PLAIN_TAGS = {_TAG + t for t in ("map", "seq", "str", "int", "float", "bool", "null")}
# YAML 1.1's printable characters (what PyYAML's reader accepts), tab and newlines.
_NOT_PRINTABLE = re.compile("[^\x09\x0A\x0D\x20-\x7E\x85\xA0-\uD7FF\uE000-\uFFFD"
                            "\U00010000-\U0010FFFF]")


def _pos(mark) -> Position:
    return mark.line + 1, mark.column + 1


def _line_col(text: str, index: int) -> Position:
    line = text.count("\n", 0, index) + 1
    return line, index - (text.rfind("\n", 0, index) + 1) + 1


def _check_text(text: str, path: str) -> None:
    size = len(text.encode("utf-8", "surrogatepass")) if len(text) > MAX_BYTES // 4 else 0
    if size > MAX_BYTES:
        raise DataError(path, None, None, f"file too large ({size} bytes); a data file is "
                                          f"at most {MAX_BYTES} bytes")
    bad = _NOT_PRINTABLE.search(text)
    if bad is not None:
        raise DataError(path, *_line_col(text, bad.start()),
                        f"control character U+{ord(bad.group()):04X} is not allowed in a "
                        "data file (only tab, newline and printable text)")


def _tag_problem(tag: str) -> str:
    return (f"unsupported YAML value: tag '{tag}' (data files hold plain maps, lists, "
            "strings and numbers)")


def _scalar(event, path: str) -> Any:
    tag = event.tag
    if tag is None or tag == "!":
        tag = _RESOLVER.resolve(yaml.ScalarNode, event.value, event.implicit)
    if tag not in _PLAIN_TAGS or tag in (_TAG + "map", _TAG + "seq"):
        raise DataError(path, *_pos(event.start_mark), _tag_problem(tag))
    node = yaml.ScalarNode(tag, event.value, event.start_mark, event.end_mark, event.style)
    try:
        return _SCALARS.yaml_constructors[tag](_SCALARS, node)
    except (ValueError, TypeError, ArithmeticError, yaml.YAMLError):
        kind = tag[len(_TAG):]
        shown = event.value if len(event.value) <= 40 else event.value[:37] + "..."
        raise DataError(path, *_pos(event.start_mark),
                        f"'{shown}' is not a valid {kind} (tag !!{kind})") from None


class _Frame:
    __slots__ = ("data", "loc", "key", "is_map")

    def __init__(self, data, loc: tuple, is_map: bool):
        self.data, self.loc, self.is_map = data, loc, is_map
        self.key: Any = _NO_KEY


_NO_KEY = object()


def _compose(loader, path: str) -> Located:
    """Plain data and positions from the loader's events (explicit stack)."""
    out = Located(path=path, data=None)
    get = loader.get_event
    get()  # StreamStartEvent
    event = get()
    if isinstance(event, yaml.StreamEndEvent):
        raise DataError(path, 1, 1, "the file is empty; expected a mapping of settings")
    doc_start = event.start_mark  # DocumentStartEvent
    stack: list[_Frame] = []
    done = False
    while not done:
        event = get()
        if isinstance(event, yaml.AliasEvent) or getattr(event, "anchor", None) is not None:
            raise DataError(path, *_pos(event.start_mark),
                            "YAML anchors (&name) and aliases (*name) are not supported in "
                            "data files; write each value out")
        top = stack[-1] if stack else None
        if isinstance(event, (yaml.MappingEndEvent, yaml.SequenceEndEvent)):
            value = stack.pop().data
            top = stack[-1] if stack else None
            start = None
        elif isinstance(event, yaml.DocumentEndEvent):
            break
        else:
            if top is not None and top.is_map:
                loc = top.loc + (top.key,) if top.key is not _NO_KEY else None
            else:
                loc = () if top is None else top.loc + (len(top.data),)
            start = _pos(event.start_mark)
            if loc is None:  # a mapping key
                if not isinstance(event, yaml.ScalarEvent):
                    raise DataError(path, *start, "a mapping key must be a plain name")
                key = _scalar(event, path)
                if not isinstance(key, (str, int, float, bool)):
                    raise DataError(path, *start, "a mapping key must be a plain name")
                if key in top.data:
                    raise DataError(path, *start, f"duplicate key '{key}'")
                top.key = key
                out.key_pos[top.loc + (key,)] = start
                continue
            out.value_pos[loc] = start
            if isinstance(event, yaml.ScalarEvent):
                value = _scalar(event, path)
            else:
                is_map = isinstance(event, yaml.MappingStartEvent)
                tag = event.tag
                if tag is not None and tag != "!" and tag != _TAG + ("map" if is_map
                                                                     else "seq"):
                    raise DataError(path, *start, _tag_problem(tag))
                if len(stack) >= MAX_DEPTH:
                    raise DataError(path, *start, f"nested more than {MAX_DEPTH} levels "
                                                  "deep; data files are flatter than that")
                stack.append(_Frame({} if is_map else [], loc, is_map))
                continue
        # a complete value: attach it to its parent
        if top is None:
            out.data = value
            done = True
        elif top.is_map:
            top.data[top.key] = value
            top.key = _NO_KEY
        else:
            top.data.append(value)
    event = get()
    if isinstance(event, yaml.DocumentEndEvent):
        event = get()
    if not isinstance(event, yaml.StreamEndEvent):
        raise DataError(path, *_pos(event.start_mark),
                        "a second YAML document starts here; a data file holds one "
                        f"(the first starts at line {doc_start.line + 1})")
    return out


def _parse(text: str, path: str, loader_class) -> Located:
    loader = loader_class(text)
    try:
        located = _compose(loader, path)
        located.text = text
        return located
    finally:
        loader.dispose()


def _syntax_error(exc: yaml.MarkedYAMLError, path: str, text: str = "") -> DataError:
    mark = exc.problem_mark or exc.context_mark
    line, col = (mark.line + 1, mark.column + 1) if mark else (None, None)
    problem = " ".join(str(exc.problem or exc.context or "invalid YAML").split())
    plain = plain_words(exc, problem, text.splitlines()) if text else None
    if plain is not None:  # the common mistakes, said as what is wrong and what to do
        line, col, problem = plain
    return DataError(path, line, col, f"YAML syntax error: {problem}")


def load_text(text: str, path: str, loader=None) -> Located:
    """Parse YAML text; raise DataError with the position of any problem. ``loader``:
    a PyYAML loader class (default: the C one if installed, else the pure-Python one)."""
    path = str(path)
    _check_text(text, path)
    loader = loader or C_LOADER or PURE_LOADER
    try:
        return _parse(text, path, loader)
    except yaml.YAMLError as exc:
        if loader is not PURE_LOADER:
            # libyaml words its errors differently: report the pure-Python parser's
            # message and mark, so that both loaders give the same one line.
            return load_text(text, path, PURE_LOADER)
        if isinstance(exc, yaml.MarkedYAMLError):
            raise _syntax_error(exc, path, text) from None
        message = " ".join(str(exc).split())
        raise DataError(path, None, None, f"YAML error: {message}") from None
    except RecursionError:  # not expected (no recursion here), but never a traceback
        raise DataError(path, None, None, "nested too deeply to read") from None


def read_text(path: str | Path) -> str:
    """A data file's text (UTF-8, at most MAX_BYTES), with the loader's one-line errors."""
    path = Path(path)
    try:
        with path.open("rb") as fh:
            if not stat.S_ISREG(os.fstat(fh.fileno()).st_mode):
                raise DataError(str(path), None, None, "not a regular file")
            raw = fh.read(MAX_BYTES + 1)
    except FileNotFoundError:
        raise DataError(str(path), None, None, "no such file") from None
    except IsADirectoryError:
        raise DataError(str(path), None, None, "is a directory, not a data file") from None
    except OSError as exc:
        raise DataError(str(path), None, None, f"cannot read: {exc.strerror}") from None
    if len(raw) > MAX_BYTES:
        raise DataError(str(path), None, None, f"file too large (over {MAX_BYTES} bytes); "
                                               f"a data file is at most {MAX_BYTES} bytes")
    try:
        return raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise DataError(str(path), *_line_col(raw.decode("utf-8", "replace"),
                                              len(raw[:exc.start].decode("utf-8", "replace"))),
                        f"not UTF-8 text ({exc.reason})") from None


def load_file(path: str | Path) -> Located:
    """Read and parse a YAML file (UTF-8)."""
    return load_text(read_text(path), str(path))
