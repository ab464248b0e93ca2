"""PyYAML's syntax errors for the common mistakes, said in plain words (see
``puppet.data.yamlfile``, whose one-line error keeps the parser's file:line:col).

The pure-Python parser's message and marks (both loaders report them) are mapped to
what is wrong and what was expected: indentation that lines up with no key above, a
line indented under a key that has its value, a key among list items or an item among
keys, a tab, a missing ': ', a '-' with no space after it, a ': ' inside a value (in a
'{ }' too), an unclosed quote or bracket, a stray bracket, a backslash escape that is
not one. Anything else keeps the parser's words (``plain_words`` returns None).

A fix offered must work when taken: a value is quoted the way that reads back as it
(single quotes when it holds a backslash or a '"'); a key is offered only the columns
of keys above, never a '-' 's, a '{ }' item's or the text lines of a 'notes: |'.

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
    flow: bool = False  # a '{ }' or '[ ]' written on the line: its keys go inside it


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


def _quote(value: str) -> str:
    """``value`` in quotes that read back as it: double quotes unless it holds a
    backslash or a double quote (which are escapes there), else single quotes with any
    ' doubled (a backslash and a " are plain inside ' ')."""
    if "\\" in value or '"' in value:
        return "'" + value.replace("'", "''") + "'"
    return f'"{value}"'


