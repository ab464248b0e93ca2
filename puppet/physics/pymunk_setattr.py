"""pymunk's objects set their attributes without its typing hook's extra Python call.

pymunk's Body, Shape and Constraint inherit ``TypingAttrMixing``, whose
``__setattr__`` only calls ``super().__setattr__`` (it is there "to make mypy accept
dynamic attributes"). Every attribute and property written on a pymunk object - the
~360 of a biped checkpoint's rebuild, a servo's gains - pays that extra call: about
a tenth of a checkpoint. Removing the override leaves ``object.__setattr__``, which
is what it called, so nothing else changes. It is removed only when it is exactly
that one delegating call (compared as bytecode), so a pymunk whose hook does more
keeps it.
"""

from __future__ import annotations

from pymunk._typing_attr import TypingAttrMixing


class _Delegating:
    def __setattr__(self, name, value):
        """(a docstring, as pymunk's has: it is the code's first constant)"""
        super().__setattr__(name, value)


def only_delegates(function) -> bool:
    """Whether ``function`` is ``super().__setattr__(name, value)`` and nothing else."""
    mine, theirs = _Delegating.__setattr__.__code__, getattr(function, "__code__", None)
    return theirs is not None and theirs.co_consts[1:] == mine.co_consts[1:] and all(
        getattr(mine, field) == getattr(theirs, field)
        for field in ("co_code", "co_names", "co_varnames", "co_freevars"))


removed = None  # pymunk's hook, once removed (tests put it back to compare)


def remove_typing_setattr() -> bool:
    """Drop pymunk's delegating ``__setattr__``; whether it was (or is already) gone."""
    global removed
    hook = TypingAttrMixing.__dict__.get("__setattr__")
    if hook is None:
        return True
    if not only_delegates(hook):
        return False
    removed = hook
    del TypingAttrMixing.__setattr__
    return True


remove_typing_setattr()
