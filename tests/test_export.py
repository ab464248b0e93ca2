"""Replay export (video, gif, joint plot), the ghost, and --record with images."""

from pathlib import Path

import imageio.v2 as imageio
import imageio.v3 as iio
import pygame
import pytest

from puppet.app.export import export_video
from puppet.app.headless import run_headless
from puppet.app.plot import plot_joints, save_joint_plot
from puppet.commands import main
from puppet.data.catalog import find, load_setup
from puppet.interface.app_keys import SetSlowdown
from puppet.testing import record_script, replay_log
from puppet.timeline.ghost import Ghost
from puppet.timeline.log import read_log
from puppet.timeline.replay import replay
from puppet.timeline.script import compile_script, load_script

SMALL = (320, 192)


@pytest.fixture(scope="module")
def hop(tmp_path_factory) -> Path:
    """The first hop (1.3 s of luxo-hop) as a log."""
    path = tmp_path_factory.mktemp("export") / "hop.jsonl"
    return record_script("luxo-hop", path, seconds=1.3)


def _hop_events():
    return compile_script(load_script(find("script", "luxo-hop")), 1 / 480)


def test_mp4_has_the_frames_and_size_written(hop, tmp_path):
    out = tmp_path / "hop.mp4"
    video = export_video(hop, out, fps=10, size=SMALL, hold=0.5, progress=False)
    assert video.frames == 1 + 13 + 5  # first frame, 1.3 s at 10 fps, 0.5 s hold
    reader = imageio.get_reader(str(out))
    assert reader.count_frames() == video.frames
    assert reader.get_meta_data()["fps"] == 10
    frames = iio.imread(str(out), index=None, plugin="FFMPEG")
    assert frames.shape == (video.frames, SMALL[1], SMALL[0], 3)
    assert frames[0].std() > 5  # a picture, not a blank frame
    # the replay behind the video ends where the log does
    assert video.session.sim.state_hash() == read_log(hop).end_hash


def test_gif_frames_scale_and_slowdown(hop, tmp_path):
    out = tmp_path / "hop.gif"
    # slowdown 2: 1.3 simulated seconds take 2.6 s of video
    video = export_video(hop, out, fps=10, size=(640, 384), scale=0.5, slowdown=2,
                         hold=0, progress=False)
    assert video.frames == 1 + 26 and video.size == SMALL
    frames = iio.imread(str(out), index=None)
    assert frames.shape[0] == video.frames  # every frame differs (the HUD clock moves)
    assert frames.shape[1:3] == (SMALL[1], SMALL[0])
    assert iio.immeta(str(out))["loop"] == 0


def test_cli_video_and_plot(hop, tmp_path, capsys):
    mp4, png = tmp_path / "v.mp4", tmp_path / "p.png"
    assert main(["replay", str(hop), "--headless", "--video", str(mp4), "--plot", str(png),
                 "--fps", "8", "--size", "320x192"]) == 0
    out = capsys.readouterr().out
    assert "same as recorded" in out and f"wrote {mp4}" in out and f"wrote {png}" in out
    assert imageio.get_reader(str(mp4)).count_frames() == 1 + 11 + 8  # ceil(1.3 * 8)
    assert pygame.image.load(str(png)).get_width() > 500


def _refused(capsys, argv, fragment):
    assert main(argv) == 2  # a usage error
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("puppet replay: ") and fragment in err[0], err


def test_cli_export_refusals(hop, tmp_path, capsys):
    _refused(capsys, ["replay", str(hop), "--video", str(tmp_path / "v.mp4")], "need --headless")
    _refused(capsys, ["replay", str(hop), "--headless", "--video", str(tmp_path / "v.webp")],
             "--video " + str(tmp_path / "v.webp") + ": '.webp'; give a file name ending in")
    _refused(capsys, ["replay", str(hop), str(hop), "--headless", "--plot",
                      str(tmp_path / "p.png")], "one log")
    # a folder or a name with no extension is refused before anything is replayed or written
    _refused(capsys, ["replay", str(hop), "--headless", "--video", str(tmp_path)],
             "is a folder; give a file name ending in .avi or .gif")
    _refused(capsys, ["replay", str(hop), "--headless", "--plot", str(tmp_path)], "is a folder")
    _refused(capsys, ["replay", str(hop), "--headless", "--plot", str(tmp_path / "noext")],
             "no extension; give a file name ending in .png")
    assert list(tmp_path.iterdir()) == []  # nothing written, not even noext.png


