"""msgspec's validation error, said in puppet's words at its file:line:col (see
``puppet.data.validate``): parse its text and path, walk the data and the types along
the path, and say what was wrong and what was expected."""

from __future__ import annotations

import difflib
import math
import re
import types
import typing
from typing import Any

import msgspec
import yaml

from puppet.data.errors import DataError
from puppet.data.validate import _DISPATCH, _dec_hook
from puppet.data.yamlfile import _RESOLVER, _SCALARS, Located

# --- the types along a path ----------------------------------------------------------

_NOTHING = object()
_FIELDS: dict[type, dict[str, Any]] = {}


def _fields(cls: type) -> dict[str, Any]:
    """encode name -> annotation of a struct's fields."""
    found = _FIELDS.get(cls)
    if found is None:
        found = _FIELDS[cls] = {f.encode_name: f.type for f in msgspec.structs.fields(cls)}
    return found


def _is_struct(t: Any) -> bool:
    return isinstance(t, type) and issubclass(t, msgspec.Struct)


def _strip(t: Any) -> tuple[Any, list]:
    """(the type under Annotated, its metadata)."""
    metas: list = []
    while typing.get_origin(t) is typing.Annotated:
        args = typing.get_args(t)
        t, metas = args[0], metas + list(args[1:])
    return t, metas


def _members(t: Any) -> list:
    base, _ = _strip(t)
    if typing.get_origin(base) in (typing.Union, types.UnionType):
        return list(typing.get_args(base))
    return [t]


def _kind(t: Any) -> str:
    """What a (stripped) type holds: struct, dict, list, tuple, float, int, bool, str,
    literal, none, dispatch."""
    base, _ = _strip(t)
    if base in _DISPATCH:
        return "dispatch"
    if _is_struct(base):
        return "struct"
    if base is type(None) or base is None:
        return "none"
    origin = typing.get_origin(base)
    if origin is typing.Literal:
        return "literal"
    if origin is dict or base is dict:
        return "dict"
    if origin is list or base is list:
        return "list"
    if origin is tuple or base is tuple:
        return "tuple"
    return {float: "float", int: "int", bool: "bool", str: "str"}.get(base, "other")


def _choose(t: Any, data: Any) -> Any:
    """The member of a union (or the dispatched struct) that ``data`` is meant as."""
    members = _members(t)
    if len(members) > 1:
        kinds = [_kind(m) for m in members]
        if data is None and "none" in kinds:
            wanted = ("none",)
        elif isinstance(data, dict):
            wanted = ("struct", "dispatch", "dict")
        elif isinstance(data, (list, tuple)):
            wanted = ("list", "tuple")
        elif isinstance(data, bool):
            wanted = ("bool", "float", "int")
        elif isinstance(data, (int, float)):
            wanted = ("float", "int")
        elif isinstance(data, str):
            wanted = ("literal", "str")
        else:
            wanted = ()
        tagged = [m for m, k in zip(members, kinds) if k == "struct"
                  and _strip(m)[0].__struct_config__.tag_field is not None]
        if isinstance(data, dict) and len(tagged) > 1:
            tag_field = _strip(tagged[0])[0].__struct_config__.tag_field
            for m in tagged:
                if _strip(m)[0].__struct_config__.tag == data.get(tag_field):
                    return m
            return t  # no member has that tag: the union itself
        for want in wanted:
            for m, k in zip(members, kinds):
                if k == want:
                    t = m
                    break
            else:
                continue
            break
        else:
            t = next((m for m, k in zip(members, kinds) if k != "none"), members[0])
    base, _ = _strip(t)
    if base in _DISPATCH:
        return _DISPATCH[base](data)
    return t


def _tagged_union(t: Any) -> tuple[str, list[str]] | None:
    """(tag field, tags) if ``t`` is a union of structs told apart by a tag field."""
    members = [_strip(m)[0] for m in _members(t)]
    structs = [m for m in members if _is_struct(m) and m.__struct_config__.tag_field]
    if len(structs) > 1:
        return structs[0].__struct_config__.tag_field, [s.__struct_config__.tag
                                                        for s in structs]
    return None


