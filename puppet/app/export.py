"""Export a replay: a video (mp4 or gif) of what the window shows, and a joint plot.

The video is the window's replay drawn off-screen: a ``LogFeeder`` advances the log by
(1 / fps) / slowdown simulated seconds per frame, the camera eases as in the window,
the HUD is drawn, and the recorded speed keys ("slower", "faster", an interface's
``slowdown:`` keys) change the slowdown as they did live, through ``SimClock.apply``.
Frames go to imageio (mp4 and other containers, through imageio-ffmpeg's bundled
ffmpeg binary) or to pillow (gif, with per-frame delays so that it keeps time).
Nothing is hand-encoded.
"""

from __future__ import annotations

import math
import sys
from dataclasses import dataclass
from pathlib import Path

from puppet.app.frame import DEFAULT_SIZE, FrameRenderer
from puppet.session import Session
from puppet.timeline.log import Log, read_log
from puppet.timeline.replay import LogFeeder, new_session, setup_for_log
from puppet.timeline.report import finished_message

VIDEO_EXTS = {".mp4", ".mov", ".mkv", ".avi"}  # through ffmpeg (imageio-ffmpeg)
GIF_EXTS = {".gif"}  # through pillow


@dataclass
class VideoResult:
    path: Path
    frames: int
    size: tuple[int, int]
    fps: float
    session: Session


