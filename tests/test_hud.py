"""The HUD as a newcomer reads it: text laid out by measured width, maps in plain
words, a compact controls panel (full on the help key), what the marks mean, messages
that are news not drawn as errors."""

import pygame
import pytest

from puppet.app.describe import app_lines, control_rows
from puppet.app.headless import FrameRenderer
from puppet.app.hud import ERROR, NEWS, layout_rows
from puppet.data import catalog
from puppet.data.catalog import load_setup
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
    full = [("controls", "")] + control_rows(spec) + app_lines(spec)
    for rows in (full, control_rows(spec, more="f1: all")):
        key_w, width, laid = layout_rows(small, rows, 640)
        assert width <= 640
        for key, text in laid:
            if text:  # the key column clears every key: no text drawn over another
                assert small.size(key)[0] < key_w
                assert key_w + small.size(text)[0] <= width - 16


def test_maps_are_described_in_plain_words():
    for name in INTERFACES:
        spec = load_setup(name).interface
        for state in spec.states or [None]:
            for _, text in control_rows(spec, state) + control_rows(spec, state, None, "f1"):
                for jargon in ("->", "mirrored", "pose grid", "_near", "_far", "mouse.x"):
                    assert jargon not in text, (name, state, text)
    lines = dict(control_rows(load_setup("luxo-mouse").interface))
    assert lines["mouse left-right"] == "leans the lower arm back (left) .. forward (right)"
    assert lines["mouse up-down"] == "folds the lamp (down) .. unfolds it (up)"
    trot = load_setup("cat-trot").interface
    assert ("mouse", "far back leg: the same, half a cycle behind the near one") in \
        control_rows(trot)  # the file's words
    bare = trot.model_copy(update={"maps": [m.model_copy(update={"description": ""})
                                            for m in trot.maps]})
    assert ("mouse", "far hip and knee: blends 6 poses, half a cycle apart") in \
        control_rows(bare)  # and, without them, what the HUD says of a grid map


@pytest.mark.parametrize("name", [n for n in INTERFACES if n.startswith("luxo")])
def test_luxos_maps_say_what_the_lamp_does(name):
    """Every map of a Luxo layout is described in the lamp's words (its lower arm, the
    lamp folding), not as a joint's angles ("ankle +80 deg at the left")."""
    spec = load_setup(name).interface
    maps = list(spec.maps) + [m for mode in spec.modes.values() for m in mode]
    for m in maps:
        assert m.description, (name, m)
        assert "deg" not in m.description and "ankle" not in m.description


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
    from puppet.app.describe import where_line
    from puppet.data.catalog import load_setup

    spec = load_setup("luxo-keys").interface
    assert where_line(spec, "upright", None, {"main": "upright", "grasp": "open"}) == \
        "state upright, grasp open"


def _walk_in(state_keys, steps):
    from puppet.interface import events as ev

    session = Session(load_setup("biped-walk"))
    for key in state_keys:
        session.handle(ev.key(key, True))
        session.handle(ev.key(key, False))
    session.advance(steps)
    return session


def test_the_walks_hud_says_what_the_mouse_does_before_it_does_anything():
    """Standing, the mouse drives nothing yet: the HUD says what it will do and when
    (the 0.3 s after each space), in the compact panel and in the full list."""
    session = _walk_in([], 10)
    assert session.runtime.mode == "standing"
    for help_ in (False, True):
        texts, _ = _drawn(session, show_help=help_)
        assert "mouse left-right" in texts and "mouse up-down" in texts, help_
        said = " ".join(texts)
        assert "for 0.3 s after space: the swing thigh back (left)" in said, help_


