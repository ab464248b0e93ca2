"""Contacts right after a restore: every checkpoint re-seats the run on a rebuilt
space, whose bodies list no contact until it steps; the sensors, the balance overlay
and the replay's sampler read the snapshot's contacts until then (a standing figure
never reads as floating at a checkpoint step)."""

from __future__ import annotations

import numpy as np
import pytest

from puppet.data.catalog import load_setup
from puppet.physics.balance import ground_contacts
from puppet.session import Session


def test_a_standing_figure_touches_the_ground_at_every_checkpoint_step():
    s = Session(load_setup("biped-stand"))
    c = s.character
    every = s.history.checkpoint_every  # steps between automatic checkpoints
    s.advance(every - 1)
    before = c.support_extent()
    s.advance(1)  # the checkpoint's step: a rebuilt space
    assert c.in_contact("foot_near") and c.in_contact("foot_far")
    at = c.support_extent()
    assert at is not None and at == pytest.approx(before, abs=2e-3)
    assert len(ground_contacts(c)) >= 2
    s.advance(1)
    assert c.in_contact("foot_near") and c.support_extent() == pytest.approx(at, abs=2e-3)


def test_after_a_rewind_the_contacts_are_there_at_once():
    s = Session(load_setup("biped-stand"))
    s.advance(1700)
    s.rewind_to(1500)
    assert s.steps == 1500 and s.character.in_contact("foot_near")


def test_the_replay_sampler_sees_the_feet_down_at_checkpoints():
    import tempfile
    from pathlib import Path

    from puppet.timeline.log import Recorder
    from puppet.timeline.replay import replay

    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "stand.jsonl"
        s = Session(load_setup("biped-stand"))
        with Recorder(s, path):
            s.advance(round(7.0 / s.sim.dt))
        traj = replay(path, trajectory=True).trajectory
    feet = [traj.index("foot_near"), traj.index("foot_far")]
    standing = traj.t > 0.5
    assert np.all(traj.contact[standing][:, feet].any(axis=1))


def test_contacts_read_the_same_right_after_a_checkpoint_as_a_body_leaves_the_ground():
    """Chipmunk keeps a lifted body's arbiter a few steps (for warm starts): read right
    after the checkpoint's rebuild, it must not count as touching."""
    from pathlib import Path

    from puppet.timeline.log import read_log
    from puppet.timeline.replay import LogFeeder, new_session, setup_for_log

    log = read_log(Path(__file__).resolve().parents[1] / "assets" / "logs" / "luxo-hop.jsonl")
    session = new_session(log, setup_for_log(log)[0])
    feeder = LogFeeder(session, log)
    feeder.advance(490)
    c = session.character
    changed = 0
    last = None
    for _ in range(40):  # the take-off at about step 504
        feeder.advance(1)
        before = {n: c.in_contact(n) for n in c.bodies}
        session.sim.checkpoint()
        after = {n: c.in_contact(n) for n in c.bodies}
        assert after == before, session.steps
        if last is not None and before != last:
            changed += 1
        last = before
    assert changed >= 1  # the window saw the base leave the ground