def _show_quoted(value: str, limit: int = 50) -> str:
    """``_quote(value)``, shortened in the middle of the text if long."""
    text = _quote(value)
    if len(text) <= limit:
        return text
    return text[:limit * 2 // 3] + " ... " + text[-(limit // 3 - 5):]


def _dash_glued(content: str) -> bool:
    """'-input: x': a '-' meant as a list item's, with no space after it."""
    return re.match(r"-[A-Za-z_{\['\"]", content) is not None


def _glued_message(row: int, col: int, content: str) -> tuple[int, int, str]:
    fixed = "- " + content[1:]
    return (row + 1, col + 1,
            f"'{_show(content, 30)}' starts with '-' but no space after it, so it is not a "
            f"list item: a list item's '-' needs a space after it ('{_show(fixed, 30)}')")


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
    if _BLOCK_TEXT.fullmatch(content):  # '- |': the item's text is on the lines below
        pass
    elif content[:1] in ("{", "["):
        out.append(Level(col, f"the '{content[0]} {_CLOSE[content[0]]}' on line {row + 1}",
                         False, False, row, content, True))
    elif content and not content.startswith("#"):
        content = re.sub(r"\s+#.*", "", content)  # a comment after it
        key = _key(content)
        out.append(Level(col, f"'{_show(key if key is not None else content, 30)}' on line "
                              f"{row + 1}", False, key is not None, row, content))
    return out[::-1]


_CLOSE = {"{": "}", "[": "]"}
# a block scalar's indicator ending a line: 'notes: |', '- >-', 'text: |2  # comment'
_BLOCK_TEXT = re.compile(r"(?:^|:\s+|^-\s+)[|>][-+0-9]*\s*(?:#.*)?$")


def _inner_rows(lines: list[str], row: int) -> set[int]:
    """The rows above ``row`` that go on a node begun on an earlier line: the text of a
    block scalar ('notes: |'), the lines of a '{ }' or '[ ]' after its first, the rest
    of a quoted or plain value. Their indentation says nothing about where keys go.
    Read from the pure-Python scanner's tokens up to where it stops."""
    rows: set[int] = set()
    opened = []

    def span(start, end):
        last = end.line - 1 if end.column == 0 else end.line
        rows.update(range(start.line + 1, min(last, row - 1) + 1))

    try:
        for token in yaml.scan("\n".join(lines[:row]) + "\n", Loader=yaml.SafeLoader):
            if token.start_mark.line >= row:
                break
            if isinstance(token, (yaml.FlowMappingStartToken, yaml.FlowSequenceStartToken)):
                opened.append(token.start_mark)
            elif isinstance(token, (yaml.FlowMappingEndToken, yaml.FlowSequenceEndToken)):
                if opened:
                    span(opened.pop(), token.end_mark)
            elif isinstance(token, yaml.ScalarToken):
                span(token.start_mark, token.end_mark)
    except yaml.YAMLError:
        pass
    for start in opened:  # still open where the lines above end
        rows.update(range(start.line + 1, row))
    return rows


def _levels_above(lines: list[str], row: int) -> list[Level]:
    """The nodes still open at ``row``: for each indentation the lines above step back
    to (nearest first), where it starts and its name; deepest first."""
    levels: list[Level] = []
    bound = None
    inner = _inner_rows(lines, row)
    for i in range(min(row, len(lines)) - 1, -1, -1):
        if _is_blank(lines[i]) or i in inner:
            continue
        ind = _indent(lines[i])
        if bound is not None and ind >= bound:
            continue
        levels += [lv for lv in _own_levels(i, lines[i]) if bound is None or lv.col < bound]
        bound = ind
        if ind == 0:
            break
    return levels


def _options(levels: list[Level], col: int, key_line: bool = True) -> str:
    """"4 spaces, like 'name' on line 2, or 2, like the '-' on line 2": the columns
    next to ``col`` that the lines above start at. A key line (``key_line``) is offered
    only the columns of keys: in a '-' 's column it would be a key among list items, in
    a '{ }' 's or a value's it would not be a key of theirs; between a '-' and the
    keys of its item, only those keys."""
    fits = [lv for lv in levels if not lv.flow and (lv.key or not key_line)]
    deeper = [lv for lv in fits if lv.col > col]
    shallower = [lv for lv in fits if lv.col < col]
    below = [lv for lv in levels if lv.col < col and not lv.flow][:1]
    if key_line and deeper and below and below[0].dash:
        shallower = []  # between a '-' and its keys: one of that item's keys
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
        top = next((i for i in range(min(row, len(lines))) if not _is_blank(lines[i])), None)
        first = _own_levels(top, lines[top])[-1:] if top is not None else []
        if first and ind < first[0].col:
            return (row + 1, col + 1,
                    f"{_what(line[ind:])} is indented {_spaces(ind)}, less than the file's "
                    f"first line ({first[0].name}, {_spaces(first[0].col)}): the top-level "
                    "keys all start in one column, usually the first")
        return None
    char = re.fullmatch(r"found character '(.*)' that cannot start any token", problem)
    if char:
        return _bad_character(row, col, line, char.group(1))
    if "quoted scalar" in (exc.context or "") and context is not None:
        return _quoted(lines, row, col, context, problem)
    flow = re.fullmatch(r"expected ',' or '([\]}])', but got '(.*)'", problem)
    if flow and context is not None:
        if flow.group(1) == "}" and flow.group(2) == ":":
            said = _colon_in_flow(line, col)
            if said is not None:
                return row + 1, col + 1, said
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


def _colon_in_flow(line: str, col: int) -> str | None:
    """A ':' the parser met after a '{ }' item's value: the value holds ': '. The item
    is the text from the ',' or '{' before it to the ',' or '}' after it."""
    begin = max(line.rfind(",", 0, col), line.rfind("{", 0, col)) + 1
    ends = [i for i in (line.find(",", col), line.find("}", col)) if i >= 0]
    item = line[begin:min(ends) if ends else len(line)].strip()
    key = _key(item)
    if key is None:
        return None
    value = item[len(key):].lstrip()[1:].strip()
    k = _show(key, 30)
    before = value.split(":", 1)[0]
    comma = (f"; or, if '{before.split()[-1]}' starts the next item, put a ',' before it"
             if len(before.split()) > 1 else "")
    return (f"the value of '{k}' holds ': ' ('{_show(value)}'): quote "
            f"the whole value ({k}: {_show_quoted(value)}){comma}")


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
    hexes = re.fullmatch(r"expected escape sequence of (\d+) hexadecimal numbers, but "
                         r"found '(.*)'", problem)
    if not escape and not hexes:
        return None
    text = lines[row]
    start = text.rfind("\\", 0, col)  # the backslash of the escape
    if start < 0:
        return None
    if escape:
        what = f"'\\{escape.group(1)}' is not an escape in a double-quoted value"
    else:
        letter = text[start + 1:start + 2]
        what = (f"'\\{letter}' in a double-quoted value starts an escape of "
                f"{hexes.group(1)} hexadecimal digits (a character code), and "
                f"'{_show(text[start:col + 1], 12)}' is not one")
    value = _double_quoted(lines, context)
    fix = (f" ({_show_quoted(value)})" if value is not None else "")
    return (row + 1, start + 1,
            f"{what}: write '\\\\' for a backslash, or quote the value with ' ' "
            f"instead{fix} (a backslash is plain there)")


def _double_quoted(lines, context) -> str | None:
    """The text between the double quote at ``context`` and its closing quote on the
    same line, escapes as written; None if it does not close there."""
    text = lines[context.line]
    match = re.match(r'"((?:[^"\\]|\\.)*)"', text[context.column:])
    return match.group(1) if match else None


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
    if _dash_glued(content):
        return _glued_message(row, ind, content)
    levels = _levels_above(lines, row)
    what = _what(content)
    if levels and levels[0].key and _dash_glued(levels[0].text):
        return _glued_message(levels[0].row, levels[0].col, levels[0].text)
    if levels and levels[0].flow and ind > (levels[1].col if len(levels) > 1 else -1):
        flow = levels[0]
        close = _CLOSE[flow.text[0]]
        held = "keys" if close == "}" else "items"
        return (row + 1, col + 1,
                f"{what} is indented under {flow.name}: a value written in "
                f"'{flow.text[0]} {close}' holds its {held} inside it, separated by ',' "
                f"(add '{_show(content, 30)}' before its closing '{close}')")
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
    options = _options(levels, ind, not content.startswith("-"))
    if levels and levels[0].col < ind and _BLOCK_TEXT.search(
            lines[levels[0].row].strip()):  # after the text of 'key: |'
        return (row + 1, col + 1,
                f"{what} is indented {_spaces(ind)}: more than {levels[0].name} above it "
                f"({_spaces(levels[0].col)}), less than the lines of its block of text "
                "('|' or '>'), which ends at the first line indented less than them: "
                f"{NESTS}: expected {options}")
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
        value = re.sub(r"\s+#.*", "", content[len(key):].lstrip()[1:]).strip()
        k = _show(key, 30)
        return (row + 1, col + 1,
                f"the value of '{k}' holds ': ' ('{_show(value)}'): quote the whole value "
                f"({k}: {_show_quoted(value)}), or put the inner key on a line of its own, "
                f"indented under '{k}'")
    prev = next((i for i in range(min(row, len(lines)) - 1, -1, -1)
                 if not _is_blank(lines[i])), None)
    if prev is None:
        return None
    own = _own_levels(prev, lines[prev])
    if not own:
        return None
    head = own[0]  # the deepest node of the line above
    if _dash_glued(head.text) and ind > head.col:
        return _glued_message(prev, head.col, head.text)
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
        options = _options(_levels_above(lines, row), ind, not line[ind:].startswith("-"))
        return (row + 1, ind + 1,
                f"{_what(line[ind:])} reads as the rest of the value '{_show(head.text, 30)}' "
                f"on line {prev + 1} (it is indented more than that line), so its ': ' is "
                f"not allowed: {NESTS}" + (f": expected {options}" if options else ""))
    return None
