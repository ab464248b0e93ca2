"""PyYAML's syntax errors for the common mistakes, said in plain words (see
``puppet.data.yamlfile``, whose one-line error keeps the parser's file:line:col).

The pure-Python parser's message and marks (both loaders report them) are mapped to
what is wrong and what was expected: indentation that lines up with no key above, a
line indented under a key that has its value, a key among list items or an item among
keys, a tab, a missing ': ', a ': ' inside a value, an unclosed quote or bracket, a
stray bracket. Anything else keeps the parser's words (``plain_words`` returns None).

The lines are read as text here (the parse failed), so the columns named are those the
lines above start at, which is what the user sees in an editor. The position may move
from where the parser noticed the mistake to where it is: a missing ':' is on the line
before the one the parser stops at, an unclosed quote where the quote opens.
"""

from __future__ import annotations

import re
from typing import NamedTuple

import yaml

# a ``key: value`` line's key (the content after the indentation and any '- ')
_KEY = re.compile(r"""("(?:[^"\\]|\\.)*"|'(?:[^']|'')*'|[^\s'"#][^#]*?)[ \t]*:(?:[ \t]|$)""")


class Level(NamedTuple):
    """Where a node of a line above starts (0-based column) and how to name it."""

    col: int
    name: str  # "'name' on line 2", "the '-' on line 2"
    dash: bool  # a list item's '-'
    key: bool  # a key (else a '-' or a value: text that is not 'key: value')
    row: int
    text: str  # the line from this column on


def _key(content: str) -> str | None:
    """The key of a ``key: value`` line's content (no indentation), else None."""
    match = _KEY.match(content)
    return match.group(1) if match else None


def _show(text: str, limit: int = 40) -> str:
    text = text.strip()
    return text if len(text) <= limit else text[:limit - 3] + "..."


def _indent(line: str) -> int:
    return len(line) - len(line.lstrip(" "))


def _spaces(n: int) -> str:
    return f"{n} space{'' if n == 1 else 's'}"


def _is_blank(line: str) -> bool:
    return not line.strip() or line.lstrip().startswith("#")


def _own_levels(row: int, line: str) -> list[Level]:
    """Where a line's nodes start, deepest first: '  - name: x' starts an item at
    column 2 and a key at 4."""
    col = _indent(line)
    out = []
    content = line[col:]
    while content.startswith("-") and content[1:2] in (" ", ""):
        out.append(Level(col, f"the '-' on line {row + 1}", True, False, row, content))
        rest = content[1:].lstrip(" ")
        col += len(content) - len(rest)
        content = rest
    if content and not content.startswith("#"):
        content = re.sub(r"\s+#.*", "", content)  # a comment after it
        key = _key(content)
        out.append(Level(col, f"'{_show(key if key is not None else content, 30)}' on line "
                              f"{row + 1}", False, key is not None, row, content))
    return out[::-1]


def _levels_above(lines: list[str], row: int) -> list[Level]:
    """The nodes still open at ``row``: for each indentation the lines above step back
    to (nearest first), where it starts and its name; deepest first."""
    levels: list[Level] = []
    bound = None
    for i in range(min(row, len(lines)) - 1, -1, -1):
        if _is_blank(lines[i]):
            continue
        ind = _indent(lines[i])
        if bound is not None and ind >= bound:
            continue
        levels += [lv for lv in _own_levels(i, lines[i]) if bound is None or lv.col < bound]
        bound = ind
        if ind == 0:
            break
    return levels


def _options(levels: list[Level], col: int) -> str:
    """"4 spaces, like 'name' on line 2, or 2, like the '-' on line 2": the columns
    next to ``col`` that the lines above start at."""
    deeper = [lv for lv in levels if lv.col > col]
    shallower = [lv for lv in levels if lv.col < col]
    picks = deeper[-1:] + shallower[:1]
    return ", or ".join(f"{_spaces(lv.col) if i == 0 else lv.col}, like {lv.name}"
                        for i, lv in enumerate(picks))


def _what(content: str) -> str:
    if content.startswith("-"):
        return f"the list item '{_show(content, 30)}'"
    key = _key(content)
    return f"'{_show(key if key is not None else content, 30)}'"


def _not_key_value(text: str) -> str:
    """Why ``text`` (a line from its node on) is not 'key: value'."""
    no_space = re.search(r":[^\s]", text.split(" #")[0])
    return (f"'{_show(text)}' is not 'key: value': expected a ':' and a space after the key"
            + ("; a ':' right before other text is part of the text" if no_space else ""))