def _even(n: float) -> int:
    return max(2, int(n) // 2 * 2)


def _forward_steps(log: Log, until_step: int | None) -> int:
    """Steps the replay will run (rewinds count again): for the progress bar."""
    fed = cur = 0
    end = log.last_step
    for e in log.events:
        if until_step is not None and e.step > until_step:
            break
        fed += max(0, e.step - cur)
        cur = max(cur, e.step)
        ev = e.event
        if ev.get("type") == "action" and ev.get("name") == "rewind":
            cur = int(ev.get("to_step", cur))
    stop = end if until_step is None else until_step
    return fed + max(0, stop - cur)


def gif_delays(frames: int, fps: float) -> list[int]:
    """Per-frame gif delays in ms, whole centiseconds (all a gif can store) whose
    running sum stays within 5 ms of frame / fps: at 15 fps 70, 60, 70, 70, 60, ...
    (a constant 6 cs would play 11 % fast). Each frame ends at round(100 k / fps) cs."""
    ends = [round(100 * k / fps) for k in range(frames + 1)]
    return [10 * (b - a) for a, b in zip(ends, ends[1:])]


class _Writer:
    """Frames (h, w, 3 uint8 arrays) to a video or gif file, by the file's extension.

    A gif is written by pillow at ``close`` (pillow saves all frames at once, as
    imageio's pillow plugin does too), with per-frame delays from ``gif_delays``;
    pillow merges identical frames and adds up their delays."""

    def __init__(self, path: Path, fps: float):
        ext = path.suffix.lower()
        path.parent.mkdir(parents=True, exist_ok=True)
        self.path = path
        self.fps = fps
        self.gif: list | None = None
        self.video = None
        if ext in GIF_EXTS:
            self.gif = []
        elif ext in VIDEO_EXTS:
            import imageio.v2 as imageio

            options = {"codec": "libx264", "pixelformat": "yuv420p"} if ext == ".mp4" else {}
            # macro_block_size=2: even sizes are kept as they are (yuv420p needs even)
            self.video = imageio.get_writer(str(path), fps=fps, macro_block_size=2,
                                            ffmpeg_log_level="error", **options)
        else:
            raise ValueError(f"cannot write '{path.suffix}' files: use one of "
                             f"{', '.join(sorted(VIDEO_EXTS | GIF_EXTS))}")

    def write(self, frame) -> None:
        if self.gif is not None:
            from PIL import Image

            self.gif.append(Image.fromarray(frame))
        else:
            self.video.append_data(frame)

    def close(self) -> None:
        if self.gif is None:
            self.video.close()
        elif self.gif:
            first, *rest = self.gif
            first.save(self.path, format="GIF", save_all=True, append_images=rest, loop=0,
                       duration=gif_delays(len(self.gif), self.fps))
            self.gif = []


def export_video(log: Log | str | Path, out: str | Path, fps: float = 30.0,
                 size=DEFAULT_SIZE, slowdown: float | None = None,
                 until_step: int | None = None, allow_truncated: bool = False,
                 scale: float = 1.0, hud: bool = True, hold: float = 1.0,
                 progress: bool | None = None, as_recorded: bool = False,
                 overlay: bool = False) -> VideoResult:
    """Replay ``log`` headless into a video at ``out`` (.mp4/.mov/.mkv/.avi or .gif).

    ``slowdown`` (default: the recorded one) is wall seconds per simulated second, as
    in the window; ``size`` is the window size drawn, ``scale`` shrinks the frames
    written (e.g. 0.5 for a small gif); ``hold`` seconds of the last frame are added
    at the end, showing the replay's verdict ("replay finished ... the same as
    recorded"), so that a player or a looping gif does not cut the last move short.
    ``progress``: a tqdm bar (None: only when stderr is a terminal).
    ``overlay``: draw the balance overlay (centre of mass, support, xcom) as F4 does.
    """
    from tqdm import tqdm

    from puppet.app.clock import SimClock

    if fps <= 0:
        raise ValueError(f"fps must be positive, got {fps}")
    if not isinstance(log, Log):
        log = read_log(log, allow_truncated)
    setup, _warnings = setup_for_log(log, as_recorded)
    chosen = slowdown
    slowdown = float(slowdown or log.header.get("slowdown") or 1.0)
    session = new_session(log, setup)
    clock = SimClock(session.sim.dt, slowdown)
    # a chosen slowdown wins over the recorded speed keys, as in the window's replay
    feeder = LogFeeder(session, log, until_step,
                       on_action=clock.apply if chosen is None else None)
    renderer = FrameRenderer(session, tuple(size), slowdown, overlay=overlay)
    pygame = renderer.pygame
    info = renderer.info
    info.fps = fps
    out_size = (_even(size[0] * scale), _even(size[1] * scale))
    frame_dt = 1.0 / fps
    per_frame = frame_dt / slowdown / session.sim.dt
    total = 1 + math.ceil(_forward_steps(log, until_step) / per_frame) + round(hold * fps)
    bar = tqdm(total=total, unit="frame", desc=f"video {Path(out).name}", file=sys.stderr,
               disable=None if progress is None else not progress, leave=False)
    writer = _Writer(Path(out), fps)
    frames = 0
    video_time = 0.0

    def emit(wall_dt: float | None) -> None:
        nonlocal frames
        info.follow_messages(session, video_time)
        info.slowdown = info.measured = clock.slowdown
        if not session.sim.blown_up():  # between two checks: keep the last good frame
            renderer.render(session, hud, wall_dt=wall_dt)
        surface = renderer.surface
        if out_size != surface.get_size():
            surface = pygame.transform.smoothscale(surface, out_size)
        writer.write(_pixels(pygame, surface))
        frames += 1
        bar.update(1)

    try:
        feeder.advance(0)  # the events logged at step 0
        emit(None)
        owed = 0.0  # simulated steps owed to the video's clock
        while not feeder.finished:
            owed += frame_dt / clock.slowdown / session.sim.dt
            n = int(owed + 1e-9)
            owed -= n
            feeder.advance(n)  # recorded speed keys reach the clock (clock.apply)
            video_time += frame_dt
            emit(frame_dt)
        if hold > 0:  # the last frame held, with the verdict (the window's message at
            done = finished_message(session, log)  # the end of a replay), not its pause
            session.say(done, error="DIFFERENT" in done)  # banner: a video has no keys
            for _ in range(round(hold * fps)):
                video_time += frame_dt
                emit(frame_dt)
    finally:
        writer.close()
        bar.close()
    return VideoResult(Path(out), frames, out_size, fps, session)


def _pixels(pygame, surface):
    import numpy as np

    w, h = surface.get_size()
    return np.frombuffer(pygame.image.tobytes(surface, "RGB"), dtype=np.uint8).reshape(h, w, 3)


# -- ``puppet replay LOG --headless --video OUT --plot PNG`` ---------------------------
def export_command(args) -> int:
    """The replay command with --video and/or --plot (one log, headless). The options'
    ranges and the output names are checked by the command line (``puppet.commands.replay``)."""
    from puppet.data.errors import UsageError
    from puppet.timeline.replay import find_log, replay
    from puppet.timeline.report import exit_code, print_one, verdict

    if not args.headless:
        raise UsageError("--video and --plot need --headless")
    if len(args.logs) != 1:
        raise UsageError("--video and --plot take one log")
    if args.video and Path(args.video).suffix.lower() in GIF_EXTS and args.fps > 50:
        raise UsageError(f"--fps {args.fps:g} is too fast for a gif (frame delays are whole "
                         "1/100 s, and players slow down delays under 2/100 s): use --fps 50 "
                         "or less, or an .mp4")
    size = tuple(args.size)
    path = find_log(args.logs[0])
    log = read_log(path, args.allow_truncated)
    result = replay(log, args.until_step, args.allow_truncated, check=args.check,
                    trajectory=bool(args.plot) or args.check, as_recorded=args.as_recorded)
    res = result.summary
    res["outcomes"] = [str(o) for o in result.outcomes]
    print_one(res, args.check)
    if args.plot:
        from puppet.app.plot import joint_limits, save_joint_plot

        setup = result.session.setup
        title = f"{Path(path).name}: {setup.character.name} joint targets and angles"
        save_joint_plot(result.trajectory, args.plot, title, joint_limits(setup.character))
        print(f"wrote {args.plot}")
    if args.video:
        video = export_video(log, args.video, args.fps, size, args.slowdown, args.until_step,
                             args.allow_truncated, args.scale, as_recorded=args.as_recorded,
                             overlay=getattr(args, "overlay", None) == "com")
        if video.session.sim.state_hash() != result.final_hash:
            print(f"{path}: warning: the video's replay ended in state "
                  f"{video.session.sim.state_hash()}, not {result.final_hash}",
                  file=sys.stderr)
        print(f"wrote {args.video} ({video.frames} frames, {video.size[0]}x{video.size[1]}, "
              f"{video.fps:g} fps)")
    return exit_code([verdict(res)], bool(res.get("blowups")))
