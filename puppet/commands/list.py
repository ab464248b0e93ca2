"""``puppet list``: what can be named on the command line, with each file's one-line
description, by kind (characters, interfaces, scenes, scripts, logs, recordings)."""

from __future__ import annotations

import argparse

# what ``puppet list`` lists; "recording": the window's own logs (recordings/)
KINDS = ("character", "interface", "scene", "script", "log", "recording")


def _kind(text: str) -> str:
    """``puppet list KIND``: a kind as the headings print it (interfaces) or singular."""
    word = text.strip().lower()
    return word[:-1] if word.endswith("s") and word[:-1] in KINDS else word


def register(subparsers) -> None:
    """``puppet list [KIND]``."""
    lst = subparsers.add_parser("list", help="list characters, interfaces, scenes, scripts, logs "
                                             "and your recordings",
                                description="List what can be named on the command line, with "
                                            "each file's one-line description: characters/, "
                                            "interfaces/, assets/scenes/, assets/scripts/, "
                                            "assets/logs/ and recordings/ (the window's own logs).")
    lst.add_argument("kind", nargs="?", choices=KINDS, metavar="KIND", type=_kind,
                     help=f"only this kind: {', '.join(KINDS)}, or the plural as the "
                          f"headings say (interfaces) (default: all)")
    lst.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from puppet.data.catalog import FOLDERS, list_kind

    kinds = [args.kind] if args.kind else list(KINDS)
    for kind in kinds:
        items = list_kind(kind)
        print(f"{kind}s ({FOLDERS[kind][0]}/):")
        if not items:
            print("  (none)")
        width = max((len(n) for n, _ in items), default=0)
        for name, text in items:
            print(f"  {name:<{width}}  {text}")
    return 0
