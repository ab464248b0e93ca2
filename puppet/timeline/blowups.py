"""How a headless run tells its blow-ups: each kind once, with a count.

A session says one message per blow-up (``Session._recover``): "the simulation left the
world at t=12.30 s; restored the checkpoint of t=0.00 s". A long run that leaves the
world again and again, each time put back on the same checkpoint, printed that line
sixteen times; ``fold`` makes it one, with the count and the first and last times. A
halted run (even the start failed again: the physics stands still) says so on its end
line instead of a centre of mass thousands of metres away (``end_words``).
"""

from __future__ import annotations

import re

_RECOVERED = re.compile(r"the simulation (?P<what>blew up|left the world) at "
                        r"t=(?P<t>-?[0-9.]+) s; restored the checkpoint of "
                        r"t=(?P<to>-?[0-9.]+) s")


def fold(messages: list[str]) -> list[str]:
    """The messages with the recoveries of one kind (blew up, left the world) said
    once, where the first came: "... left the world 16 times (first at t=1.20 s, last
    at t=31.85 s); restored the checkpoint of t=0.00 s each time" (or "the last
    checkpoint before it each time, t=3.00..30.00 s" when those differ). Any other
    message (a halt) stays as it is, in its place."""
    groups: dict[str, list[tuple[str, str]]] = {}
    order: list = []
    for text in messages:
        m = _RECOVERED.fullmatch(text)
        if m is None:
            order.append(("text", text))
            continue
        if m["what"] not in groups:
            groups[m["what"]] = []
            order.append(("group", m["what"]))
        groups[m["what"]].append((m["t"], m["to"]))
    out = []
    for kind, item in order:
        if kind == "text":
            out.append(item)
            continue
        seen = groups[item]
        if len(seen) == 1:
            out.append(f"the simulation {item} at t={seen[0][0]} s; restored the "
                       f"checkpoint of t={seen[0][1]} s")
            continue
        tos = [to for _, to in seen]
        restored = (f"restored the checkpoint of t={tos[0]} s each time" if len(set(tos)) == 1
                    else f"restored the last checkpoint before it each time "
                         f"(t={min(tos, key=float)}..{max(tos, key=float)} s)")
        out.append(f"the simulation {item} {len(seen)} times (first at t={seen[0][0]} s, "
                   f"last at t={seen[-1][0]} s); {restored}")
    return out


def end_words(session) -> str | None:
    """What a headless run's end line says instead of where the figure is, when the
    physics halted: "halted at t=... s after N blow-ups" (None: it did not)."""
    if not session.halted:
        return None
    at = getattr(session, "halted_at", None)
    when = f" at t={at:.2f} s" if at is not None else ""
    n = session.blowups
    return f"halted{when} after {n} blow-up{'' if n == 1 else 's'}"