def _converts(value: Any, t: Any) -> bool:
    try:
        msgspec.convert(value, t, dec_hook=_dec_hook, strict=False)
        return True
    except msgspec.ValidationError:
        return False


_TOKEN = re.compile(r"\.([^.\[\]]+)|\[(\d+)\]|\[(\.\.\.)\]")
_AT = re.compile(r" - at `(?:(key)` in `)?(\$[^`]*)`$")


def _split(text: str) -> tuple[str, list]:
    """msgspec's message and the path it gives, outermost segment first."""
    segments = []
    while True:
        match = _AT.search(text)
        if not match:
            break
        segments.append((match.group(2), bool(match.group(1))))
        text = text[:match.start()]
    tokens: list = []
    for path, is_key in segments:  # outermost first
        tokens += [m.group(1) if m.group(1) is not None else
                   int(m.group(2)) if m.group(2) is not None else ...
                   for m in _TOKEN.finditer(path[1:])]
        if is_key:
            tokens.append("<key>")
    return text, tokens


class _Place:
    """Where an error is: the data path, the value there, its type and its parent's."""

    def __init__(self, loc: tuple, value: Any, kind: Any, parent: Any):
        self.loc, self.value, self.kind, self.parent = loc, value, kind, parent


def _walk(model: type, data: Any, tokens: list) -> _Place:
    t, loc, parent = model, [], None
    for token in tokens:
        t = _choose(t, data)
        base, _ = _strip(t)
        parent = t
        if token == "<key>":  # a key of this mapping is of the wrong type
            key_type = str if _is_struct(base) else (
                typing.get_args(base)[0] if typing.get_args(base) else Any)
            bad = next((k for k in data if not _converts(k, key_type)), _NOTHING) \
                if isinstance(data, dict) else _NOTHING
            return _Place(tuple(loc) + ((bad,) if bad is not _NOTHING else ()), bad,
                          key_type, parent)
        if isinstance(token, str):
            tag = _tagged_union(base)
            if (tag and token == tag[0]) or (
                    _is_struct(base) and token == base.__struct_config__.tag_field):
                t = "<tag>"
            else:
                t = _fields(base).get(token, Any) if _is_struct(base) else Any
            if isinstance(data, dict) and token in data:
                data = data[token]
                loc.append(token)
            else:
                data = _NOTHING
                loc.append(token)
        elif isinstance(token, int):
            args = typing.get_args(base)
            if _kind(base) == "tuple" and args and args[-1] is not Ellipsis:
                t = args[token] if token < len(args) else Any
            else:
                t = args[0] if args else Any
            if isinstance(data, (list, tuple)) and 0 <= token < len(data):
                data = data[token]
            else:
                data = _NOTHING
            loc.append(token)
        else:  # [...]: a value of a mapping; the first in order that does not convert
            args = typing.get_args(base)
            t = args[1] if len(args) == 2 else Any
            key = next((k for k, v in data.items() if not _converts(v, t)), _NOTHING) \
                if isinstance(data, dict) else _NOTHING
            if key is _NOTHING:
                break
            data = data[key]
            loc.append(key)
    return _Place(tuple(loc), data, t, parent)


def _submodels(annotation: Any) -> list[type]:
    """The structs an annotation may hold (through Optional, list, dict, Union)."""
    annotation, _ = _strip(annotation)
    if annotation in _DISPATCH:
        return list(getattr(annotation, "choices", ()))
    if _is_struct(annotation):
        return [annotation]
    origin = typing.get_origin(annotation)
    if origin in (typing.Union, types.UnionType, list, tuple, dict):
        found: list = []
        for arg in typing.get_args(annotation):
            found += _submodels(arg)
        return found
    return []


def _allowed_keys(model: type, loc: tuple) -> list[str]:
    """Field names accepted at ``loc`` (a path of keys), walking the struct tree (every
    member of a union): where the entry itself does not say which member it is."""
    candidates = [model]
    for part in loc:
        if not isinstance(part, str):
            continue
        nxt = []
        for cand in candidates:
            if part in _fields(cand):
                nxt += _submodels(_fields(cand)[part])
        if nxt:
            candidates = nxt
    keys: list[str] = []
    for cand in candidates:
        keys += list(_fields(cand))
    return sorted(set(keys))


