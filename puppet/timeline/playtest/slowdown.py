"""The slowdown in force at each event of a log: what a person's real-time error is
divided by.

A log starts at its header's slowdown; the app's slower / faster keys and an interface
key's ``slowdown:`` change it as they did live (the window's clock follows the same
actions when it replays: ``SimClock.apply``). Which key does what can depend on the
interface's state, so a log that may change it is replayed once, with nothing
perturbed, to read the actions its events asked for; a log that cannot (no such key
pressed, no hot reload) keeps its header's slowdown throughout, at no cost.
"""

from __future__ import annotations

from puppet.data.catalog import Setup
from puppet.data.interface_refs import actions
from puppet.data.keys import normalize_key
from puppet.timeline.log import Log
from puppet.timeline.reactive import Speed


def _chord(event: dict) -> str | None:
    """The key (or button acting as a key) an event presses, else None."""
    kind = event["type"]
    if kind == "key" and event["down"]:
        return normalize_key(event["key"])
    if kind == "mouse_button" and event["down"]:
        return f"mouse.{event['button']}"
    if kind == "gamepad":
        return f"gamepad.{event['name']}"
    return None


def may_change(log: Log, setup: Setup) -> bool:
    """Whether any event of the log could change the slowdown: a press of the app's
    slower / faster key, any press when the interface binds a ``slowdown:``, a reload."""
    table = setup.interface.app_key_table()
    speed_keys = {table.get("slower"), table.get("faster")}
    binds = any(a.slowdown is not None for _, a in actions(setup.interface))
    for e in log.events:
        if e.event["type"] == "reload":
            return True
        chord = _chord(e.event)
        if chord is not None and (binds or chord in speed_keys):
            return True
    return False


def in_force(log: Log, setup: Setup) -> list[float]:
    """The slowdown in force when each of ``log.events`` acted (before it acts)."""
    start = float(log.header.get("slowdown") or 1.0)
    if not may_change(log, setup):
        return [start] * len(log.events)
    from puppet.timeline.replay import LogFeeder, new_session

    session = new_session(log, setup)
    speed = Speed(start)
    after: dict[int, float] = {}  # event index -> the slowdown after it acted

    def on_action(action) -> None:
        speed.apply(action)
        after[feeder.i - 1] = speed.value

    feeder = LogFeeder(session, log, on_action=on_action)
    while not feeder.finished:
        feeder.advance(1 << 30)
    out, now = [], start
    for i in range(len(log.events)):
        out.append(now)
        now = after.get(i, now)
    return out
