"""Restoring a snapshot with cached contacts frees the arbiters the previous space
allocated (pymunk's unpickling never does: about 0.2 kB per cached arbiter per
restore, 25-90 MB over 30 minutes of scrubbing before)."""

import gc

from puppet.data.catalog import load_setup
from puppet.physics import snapshot
from puppet.session import Session


def test_each_restore_frees_the_arbiters_of_the_space_it_replaces(monkeypatch):
    session = Session(load_setup("cat-trot"))
    session.advance(960)  # standing: contacts cached
    snap = session.sim.snapshot()
    cached = len(session.sim.space._get_arbiters())
    assert cached >= 2
    freed = []
    real = snapshot._libc_free()
    monkeypatch.setattr(snapshot, "_FREE", lambda p: freed.append(p) or real(p))
    session.sim.restore(snap)  # the space before it held arbiters of its own making
    gc.collect()
    freed.clear()
    for _ in range(50):
        session.sim.restore(snap)
    gc.collect()
    assert len(freed) == 50 * cached  # every replaced space's, none of the live one's
    assert len(set(freed)) >= cached
    ends = []
    for _ in range(3):  # each restored space steps alike: nothing live was freed
        session.sim.restore(snap)
        gc.collect()
        session.sim.step(480)
        ends.append(session.sim.state_hash())
    assert not session.sim.blown_up() and len(set(ends)) == 1
