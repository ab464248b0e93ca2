"""Arithmetic a tuning spec may write where a number goes: ``t_push + flick + 0.05``.

A data file never runs code, so this is not Python's ``eval``: the text is parsed by
``ast`` and only numbers, names, ``+ - * / **``, parentheses and a few functions
(``min max abs sqrt sin cos floor ceil``) and the constant ``pi`` are accepted; anything
else is a one-line error naming what is not allowed. Names are the stage's parameters,
its ``let:`` values and what the stage defines (``cycle``, ``cycles_end``); an unknown
name is refused when the spec is read, not when a try runs.
"""

from __future__ import annotations

import ast
import math
from collections.abc import Callable, Iterable

FUNCTIONS: dict[str, Callable[..., float]] = {
    "min": min, "max": max, "abs": abs, "sqrt": math.sqrt, "sin": math.sin,
    "cos": math.cos, "floor": math.floor, "ceil": math.ceil,
}
CONSTANTS = {"pi": math.pi}
_BINARY = {ast.Add: lambda a, b: a + b, ast.Sub: lambda a, b: a - b,
           ast.Mult: lambda a, b: a * b, ast.Div: lambda a, b: a / b,
           ast.Pow: lambda a, b: a ** b}


class ExprError(ValueError):
    """What is wrong with an expression, one line."""


class Expr:
    """A parsed expression: ``names`` it reads, ``__call__(values)`` its number."""

    def __init__(self, text: str | float | int):
        self.text = str(text)
        if isinstance(text, (int, float)) and not isinstance(text, bool):
            value = float(text)
            self.names: frozenset[str] = frozenset()
            self._fn = lambda values: value
            return
        try:
            tree = ast.parse(self.text.strip(), mode="eval")
        except SyntaxError:
            raise ExprError(f"'{self.text}' is not arithmetic (expected numbers, names, "
                            "+ - * / ** and parentheses, e.g. 'hold + 0.15')") from None
        names: set[str] = set()
        self._fn = _compile(tree.body, names, self.text)
        self.names = frozenset(names)

    def check(self, known: Iterable[str], where: str = "") -> None:
        """ExprError for a name that is neither known nor a constant."""
        known = set(known)
        for name in sorted(self.names):
            if name not in known and name not in CONSTANTS:
                listed = ", ".join(sorted(known)) or "none"
                raise ExprError(f"'{self.text}': unknown name '{name}'"
                                f"{' ' + where if where else ''}; the names here: {listed}")

    def __call__(self, values: dict[str, float]) -> float:
        try:
            out = float(self._fn(values))
        except ZeroDivisionError:
            raise ExprError(f"'{self.text}' divides by zero") from None
        except (OverflowError, ValueError) as exc:
            raise ExprError(f"'{self.text}': {exc}") from None
        if not math.isfinite(out):
            raise ExprError(f"'{self.text}' is not a finite number")
        return out

    def __repr__(self) -> str:
        return f"Expr({self.text!r})"


def _compile(node, names: set[str], text: str):
    if isinstance(node, ast.Constant) and isinstance(node.value, (int, float)) \
            and not isinstance(node.value, bool):
        value = float(node.value)
        return lambda v: value
    if isinstance(node, ast.Name):
        name = node.id
        if name in CONSTANTS:
            const = CONSTANTS[name]
            return lambda v: const
        names.add(name)
        return lambda v: v[name]
    if isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.USub, ast.UAdd)):
        inner = _compile(node.operand, names, text)
        return (lambda v: -inner(v)) if isinstance(node.op, ast.USub) else inner
    if isinstance(node, ast.BinOp) and type(node.op) in _BINARY:
        op = _BINARY[type(node.op)]
        a, b = _compile(node.left, names, text), _compile(node.right, names, text)
        return lambda v: op(a(v), b(v))
    if isinstance(node, ast.Call) and isinstance(node.func, ast.Name) \
            and node.func.id in FUNCTIONS and not node.keywords and node.args:
        fn = FUNCTIONS[node.func.id]
        args = [_compile(a, names, text) for a in node.args]
        return lambda v: fn(*(a(v) for a in args))
    what = (f"the function '{node.func.id}'" if isinstance(node, ast.Call)
            and isinstance(node.func, ast.Name) else f"'{ast.unparse(node)}'")
    raise ExprError(f"'{text}': {what} is not allowed (expected numbers, names, "
                    f"+ - * / **, and {', '.join(FUNCTIONS)})")