NESTS = ("YAML nests by indentation, so a line starts in the column of the keys it "
         "belongs with")


def plain_words(exc: yaml.MarkedYAMLError, problem: str,
                lines: list[str]) -> tuple[int, int, str] | None:
    """(line, column, message), 1-based, for a common mistake; None keeps the parser's
    words. ``problem``: the parser's message on one line; ``lines``: the file's text."""
    mark, context = exc.problem_mark, exc.context_mark
    if mark is None or mark.line > len(lines):
        return None
    row, col = mark.line, mark.column
    line = lines[row] if row < len(lines) else ""
    ind = _indent(line)
    if context is not None and context.line >= len(lines):
        context = None
    found = re.fullmatch(r"expected <block end>, but found '(.*)'", problem)
    if found:
        return _block_end(lines, row, col, line, ind, found.group(1))
    if problem == "mapping values are not allowed here":
        return _colon_in_value(lines, row, col, line, ind)
    if problem == "sequence entries are not allowed here" and line[:col].strip():
        return (row + 1, col + 1,
                f"a list item ('- ') after '{_show(line[:col])}' on the same line: a list's "
                "items start lines of their own ('- item', one a line, under the key)")
    if problem == "could not find expected ':'" and context is not None:
        return (context.line + 1, context.column + 1,
                _not_key_value(lines[context.line][context.column:])
                + " (or '- ' before a list item)")
    document = re.fullmatch(r"expected '<document start>', but found '(.*)'", problem)
    if document and col == ind:
        first = _levels_above(lines, row)
        if first and ind < first[-1].col:
            return (row + 1, col + 1,
                    f"{_what(line[ind:])} is indented {_spaces(ind)}, less than the file's "
                    f"first line ({first[-1].name}, {_spaces(first[-1].col)}): the top-level "
                    "keys all start in one column, usually the first")
        return None
    char = re.fullmatch(r"found character '(.*)' that cannot start any token", problem)
    if char:
        return _bad_character(row, col, line, char.group(1))
    if "quoted scalar" in (exc.context or "") and context is not None:
        return _quoted(lines, row, col, context, problem)
    flow = re.fullmatch(r"expected ',' or '([\]}])', but got '(.*)'", problem)
    if flow and context is not None:
        close = flow.group(1)
        opened = "[" if close == "]" else "{"
        where = ("the end of the file" if flow.group(2) == "<stream end>"
                 else f"line {row + 1}, column {col + 1}")
        return (row + 1, col + 1,
                f"the '{opened}' at line {context.line + 1}, column {context.column + 1} is "
                f"not closed by {where}: expected ',' between its items or '{close}' to "
                f"end it (a '# comment' inside {opened} {close} hides the rest of its line, "
                "closing bracket included)")
    if problem == "expected the node content, but found ','":
        return row + 1, col + 1, "two commas with no item between them: remove one"
    return None


def _bad_character(row: int, col: int, line: str, char: str):
    if char == "\\t":
        if not line[:col].strip():
            return (row + 1, col + 1,
                    "a tab in the indentation: YAML indents with spaces only; replace the "
                    "tab with spaces (as many as line up with the keys it belongs with)")
        return (row + 1, col + 1,
                f"a tab after '{_show(line[:col])}': YAML separates with spaces, not tabs; "
                "replace the tab with a space")
    if char in ("@", "`"):
        return (row + 1, col + 1,
                f"'{char}' cannot start an unquoted value (YAML reserves it): quote the value")
    return None


def _quoted(lines, row, col, context, problem):
    quote = lines[context.line][context.column:context.column + 1] or '"'
    if problem == "found unexpected end of stream":
        return (context.line + 1, context.column + 1,
                f"the quote ({quote}) that starts here is never closed: expected a closing "
                f"{quote} (the value runs on to the end of the file)")
    escape = re.fullmatch(r"found unknown escape character '(.*)'", problem)
    if escape:
        return (row + 1, col, f"'\\{escape.group(1)}' is not an escape in a double-quoted "
                              "value: write '\\\\' for a backslash, or quote the value with "
                              "' ' instead (a backslash is plain there)")
    return None