def test_plot_has_one_subplot_per_actuated_joint(hop, tmp_path):
    result = replay_log(hop)
    traj = result.trajectory
    fig = save_joint_plot(traj, tmp_path / "joints.png", "hop", {"knee": (-40.0, 165.0)})
    assert (tmp_path / "joints.png").stat().st_size > 10_000
    joints = list(result.session.character.servos)
    assert traj.joints == joints and len(joints) == 2
    assert len(fig.axes) == len(joints)
    for ax, name in zip(fig.axes, joints):
        assert name in ax.get_ylabel()
        labels = [line.get_label() for line in ax.get_lines()]
        assert labels[:2] == ["target", "angle"]
        assert len(ax.get_lines()[1].get_xdata()) == len(traj)
    # the limits are drawn on the knee only (2 extra lines)
    assert len(fig.axes[joints.index("knee")].get_lines()) == 4
    assert len(plot_joints(traj).axes) == len(joints)


def test_ghost_does_not_change_the_live_run(hop, tmp_path):
    setup = load_setup("luxo-mouse")
    events = _hop_events()
    plain = run_headless(setup, events, 1.0, screenshot=str(tmp_path / "plain.png"),
                         size=SMALL)
    ghost = Ghost(hop)
    with_ghost = run_headless(setup, [], 1.0, size=SMALL)  # the live lamp stands still
    haunted = run_headless(setup, events, 1.0, frames_dir=str(tmp_path / "frames"), fps=10,
                           screenshot=str(tmp_path / "ghost.png"), size=SMALL, ghost=ghost)
    assert haunted.sim.state_hash() == plain.sim.state_hash()
    assert ghost.session is not haunted and ghost.session.sim.space is not haunted.sim.space
    assert ghost.session.steps == haunted.steps == 480  # in lock-step
    assert len(list((tmp_path / "frames").glob("*.png"))) == 10
    # beside a lamp standing still, the ghost shows up in the picture
    still = run_headless(setup, [], 1.0, screenshot=str(tmp_path / "still.png"), size=SMALL)
    ghost2 = Ghost(hop)
    ghost2.sync(still)
    assert ghost2.session.sim.state_hash() == replay(hop, until_step=480).final_hash
    assert with_ghost.sim.state_hash() == still.sim.state_hash()
    a = pygame.image.tobytes(pygame.image.load(str(tmp_path / "still.png")), "RGB")
    run_headless(setup, [], 1.0, screenshot=str(tmp_path / "still-ghost.png"), size=SMALL,
                 ghost=Ghost(hop))
    b = pygame.image.tobytes(pygame.image.load(str(tmp_path / "still-ghost.png")), "RGB")
    assert a != b


def test_ghost_follows_the_live_time_back(hop):
    setup = load_setup("luxo-mouse")
    live = run_headless(setup, [], 1.0)
    ghost = Ghost(hop)
    ghost.sync(live)
    late = ghost.session.sim.state_hash()
    live.rewind_to(240)  # the live run goes back: so does the ghost
    ghost.sync(live)
    assert ghost.session.steps == 240
    assert ghost.session.sim.state_hash() == replay(hop, until_step=240).final_hash
    live.advance(240)
    ghost.sync(live)
    assert ghost.session.sim.state_hash() == late
    # a longer log, across the ghost's own checkpoints (every 3 s): it rewinds through
    # them, exactly, with no replay from the start
    full = Path(__file__).resolve().parents[1] / "assets" / "logs" / "luxo-hop.jsonl"
    ghost = Ghost(full)
    live.advance(round(3.5 / live.sim.dt) - live.steps)
    ghost.sync(live)
    rebuilt = []
    ghost._start = lambda: rebuilt.append(True)  # must not replay from the start
    live.rewind_to(1500)  # after its checkpoint at 3 s
    ghost.sync(live)
    assert not rebuilt and ghost.session.steps == 1500
    assert ghost.session.sim.state_hash() == replay(full, until_step=1500).final_hash


def test_headless_record_with_screenshot_and_frames(tmp_path, capsys):
    log, shot, frames = tmp_path / "rec.jsonl", tmp_path / "shot.png", tmp_path / "frames"
    assert main(["play", "luxo-mouse", "--headless", "--input", "luxo-hop", "--seconds",
                 "0.5", "--record", str(log), "--screenshot", str(shot), "--frames",
                 str(frames), "--fps", "10"]) == 0
    out = capsys.readouterr().out
    assert f"recorded {log}" in out and f"wrote {shot}" in out
    assert pygame.image.load(str(shot)).get_size() == (1280, 720)
    assert len(list(frames.glob("frame_*.png"))) == 5
    recorded = read_log(log)
    printed = out.split("state=")[1].split()[0]
    assert recorded.end_hash == printed == replay(log).final_hash
    assert recorded.header["description"]  # the script's description is kept
    # the same run without images records the same log
    plain = tmp_path / "plain.jsonl"
    assert main(["play", "luxo-mouse", "--headless", "--input", "luxo-hop", "--seconds",
                 "0.5", "--record", str(plain)]) == 0
    assert plain.read_text() == log.read_text()