def _entry_keys(t: Any, data: Any, key: str) -> tuple[list[str], str] | None:
    """(the keys allowed, a note) for an unknown ``key`` of the entry ``data`` held by a
    field of type ``t``; None if the entry does not say which struct it is. A union's
    member is the one the entry is: by its tag (a circle's keys, not a box's ``size``;
    the note says which types have the key), or as the dispatch picks it (a map with
    ``grid`` is a grid map). A key that the entry, with ``key`` renamed to it, would
    have as the member it then is, is allowed too (``gird`` -> ``grid`` makes a linear
    map a grid map)."""
    if not isinstance(data, dict):
        return None
    member = _strip(_choose(t, data))[0]
    if not _is_struct(member):
        return None  # a tag no member has
    own = set(_fields(member))
    base, _ = _strip(t)
    others = list(getattr(base, "choices", ())) if base in _DISPATCH else [
        _strip(m)[0] for m in _members(t)]
    switch = set()
    for other in others:
        if other is member or not _is_struct(other):
            continue
        for k in set(_fields(other)) - own:
            renamed = {n: v for n, v in data.items() if n != key} | {k: data.get(key)}
            if _strip(_choose(t, renamed))[0] is other:
                switch.add(k)
    note = ""
    tag_field = member.__struct_config__.tag_field
    if tag_field is not None:
        having = [o.__struct_config__.tag for o in others if _is_struct(o)
                  and o is not member and key in _fields(o)]
        if having:
            note = (f" (a key of {tag_field} {', '.join(having)}, not "
                    f"{member.__struct_config__.tag})")
    return sorted(own | switch), note


# --- the message ---------------------------------------------------------------------

def _describe(value: Any) -> str:
    text = repr(value)
    return text if len(text) <= 40 else text[:37] + "..."


_WHAT = {"float": "a number", "int": "a whole number", "bool": "true or false",
         "str": "text", "array": "a list", "null": "nothing (null)"}
_BOUND = re.compile(r"Expected `(\w+)` (>=|>|<=|<) (\S+)$")
_LENGTH = re.compile(r"Expected `(\w+)` of length (>=|<=)? ?(\d+)(?:, got (\d+))?$")
_TYPE = re.compile(r"Expected `([^`]+)`(?:, got `([^`]+)`)?$")
_WORDS = {">=": "at least", ">": "more than", "<=": "at most", "<": "less than"}


def _num(text: str) -> str:
    try:
        return f"{float(text):g}"
    except ValueError:
        return text


def _finite(value: Any) -> bool:
    """False for NaN and the infinities, given as numbers or as text ('nan')."""
    try:
        return math.isfinite(float(value))
    except (TypeError, ValueError, OverflowError):
        return True  # not a number at all: another message says so


def _bounds(metas: list) -> str:
    """A number's bounds as the messages say them: 'at least 0 and less than 1'."""
    said = []
    for meta in metas:
        if isinstance(meta, msgspec.Meta):
            for name, op in (("ge", ">="), ("gt", ">"), ("le", "<="), ("lt", "<")):
                if getattr(meta, name) is not None:
                    said.append(f"{_WORDS[op]} {_num(str(getattr(meta, name)))}")
    return " and ".join(said)


def _what(name: str, t: Any) -> str:
    if name == "object":
        kind = _kind(t) if t is not None else "struct"
        return "a mapping" if kind == "dict" else "a mapping of settings"
    return _WHAT.get(name, name)


def _range_of(metas: list) -> dict:
    for meta in metas:
        if isinstance(meta, msgspec.Meta) and meta.extra:
            return meta.extra
    return {}


def _literals(t: Any) -> list:
    values: list = []
    for member in _members(t):
        base, _ = _strip(member)
        if typing.get_origin(base) is typing.Literal:
            values += list(typing.get_args(base))
    return values


_KIND_WORDS = {"float": "a number", "int": "a whole number", "bool": "true or false",
               "list": "a list", "tuple": "a list", "struct": "a mapping of settings",
               "dispatch": "a mapping of settings", "dict": "a mapping"}


_PLAIN_END = re.compile(r"\s+#|[,\]}]|\s*$")  # where a plain scalar ends on its line


