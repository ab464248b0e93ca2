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