def test_play_ghost_option(hop, tmp_path, capsys):
    shot = tmp_path / "g.png"
    assert main(["play", "luxo-mouse", "--headless", "--seconds", "0.3", "--ghost", str(hop),
                 "--screenshot", str(shot)]) == 0
    assert shot.exists()
    assert main(["play", "luxo-mouse", "--headless", "--seconds", "0.3", "--ghost",
                 str(tmp_path / "missing.jsonl")]) == 2


def test_window_draws_a_ghost_and_records_only_the_live_run(hop, tmp_path, monkeypatch):
    from puppet.app import window

    frame = {"n": 0}
    real_get = pygame.event.get

    def key(kind, k):
        return pygame.event.Event(kind, key=k, mod=0, unicode="", scancode=0)

    plan = {30: [key(pygame.KEYDOWN, pygame.K_b)], 45: [key(pygame.KEYUP, pygame.K_b)],
            70: [pygame.event.Event(pygame.QUIT)]}

    def fake_get(*args, **kw):  # scripted window events: hold rewind a while, then quit
        frame["n"] += 1
        real_get()
        return plan.get(frame["n"], [])

    monkeypatch.setattr(pygame.event, "get", fake_get)
    monkeypatch.setattr(pygame.mouse, "get_focused", lambda: False)
    path = tmp_path / "live.jsonl"
    ghost = Ghost(hop)
    assert window.run_window(load_setup("luxo-mouse"), record=str(path), ghost=ghost) == 0
    log = read_log(path)
    assert any(e.event.get("name") == "rewind" for e in log.events)
    assert ghost.fed == log.end_step  # the ghost ended at the live time
    assert replay(path).final_hash == log.end_hash  # the live log replays without it


@pytest.fixture(scope="module")
def slowed(tmp_path_factory) -> Path:
    """luxo-keys: 0.1 s, then `l` (slowdown 4) for 0.2 s, then `k` (1x) for 0.3 s."""
    from puppet.interface import events as ev
    from puppet.interface.app_keys import SetSlowdown
    from puppet.session import Session
    from puppet.timeline.log import Recorder

    session = Session(load_setup("luxo-keys"))
    path = tmp_path_factory.mktemp("slowed") / "slowed.jsonl"
    with Recorder(session, path, slowdown=1.0):
        session.advance(48)
        assert session.handle(ev.key("l", True)) == SetSlowdown(4)
        session.handle(ev.key("l", False))
        session.advance(96)
        assert session.handle(ev.key("k", True)) == SetSlowdown(1)
        session.handle(ev.key("k", False))
        session.advance(144)
    return path


def test_video_follows_a_recorded_slowdown_key(slowed, tmp_path, monkeypatch):
    import puppet.app.export as export

    budgets = []

    class Spy(export.LogFeeder):
        def advance(self, steps):
            budgets.append(steps)
            super().advance(steps)

    monkeypatch.setattr(export, "LogFeeder", Spy)
    video = export_video(slowed, tmp_path / "slowed.gif", fps=10, size=SMALL, hold=0,
                         progress=False)
    # as live: 0.1 s a frame is 48 steps at 1x, 12 at 4x (the events at step 0 first)
    assert budgets == [0, 48] + [12] * 8 + [48] * 3
    assert video.frames == 1 + 1 + 8 + 3
    assert video.session.sim.state_hash() == read_log(slowed).end_hash


def test_window_replay_follows_a_recorded_slowdown_key(slowed, monkeypatch):
    import puppet.app.clock as clock_mod
    import puppet.timeline.replay as replay_mod
    from puppet.app import window

    seen, feeders = [], []

    class SpyClock(clock_mod.SimClock):
        def apply(self, action):
            applied = super().apply(action)
            seen.append((action, applied, self.slowdown))
            return applied

    class SpyFeeder(replay_mod.LogFeeder):
        def __init__(self, *a, **kw):
            super().__init__(*a, **kw)
            feeders.append(self)

    real_get = pygame.event.get

    def fake_get(*args, **kw):  # quit once the replay is over
        real_get()
        done = feeders and feeders[0].finished
        return [pygame.event.Event(pygame.QUIT)] if done else []

    monkeypatch.setattr(clock_mod, "SimClock", SpyClock)
    monkeypatch.setattr(replay_mod, "LogFeeder", SpyFeeder)
    monkeypatch.setattr(pygame.event, "get", fake_get)
    monkeypatch.setattr(pygame.mouse, "get_focused", lambda: False)
    log = read_log(slowed)
    assert window.run_window(load_setup("luxo-keys"), replay=log) == 0
    assert seen == [(SetSlowdown(4), True, 4.0), (SetSlowdown(1), True, 1.0)]
    assert feeders[0].session.sim.state_hash() == log.end_hash


