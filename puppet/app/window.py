"""The real-time window: pygame events in, Session out, drawn every frame.

This loop only translates devices into input events and wall time into a number of
steps; everything that changes the simulation goes through ``Session.handle``.
"""

from __future__ import annotations

import contextlib
import os
import shlex
import sys
import tempfile
import time
import warnings
from pathlib import Path

from puppet.app.devices import Gamepads, device_events
from puppet.app.virtual_pad import pad_events
from puppet.data.catalog import Setup
from puppet.data.errors import UsageError
from puppet.data.keys import key_chord
from puppet.interface import events as ev
from puppet.session import Session

MIN_SIZE = (1024, 640)
START_SIZE = (1280, 720)
MODIFIER_KEYS = {"left ctrl", "right ctrl", "left shift", "right shift", "left alt",
                 "right alt", "left meta", "right meta"}


def run_window(setup: Setup, slowdown: float | None = None, size=START_SIZE,
               record: str | None = None, no_record: bool = False, replay=None,
               until_step: int | None = None, ghost=None, note: str = "",
               slowdown_chosen: bool = False, overlay: bool = False, sources=(),
               virtual_pad: bool = False, script=None,
               script_text: tuple[str, str] | None = None) -> int:
    """Play ``setup`` in a window, recording a log (to ``record``, or by default to
    recordings/). With ``replay`` (a ``Log``), events come from the log instead of
    the devices, at the recorded slowdown; the devices only drive the window.
    ``ghost`` (a ``puppet.timeline.ghost.Ghost``) replays beside the character in
    step with its time, drawn translucently; it never touches the live session.
    ``note``: shown on screen at the start (e.g. what is wrong with a replayed log).
    ``slowdown_chosen``: the replay's slowdown was chosen (--slowdown), so the log's
    recorded speed keys do not change it (the viewer's own keys still do).
    ``sources``: live input sources (``puppet.input.live.LiveQueue``s, e.g. a mocap
    stream) drained once a frame into the session, like the devices. ``script``: a
    script (``ScriptSpec``) that plays alongside them, its rules reacting at the
    slowdown in force (``puppet.timeline.reactive``); ``script_text``: its (name,
    text), kept in the log's header."""
    os.environ.setdefault("PYGAME_HIDE_SUPPORT_PROMPT", "1")
    import pygame

    from puppet.app.camera import camera_for, subject_of
    from puppet.app.clock import SimClock
    from puppet.app.hud import HudInfo, draw_hud, frame_under_panels
    from puppet.app.render import draw_world

    hint = headless_hint(replay)  # the command that was run: play, or replay LOG
    with _held_stderr() as said:  # what SDL prints while it looks for a display
        try:
            pygame.display.init()  # no pygame.init(): puppet makes no sound
            missing = no_display(pygame, hint)
        except pygame.error as exc:
            missing = f"no display found ({exc}); {hint}"
    if missing:  # before anything is recorded; SDL's own lines would only come first
        pygame.quit()
        raise UsageError(missing)
    if said:  # a display was found: SDL's words may matter (a driver's warning)
        sys.stderr.write(said[0])
    pygame.font.init()
    pygame.joystick.init()  # gamepads arrive as JOYDEVICEADDED events (hot-plug)
    gamepads = Gamepads(pygame)
    screen = pygame.display.set_mode(size, pygame.RESIZABLE)
    title = f"puppet - {setup.interface.name}"
    try:  # pygame-ce: the display's Window object carries the title and a minimum size
        with warnings.catch_warnings():  # we draw through pygame.display, knowingly
            warnings.simplefilter("ignore", DeprecationWarning)
            window = pygame.Window.from_display_module()
        window.title = title
        window.minimum_size = MIN_SIZE
    except (AttributeError, pygame.error):
        pygame.display.set_caption(title)
    font = pygame.font.Font(None, 24)
    small = pygame.font.Font(None, 20)

    feeder = recorder = None
    slowdown = slowdown or setup.interface.slowdown
    if replay is not None:  # events come from a log; the devices only drive the window
        from puppet.timeline.replay import LogFeeder, new_session
        from puppet.timeline.report import finished_message

        session = new_session(replay, setup)
    else:
        session = Session(setup)
    clock = SimClock(session.sim.dt, slowdown)
    if replay is not None:  # the recorded speed keys change the slowdown as they did live
        feeder = LogFeeder(session, replay, until_step,
                           on_action=None if slowdown_chosen else clock.apply)
    if replay is None and not no_record:
        from puppet.timeline.log import Recorder, default_path

        path = record or default_path(setup.interface.name)
        recorder = Recorder(session, path, slowdown=slowdown,
                            script=script_text if script is not None else None)
        print(f"recording to {path}")
    player = None
    if script is not None and replay is None:  # timed events and rules, on the window's clock
        from puppet.timeline.reactive import ScriptPlayer

        player = ScriptPlayer(session, script, None, lambda: clock.slowdown, clock.apply)
    from puppet.session.history import Scrubber

    scrub = Scrubber(session)
    camera = camera_for(setup)
    camera.resize(*screen.get_size())
    camera.follow(subject_of(session), None)
    info = HudInfo(replaying=Path(replay.path).name if replay is not None else "",
                   overlay=overlay)
    from puppet.timeline.playtest.store import figure_line, last_for

    info.playtest = figure_line(last_for(setup.interface.name))  # how forgiving, last measured
    reloader = None
    reload_error = ""  # shown until the file is valid again
    if feeder is None:  # hot reload: saving the interface file applies it at once
        from puppet.app.reloader import Reloader
        from puppet.data.catalog import parse_interface_text

        def check_text(text: str) -> None:
            parse_interface_text(text, str(setup.interface_path), setup.character,
                                 setup.character_path, setup.scene)

        reloader = Reloader(setup.interface_path, check_text, now=time.perf_counter())
    from puppet.app.gestures import GestureRecorder

    gestures = GestureRecorder()

    def save_gestures() -> str:
        """Write the live interface's gestures into its file (the reload follows)."""
        from puppet.data.errors import DataError
        from puppet.data.gesture_file import replace_gestures
        from puppet.data.yamlfile import read_text

        if reload_error:
            return "the interface file has an error: fix it before saving gestures"
        path = setup.interface_path
        try:
            text = replace_gestures(read_text(path), session.interface.gestures)
            check_text(text)
            path.write_text(text, encoding="utf-8")
        except (DataError, OSError) as exc:
            return f"gestures not saved: {exc}"
        gestures.unsaved.clear()
        return f"saved {len(session.interface.gestures)} gesture(s) into {path}"
    if note:
        session.say(note)
    held_at: set = set()  # pointer positions (pixels) that are not input: see hold_pose
    start_pointer: dict = {}  # interface version -> where the mouse holds the start pose

    def start_pose_pointer():
        """The pointer (0..1) at which the live interface's mouse maps hold the start
        pose (None if no mouse map drives a joint): found on a fresh session of the
        same interface, so it holds after a hot reload too."""
        version = session.version
        if version not in start_pointer:
            import dataclasses

            fresh = Session(dataclasses.replace(setup, interface=session.interface))
            start_pointer[version] = fresh.runtime.pointer_for_pose()
        return start_pointer[version]

    def hold_pose(after_reset: bool = False) -> bool:
        """Put the pointer where the mouse maps hold the start pose, and send no mouse
        input until the user moves it, so the first mouse event does not throw the
        character out of its pose. After a reset the maps are first given that
        position (a logged mouse event: the reset re-applies the last inputs, which
        threw the lamp). If the pointer cannot be moved (some systems refuse), the
        pose is still held until the mouse moves. False if no mouse map drives a joint."""
        nonlocal last_mouse
        rest = start_pose_pointer()
        if rest is None:
            return False
        if after_reset:
            session.handle(ev.mouse(*rest))
            last_mouse = rest
        held_at.clear()
        held_at.add(tuple(pygame.mouse.get_pos()))
        w, h = screen.get_size()
        target = (round(rest[0] * (w - 1)), round((1.0 - rest[1]) * (h - 1)))
        pygame.mouse.set_pos(target)
        held_at.add(target)
        return True

    pressed: dict[str, str] = {}  # key name -> chord it was pressed as
    dragging = False
    last_mouse = None
    pad = None  # --virtual-pad: the mouse and a few keys are a gamepad
    if virtual_pad and feeder is None:
        from puppet.app.virtual_pad import HELP, VirtualPad

        pad = VirtualPad()
        w, h = screen.get_size()
        pygame.mouse.set_pos((w // 2, h // 2))  # the stick at rest
        taken = VirtualPad.clashes(setup.interface)
        session.say(HELP + (f" (the layout's own {', '.join(taken)} do not reach it)"
                            if taken else ""))
        print(f"puppet play: {HELP}", file=sys.stderr)
    elif feeder is None and hold_pose():  # start where the mouse maps hold the start pose
        session.say("the pointer starts where the mouse holds the start pose")
    frames = pygame.time.Clock()
    start = time.perf_counter()

    def ctrl_held() -> bool:
        return bool(pygame.key.get_mods() & pygame.KMOD_CTRL)

    def mods() -> list[str]:
        m = pygame.key.get_mods()
        return [n for n, flag in (("ctrl", pygame.KMOD_CTRL), ("shift", pygame.KMOD_SHIFT),
                                  ("alt", pygame.KMOD_ALT)) if m & flag]

    def handle(event) -> str | None:
        """Send an input event to the session (not while replaying or scrubbing)."""
        if feeder is not None:  # replaying: only the window's own keys do anything
            if event["type"] == "key" and event["down"]:
                action = session.key_to_app.get(event["key"])
                return action if action not in ("rewind", "forward") else None
            return None
        if scrub.active and event["type"] in ("mouse", "drag"):
            return None
        if event["type"] == "key":
            action = session.app_action_of(event["key"])
            if action in ("rewind", "forward"):  # the window's own: the scrub commits
                return action if event["down"] else None  # with a logged rewind action
        scrub.commit()  # a key while scrubbing acts at the step shown, in the log too
        reset = (event["type"] == "key" and event["down"]
                 and session.key_to_app.get(event["key"]) == "reset"
                 and not session.runtime.handles_key(event["key"]))
        action = session.handle(event)
        if reset and pad is None and hold_pose(after_reset=True):
            session.say("reset: the pointer is back where the mouse holds the start pose")
        return action

    def send_mouse() -> None:
        """The pointer's position to the session if it moved. Not while paused: moving
        the mouse to the keys would be new input, branching away the future that the
        scrub keys can still move through; it acts when the simulation steps again."""
        nonlocal last_mouse
        if dragging or ctrl_held() or not pygame.mouse.get_focused():
            return  # Ctrl is the drag's: the mouse does not drive the maps meanwhile
        w, h = screen.get_size()
        mx, my = pygame.mouse.get_pos()
        if held_at:
            if (mx, my) in held_at:
                return  # holding the pose until the user moves the mouse
            held_at.clear()
        pos = (min(1.0, max(0.0, mx / max(1, w - 1))),
               min(1.0, max(0.0, 1.0 - my / max(1, h - 1))))
        if pad is not None:  # the mouse is a stick
            for event_ in pad.mouse(*pos):
                handle(event_)
            last_mouse = pos
        elif pos != last_mouse:
            handle(ev.mouse(*pos))
            gestures.add(session.time, *pos)
            last_mouse = pos

    def app_action(name: str | None) -> bool:
        """Do a window-side app action; False means quit."""
        if name == "quit":
            return False
        if clock.apply(name):  # slower, faster, an interface key's slowdown
            return True
        if name in ("rewind", "forward"):
            scrub.start(forward=name == "forward")
        if name == "pause":
            clock.toggle_pause()
        elif name == "step":
            if clock.paused and feeder is not None:
                feeder.advance(1)  # the log's events due there act first
            elif clock.paused:
                send_mouse()
                session.advance(1)
        elif name == "help":
            info.show_help = not info.show_help
        elif name == "balance":
            info.overlay = not info.overlay
        elif name == "branches":
            near = session.history.branches_near(session.steps)
            if not near:
                info.branch = None
                session.say("no branches yet: rewind (hold B) and play on to keep one")
            elif info.branch not in near:
                info.branch = near[0]
            elif near.index(info.branch) + 1 < len(near):
                info.branch = near[near.index(info.branch) + 1]
            else:
                info.branch = None  # past the last one: the list closes
        elif name == "take_branch" and feeder is None:
            take_branch()
        elif name == "export_branch" and feeder is None:
            export_branch()
        elif name == "record_gesture" and feeder is None:
            session.say(gestures.toggle(session.time, last_mouse,
                                        session.app_keys["record_gesture"]))
        elif name == "save_gestures" and reloader is not None:
            session.say(save_gestures())
        return True

    def selected_branch():
        history = session.history
        if info.branch is None or info.branch >= len(history.branches):
            session.say(f"choose a branch first: {session.app_keys['branches']} lists them")
            return None
        return history.branches[info.branch]

    def take_branch() -> None:
        """Take up the selected branch: a logged "take" action (a replay does the same)."""
        chosen = selected_branch()
        if chosen is None:
            return
        history = session.history
        if not history.oldest() <= chosen.fork <= history.head:
            session.say("that branch forks before the history kept", error=True)
            return
        scrub.commit()
        handle(ev.action("take") | {"branch": info.branch})
        info.branch = None

    def export_branch() -> None:
        """Write the selected branch, from step 0, as a log of its own."""
        from puppet.timeline.log import default_path, record_events

        chosen = selected_branch()
        if chosen is None:
            return
        events = session.branch_events(info.branch)
        if events is None:
            session.say("the history no longer reaches back to the start: cannot export",
                        error=True)
            return
        path = default_path(f"{setup.interface.name}-branch")
        at = chosen.fork * session.sim.dt
        fresh = Session(setup, dt=session.sim.dt,
                        checkpoint_interval=session.checkpoint_interval)
        record_events(fresh, events, chosen.head, path, slowdown=slowdown,
                      description=f"a branch of {setup.interface.name} from t={at:.2f} s")
        session.say(f"exported the branch to {path}")

    running = True
    while running:
        wall_dt = frames.tick(60) / 1000.0
        for event in pygame.event.get():
            translated = device_events(pygame, event, gamepads, session.interface.gamepad)
            consumed = False
            if pad is not None:  # mouse buttons and the pad's keys are the pad's
                translated, consumed = pad_events(pygame, pad, event, translated)
            for one in translated:
                running = app_action(handle(one)) and running
            if consumed:  # a key of the pad: not a key of the layout too
                continue
            if event.type == pygame.QUIT:
                running = False
            elif event.type == pygame.WINDOWRESIZED or event.type == pygame.VIDEORESIZE:
                camera.resize(*screen.get_size())
            elif event.type == pygame.KEYDOWN:
                name = pygame.key.name(event.key)
                if name in MODIFIER_KEYS or not name:
                    continue
                chord = key_chord(name, mods())
                if gestures.binding:  # the key a recorded gesture goes on
                    event_, text = gestures.bind(chord, session.interface,
                                                 session.app_keys["save_gestures"])
                    if event_ is not None:
                        handle(event_)
                    session.say(text)
                    continue
                pressed[name] = chord
                running = app_action(handle(ev.key(chord, True))) and running
            elif event.type == pygame.KEYUP:
                name = pygame.key.name(event.key)
                if name in pressed:
                    chord = pressed.pop(name)
                    if session.key_to_app.get(chord) in ("rewind", "forward"):
                        scrub.release()  # play on from the snapshot shown
                    handle(ev.key(chord, False))
            elif event.type == pygame.MOUSEBUTTONDOWN and event.button == 1 \
                    and pygame.key.get_mods() & pygame.KMOD_CTRL:
                picked = _pick(session, camera, event.pos)
                if picked is not None:
                    link, local = picked
                    handle(ev.drag_start(link, local, camera.to_world(event.pos)))
                    dragging = True
            elif event.type == pygame.MOUSEBUTTONUP and event.button == 1 and dragging:
                handle(ev.drag_end())
                dragging = False
            elif event.type == pygame.MOUSEMOTION and dragging:
                handle(ev.drag_move(camera.to_world(event.pos)))
        if not clock.paused:
            send_mouse()
            if feeder is None:
                for source in sources:  # live streams and clips (on the sim clock)
                    for event_ in source.drain(session.time):
                        handle(event_)

        if reloader is not None and not scrub.active:
            change = reloader.poll(time.perf_counter())
            if change is not None and not change.ok:
                reload_error = change.error  # the last good version keeps running
                print(f"puppet play: {change.error} (the last valid version keeps "
                      "running)", file=sys.stderr, flush=True)  # the whole line, to copy
            elif change is not None:
                reload_error = ""
                handle(ev.reload(change.text, str(setup.interface_path)))
                for event_ in gestures.rebind_after_reload(session.interface):
                    handle(event_)  # bound since the last save: keep them
                session.say(f"reloaded {setup.interface_path}")
        steps = clock.steps_for(wall_dt)
        if scrub.active:
            scrub.update(wall_dt, forward=bool(pygame.key.get_mods() & pygame.KMOD_SHIFT))
        elif feeder is not None:
            feeder.advance(steps)
            if feeder.finished and not clock.paused:
                clock.toggle_pause()
                done = finished_message(session, replay)
                session.say(done, error="DIFFERENT" in done)
        elif player is not None:
            player.advance(steps)
        else:
            session.advance(steps)
        if session.halted and not clock.paused and not scrub.active:
            clock.toggle_pause()  # even the start blew up: pause on its one message
        info.follow_messages(session, time.perf_counter())
        if reload_error:
            info.message, info.message_error = reload_error, True
        info.scrubbing = scrub.active
        clock.sample(time.perf_counter() - start, session.time)
        info.slowdown = clock.slowdown
        info.measured = clock.measured_slowdown()
        info.fps = frames.get_fps() or None
        info.sources = [s.hud_line() if hasattr(s, "hud_line") else s.status()
                        for s in sources]  # a live stream's line is the short one
        info.paused = clock.paused

        if not session.sim.blown_up():  # else (until the next health check recovers
            if not (dragging or ctrl_held()):  # it) the last world drawn stays; the
                frame_under_panels(screen, camera, session, info, font, small)
                camera.follow(subject_of(session), wall_dt)  # camera holds for a drag
            if ghost is not None:
                ghost.sync(session)
            draw_world(screen, session, camera, small,
                       ghost=ghost.session if ghost is not None else None,
                       overlay=info.overlay)
        draw_hud(screen, session, info, font, small)
        pygame.display.flip()
    scrub.release()
    if recorder is not None:
        recorder.close()
        print(f"recorded {recorder.path}")
    pygame.quit()
    return 0


HEADLESS_HINT = ("use --headless to run without a window (e.g. puppet play luxo-mouse "
                 "--headless --input luxo-hop --screenshot out.png)")
OFFSCREEN_DRIVERS = ("offscreen", "dummy")


def headless_hint(replay=None) -> str:
    """What to run instead without a display: ``puppet play`` 's headless example, or
    for a replay (``replay``: its ``Log``) the same replay headless: the log by its
    bare name if that name finds this very file (``find_log``: assets/logs/ is searched
    before recordings/, so recordings/luxo-hop.jsonl is not 'luxo-hop' when
    assets/logs/luxo-hop.jsonl exists), else its path, quoted for the shell."""
    if replay is None:
        return HEADLESS_HINT
    from puppet.data.errors import DataError
    from puppet.timeline.replay import find_log

    path = Path(replay.path)
    try:
        named = Path(find_log(path.stem)).resolve() == path.resolve()
    except (DataError, OSError):
        named = False
    log = path.stem if named else _quoted(str(replay.path))
    return (f"use --headless to replay without a window (e.g. puppet replay {log} "
            f"--headless, or add --video out.mp4 to see it)")


@contextlib.contextmanager
def _held_stderr():
    """Hold what is written to the process's stderr (file descriptor 2, where SDL's C
    code writes: "error: XDG_RUNTIME_DIR is invalid or not set" before the no-display
    line) until the block ends; yields a list that then holds the text."""
    said: list[str] = []
    try:
        sys.stderr.flush()
        saved = os.dup(2)
    except (OSError, ValueError):  # no real stderr (an embedding): nothing to hold
        yield said
        return
    with tempfile.TemporaryFile() as held:
        os.dup2(held.fileno(), 2)
        try:
            yield said
        finally:
            os.dup2(saved, 2)
            os.close(saved)
            held.seek(0)
            said.append(held.read().decode("utf-8", "replace"))
    if not said[0]:
        said.clear()


def _quoted(text: str) -> str:
    """A path as the user's shell takes it: POSIX quoting, or on Windows double quotes
    around a path with a space or a character cmd.exe or PowerShell treat specially
    (neither reads POSIX single quotes)."""
    if os.name == "nt":
        return f'"{text}"' if any(c in text for c in ' &()^;,\'') else text
    return shlex.quote(text)


def no_display(pygame, hint: str = HEADLESS_HINT) -> str:
    """Why no window can be seen ("" if one can). Without a display SDL falls back to
    an off-screen video driver, and the window would run, invisibly, for ever. A
    driver asked for by name (SDL_VIDEODRIVER=dummy, as the tests do) is the user's
    choice."""
    try:
        driver = pygame.display.get_driver()
    except pygame.error:
        driver = ""
    asked = os.environ.get("SDL_VIDEODRIVER", "").strip().lower()
    if driver and (driver not in OFFSCREEN_DRIVERS or asked == driver):
        return ""
    return f"no display found (SDL could only open its '{driver or 'none'}' video driver); " \
           f"{hint}"


def _pick(session: Session, camera, screen_pos) -> tuple[str, tuple[float, float]] | None:
    """The character link under the cursor and the grabbed point in its frame."""
    import pymunk

    world = camera.to_world(screen_pos)
    tolerance = 12.0 / camera.scale
    hit = session.sim.space.point_query_nearest(world, tolerance, pymunk.ShapeFilter())
    if hit is None or hit.shape is None:
        return None
    for name, shapes in session.character.shapes.items():
        if hit.shape in shapes:
            local = session.character.bodies[name].world_to_local(hit.point)
            return name, (local.x, local.y)
    return None

