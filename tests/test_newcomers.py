"""What a newcomer sees first: each interface's how-to-play line on the HUD, whole;
keys meant for another scene neither listed nor bound."""

from __future__ import annotations

import os

import pytest

from puppet.app.describe import control_rows, live_keys
from puppet.data.catalog import ROOT, load_setup
from puppet.session import Session

INTERFACES = sorted(p.stem for p in (ROOT / "interfaces").glob("*.yaml"))


@pytest.fixture(scope="module")
def pygame():
    os.environ.setdefault("SDL_VIDEODRIVER", "dummy")
    import pygame

    pygame.font.init()
    return pygame


def test_every_shipped_interface_says_how_to_play():
    for name in INTERFACES:
        how = load_setup(name).interface.how_to_play
        assert 40 <= len(how) <= 260, (name, how)


def test_the_walks_line_says_where_the_mouse_goes_and_the_rhythm():
    how = load_setup("biped-walk").interface.how_to_play
    assert "(0.55, 0.3)" in how and "space every 1.8 s" in how
    assert "back to the middle" in load_setup("luxo-mouse").interface.how_to_play


def test_the_hud_shows_the_whole_line_wrapped_under_the_title(pygame):
    from puppet.app.headless import FrameRenderer
    from puppet.app.hud import wrap

    session = Session(load_setup("biped-walk"))
    renderer = FrameRenderer(session, (1024, 640))
    renderer.render(session)
    how = session.setup.interface.how_to_play
    drawn = [v for k, v in renderer.info._laid.items() if k[0] == "how"]
    assert len(drawn) == 1 and len(drawn[0]) >= 3  # rows of the panel's width
    lines = wrap(renderer.small, "how to play: " + how, 300 - 16)
    assert " ".join(lines) == "how to play: " + how  # no row cut off with "..."


def test_keys_for_the_ladder_are_not_offered_or_bound_on_the_high_bar():
    bar = Session(load_setup("biped-gymnast"))
    ladder = Session(load_setup("biped-gymnast", "ladder"))
    for key in ("e", "d"):
        assert bar.runtime.binding(key) is None
        assert ladder.runtime.binding(key).pose in ("reach_ladder", "reach_low")
    spec = bar.interface
    shown = {k for k, _ in control_rows(spec, scene="highbar")}
    assert "e" not in shown and "d" not in shown and "1" in shown
    assert {"e", "d"} <= {k for k, _ in control_rows(spec, scene="ladder")}
    assert {k.key for k in live_keys(spec, None, "highbar")} & {"e", "d"} == set()


@pytest.mark.parametrize("name", ["biped-bars", "biped-gymnast", "biped-ladder"])
@pytest.mark.parametrize("size", [(1024, 640), (1280, 720)])
def test_no_bar_or_rung_is_under_the_top_panels(pygame, name, size):
    """A scene with a view of its own (an apparatus) is framed below the HUD's panels:
    every point of every prop (bars 2 m ahead and more included) is drawn under them."""
    from puppet.app.headless import FrameRenderer

    session = Session(load_setup(name))
    renderer = FrameRenderer(session, size)
    renderer.render(session)
    band, camera = renderer.info.top_band, renderer.camera
    assert 100 < band < size[1] // 2 and camera.top_px == band
    for prop in session.sim.props.values():
        points = [prop.point_world(p) for p in prop.points]
        for shape in prop.shapes:
            if hasattr(shape, "a"):
                a, b = (prop.body.local_to_world(p) for p in (shape.a, shape.b))
                points += [(a.x + (b.x - a.x) * k / 20, a.y + (b.y - a.y) * k / 20)
                           for k in range(21)]
        for p in points:
            x, y = camera.to_screen(p)
            if 0 <= x < size[0]:
                assert y > band, (name, size, p, y, band)


def test_a_long_error_wraps_on_screen_with_nothing_cut_off(pygame):
    from puppet.app.hud import message_lines

    font = pygame.font.Font(None, 24)
    error = ("/home/someone/projects/puppet-layouts/interfaces/my-long-named-layout.yaml:"
             "12:5: key 'r' is the app's 'reset' key; bind another key or move the app's "
             "with app_keys: {reset: <key>}")
    lines = message_lines(font, error, 400)
    assert len(lines) >= 3 and all(font.size(line)[0] <= 400 for line in lines)
    assert "".join(lines).replace(" ", "") == error.replace(" ", "")


def test_a_refused_hot_reload_is_also_printed_to_the_terminal(tmp_path, monkeypatch, capsys,
                                                              pygame):
    """The window (SDL dummy driver): a bad save is said on screen and, whole, on
    stderr, where it can be read and copied; the last good version keeps running."""
    from puppet.app import window

    path = tmp_path / "iface.yaml"
    good = "name: t\ndescription: test\ncharacter: luxo\nkeys:\n  - {key: h, pose: p}\n" \
           "poses:\n  p: {joints: {knee: 90}}\n"
    path.write_text(good)
    frame = {"n": 0, "start": None}
    real_get = pygame.event.get

    def fake_get(*args, **kw):
        import time

        frame["n"] += 1
        if frame["n"] == 3:
            path.write_text(good.replace("key: h", "key: r"))  # the app's reset key
            frame["start"] = time.perf_counter()
        real_get()
        done = frame["start"] is not None and time.perf_counter() - frame["start"] > 1.2
        return [pygame.event.Event(pygame.QUIT)] if done else []

    monkeypatch.setattr(pygame.event, "get", fake_get)
    assert window.run_window(load_setup(str(path)), no_record=True) == 0
    err = capsys.readouterr().err
    assert f"puppet play: {path}:5:" in err and "key 'r' is the app's 'reset' key" in err
    assert "(the last valid version keeps running)" in err


@pytest.mark.parametrize("name", ["biped-recover", "luxo-keys", "cat-bound", "biped-floor"])
def test_f1_pose_pictures_are_large_and_drawn_once(pygame, name, monkeypatch):
    """F1's pose keys as pictures at least 84 px (they were 58) in a 1280x720 window,
    inside the room beside the other help panels; the panel is drawn once and then only
    blitted (no text measured or rendered again while it is shown)."""
    from puppet.app import keymap
    from puppet.app.headless import FrameRenderer

    session = Session(load_setup(name))
    renderer = FrameRenderer(session, (1280, 720))
    renderer.info.show_help = True
    chosen = []
    real = keymap.keymap_layout
    monkeypatch.setattr(keymap, "keymap_layout",
                        lambda blocks, room: chosen.append(real(blocks, room)) or chosen[-1])
    renderer.render(session)
    assert len(chosen) == 1 and chosen[0][0] >= 84, chosen
    calls = []
    monkeypatch.setattr(keymap, "_render_keymap", lambda *a: calls.append(a))
    renderer.render(session)
    renderer.render(session)
    assert calls == [] and len(chosen) == 1  # the cached panel, blitted


def test_an_apparatus_is_drawn_on_a_stand_a_low_handhold_is_not():
    from puppet.app.render import prop_stands

    bar = prop_stands(Session(load_setup("biped-gymnast")))
    assert len(bar) == 3 and bar[0][2] == 28  # a post as thick as the bar, two stays
    (x, top), (_, floor), _ = bar[0]
    assert (x, floor) == (0.0, 0.0) and top == pytest.approx(2.8 - 0.014)
    bars = prop_stands(Session(load_setup("biped-bars")))
    assert sorted(round(a[0], 2) for a, _, _ in bars) == [-0.1, 3.75]  # each end
    assert prop_stands(Session(load_setup("luxo-mouse", "pendulum"))) == []  # 0.36 m up
