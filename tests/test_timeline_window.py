"""The window records what it does, replays logs, and draws the timeline bar
(SDL's dummy video driver, scripted pygame events)."""

import pygame
import pytest

import puppet.timeline.replay as replay_mod
from puppet.app import window
from puppet.data.catalog import load_setup
from puppet.session import Session
from puppet.timeline.log import read_log
from puppet.timeline.replay import replay


def _key(kind, key):
    return pygame.event.Event(kind, key=key, mod=0, unicode="", scancode=0)


@pytest.fixture
def scripted_events(monkeypatch):
    """Install a list of (frame, event) to be delivered by pygame.event.get."""
    plan = {"events": [], "frame": 0, "quit_when": None}
    real_get = pygame.event.get

    def fake_get(*args, **kw):
        plan["frame"] += 1
        out = [e for f, e in plan["events"] if f == plan["frame"]]
        if plan["quit_when"] is not None and plan["quit_when"]():
            out.append(pygame.event.Event(pygame.QUIT))
        real_get()
        return out

    monkeypatch.setattr(pygame.event, "get", fake_get)
    monkeypatch.setattr(pygame.mouse, "get_focused", lambda: False)
    return plan


def test_window_records_checkpoint_and_rewind_and_the_log_replays(tmp_path, scripted_events):
    scripted_events["events"] = [
        (20, _key(pygame.KEYDOWN, pygame.K_c)), (21, _key(pygame.KEYUP, pygame.K_c)),
        (60, _key(pygame.KEYDOWN, pygame.K_b)), (80, _key(pygame.KEYUP, pygame.K_b)),
        (100, pygame.event.Event(pygame.QUIT))]
    path = tmp_path / "win.jsonl"
    assert window.run_window(load_setup("luxo-mouse"), record=str(path)) == 0
    log = read_log(path)
    names = [e.event.get("name") or e.event.get("key") for e in log.events]
    assert names[:2] == ["c", "c"] and "rewind" in names
    assert log.end is not None
    assert replay(path).final_hash == log.end_hash


def test_window_replays_a_log(tmp_path, scripted_events, monkeypatch):
    from puppet.interface import events as ev
    from puppet.timeline.log import Recorder

    session = Session(load_setup("luxo-mouse"))
    path = tmp_path / "short.jsonl"
    with Recorder(session, path):
        session.handle(ev.mouse(0.9, 0.1))
        session.advance(60)
        session.handle(ev.action("checkpoint"))
        session.handle(ev.mouse(0.1, 0.9))
        session.advance(60)
    feeders = []

    class Spy(replay_mod.LogFeeder):
        def __init__(self, *a, **kw):
            super().__init__(*a, **kw)
            feeders.append(self)

    monkeypatch.setattr(replay_mod, "LogFeeder", Spy)
    scripted_events["quit_when"] = lambda: bool(feeders) and feeders[0].finished
    log = read_log(path)
    assert window.run_window(load_setup("luxo-mouse"), 1.0, replay=log) == 0
    assert feeders[0].session.sim.state_hash() == log.end_hash
    assert not (tmp_path / "recordings").exists()


def test_hud_timeline_bar_draws(tmp_path):
    from puppet.app.headless import FrameRenderer

    session = Session(load_setup("luxo-mouse"))
    session.advance(1000)
    session.checkpoint()
    session.advance(500)
    renderer = FrameRenderer(session, size=(640, 360))
    surface = renderer.render(session)
    # the current-position marker is at the right end of the bar (before its end time), dark
    w, h = surface.get_size()
    row = [surface.get_at((x, h - 18))[:3] for x in range(w - 90, w - 10)]
    assert (20, 30, 50) in row


def test_paused_scrub_back_release_then_forward_keeps_the_future(tmp_path, scripted_events,
                                                                 monkeypatch):
    """Pause, hold B (back), release, press F1 (help), hold Shift+B (forward): neither
    the scrub key's release nor a window key is input, so the future scrubbed back from
    is still there to go forward to."""
    sessions, seen = [], {}

    class Spy(Session):
        def __init__(self, *a, **kw):
            super().__init__(*a, **kw)
            sessions.append(self)

    monkeypatch.setattr(window, "Session", Spy)
    shift = {"on": False}
    monkeypatch.setattr(pygame.key, "get_mods",
                        lambda: pygame.KMOD_SHIFT if shift["on"] else 0)

    def watch():
        frame = scripted_events["frame"]
        if sessions:
            seen[frame] = sessions[0].steps
        shift["on"] = 100 <= frame <= 131
        return frame >= 140

    scripted_events["quit_when"] = watch
    scripted_events["events"] = [
        (60, _key(pygame.KEYDOWN, pygame.K_p)), (61, _key(pygame.KEYUP, pygame.K_p)),
        (62, _key(pygame.KEYDOWN, pygame.K_b)), (92, _key(pygame.KEYUP, pygame.K_b)),
        (95, _key(pygame.KEYDOWN, pygame.K_F1)), (96, _key(pygame.KEYUP, pygame.K_F1)),
        (100, _key(pygame.KEYDOWN, pygame.K_b)), (130, _key(pygame.KEYUP, pygame.K_b))]
    path = tmp_path / "scrub.jsonl"
    assert window.run_window(load_setup("luxo-mouse"), record=str(path)) == 0
    paused, back, forward = seen[61], seen[95], seen[135]
    assert back < paused - 50  # scrubbed back
    assert back < forward <= paused  # and forward again, within the kept future
    log = read_log(path)
    assert replay(path).final_hash == log.end_hash
