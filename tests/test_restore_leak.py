"""Restoring a snapshot with cached contacts, again and again, is safe, exact and
leaks nothing.

The arbiters a rebuild allocates (pymunk's ``cpArbiterNew``, as its own unpickling
does) are freed right after Chipmunk frees their space (puppet/physics/snapshot.py,
``_free_with_space``); before issue 32 they were never freed: 0.2 kB per cached arbiter
per restore, for good. This checks the many-restore path a scrub takes: every restored
space steps alike, nothing blows up, a process that restores hundreds of times exits
cleanly, and the memory in use stays flat over restores and over rounds of scrubbing
(``puppet.commands.bench.soak``, the bench's 30-minute soak in a few rounds) on the cat
and the biped."""

import gc
import subprocess
import sys

import pytest

from puppet.commands.bench.soak import malloc_bytes, rss_mb, soak
from puppet.data.catalog import load_setup
from puppet.session import Session


def test_many_restores_step_alike():
    session = Session(load_setup("cat-trot"))
    session.advance(960)  # standing: contacts cached
    snap = session.sim.snapshot()
    assert len(session.sim.space._get_arbiters()) >= 2
    ends = []
    for _ in range(3):
        for _ in range(50):
            session.sim.restore(snap)
        session.sim.step(480)
        ends.append(session.sim.state_hash())
    assert not session.sim.blown_up() and len(set(ends)) == 1


def test_a_process_that_restores_often_ends_cleanly():
    code = ("from puppet.data.catalog import load_setup\n"
            "from puppet.session import Session\n"
            "s = Session(load_setup('biped-stand'))\n"
            "s.advance(960)\n"
            "snap = s.sim.snapshot()\n"
            "for _ in range(300):\n"
            "    s.sim.restore(snap)\n"
            "    s.sim.step(4)\n"
            "print('ok')\n")
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          timeout=120)
    assert proc.returncode == 0 and proc.stdout.strip() == "ok", proc.stderr[-500:]


@pytest.mark.parametrize("interface", ["cat-trot", "biped-walk"])
def test_restores_leak_nothing(interface):
    """700 restores of a snapshot with its cached contacts: the C allocator's bytes
    in use do not grow with them (they grew by 0.4-0.8 kB a restore: the arbiters),
    nor does the resident set."""
    session = Session(load_setup(interface))
    session.advance(960)
    snap = session.sim.snapshot()
    assert len(session.sim.space._get_arbiters()) >= 2

    def rounds(n):
        for _ in range(n):
            session.sim.restore(snap)
            session.sim.step(4)
        gc.collect()

    rounds(150)  # warm: the allocator's free lists and Python's caches settle
    before, rss = malloc_bytes(), rss_mb()
    rounds(700)
    after = malloc_bytes()
    if before is not None:  # (a few tens of kB move either way whatever is done)
        assert (after - before) / 700 < 100, f"{(after - before) / 700:.0f} B a restore"
    assert rss_mb() - rss <= 2.0


@pytest.mark.parametrize("interface", ["cat-trot", "biped-walk"])
def test_scrubbing_stays_flat(interface):
    """The bench's soak (``puppet bench --soak MINUTES``), counted in rounds: play,
    scrub back, release, rewind; once the history's abandoned futures are all kept,
    15 rounds (over 300 restores) leave the resident set flat and the allocator's
    bytes in use per restore low (0.2-0.8 kB before the fix; a few tens of kB move
    either way whatever is done, so this bound is loose: test_restores_leak_nothing
    is the sharp one)."""
    got = soak(interface, rounds=15, warmup=52)
    assert got["restores"] >= 300, got
    assert got["pass"] and got["growth_mb"] <= 2.0, got
    if got["malloc_per_restore"] is not None:
        assert got["malloc_per_restore"] < 300, got
