"""Turn pydantic validation errors into one-line, file:line:col DataErrors.

pydantic does the checking (types, ranges, unknown keys); this module only says
*where* in the YAML file the problem is, and suggests the key that was meant.
"""

from __future__ import annotations

import difflib
import types
import typing
from typing import Any, TypeVar

import pydantic

from puppet.data.errors import DataError
from puppet.data.yamlfile import Located

M = TypeVar("M", bound=pydantic.BaseModel)


class Spec(pydantic.BaseModel):
    """Base of every data-file model: unknown keys are errors, values are checked."""

    # defer_build: a model's validator is built when it first validates, so a command
    # builds only the models it reads (``puppet check`` of a character, no interface's)
    model_config = pydantic.ConfigDict(extra="forbid", populate_by_name=True, frozen=False,
                                       defer_build=True)


def _submodels(annotation: Any) -> list[type[pydantic.BaseModel]]:
    """The pydantic models an annotation may hold (through Optional, list, dict, Union)."""
    if isinstance(annotation, type) and issubclass(annotation, pydantic.BaseModel):
        return [annotation]
    origin = typing.get_origin(annotation)
    args = typing.get_args(annotation)
    if origin is typing.Annotated:
        return _submodels(args[0])
    if origin in (typing.Union, types.UnionType, list, tuple, dict):
        found: list = []
        for arg in args:
            found += _submodels(arg)
        return found
    return []


def _allowed_keys(model: type[pydantic.BaseModel], loc: tuple) -> list[str]:
    """Field names accepted at ``loc`` (a path of keys), walking the model tree."""
    candidates = [model]
    for part in loc:
        if not isinstance(part, str):
            continue
        nxt = []
        for cand in candidates:
            for name, info in cand.model_fields.items():
                if part in (name, info.alias):
                    nxt += _submodels(info.annotation)
        if nxt:
            candidates = nxt
    keys: list[str] = []
    for cand in candidates:
        keys += [info.alias or name for name, info in cand.model_fields.items()]
    return sorted(set(keys))


def _describe(value: Any) -> str:
    text = repr(value)
    return text if len(text) <= 40 else text[:37] + "..."


def validate(located: Located, model: type[M]) -> M:
    """Validate located data against ``model``; raise a DataError at the first problem."""
    if not isinstance(located.data, dict):
        raise located.error((), f"expected a mapping of settings for a {model.__name__}, "
                                f"got {type(located.data).__name__}")
    try:
        return model.model_validate(located.data)
    except pydantic.ValidationError as exc:
        raise to_data_error(located, model, exc) from None


def _data_loc(located: Located, loc: tuple) -> tuple:
    """Drop the parts of a pydantic loc (union branch tags) that are not data keys."""
    data, path = located.data, []
    for part in loc:
        if isinstance(part, str) and part.startswith("<") and part != "<key>":
            continue  # a tagged union's branch name, e.g. "<grid>"
        if isinstance(data, dict) and part not in data and data.get("type") == part:
            continue  # a discriminated union's branch ("type: circle")
        if isinstance(data, dict) and part in data:
            data = data[part]
            path.append(part)
        elif isinstance(data, list) and isinstance(part, int) and 0 <= part < len(data):
            data = data[part]
            path.append(part)
        elif isinstance(part, str) and part not in ("<key>",) and isinstance(data, dict):
            path.append(part)  # a missing key; keep for the message
            break
    return tuple(path)


def to_data_error(located: Located, model: type[pydantic.BaseModel],
                  exc: pydantic.ValidationError) -> DataError:
    errors = exc.errors()
    # A misspelt key also makes the intended key "missing": report the misspelling.
    # A union error lists one entry per branch; the most specific (longest loc) is best.
    err = max(errors, key=lambda e: (e["type"] == "extra_forbidden",
                                     len(_data_loc(located, e["loc"]))))
    loc = _data_loc(located, err["loc"])
    name = ".".join(str(p) for p in loc) or "(top level)"
    kind = err["type"]
    if kind == "extra_forbidden":
        key = loc[-1] if loc else "?"
        allowed = _allowed_keys(model, loc[:-1])
        close = difflib.get_close_matches(str(key), allowed, n=1)
        hint = f"; did you mean '{close[0]}'?" if close else ";"
        return located.error(loc, f"unknown key '{key}'{hint} expected one of: "
                                  f"{', '.join(allowed)}", prefer_key=True)
    if kind == "missing":
        parent = loc[:-1]
        return located.error(parent, f"missing required key '{loc[-1]}' in "
                                     f"{'.'.join(str(p) for p in parent) or 'the file'}")
    got = f" (got {_describe(err['input'])})" if "input" in err else ""
    return located.error(loc, f"bad value for '{name}': {plain_message(err)}{got}")


def _quoted(values) -> str:
    if isinstance(values, str):  # pydantic's own list, e.g. "'box', 'circle'"
        values = [v.strip().strip("'") for v in values.replace(" or ", ",").split(",")]
    return ", ".join(str(v) for v in values if str(v))


_BOUNDS = {"greater_than": ("gt", "more than"), "greater_than_equal": ("ge", "at least"),
           "less_than": ("lt", "less than"), "less_than_equal": ("le", "at most")}
_KINDS = {"float": "a number", "int": "a whole number", "bool": "true or false",
          "string": "text", "list": "a list", "tuple": "a list", "dict": "a mapping",
          "model": "a mapping of settings", "dataclass": "a mapping of settings",
          "set": "a list"}


def plain_message(err: dict) -> str:
    """What a pydantic error means, in puppet's words (pydantic's own wording, such as
    "Input tag 'x' found using 'type' does not match any of the expected tags", is
    library talk): by the error's type, with its context values."""
    kind, ctx = err["type"], err.get("ctx") or {}
    if kind in ("value_error", "assertion_error"):
        msg = str(ctx.get("error", err["msg"]))
        for prefix in ("Value error, ", "Assertion failed, "):
            msg = msg.removeprefix(prefix)
        return msg
    if kind == "union_tag_invalid":
        return (f"unknown {str(ctx.get('discriminator', 'type')).strip(chr(39))} "
                f"'{ctx.get('tag')}'; expected one of: {_quoted(ctx.get('expected_tags', ''))}")
    if kind == "union_tag_not_found":
        key = str(ctx.get("discriminator", "type")).strip("'")
        return f"missing '{key}', which says what it is"
    if kind in ("literal_error", "enum"):
        return f"expected one of: {_quoted(ctx.get('expected', ''))}"
    if kind in _BOUNDS:
        key, words = _BOUNDS[kind]
        value = ctx.get(key)
        return f"must be {words} {value:g}" if isinstance(value, (int, float)) \
            else f"must be {words} {value}"
    if kind == "too_short":
        return f"expected at least {ctx.get('min_length')} item(s)"
    if kind == "too_long":
        return f"expected at most {ctx.get('max_length')} item(s)"
    if kind == "finite_number":
        return "expected a finite number"
    for prefix, what in _KINDS.items():
        if kind.startswith(prefix + "_") or kind == prefix:
            return f"expected {what}"
    if kind in ("int_from_float",):
        return "expected a whole number"
    msg = err["msg"]  # a kind not met yet: pydantic's words, made less like a library's
    return msg.replace("Input should be", "expected").replace("Input", "the value")