def test_gif_frame_delays_keep_time_in_whole_centiseconds(hop, tmp_path):
    """A gif stores whole 1/100 s per frame: at 15 fps the delays alternate 7 and 6 cs
    (70, 60, 70, 70, 60, ...) so that n frames last n / 15 s, not 0.06 n s (11 % fast)."""
    from PIL import Image, ImageSequence

    out = tmp_path / "hop.gif"
    video = export_video(hop, out, fps=15, size=SMALL, hold=0, progress=False)
    with Image.open(out) as gif:
        delays = [frame.info["duration"] for frame in ImageSequence.Iterator(gif)]
    assert len(delays) == video.frames  # every frame differs: none merged
    assert set(delays) == {60, 70}
    for n in range(1, len(delays) + 1):  # never more than 5 ms off the clock
        assert abs(sum(delays[:n]) - n * 1000 / 15) <= 5, n


def test_cli_refuses_a_gif_faster_than_50_fps(hop, tmp_path, capsys):
    _refused(capsys, ["replay", str(hop), "--headless", "--video", str(tmp_path / "v.gif"),
                      "--fps", "60"], "too fast for a gif")
    assert not (tmp_path / "v.gif").exists()


def test_a_chosen_slowdown_wins_over_the_recorded_speed_keys(slowed, tmp_path, monkeypatch):
    """--slowdown 0.5 on a log with recorded slowdown keys: the video and the window's
    replay keep 0.5 throughout (the recorded keys are not applied)."""
    import puppet.app.clock as clock_mod
    import puppet.app.export as export
    import puppet.timeline.replay as replay_mod
    from puppet.app import window

    budgets = []

    class Spy(export.LogFeeder):
        def advance(self, steps):
            budgets.append(steps)
            super().advance(steps)

    monkeypatch.setattr(export, "LogFeeder", Spy)
    video = export_video(slowed, tmp_path / "fast.gif", fps=10, size=SMALL, hold=0,
                         progress=False, slowdown=0.5)
    assert set(budgets[1:]) == {96}  # 0.1 s a frame at 0.5: 96 steps, every frame
    assert video.session.sim.state_hash() == read_log(slowed).end_hash

    slowdowns, feeders = [], []

    class SpyClock(clock_mod.SimClock):
        def steps_for(self, wall_dt):
            slowdowns.append(self.slowdown)
            return super().steps_for(wall_dt)

    class SpyFeeder(replay_mod.LogFeeder):
        def __init__(self, *a, **kw):
            super().__init__(*a, **kw)
            feeders.append(self)

    real_get = pygame.event.get

    def fake_get(*args, **kw):
        real_get()
        return [pygame.event.Event(pygame.QUIT)] if feeders and feeders[0].finished else []

    monkeypatch.setattr(clock_mod, "SimClock", SpyClock)
    monkeypatch.setattr(replay_mod, "LogFeeder", SpyFeeder)
    monkeypatch.setattr(pygame.event, "get", fake_get)
    monkeypatch.setattr(pygame.mouse, "get_focused", lambda: False)
    log = read_log(slowed)
    assert window.run_window(load_setup("luxo-keys"), 0.5, replay=log,
                             slowdown_chosen=True) == 0
    assert set(slowdowns) == {0.5}
    assert feeders[0].session.sim.state_hash() == log.end_hash


def test_the_videos_hold_shows_the_verdict_not_the_pause_banner(hop, tmp_path, monkeypatch):
    """The second held at the end shows the replay's verdict, and no 'PAUSED (. steps,
    p resumes)': a video has no keys to resume it."""
    from puppet.app import hud

    seen, real = [], hud.draw_hud

    class Spy:
        def __init__(self, font):
            self.font = font

        def render(self, text, *a):
            seen[-1].append(text)
            return self.font.render(text, *a)

        def __getattr__(self, name):
            return getattr(self.font, name)

    def spy(surface, session, info, font, small):
        seen.append([])
        return real(surface, session, info, Spy(font), Spy(small))

    monkeypatch.setattr(hud, "draw_hud", spy)
    video = export_video(hop, tmp_path / "hold.gif", fps=10, size=SMALL, hold=0.5,
                         progress=False)
    assert len(seen) == video.frames == 1 + 13 + 5
    for texts in seen[-5:]:  # the hold
        assert not any(t.startswith("PAUSED") for t in texts), texts
        assert any(t.startswith("replay finished") for t in texts), texts
    assert not any(t.startswith("PAUSED") for texts in seen for t in texts)


def test_cli_frames_says_how_many_it_wrote(tmp_path, capsys):
    out = tmp_path / "frames"
    assert main(["play", "luxo-mouse", "--headless", "--input", "luxo-hop", "--seconds",
                 "0.5", "--frames", str(out), "--fps", "10"]) == 0
    written = sorted(out.glob("frame_*.png"))
    assert len(written) == 5
    assert f"wrote 5 frames to {out}" in capsys.readouterr().out