def _block_end(lines, row, col, line, ind, found):
    """'expected <block end>, but found X': a line whose indentation matches no node
    above it, a key among list items (or the other way round), a ':' with no key, or
    a stray bracket or text after a value."""
    if col != ind:  # not the start of a line: something after a complete value
        if found in ("]", "}"):
            opened = "[" if found == "]" else "{"
            return (row + 1, col + 1, f"a '{found}' with no '{opened}' open before it: "
                                      f"remove it, or add the '{opened}' it closes")
        before = line[:col].rstrip()
        if found == "<scalar>" and before[-1:] in ("'", '"'):
            return (row + 1, col + 1,
                    f"text after the closing quote ({before[-1]}) of a value: a quoted value "
                    "ends at its quote; inside ' ' write a ' as '' (it''s), inside \" \" "
                    "as \\\" (or check the quotes above: one may be unclosed)")
        return None
    content = line[ind:]
    if found == ":":
        return (row + 1, col + 1, "a ':' with no key before it: expected 'key: value'")
    levels = _levels_above(lines, row)
    what = _what(content)
    same = [lv for lv in levels if lv.col == ind]
    if same and same[0].dash and found in ("?", "<block mapping start>"):
        keys = ([lv for lv in levels if lv.col > ind and lv.key][-1:]  # an item's keys
                or [lv for lv in levels if lv.col < ind and lv.key][:1])  # or the list's
        return (row + 1, col + 1,
                f"{what} is a key in the column of the list items above ({same[0].name}): "
                f"a list holds '- ' items only; make it one ('- {_show(content, 30)}')"
                + (f", or indent it like the keys it belongs with: {_spaces(keys[0].col)}, "
                   f"like {keys[0].name}" if keys else ""))
    if same and same[0].key and found in ("-", "<block sequence start>"):
        return (row + 1, col + 1,
                f"{what} is in the column of the keys above ({same[0].name}): a mapping "
                "holds 'key: value' lines only; a list is the value of a key ('key:', its "
                "'- ' items on the lines below)")
    if same and not same[0].dash and not same[0].key:  # under text that is not a key
        return (same[0].row + 1, same[0].col + 1,
                _not_key_value(same[0].text) + f", so {what} on line {row + 1} cannot "
                                               "go with it")
    if same:
        return None
    options = _options(levels, ind)
    if levels and levels[0].col < ind:  # deeper than every line above: under a value
        return (row + 1, col + 1,
                f"{what} is indented {_spaces(ind)}, more than {levels[0].name} above it "
                f"({_spaces(levels[0].col)}), which has its value on its line: {NESTS}: "
                f"expected {options}")
    return (row + 1, col + 1,
            f"{what} is indented {_spaces(ind)}, which lines up with nothing above it: "
            f"{NESTS}" + (f": expected {options}" if options else ""))


def _colon_in_value(lines, row, col, line, ind):
    """'mapping values are not allowed here': a ': ' inside a value, either on the line
    of its key or on a line read as the rest of the value above."""
    content = line[ind:].lstrip("- ")
    key = _key(content)
    if re.search(r":\s", line[:col]) and key is not None:
        value = content[content.index(":") + 1:].strip()
        k = _show(key, 30)
        return (row + 1, col + 1,
                f"the value of '{k}' holds ': ' ('{_show(value)}'): quote the whole value "
                f"({k}: \"{_show(value)}\"), or put the inner key on a line of its own, "
                f"indented under '{k}'")
    prev = next((i for i in range(min(row, len(lines)) - 1, -1, -1)
                 if not _is_blank(lines[i])), None)
    if prev is None:
        return None
    own = _own_levels(prev, lines[prev])
    if not own:
        return None
    head = own[0]  # the deepest node of the line above
    if not head.key and not head.dash and head.col == ind:
        return (prev + 1, head.col + 1,
                _not_key_value(head.text) + f", so it runs on into line {row + 1}, where "
                                            "the ': ' is then not allowed")
    if head.key and ind > head.col:
        k = _show(_key(head.text) or "", 30)
        return (row + 1, ind + 1,
                f"{_what(line[ind:])} is indented {_spaces(ind)}, more than '{k}' on line "
                f"{prev + 1} above it ({_spaces(head.col)}), so it reads as the rest of "
                f"{k}'s value: {NESTS}: expected {_spaces(head.col)}, like '{k}' on line "
                f"{prev + 1}")
    if ind > _indent(lines[prev]):  # read on from the value of the line above
        options = _options(_levels_above(lines, row), ind)
        return (row + 1, ind + 1,
                f"{_what(line[ind:])} reads as the rest of the value '{_show(head.text, 30)}' "
                f"on line {prev + 1} (it is indented more than that line), so its ': ' is "
                f"not allowed: {NESTS}" + (f": expected {options}" if options else ""))
    return None
