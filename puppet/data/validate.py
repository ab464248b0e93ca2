"""Validate located YAML data with msgspec; turn its errors into one-line, file:line:col
DataErrors in puppet's words.

msgspec does the checking (types, ranges, lengths, unknown keys; ``msgspec.convert``
in C). Its error is one line of text, ``what - at `$.links[0].mass```; this module
parses that text, walks the data and the types along the path (which file position,
which range, which keys were allowed) and says it as puppet does: ``bad value for
'links.0.mass': must be a finite number in 0.001..1000 kg (got -1.0)``. None of
msgspec's own wording reaches the user.

Conversion is not strict (``strict=False``), as pydantic's lax mode was not: a whole
number for a decimal one (``2`` -> ``2.0``, as in strict mode), ``2.0`` for a whole
number, a number written as text (``'0.5'``), 1 and 0 for true and false; true/false
is never a number, a number never text. Not quite every file pydantic took is taken:
true/false for a plain bounded number (pydantic took it as 1/0 there), ``'yes'`` and
``0.0`` for true/false, and text numbers such as ``' 7'``, ``'.5'``, ``'1_0'`` are now
refused (none of the shipped files has one); ``'1e3'`` for a whole number is now taken.

Two things msgspec leaves to us, done here:

- a union of several mapping types told apart by a callable rather than a ``type:``
  key (a map is a grid map if it has ``grid``): the field is annotated with a marker
  class registered with ``dispatch``, which the ``dec_hook`` converts to the class the
  callable picks (the inner error keeps its path: ``... - at `$.grid[0]` - at
  `$.maps[1]```);
- a check of one field inside a struct's ``__post_init__`` (an input's name): raise
  ``at(field, message)``, whose path points at the field.

The message is made by ``puppet.data.validate_errors``, imported only when there is an
error (process start).
"""

from __future__ import annotations

import copy
from collections.abc import Callable
from typing import Any, TypeVar

import msgspec

from puppet.data.yamlfile import Located

M = TypeVar("M")

field = msgspec.field
Meta = msgspec.Meta


class Spec(msgspec.Struct, forbid_unknown_fields=True):
    """Base of every data-file struct: unknown keys are errors, values are checked.
    (Each subclass also says ``kw_only=True``: msgspec does not inherit it, and fields
    with defaults come before required ones in our files' order.)"""

    def model_copy(self, update: dict | None = None):
        """A copy with some fields replaced, not checked again (``structs.replace`` would
        run ``__post_init__``: a map renamed to a channel's bare name is no input)."""
        new = copy.copy(self)
        for name, value in (update or {}).items():
            setattr(new, name, value)
        return new

    @classmethod
    def model_validate(cls, data):
        """``data`` (plain Python) converted to this struct; msgspec.ValidationError."""
        return msgspec.convert(data, cls, dec_hook=_dec_hook, strict=False)


_DISPATCH: dict[type, Callable[[Any], type]] = {}


def dispatch(marker: type, choose: Callable[[Any], type]) -> None:
    """Fields annotated ``marker`` hold the struct ``choose(data)`` picks."""
    _DISPATCH[marker] = choose


def _dec_hook(kind: type, obj: Any) -> Any:
    choose = _DISPATCH.get(kind)
    if choose is None:
        raise NotImplementedError(kind)
    try:
        return msgspec.convert(obj, choose(obj), dec_hook=_dec_hook, strict=False)
    except msgspec.ValidationError as exc:
        raise ValueError(str(exc)) from None  # msgspec adds where the field is


def at(name: str, message: str) -> ValueError:
    """The error of one field's check made in ``__post_init__``, located at the field."""
    return ValueError(f"{message} - at `$.{name}`")


def validate(located: Located, model: type[M]) -> M:
    """Validate located data against ``model``; raise a DataError at the first problem."""
    if not isinstance(located.data, dict):
        raise located.error((), f"expected a mapping of settings for a {model.__name__}, "
                                f"got {type(located.data).__name__}")
    try:
        return msgspec.convert(located.data, model, dec_hook=_dec_hook, strict=False)
    except msgspec.ValidationError as exc:
        from puppet.data.validate_errors import to_data_error  # only when there is one

        raise to_data_error(located, model, str(exc)) from None


def located_data(data: Any, path: str) -> Located:
    """Data built in code (not read from a file) to validate: errors carry no line."""
    return Located(path, data)
