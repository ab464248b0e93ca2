"""The ``puppet`` command: one module per sub-command (play, replay, check, list, bench,
mocap, playtest, tune), each with ``register(subparsers)`` (its options) and the function it runs.

argparse (standard library) rather than a CLI framework: it gives sub-commands,
--help and typed options with no extra dependency. Every module imports only argparse
and the data layer at the top, and what its run needs when it runs: ``puppet
--version`` and ``puppet check`` start fast.
"""

from __future__ import annotations

import argparse
import contextlib
import os
import sys

from puppet import __version__
from puppet.commands import bench, check, mocap, play, playtest, replay, tune
from puppet.commands import list as list_command
from puppet.commands.options import EXIT_DATA_ERROR
from puppet.data.errors import DataError, UsageError, did_you_mean

SUBCOMMANDS = (play, mocap, replay, list_command, check, playtest, tune, bench)  # in --help's order


class Parser(argparse.ArgumentParser):
    """argparse's parser, its mistakes in one line (docs/playing.md, Errors): ``puppet play:
    argument --seconds: '-1' is not ... (puppet play --help)``, exit 2, with no usage
    block above it; a mistyped choice or option gets a did-you-mean. Sub-command parsers
    are made of the same class (add_subparsers). No abbreviations: ``--headles`` is a
    mistake, not ``--headless`` (a prefix that happens to fit today would quietly mean
    another option once one is added)."""

    def __init__(self, *args, allow_abbrev: bool = False, **kwargs):
        super().__init__(*args, allow_abbrev=allow_abbrev, **kwargs)

    def error(self, message: str):
        self.exit(EXIT_DATA_ERROR, f"{self.prog}: {message} ({self.prog} --help)\n")

    def parse_known_args(self, args=None, namespace=None):
        # The innermost parser's prog ("puppet mocap send") ends up in the namespace: a
        # sub-command's parser writes it after its parent did (argparse copies the
        # sub-namespace over), so messages name the command that was run; and its
        # options, for a did-you-mean on an unrecognized one.
        namespace = argparse.Namespace() if namespace is None else namespace
        namespace.command_prog = self.prog
        namespace.command_options = sorted(self._option_string_actions)
        return super().parse_known_args(args, namespace)

    def _check_value(self, action, value):
        # argparse's own check of a choice (a sub-command, a list kind, a format): the
        # same message with the nearest choice named (Python 3.14's suggest_on_error)
        if action.choices is not None and value not in action.choices:
            choices = ", ".join(repr(c) for c in action.choices)
            raise argparse.ArgumentError(action, f"invalid choice: {value!r}"
                                                 f"{did_you_mean(value, action.choices)} "
                                                 f"(choose from {choices})")
        super()._check_value(action, value)


def build_parser() -> argparse.ArgumentParser:
    parser = Parser(
        prog="puppet",
        description="Drive physically simulated planar characters in real time.")
    parser.add_argument("--version", action="version", version=f"puppet {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    for command in SUBCOMMANDS:
        command.register(sub)
    return parser


def main(argv: list[str] | None = None) -> int:
    # pygame's banner goes to stdout on import: it would break `--json` output (bench)
    os.environ.setdefault("PYGAME_HIDE_SUPPORT_PROMPT", "1")
    parser = build_parser()
    args, extra = parser.parse_known_args(argv)
    if extra:  # argparse's parse_args says this as the root parser ("puppet: ...")
        hint = next((h for h in (did_you_mean(x, args.command_options, 0.75) for x in extra
                                 if x.startswith("-")) if h), "")
        parser.exit(EXIT_DATA_ERROR, f"{args.command_prog}: unrecognized arguments: "
                                     f"{' '.join(extra)}{hint} ({args.command_prog} --help)\n")
    if not getattr(args, "func", None):
        parser.print_help()
        return 0
    try:
        return args.func(args)
    except (DataError, UsageError) as exc:  # "puppet mocap send: ...", "puppet play: ..."
        print(f"{args.command_prog}: {exc}", file=sys.stderr)
        return EXIT_DATA_ERROR
    except KeyboardInterrupt:
        return 130
    except BrokenPipeError:  # the output went to a pipe that closed (| head): fine
        with contextlib.suppress(OSError):
            sys.stdout = open(os.devnull, "w")  # noqa: SIM115 - kept open till exit
        return 0
