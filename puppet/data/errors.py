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
        return f"{where}: {self.message}"


class UsageError(Exception):
    """A command used wrongly (a bad option, a path that is not there, no display).

    The command line prints it as one line, ``puppet COMMAND: message``, and exits 2."""
