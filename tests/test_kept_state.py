"""Snapshots kept unpickled (``Simulation.keep``): nothing mutates a kept state, so a run
restoring from it has the bits of a run restoring from its pickle (taken at once)."""

import pickle

import pytest

from puppet.data.catalog import load_setup
from puppet.physics.simulation import Kept
from puppet.session import Session
from puppet.session import history as history_module


def _script(session: Session) -> list[str]:
    """Play with input, checkpoints, restores (twice from one), rewinds in a loop and
    play after them; the state hash after each."""
    hashes = []

    def mark() -> None:
        hashes.append(session.sim.state_hash())

    for k in range(6):
        x = 0.2 + 0.1 * k
        session.handle({"type": "mouse", "x": x, "y": 1.0 - x})
        session.advance(300)
        if k == 2:
            session.handle({"type": "action", "name": "checkpoint"})
    mark()
    for _ in range(2):  # twice from one snapshot
        session.handle({"type": "action", "name": "restore"})
        mark()
        session.advance(250)
        mark()
    for to in (1100, 500, 800, 300, 700, 500):  # to and fro, with play after some
        session.handle({"type": "action", "name": "rewind", "to_step": to})
        mark()
        if to in (500, 300):
            session.handle({"type": "mouse", "x": 0.7, "y": 0.4})
            session.advance(400)
            mark()
    return hashes


def _pickles(session: Session) -> list[bytes]:
    h = session.history
    snaps = [*h.auto, *h.manual, *(s for b in h.branches for s in (*b.auto, *b.manual))]
    return [s.sim._data if s.sim.frozen else
            pickle.dumps(s.sim.state(), protocol=pickle.HIGHEST_PROTOCOL) for s in snaps]


@pytest.mark.parametrize("interface", ["biped-walk", "cat-trot"])
def test_kept_states_restore_as_their_pickles(interface, monkeypatch):
    kept = Session(load_setup(interface), checkpoint_interval=0.5)
    got = _script(kept)
    assert any(not s.sim.frozen for s in kept.history.auto)
    monkeypatch.setattr(history_module, "KEEP_UNPICKLED", 0)  # pickled when taken
    pickled = Session(load_setup(interface), checkpoint_interval=0.5)
    assert _script(pickled) == got
    assert all(s.sim.frozen for s in pickled.history.auto)
    # and the states kept, after all those restores, are still what was taken
    assert _pickles(kept) == _pickles(pickled)


def test_only_the_latest_are_kept_unpickled(monkeypatch):
    monkeypatch.setattr(history_module, "KEEP_UNPICKLED", 3)
    session = Session(load_setup("biped-walk"), checkpoint_interval=0.5)
    session.advance(240 * 10)
    auto = list(session.history.auto)
    assert [s.sim.frozen for s in auto[-4:]] == [True, False, False, False]
    assert all(isinstance(s.sim, Kept) for s in auto)
    first = auto[0].sim
    assert first.frozen and pickle.loads(first._data)[2] == 0  # the start, step 0
