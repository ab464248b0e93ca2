"""Keep every take: a future abandoned by a rewind (or by going back to a checkpoint)
is kept as a branch, can be taken up again (the very run that was abandoned, to the
bit; a logged "take" action, so a replay does the same) or exported as a log."""

import random

from puppet.data.catalog import load_setup
from puppet.interface import events as ev
from puppet.session import Session
from puppet.timeline.log import Recorder, read_log, record_events
from puppet.timeline.replay import replay


def _wiggle(session, frames, seed):
    rng = random.Random(seed)
    for _ in range(frames):
        session.handle(ev.mouse(rng.random(), rng.random()))
        session.advance(8)


def test_a_rewound_future_is_kept_and_taken_up_again_exactly(tmp_path):
    path = tmp_path / "takes.jsonl"
    session = Session(load_setup("luxo-mouse"))
    with Recorder(session, path):
        _wiggle(session, 300, seed=1)  # 5 s: the first take
        first_end, first_head = session.sim.state_hash(), session.steps
        session.handle(ev.action("rewind") | {"to_step": 1000})
        _wiggle(session, 200, seed=2)  # new input: the first take becomes a branch
        second_end, second_head = session.sim.state_hash(), session.steps
        history = session.history
        assert len(history.branches) == 1
        kept = history.branches[0]
        assert (kept.fork, kept.head) == (1000, first_head)
        assert history.branches_near(1000) == [0]

        session.handle(ev.action("take") | {"branch": 0})
        assert session.steps == first_head
        assert session.sim.state_hash() == first_end  # the very run abandoned
        assert [(b.fork, b.head) for b in history.branches] == [(1000, second_head)]
        session.handle(ev.action("take") | {"branch": 0})  # and back to the second
        assert session.sim.state_hash() == second_end
        _wiggle(session, 30, seed=3)
        live_end = session.sim.state_hash()
    log = read_log(path)
    takes = [e.event for e in log.events if e.event.get("name") == "take"]
    assert takes == [{"type": "action", "name": "take", "branch": 0}] * 2
    result = replay(path)  # the replay keeps the same branches and takes them alike
    assert result.final_hash == live_end == log.end_hash


def test_going_back_to_a_checkpoint_keeps_the_future_too_and_a_branch_exports(tmp_path):
    session = Session(load_setup("cat-trot"))
    _wiggle(session, 120, seed=4)
    session.handle(ev.action("checkpoint"))
    _wiggle(session, 120, seed=5)
    branch_end, head = session.sim.state_hash(), session.steps
    session.handle(ev.action("restore"))  # back to the checkpoint: the future is kept
    assert [b.head for b in session.history.branches] == [head]
    events = session.branch_events(0)
    out = record_events(Session(load_setup("cat-trot")), events, head, tmp_path / "b.jsonl")
    assert replay(out).final_hash == branch_end == read_log(out).end_hash


def test_a_replays_trajectory_is_the_history_kept_after_a_take(tmp_path):
    path = tmp_path / "take.jsonl"
    session = Session(load_setup("luxo-mouse"))
    with Recorder(session, path):
        _wiggle(session, 240, seed=6)  # 0..1920
        session.handle(ev.action("rewind") | {"to_step": 960})
        _wiggle(session, 60, seed=7)  # 960..1440: this present is left for the branch
        session.handle(ev.action("take") | {"branch": 0})  # back on 960..1920
        _wiggle(session, 20, seed=8)
    steps = list(replay(path, trajectory=True).trajectory.step)
    assert steps == sorted(steps)  # one history, in order
    assert not [s for s in steps if 960 < s < 1920]  # nothing of the present left


def test_the_window_lists_takes_up_and_exports_a_branch(tmp_path, monkeypatch):
    import pygame

    import puppet.timeline.log as log_mod
    from puppet.app import window

    def key(kind, k):
        return pygame.event.Event(kind, key=k, mod=0, unicode="", scancode=0)

    plan = {40: [key(pygame.KEYDOWN, pygame.K_b)], 60: [key(pygame.KEYUP, pygame.K_b)],
            61: [key(pygame.KEYDOWN, pygame.K_SPACE)],  # new input: the future is kept
            80: [key(pygame.KEYDOWN, pygame.K_F9)], 81: [key(pygame.KEYDOWN, pygame.K_F11)],
            82: [key(pygame.KEYDOWN, pygame.K_F10)], 100: [pygame.event.Event(pygame.QUIT)]}
    frame = {"n": 0}
    real_get = pygame.event.get

    def fake_get(*a, **k):
        real_get()
        frame["n"] += 1
        return plan.get(frame["n"], [])

    exported = tmp_path / "branch.jsonl"
    monkeypatch.setattr(pygame.event, "get", fake_get)
    monkeypatch.setattr(pygame.mouse, "get_focused", lambda: False)
    monkeypatch.setattr(log_mod, "default_path", lambda name, *a, **k: exported)
    path = tmp_path / "win.jsonl"
    assert window.run_window(load_setup("luxo-designer"), record=str(path)) == 0
    log = read_log(path)
    assert [e.event for e in log.events if e.event.get("name") == "take"] == \
        [{"type": "action", "name": "take", "branch": 0}]
    assert replay(path).final_hash == log.end_hash
    assert exported.exists() and replay(exported).final_hash == read_log(exported).end_hash


def _wiggle_hashing(session, frames, seed, hashes):
    rng = random.Random(seed)
    for _ in range(frames):
        session.handle(ev.mouse(rng.random(), rng.random()))
        session.advance(8)
        hashes[session.steps] = session.sim.state_hash()


def test_a_rewind_after_a_branch_shows_the_branch_not_the_abandoned_input():
    s = Session(load_setup("luxo-mouse"))
    first: dict[int, str] = {}
    _wiggle_hashing(s, 250, 1, first)  # 2000 steps of the first take
    s.handle(ev.action("rewind") | {"to_step": 600})
    s.advance(4)  # new input lands between the abandoned events' steps
    live: dict[int, str] = {}
    _wiggle_hashing(s, 150, 2, live)  # the branch: steps 604..1804
    head = s.steps
    for step in (1404, 900, 1796):  # rewinds past the branch point, into the branch
        s.handle(ev.action("rewind") | {"to_step": step})
        assert s.steps == step
        assert s.sim.state_hash() == live[step]
    s.handle(ev.action("rewind") | {"to_step": 296})  # before the fork: the common past
    assert s.sim.state_hash() == first[296]
    s.handle(ev.action("rewind") | {"to_step": head})  # and forward again to the head
    assert s.sim.state_hash() == live[head]
