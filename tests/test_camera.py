"""The camera frames the character and the ground it stands on, in the window and in
the video export alike (both follow ``subject_of(session)`` with wall time)."""

import pytest

from puppet.app.camera import BOTTOM_RESERVED_PX, Camera, subject_of
from puppet.timeline.log import read_log
from puppet.timeline.replay import LogFeeder, find_log, new_session, setup_for_log

SIZE = (1280, 720)


def _frames(name, fps=30.0, slowdown=1.0):
    """(camera, session) after each video frame of the log, eased as the export does."""
    log = read_log(find_log(name))
    setup, _ = setup_for_log(log, False)
    session = new_session(log, setup)
    feeder = LogFeeder(session, log)
    camera = Camera(setup.character.view_height)
    camera.resize(*SIZE)
    feeder.advance(0)
    camera.follow(subject_of(session), None)
    per_frame = round(1.0 / fps / slowdown / session.sim.dt)
    while not feeder.finished:
        feeder.advance(per_frame)
        camera.follow(subject_of(session), 1.0 / fps)
        yield camera, session


def _screen_box(camera, session):
    left, bottom, right, top = subject_of(session).box
    x0, y_bottom = camera.to_screen((left, bottom))
    x1, y_top = camera.to_screen((right, top))
    return x0, y_top, x1, y_bottom


def test_on_flat_ground_the_floor_holds_still_while_luxo_hops():
    ys = [camera.to_screen((0.0, 0.0))[1] for camera, _ in _frames("luxo-hop")]
    assert max(ys) - min(ys) < 1.0  # pixels: the floor does not bob with the hops


@pytest.mark.parametrize("name", ["luxo-backflip", "luxo-ski-jump", "cat-trot"])
def test_the_character_is_never_behind_the_timeline_bar_nor_off_screen(name):
    seen_ground = total = 0
    for camera, session in _frames(name, slowdown=2.0 if name == "luxo-backflip" else 1.0):
        x0, y_top, x1, y_bottom = _screen_box(camera, session)
        assert y_bottom <= SIZE[1] - BOTTOM_RESERVED_PX, session.steps
        assert y_top >= 0 and x0 >= 0 and x1 <= SIZE[0], session.steps
        ground = session.setup.scene.ground_height(session.character.com()[0])
        if ground is not None:
            total += 1
            seen_ground += camera.to_screen((0.0, ground))[1] < SIZE[1] - BOTTOM_RESERVED_PX
    assert seen_ground >= 0.9 * total  # the ground it stands on stays in view


def test_the_backflip_keeps_the_floor_in_view_by_widening_the_view():
    heights = []
    for camera, session in _frames("luxo-backflip", slowdown=2.0):
        assert camera.to_screen((0.0, 0.0))[1] < SIZE[1] - BOTTOM_RESERVED_PX, session.steps
        heights.append(camera.view_height)
    assert max(heights) > 1.2 * heights[0]  # it zoomed out for the flip
    assert heights[-1] == pytest.approx(heights[0], rel=0.02)  # and back in after it


def test_a_scene_view_holds_the_apparatus_in_the_frame():
    """The high bar's view: the figure hanging from the bar 2.8 m up is framed with the
    bar below the key panel, not at the top edge under it as the character's own view
    (2.4 m high) put it."""
    from puppet.app.camera import camera_for
    from puppet.data.catalog import load_setup
    from puppet.session import Session

    s = Session(load_setup("biped-gymnast"))
    s.advance(240)
    cam = camera_for(s.setup)
    cam.resize(1280, 720)
    cam.follow(subject_of(s), None)
    view = s.setup.scene.view
    assert (cam.view_height, cam.cx, cam.cy) == (view.height, view.x, view.y)
    for name in s.sim.grasps:  # the held bar is on screen, under the key panel's strip
        x, y = cam.to_screen(s.sim.grasp_point(name))
        assert 0 < x < 1280 and 160 < y < 720 - 36
    plain = Camera(s.setup.character.view_height)
    plain.resize(1280, 720)
    plain.follow(subject_of(s), None)
    assert plain.to_screen(s.sim.grasp_point("hand_near"))[1] < 160  # under the key panel
