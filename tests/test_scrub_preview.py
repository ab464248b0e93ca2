"""Scrubbing shows cached poses of the history (puppet.session.preview): each the pose
an exact rewind gives, without restoring the live space each frame; the one exact
rewind comes on release."""

import math
import random

import pytest

from puppet.data.catalog import load_setup
from puppet.interface import events as ev
from puppet.session import Session
from puppet.session.history import Scrubber


def _played(interface, seed=4):
    """A session played with random mouse and key input for 7 s (two keyframes back),
    60 frames a second on its character's own step (1/480 s; the cat's 1/240 s)."""
    session = Session(load_setup(interface))
    per_frame = round(1 / (60 * session.sim.dt))  # steps a frame
    rng = random.Random(seed)
    keys = [k.key for k in session.setup.interface.keys][:4]
    for frame in range(420):
        if frame % 5 == 0:
            session.handle(ev.mouse(rng.random(), rng.random()))
        if keys and frame % 37 == 0:
            k = rng.choice(keys)
            session.handle(ev.key(k, True))
            session.handle(ev.key(k, False))
        session.advance(per_frame)
    return session


def _pose(session):
    return [(tuple(b.position), b.angle) for b in session.character.bodies.values()]


@pytest.mark.parametrize("interface", ["luxo-mouse", "cat-trot", "cat-bound"])
def test_the_preview_shows_the_exact_past_and_restores_nothing_until_release(interface,
                                                                            monkeypatch):
    live = _played(interface)
    reference = _played(interface)  # the same run, rewound exactly for comparison
    restores = []
    real_restore = live.sim.restore
    monkeypatch.setattr(live.sim, "restore", lambda *a, **k: (restores.append(1),
                                                              real_restore(*a, **k))[1])
    scrub = Scrubber(live)
    scrub.start()
    shown, checked = set(), 0
    for frame in range(150):  # 2.5 s of holding the key: back across a keyframe
        scrub.update(1 / 60)
        if live.steps not in shown and frame % 9 == 0:
            shown.add(live.steps)
            reference.rewind_to(live.steps)
            assert _pose(live) == _pose(reference), live.steps  # to the bit
            checked += 1
    assert not restores  # the live space was never restored while scrubbing
    assert checked >= 5 and min(shown) * live.sim.dt < 7.0 - 3.0  # it crossed into an
    # earlier interval (3360 - 1440 steps at 1/480 s)
    step = live.steps
    scrub.release()  # the one exact rewind, to the step shown
    assert len(restores) == 1 and live.steps == step
    reference.rewind_to(step)
    assert live.sim.state_hash() == reference.sim.state_hash()


def test_the_preview_uses_the_sessions_own_step_and_interval():
    """A replayed log's session may step at another dt and checkpoint interval than
    the interface's defaults: the preview re-simulates with the session's own."""
    def played():
        session = Session(load_setup("luxo-mouse"), dt=1 / 240, checkpoint_interval=1.0)
        rng = random.Random(2)
        for _ in range(240):
            session.handle(ev.mouse(rng.random(), rng.random()))
            session.advance(4)
        return session

    live, reference = played(), played()
    scrub = Scrubber(live)
    scrub.start()
    for _ in range(40):
        scrub.update(1 / 60)
    assert live.steps < 960
    reference.rewind_to(live.steps)
    assert _pose(live) == _pose(reference)


def test_the_preview_after_a_branch_shows_the_new_branch_not_the_cached_old_one():
    from puppet.session.history import Scrubber

    def played():
        s = Session(load_setup("luxo-mouse"))
        for k in range(180):
            s.handle(ev.mouse(0.5 + 0.4 * math.sin(k / 9), 0.5 + 0.3 * math.cos(k / 7)))
            s.advance(8)
        return s

    live, ref = played(), played()
    scrub = Scrubber(live)
    scrub.start()
    for _ in range(40):  # back about 0.7 s, filling the preview's cache on the way
        scrub.update(1 / 60)
    scrub.release()
    at = live.steps
    for k in range(40):  # new input: the history branches here
        for s in (live, ref):
            if k == 0:
                s.rewind_to(at) if s is ref else None
            s.handle(ev.mouse(0.1, 0.9))
            s.advance(8)
    scrub.start()
    checked = 0
    for frame in range(30):  # back into the new branch (the old one's steps, new poses)
        scrub.update(1 / 60)
        if live.steps > at and frame % 5 == 0:
            ref.rewind_to(live.steps)
            assert _pose(live) == _pose(ref), live.steps
            checked += 1
    scrub.release()
    assert checked >= 2
