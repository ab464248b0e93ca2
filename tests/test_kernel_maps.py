"""The cat's pose grids in the kernel (``pk_grid_run``, ``physics.kernel_maps``) write
the targets ``maps._grid_run``'s Python writes, to the bit: over the whole mouse
square, its edges and corners, outside it, on whole numbers and on NaN; and after a
rebuild has bound new springs."""

from __future__ import annotations

import math
import struct

from kernel_paths import needs_cc

from puppet.timeline.log import read_log
from puppet.timeline.replay import new_session, setup_for_log

POINTS = [(x / 20.0, y / 20.0) for x in range(-2, 23) for y in range(-2, 23)] + [
    (0, 0), (1, 1), (0, 1), (1, 0), (0.5, math.nan), (math.nan, 0.5), (math.inf, -math.inf),
    (0.999999999, 1e-12), (1 / 3, 2 / 3)]


def _bits(v: float) -> bytes:
    return struct.pack("<d", v)


def _session(name: str = "cat-trot"):
    log = read_log(f"assets/logs/{name}.jsonl")
    return new_session(log, setup_for_log(log)[0])


def _targets(session, points) -> list:
    rt = session.runtime
    out = []
    for x, y in points:
        values = {"mouse.x": x, "mouse.y": y}
        for apply in rt._mouse_maps:
            apply(values)
        out.append([_bits(s.target) for s in session.character.servos.values()])
    return out


@needs_cc
def test_the_grids_in_the_kernel_write_pythons_bits(path_of, monkeypatch):
    assert path_of("c") is not None
    fast = _session()
    kinds = [getattr(a, "__name__", "") for a in fast.runtime._mouse_maps]
    assert kinds == ["apply_grid_run_kernel"], kinds
    with_kernel = _targets(fast, POINTS)
    assert path_of("python") is None
    slow = _session()
    assert [a.__name__ for a in slow.runtime._mouse_maps] == ["apply_grid_run"]
    assert with_kernel == _targets(slow, POINTS)
    # a rebuild on a fresh space binds new springs: the kernel follows them
    from puppet.physics import simulation

    rebuild = simulation.snapshot.rebuild
    monkeypatch.setattr(simulation.snapshot, "rebuild",
                        lambda state, into=None: rebuild(state, into=None))
    for session in (fast, slow):
        session.advance(300)
        springs = [s.spring for s in session.character.servos.values()]
        session.checkpoint()
        assert not any(s.spring is k for s, k in zip(session.character.servos.values(),
                                                      springs))
    assert _targets(fast, POINTS[:40]) == _targets(slow, POINTS[:40])
    for session in (fast, slow):
        session.advance(50)
    assert fast.sim.state_hash() == slow.sim.state_hash()
