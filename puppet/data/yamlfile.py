"""Safe YAML loading that remembers where every key and value came from.

Validation errors must name file:line:col, so we compose the YAML node tree with
the safe loader (no tags that run code) and build plain Python data plus a map
from each data path (tuple of keys/indices) to its source position.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import yaml

from puppet.data.errors import DataError

Position = tuple[int, int]  # 1-based line, column
_SCALARS = yaml.constructor.SafeConstructor()


@dataclass
class Located:
    """Plain data from a YAML file and the source position of every path in it."""

    path: str
    data: Any
    value_pos: dict[tuple, Position] = field(default_factory=dict)
    key_pos: dict[tuple, Position] = field(default_factory=dict)

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


def _pos(node: yaml.Node) -> Position:
    return node.start_mark.line + 1, node.start_mark.column + 1


_PLAIN_TAGS = {f"tag:yaml.org,2002:{t}" for t in
               ("map", "seq", "str", "int", "float", "bool", "null")}


def _build(node: yaml.Node, loc: tuple, out: Located) -> Any:
    out.value_pos[loc] = _pos(node)
    if node.tag not in _PLAIN_TAGS:
        raise DataError(out.path, *_pos(node), f"unsupported YAML value: tag '{node.tag}' "
                        "(data files hold plain maps, lists, strings and numbers)")
    if isinstance(node, yaml.MappingNode):
        result: dict = {}
        for key_node, value_node in node.value:
            key = _build(key_node, loc + ("<key>",), out)
            if not isinstance(key, (str, int, float, bool)):
                raise DataError(out.path, *_pos(key_node), "a mapping key must be a plain name")
            if key in result:
                raise DataError(out.path, *_pos(key_node), f"duplicate key '{key}'")
            out.key_pos[loc + (key,)] = _pos(key_node)
            result[key] = _build(value_node, loc + (key,), out)
        out.value_pos.pop(loc + ("<key>",), None)
        return result
    if isinstance(node, yaml.SequenceNode):
        return [_build(item, loc + (i,), out) for i, item in enumerate(node.value)]
    # Scalars: the safe constructor resolves the implicit type (int, float, bool, null).
    return _SCALARS.construct_object(node, deep=True)


def load_text(text: str, path: str) -> Located:
    """Parse YAML text; raise DataError with the position of any syntax error."""
    try:
        node = yaml.compose(text, Loader=yaml.SafeLoader)
    except yaml.MarkedYAMLError as exc:
        mark = exc.problem_mark or exc.context_mark
        line, col = (mark.line + 1, mark.column + 1) if mark else (None, None)
        problem = exc.problem or exc.context or "invalid YAML"
        if "expected ',' or" in problem:  # an unclosed or broken { } / [ ] item
            problem += (" (look at the lines above too: inside { } and [ ] items are "
                        "separated by commas, and a '# comment' there hides the rest of "
                        "its line, closing bracket included)")
        raise DataError(path, line, col, f"YAML syntax error: {problem}") from None
    except yaml.YAMLError as exc:
        raise DataError(path, None, None, f"YAML error: {exc}") from None
    located = Located(path=path, data=None)
    if node is None:
        raise DataError(path, 1, 1, "the file is empty; expected a mapping of settings")
    try:
        located.data = _build(node, (), located)
    except yaml.constructor.ConstructorError as exc:
        mark = exc.problem_mark
        raise DataError(path, mark.line + 1 if mark else None, mark.column + 1 if mark else None,
                        f"unsupported YAML value: {exc.problem}") from None
    return located


def read_text(path: str | Path) -> str:
    """A data file's text (UTF-8), with the loader's one-line errors."""
    path = Path(path)
    try:
        return path.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise DataError(str(path), None, None, "no such file") from None
    except UnicodeDecodeError as exc:
        raise DataError(str(path), None, None, f"not UTF-8 text ({exc.reason})") from None
    except OSError as exc:
        raise DataError(str(path), None, None, f"cannot read: {exc.strerror}") from None


def load_file(path: str | Path) -> Located:
    """Read and parse a YAML file (UTF-8)."""
    return load_text(read_text(path), str(path))
