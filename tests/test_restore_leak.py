"""Restoring a snapshot with cached contacts, again and again, is safe and exact.

The arbiters a rebuild allocates are not freed (as pymunk's own unpickling leaves
them: about 0.2 kB per cached arbiter per restore); freeing them once their space
went corrupted the heap (puppet/physics/snapshot.py, at ``rebuild``). This checks the
many-restore path a scrub takes: every restored space steps alike, nothing blows up,
and a process that restores hundreds of times exits cleanly."""

import subprocess
import sys

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