def _written(located: Located, loc: tuple, value: Any) -> str:
    """The scalar at ``loc`` as the file writes it (``0x1F``, ``07``, ``1:30``, ``no``),
    read from the text at its located start; ``str(value)`` if the text is not there
    (data built in code) or does not read back as ``value``."""
    pos = located.value_pos.get(tuple(loc))
    if located.text is None or pos is None:
        return str(value)
    lines = located.text.splitlines()
    line, col = pos
    if not 0 < line <= len(lines):
        return str(value)
    rest = lines[line - 1][col - 1:]
    word = rest[:_PLAIN_END.search(rest).start()]
    try:  # read back as the loader reads a plain scalar
        tag = _RESOLVER.resolve(yaml.ScalarNode, word, (True, False))
        node = yaml.ScalarNode(tag, word)
        same = _SCALARS.yaml_constructors[tag](_SCALARS, node)
    except (KeyError, ValueError, TypeError, ArithmeticError, yaml.YAMLError):
        return str(value)
    if type(same) is not type(value) or repr(same) != repr(value):  # (NaN: by its repr)
        return str(value)
    return word


def _value_message(text: str, place: _Place, located: Located) -> str:
    """What a value's error means, in puppet's words (``located``: the file, to quote
    a value as it was written)."""
    value, t = place.value, place.kind
    member = _choose(t, value) if value is not _NOTHING else t
    base, metas = _strip(member)
    extra = _range_of(metas)
    bound, length, wrong = _BOUND.match(text), _LENGTH.match(text), _TYPE.match(text)
    if extra.get("range"):  # a Num: not true/false, a number, inside its range
        from puppet.data.ranges import problem

        if isinstance(value, bool):
            return "expected a number, got true/false"
        if wrong:
            return "expected a number"
        if isinstance(value, str):  # a number written as text ('1e400', '-1'): its value
            try:
                value = float(value)
            except ValueError:
                return "expected a number"
        return problem(extra["range"], value) or text
    if bound and _kind(base) == "float" and not _finite(value):
        return f"must be a finite number, {_bounds(metas)}"  # (NaN fails every bound)
    if extra.get("message") and (bound or wrong and _kind(base) == "int"
                                 and isinstance(value, int) and not isinstance(value, bool)):
        return extra["message"]
    if bound:
        return f"must be {_WORDS[bound.group(2)]} {_num(bound.group(3))}"
    if length:
        op, n, got = length.group(2), length.group(3), length.group(4)
        if op == ">=":
            return f"expected at least {n} item(s)"
        if op == "<=":
            return f"expected at most {n} item(s)"
        return f"expected {n} items, got {got}"
    if text == "Number out of range":  # text such as '1e400' read as a number
        within = _bounds(metas)
        return f"must be a finite number, {within}" if within else "expected a finite number"
    if text.startswith("Invalid enum value"):  # text, not one of the words: say the
        others = []                             # union's other kinds too
        for member in _members(t):
            kind = _kind(member)
            said = _KIND_WORDS.get(kind)
            fields = list(_fields(_strip(member)[0])) if kind == "struct" else []
            if 0 < len(fields) <= 3:  # a small struct: its shape ('{power: ...}')
                said = "{" + ", ".join(f"{n}: ..." for n in fields) + "}"
            if said and said not in others:
                others.append(said)
        return "expected one of: " + ", ".join(str(v) for v in _literals(t)) + \
            "".join(f", or {w}" for w in others)
    if wrong:
        names = [n.strip() for n in wrong.group(1).split("|")]
        literals = _literals(t)
        words = []
        for name in names:
            if name == "str" and literals:
                words.append(", ".join(f"'{v}'" for v in literals))
            elif name != "null":
                words.append(_what(name, next((m for m in _members(t)
                                               if _kind(m) in ("struct", "dispatch", "dict")),
                                              None) if name == "object" else None))
        if not words:
            words = ["nothing (null)"]
        if len(words) == 1 and literals and "str" in names:  # the words alone
            return "expected one of: " + ", ".join(str(v) for v in literals)
        said = "expected " + (words[0] if len(words) == 1 else
                              ", ".join(words[:-1]) + " or " + words[-1])
        if names == ["str"] and isinstance(value, (int, float)):  # key: 3, key: no
            written = _written(located, place.loc, value)
            reads = (("true" if value else "false") if isinstance(value, bool)
                     else "a number")
            said += f" in quotes, '{written}' (unquoted, YAML reads it as {reads})"
        return said
    return text  # a check of ours (a __post_init__'s ValueError): already puppet's words


