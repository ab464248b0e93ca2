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

    model_config = pydantic.ConfigDict(extra="forbid", populate_by_name=True, frozen=False)


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
    msg = err["msg"]
    if msg.startswith("Value error, "):
        msg = msg[len("Value error, "):]
    got = f" (got {_describe(err['input'])})" if "input" in err else ""
    return located.error(loc, f"bad value for '{name}': {msg}{got}")
