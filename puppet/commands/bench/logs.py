"""Replay speed of every shipped log, with its expectations, as the tests replay them."""

from __future__ import annotations

import gc
import statistics

from puppet.commands.bench.config import clock


def measure_logs(repeats: int, seconds: float | None = None) -> dict:
    """Each shipped log replayed headless (with its trajectory, as the tests do): the
    whole log, or (``seconds``, the quick run) its first seconds only."""
    from puppet.data.catalog import folder

    logs = sorted(folder("log").glob("*.jsonl"))
    if not logs:
        return {"status": "no logs", "items": []}
    from puppet.timeline.log import read_log
    from puppet.timeline.replay import replay

    items = []
    gc.collect()
    for path in logs:
        item: dict = {"log": path.stem}
        try:
            log = read_log(path)  # read once: the figure is the replay's, as in the tests
            until = None if seconds is None else round(seconds / log.header["dt"])
            walls = []
            result = None
            for _ in range(repeats):
                if repeats > 1:  # a full collection costs ~70 ms on the bench's heap
                    gc.collect()
                t0 = clock()
                result = replay(log, until_step=until)
                walls.append(clock() - t0)
            wall = statistics.median(walls)
            played = result.time
            item.update({"wall_s": wall, "sim_seconds": played,
                         "speed_x": played / wall if played and wall > 0 else None})
        except Exception as exc:  # noqa: BLE001 - a report, not a test
            item["error"] = f"{type(exc).__name__}: {exc}"
        items.append(item)
    return {"status": "ok" if seconds is None else f"ok, the first {seconds:g} s of each",
            "items": items}
