"""The HUD as a newcomer reads it: text laid out by measured width, maps in plain
words, a compact controls panel (full on the help key), what the marks mean, messages
that are news not drawn as errors."""

import pygame
import pytest

from puppet.app.headless import FrameRenderer
from puppet.app.hud import ERROR, NEWS, layout_rows
from puppet.data import catalog
from puppet.data.catalog import load_setup
from puppet.app.describe import app_lines, compact_lines, interface_lines
from puppet.session import Session

INTERFACES = [n for n, _ in catalog.list_kind("interface")]


class SpyFont:
    """A font that notes what it draws (text, colour) and draws it as pygame does."""

    def __init__(self, font, seen):
        self.font, self.seen = font, seen

    def render(self, text, antialias, color, *a):
        self.seen.append((text, tuple(color)[:3]))
        return self.font.render(text, antialias, color, *a)

    def __getattr__(self, name):
        return getattr(self.font, name)


def _drawn(session, **info):
    renderer = FrameRenderer(session, (1280, 720))
    seen = []
    renderer.font, renderer.small = SpyFont(renderer.font, seen), SpyFont(renderer.small, seen)
    for k, v in info.items():
        setattr(renderer.info, k, v)
    renderer.info.follow_messages(session, 0.0)
    renderer.render(session)
    return [t for t, _ in seen], seen


@pytest.mark.parametrize("name", INTERFACES)
def test_rows_are_laid_out_by_measured_width(name):
    pygame.font.init()
    small = pygame.font.Font(None, 20)
    spec = load_setup(name).interface
    full = [("controls", "")] + interface_lines(spec) + app_lines(spec)
    for rows in (full, compact_lines(interface_lines(spec), "f1: all")):
        key_w, width, laid = layout_rows(small, rows, 640)
        assert width <= 640
        for key, text in laid:
            if text:  # the key column clears every key: no text drawn over another
                assert small.size(key)[0] < key_w
                assert key_w + small.size(text)[0] <= width - 16


def test_maps_are_described_in_plain_words():
    for name in INTERFACES:
        for _, text in interface_lines(load_setup(name).interface):
            for jargon in ("->", "mirrored", "pose grid", "_near", "_far", "mouse.x"):
                assert jargon not in text, (name, text)
    lines = dict(interface_lines(load_setup("luxo-mouse").interface))
    assert lines["mouse left-right"] == "ankle +80 deg at the left .. -80 at the right"
    trot = interface_lines(load_setup("cat-trot").interface)
    assert ("mouse", "far hip and knee: blends 6 poses, half a cycle apart") in trot


def test_the_controls_panel_is_compact_until_the_help_key():
    session = Session(load_setup("cat-bound"))
    compact, _ = _drawn(session)
    full, _ = _drawn(session, show_help=True)
    assert "back legs folded behind" in compact and "front legs reach forward" not in compact
    assert "front legs reach forward" in full
    assert "all keys, pose pictures, what the marks mean" in compact
    # the help shows what the marks mean: the orange cross, the bar's colours
    assert "the centre of mass" in full and "distance along the ground, in metres" in full
    assert "pull a body with a spring (the mouse maps and the camera wait)" in full
    trot, _ = _drawn(Session(load_setup("cat-trot")))
    assert "4 maps (f1: all)" in trot  # four pose grids on the mouse: one row


def test_paused_names_the_step_key_and_the_replay_line_is_whole():
    session = Session(load_setup("luxo-mouse"))
    long_name = "luxo-mouse-20261201-120000-a-long-recording-name-indeed.jsonl"
    texts, _ = _drawn(session, paused=True, replaying=long_name)
    assert "PAUSED  (. steps, p resumes)" in texts
    assert f"REPLAY  {long_name}" in texts


def test_news_is_not_drawn_as_an_error():
    session = Session(load_setup("luxo-mouse"))
    session.say("replay finished at step 10: state abc (the same as recorded)")
    _, seen = _drawn(session)
    assert (session.message, NEWS) in seen
    session.say("the simulation blew up", error=True)
    _, seen = _drawn(session)
    assert (session.message, ERROR) in seen


def test_the_timeline_bar_is_labelled_with_its_end_time():
    session = Session(load_setup("luxo-mouse"))
    session.advance(480 * 4)
    texts, _ = _drawn(session)
    assert "4.0 s" in texts  # the bar's right end


def test_gamepad_pose_buttons_get_their_own_strip_labelled_by_name():
    from puppet.app.keymap import draw_keymap

    pygame.font.init()
    setup = load_setup("luxo-gamepad")
    seen = []
    font = SpyFont(pygame.font.Font(None, 20), seen)
    draw_keymap(pygame.Surface((800, 400)), setup.interface, setup.character, font, (0, 0))
    texts = [t for t, _ in seen]
    assert "gamepad buttons" in texts and {"a", "b", "x", "y"} <= set(texts)
    assert "gamepad.a" not in texts and "other" not in texts


def test_the_hud_says_what_keys_changed_in_the_world():
    from puppet.app.hud import world_changes
    from puppet.data.catalog import load_setup
    from puppet.interface import events as ev
    from puppet.session import Session

    s = Session(load_setup("luxo-designer"))
    assert world_changes(s) == ""
    spec = s.setup.interface
    gravity = next((k for k in spec.keys if k.gravity is not None), None)
    if gravity is None:  # the layout has no such key: change the world as a key would
        from puppet.interface import meta
        meta.set_gravity(s.sim, (0.0, -1.6))
        meta.set_friction(s.sim, 0.1)
    else:
        s.handle(ev.key(gravity.key))
    s.runtime.perturber.switch("on", s.steps)
    text = world_changes(s)
    assert text.startswith("world: gravity") and "(scene 0, -9.81)" in text
    assert "random kicks on" in text


def test_where_line_names_each_machines_state():
    from puppet.data.catalog import load_setup
    from puppet.app.describe import where_line

    spec = load_setup("luxo-keys").interface
    assert where_line(spec, "upright", None, {"main": "upright", "grasp": "open"}) == \
        "state upright, grasp open"