def test_sensor_maps_come_after_the_players_controls_folded_until_the_help_key():
    session = _walk_in(["space"], 240)  # past the 0.3 s of stepping: reaching
    assert session.runtime.mode == "reaching"
    texts, _ = _drawn(session)
    assert not any(t.startswith("(balance)") for t in texts)
    rows = [t for t in texts if t in ("mouse left-right", "space", "a", "sensors")]
    assert rows == ["mouse left-right", "space", "a", "sensors"]
    assert "4 maps acting by themselves (f1: all)" in texts
    full, _ = _drawn(session, show_help=True)
    heading = full.index("by themselves, from the body's sensors")
    assert full.index("shift+a") < heading < full.index(
        "body ahead of the stance foot: swing foot further the more ahead")


@pytest.mark.parametrize("help_", [False, True])
def test_no_hud_text_is_cut_short(help_):
    """Long texts wrap onto the next row instead of ending in an ellipsis, in every
    state of every shipped interface."""
    for name in INTERFACES:
        session = Session(load_setup(name))
        spec = session.setup.interface
        for state in spec.states or [None]:
            enter = spec.states[state].enter if state is not None else None
            mode = enter.mode if enter is not None and enter.mode else session.runtime.mode
            runtime = _Seen(session.runtime, state=state, mode=mode, states=None)
            texts, _ = _drawn(_Seen(session, runtime=runtime), show_help=help_)
            cut = [t for t in texts if t.endswith("...") and t != "..."]
            assert not cut, (name, state, cut)


class _Seen:
    """An object as another with some attributes changed (a session in another state)."""

    def __init__(self, of, **changed):
        self._of, self._changed = of, changed

    def __getattr__(self, name):
        changed = self.__dict__["_changed"]
        return changed[name] if name in changed else getattr(self.__dict__["_of"], name)


def test_tracking_without_a_stream_says_so_once():
    from puppet.interface import events as ev

    session = _walk_in(["a"], 240)
    texts, _ = _drawn(session)
    assert "a: no motion capture stream (start with --mocap CLIP)" in texts
    # and the tracking line says why nothing follows (not only LOST after 0.25 s)
    assert "tracking angles: no motion capture stream" in texts
    serial = session.message_serial
    session.handle(ev.key("a", True))  # already tracking: no second notice
    assert session.message_serial == serial
    fed = Session(load_setup("biped-walk"))  # a stream is there: no notice
    fed.handle({"type": "channels", "values": {c: 0.0 for c in
                                                fed.runtime.tracker.joints.values()}})
    fed.handle(ev.key("a", True))
    assert fed.message_serial == 0


@pytest.mark.parametrize("name", ["biped-recover", "luxo-keys", "cat-bound", "biped-bars"])
def test_the_help_panels_do_not_cover_each_other(name, monkeypatch):
    """With the help key: the controls, the pose key pictures and the legend side by side."""
    from puppet.app import hud

    rects = []
    for fn in ("draw_rows", "draw_keymap"):
        real = getattr(hud, fn)

        def spy(*a, _real=real, **k):
            rect = _real(*a, **k)
            if rect is not None:
                rects.append(rect)
            return rect
        monkeypatch.setattr(hud, fn, spy)
    _drawn(Session(load_setup(name)), show_help=True)
    assert len(rects) >= 3
    for i, a in enumerate(rects):
        for b in rects[i + 1:]:
            assert not a.colliderect(b), (name, a, b)


class CountingFont(SpyFont):
    """A font that counts the texts it measures."""

    def __init__(self, font, seen):
        super().__init__(font, seen)
        self.measured = 0

    def size(self, text):
        self.measured += 1
        return self.font.size(text)


@pytest.mark.parametrize("help_", [False, True])
def test_a_frame_that_changes_nothing_measures_no_text_again(help_):
    """The controls panel's rows and their layout are kept from frame to frame while
    what they depend on stays the same: the next frame measures no text of them."""
    session = Session(load_setup("biped-walk"))  # no pose keys: no key map pictures
    renderer = FrameRenderer(session, (1280, 800))
    renderer.small = CountingFont(renderer.small, [])
    renderer.info.show_help = help_
    renderer.render(session)
    assert renderer.small.measured > 50  # the first frame lays the panels out
    session.advance(8)
    renderer.small.measured = 0
    renderer.render(session)
    assert renderer.small.measured == 0


