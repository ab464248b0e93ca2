"""Motion capture: reading, forward kinematics and retargeting of the shipped clips,
KD control of the walk clip, and a live sample's latency (``latency.py``)."""

from __future__ import annotations

import dataclasses
import statistics
import time

from puppet.commands.bench.config import BVH_READ_TARGET_MS, median_ms, target


def measure_mocap(repeats: int, seconds: float = 8.0) -> dict:
    """Reading each shipped BVH clip (assets/mocap/), its forward kinematics and its
    retargeting (through the first mapping that names its joints); then the figure
    driven by the walk clip under KD control (biped-mocap), against the same clip's
    channels with tracking off (what the pulls and the tracker cost)."""
    from puppet.data.catalog import ROOT, load_setup
    from puppet.mocap.bvh import read_bvh
    from puppet.mocap.clip_source import ClipSource
    from puppet.mocap.info import matching_mappings
    from puppet.mocap.retarget import retarget_clip
    from puppet.session import Session

    items = []
    walk = None
    for path in sorted((ROOT / "assets" / "mocap").glob("*.bvh")):
        clip = read_bvh(path)
        read_ms = median_ms(lambda path=path: read_bvh(path), repeats)
        fk_ms = median_ms(clip.world_positions, repeats)
        item = {"clip": path.name, "bytes": path.stat().st_size, "frames": clip.frames,
                "joints": len(clip.joints), "read_ms": read_ms, "fk_ms": fk_ms}
        found = matching_mappings(clip)
        if found:
            name, mapping = found[0]
            item["mapping"] = name
            item["retarget_ms"] = median_ms(lambda clip=clip, mapping=mapping:
                                            retarget_clip(clip, mapping), repeats)
            if "walk" in path.name:
                walk = retarget_clip(clip, mapping)
        items.append(item)
    out = {"items": items,
           "targets": [target(f"read {i['clip']}", i["read_ms"], "<", BVH_READ_TARGET_MS,
                               "ms") for i in items]}
    if walk is not None:
        setup = load_setup("biped-mocap")
        off = setup.interface.model_copy(update={"tracking": setup.interface.tracking.model_copy(
            update={"start": "off"})})
        runs = {"kd": setup, "off": dataclasses.replace(setup, interface=off)}
        walls = {k: [] for k in runs}
        for _ in range(max(1, repeats)):
            for kind, s in runs.items():
                session = Session(s)
                events = ClipSource(walk).events(session.sim.dt, min(seconds, walk.duration))
                until = events[-1][0] + 1
                t0 = time.perf_counter()
                fed = iter(events)
                nxt = next(fed, None)
                while session.steps < until:
                    while nxt is not None and nxt[0] <= session.steps:
                        session.handle(nxt[1])
                        nxt = next(fed, None)
                    session.advance((nxt[0] if nxt is not None else until) - session.steps)
                walls[kind].append(time.perf_counter() - t0)
        sim = until * session.sim.dt
        kd, bare = statistics.median(walls["kd"]), statistics.median(walls["off"])
        out["kd_walk"] = {"seconds": sim, "kd_speed_x": sim / kd, "off_speed_x": sim / bare,
                          "overhead_pct": 100.0 * (kd / bare - 1.0)}
    return out


def measure_mocap_latency(seconds: float) -> dict:
    """A live sample's way from its arrival over loopback to the servo targets, in a
    60 fps frame loop (``latency.py``: puppet channels onto maps, and VMC
    bones retargeted onto KD tracking): it must act at the next frame."""
    from puppet.commands.bench.latency import measure_latency

    out = {}
    for path in ("puppet", "vmc"):
        res = measure_latency(seconds, path=path)
        res["target"] = target(f"mocap-latency ({path}): samples acting at the next "
                                f"60 fps frame", res["next_frame_pct"], ">=", 100.0, "%")
        out[path] = res
    return out
