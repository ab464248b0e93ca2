"""The ``puppet`` command: one module per sub-command (play, replay, check, list, bench,
mocap), each with ``register(subparsers)`` (its options) and the function it runs.

argparse (standard library) rather than a CLI framework: it gives sub-commands,
--help and typed options with no extra dependency. Every module imports only argparse
and the data layer at the top, and what its run needs when it runs: ``puppet
--version`` and ``puppet check`` start fast.
"""

from __future__ import annotations

import argparse
import os
import sys

from puppet import __version__
from puppet.commands import bench, check, mocap, play, replay
from puppet.commands import list as list_command
from puppet.commands.options import EXIT_DATA_ERROR
from puppet.data.errors import DataError, UsageError

SUBCOMMANDS = (play, mocap, replay, list_command, check, bench)  # in --help's order


class Parser(argparse.ArgumentParser):
    """argparse's parser, its mistakes in one line (README, Errors): ``puppet play:
    argument --seconds: '-1' is not ... (puppet play --help)``, exit 2, with no usage
    block above it. Sub-command parsers are made of the same class (add_subparsers)."""

    def error(self, message: str):
        self.exit(EXIT_DATA_ERROR, f"{self.prog}: {message} ({self.prog} --help)\n")

    def parse_known_args(self, args=None, namespace=None):
        # The innermost parser's prog ("puppet mocap send") ends up in the namespace: a
        # sub-command's parser writes it after its parent did (argparse copies the
        # sub-namespace over), so messages name the command that was run.
        namespace = argparse.Namespace() if namespace is None else namespace
        namespace.command_prog = self.prog
        return super().parse_known_args(args, namespace)


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
    parser = build_parser()
    args, extra = parser.parse_known_args(argv)
    if extra:  # argparse's parse_args says this as the root parser ("puppet: ...")
        parser.exit(EXIT_DATA_ERROR, f"{args.command_prog}: unrecognized arguments: "
                                     f"{' '.join(extra)} ({args.command_prog} --help)\n")
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
        try:
            sys.stdout = open(os.devnull, "w")  # noqa: SIM115 - kept open till exit
        except OSError:
            pass
        return 0