def _pixels(surface):
    return pygame.image.tobytes(surface, "RGB")


class _KeptAndFresh:
    """A HUD kept across frames beside one drawing its first frame, over one world."""

    def __init__(self, name):
        from puppet.app import hud

        self.hud = hud
        self.session = Session(load_setup(name))
        self.renderer = FrameRenderer(self.session, (1280, 720))
        self.kept = hud.HudInfo()

    def press(self, key, steps=8):
        from puppet.interface import events as ev

        self.session.handle(ev.key(key, True))
        self.session.handle(ev.key(key, False))
        self.session.advance(steps)

    def same(self, note, size=None, **info):
        """The two draw the same pixels (after resizing the window to ``size`` and
        setting the kept HUD's ``info``)."""
        renderer, session, kept = self.renderer, self.session, self.kept
        if size is not None:
            renderer.surface = pygame.Surface(size)
            renderer.camera.resize(*size)
        world = renderer.render(session, hud=False).copy()
        for k, v in info.items():
            setattr(kept, k, v)
        fresh = self.hud.HudInfo(show_help=kept.show_help, paused=kept.paused)
        drawn = []
        for i in (kept, fresh):
            i.follow_messages(session, 0.0)
            surface = world.copy()
            self.hud.draw_hud(surface, session, i, renderer.font, renderer.small)
            drawn.append(_pixels(surface))
        assert drawn[0] == drawn[1], note


def test_the_kept_hud_layout_is_the_one_a_fresh_hud_draws():
    """Through what changes the controls panel (the state and mode, the help key, the
    tracking line, the window's size, a hot reload), a HUD that keeps its layout across
    frames draws what a HUD drawing its first frame draws, to the pixel."""
    walk = _KeptAndFresh("biped-walk")
    walk.same("start")
    walk.same("help", show_help=True)
    walk.same("compact again", show_help=False)
    walk.press("space")
    assert walk.session.runtime.mode == "stepping"
    walk.same("stepping")
    walk.session.advance(240)
    walk.same("reaching")
    walk.press("a")  # tracking, with no stream: a line more on the left
    walk.same("tracking")
    walk.same("tracking, help", show_help=True)
    walk.same("narrower", size=(1024, 720))
    walk.same("lower", size=(1024, 640))
    walk.same("lower, compact", show_help=False)
    text = walk.session.setup.interface_path.read_text()
    walk.session.reload(text.replace("the swing thigh back (left)", "the thigh swung back"))
    walk.same("reloaded")
    walk.same("paused", paused=True)
    kept = walk.hud.LAID_KEPT
    for width in range(1024, 1024 + 3 * kept):  # a window being resized
        walk.same(f"width {width}", size=(width, 640))
    assert len(walk.kept._laid) <= kept

    gymnast = _KeptAndFresh("biped-gymnast")  # a mode key; one state machine per limb
    gymnast.same("start")
    gymnast.press("2")
    assert gymnast.session.runtime.mode == "bound"
    gymnast.same("bound")
    before = gymnast.session.runtime.states
    gymnast.press("w", 240)  # the far hand lets go: another machine's state
    assert gymnast.session.runtime.states["far_hand"] != before["far_hand"]
    assert gymnast.session.runtime.state == before["near_hand"]
    gymnast.same("far hand free")


def test_the_time_a_map_waits_for_is_said_as_the_file_gives_it():
    """"for 1.25 s after space", not rounded to two digits ("for 1.2 s")."""
    from pathlib import Path

    from puppet.data.catalog import setup_from_text

    path = Path(load_setup("biped-walk").interface_path)
    text = path.read_text()
    assert text.count("after: 0.3}") == 2  # the swing after each swap of the legs
    spec = setup_from_text(text.replace("after: 0.3}", "after: 1.25}"), path).interface
    for more in (None, "f1: all"):
        said = " ".join(t for _, t in control_rows(spec, None, None, more))
        assert "for 1.25 s after space: " in said, more