_UNKNOWN = re.compile(r"Object contains unknown field `(.*)`$", re.S)
_MISSING = re.compile(r"Object missing required field `(.*)`$", re.S)


def _unknown_cuts(message: str):
    """(key, path tokens) for each way to read an unknown-field message as a key up to a
    "` - at `" and a path alone after it, or as a key alone (a top-level one): a user's
    key may hold that text."""
    prefix = "Object contains unknown field `"
    if not message.startswith(prefix):
        return
    i = len(prefix)
    while (i := message.find("` - at `", i)) >= 0:
        rest, tokens = _split(message[i + 1:])
        if rest == "":
            yield message[len(prefix):i], tokens
        i += 1
    if message.endswith("`"):  # at the top level msgspec gives no path at all
        yield message[len(prefix):-1], []


def to_data_error(located: Located, model: type, message: str) -> DataError:
    """The DataError of msgspec's error ``message`` for ``located`` validated as
    ``model``."""
    text, tokens = _split(message)
    place = _walk(model, located.data, tokens)
    unknown, missing = _UNKNOWN.match(text), _MISSING.match(text)
    if unknown and not (isinstance(place.value, dict) and unknown.group(1) in place.value):
        # a key that itself reads like a path ("a` - at `$.x"): the cut of the message
        # whose key is there, at the place its path names
        for key, path in _unknown_cuts(message):
            there = _walk(model, located.data, path)
            if isinstance(there.value, dict) and key in there.value:
                text, tokens, place = f"Object contains unknown field `{key}`", path, there
                unknown = _UNKNOWN.match(text)
                break
    loc = place.loc
    struct_key = tokens[-1:] == ["<key>"] and _is_struct(_strip(place.parent)[0])
    if unknown or struct_key:  # (a number as a key of settings: no such key either)
        key = unknown.group(1) if unknown else loc[-1] if loc else "?"
        loc = loc + (key,) if unknown else loc
        entry = _entry_keys(place.kind, place.value, key) if unknown else (
            sorted(_fields(_strip(place.parent)[0])), "")  # (a number: the struct's)
        allowed, note = entry or (_allowed_keys(model, loc[:-1]), "")
        close = difflib.get_close_matches(str(key), allowed, n=1)
        hint = f"; did you mean '{close[0]}'?" if close else ";"
        return located.error(loc, f"unknown key '{key}'{note}{hint} expected one of: "
                                  f"{', '.join(allowed)}", prefer_key=True)
    name = ".".join(str(p) for p in loc) or "(top level)"
    got = f" (got {_describe(place.value)})" if place.value is not _NOTHING else ""
    if missing:
        key = missing.group(1)
        tag = _tagged_union(place.kind)
        if tag and tag[0] == key:
            return located.error(loc, f"bad value for '{name}': missing '{key}', which "
                                      f"says what it is{got}")
        return located.error(loc, f"missing required key '{key}' in "
                                  f"{'.'.join(str(p) for p in loc) or 'the file'}")
    if place.kind == "<tag>":  # a tagged struct's tag: an unknown kind of thing
        return _tag_error(located, model, tokens, loc)
    return located.error(loc, f"bad value for '{name}': "
                              f"{_value_message(text, place, located)}{got}")


def _tag_error(located: Located, model: type, tokens: list, loc: tuple) -> DataError:
    """An unknown (or not text) ``type:`` of a tagged union's member, at the member."""
    parent = _walk(model, located.data, tokens[:-1])
    tag = _tagged_union(parent.kind)
    tag_field, tags = tag if tag else (str(loc[-1]), [])
    value = parent.value.get(tag_field) if isinstance(parent.value, dict) else None
    name = ".".join(str(p) for p in parent.loc) or "(top level)"
    return located.error(parent.loc, f"bad value for '{name}': unknown {tag_field} "
                                     f"'{value}'; expected one of: {', '.join(tags)} "
                                     f"(got {_describe(parent.value)})")
