"""The one error a user's data mistake raises: where it is and what was expected."""

from __future__ import annotations


class DataError(Exception):
    """A malformed data file. Printed as one line: ``file:line:col: message``."""

    def __init__(self, path: str, line: int | None, col: int | None, message: str):
        self.path = str(path)
        self.line = line
        self.col = col
        self.message = message
        super().__init__(str(self))

    def __str__(self) -> str:
        where = self.path
        if self.line is not None:
            where += f":{self.line}"
            if self.col is not None:
                where += f":{self.col}"
        return one_line(f"{where}: {self.message}")


_CONTROL = {i: f"\\x{i:02x}" for i in range(32)} | {10: "\\n", 13: "\\r", 9: "\\t",
                                                     0x85: "\\x85", 0x2028: "\\u2028",
                                                     0x2029: "\\u2029", 127: "\\x7f"}


def one_line(text: str) -> str:
    """``text`` with line breaks and control characters written as escapes (a name
    from a file may hold them; the error must stay one line)."""
    return text.translate(_CONTROL)


def did_you_mean(name, known, cutoff: float = 0.6) -> str:
    """``; did you mean 'x'?`` naming the one of ``known`` closest to a mistyped
    ``name`` (difflib's ratio at least ``cutoff``), else nothing."""
    import difflib  # only for a mistake (process start)

    close = difflib.get_close_matches(str(name), [str(k) for k in known], n=1, cutoff=cutoff)
    return f"; did you mean '{close[0]}'?" if close else ""


class UsageError(Exception):
    """A command used wrongly (a bad option, a path that is not there, no display).

    The command line prints it as one line, ``puppet COMMAND: message``, and exits 2."""
