"""The real-time window: pygame events in, Session out, drawn every frame.

This loop only translates devices into input events and wall time into a number of
steps; everything that changes the simulation goes through ``Session.handle``.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

from puppet.app.devices import Gamepads, device_events
from puppet.app.display import HEADLESS_HINT, headless_hint, no_display, open_display
from puppet.app.virtual_pad import pad_events
from puppet.data.catalog import Setup
from puppet.data.keys import key_chord
from puppet.interface import events as ev
from puppet.session import Session

__all__ = ["HEADLESS_HINT", "Window", "headless_hint", "no_display", "run_window"]

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
    window = Window(setup, slowdown, size, record, no_record, replay, until_step, ghost,
                    note, slowdown_chosen, overlay, sources, virtual_pad, script,
                    script_text)
    return window.run()


class Window:
    """One window's session: its devices in (``poll_events``), the app's actions
    (``app_action``), the frame (``step`` then ``draw``), branches, gestures and the
    recording. Everything that changes the simulation goes through ``handle``."""

    def __init__(self, setup: Setup, slowdown, size, record, no_record, replay,
                 until_step, ghost, note, slowdown_chosen, overlay, sources,
                 virtual_pad, script, script_text):
        from puppet.app.camera import subject_of
        from puppet.app.clock import SimClock
        from puppet.app.frame import FrameRenderer
        from puppet.app.hud import HudInfo

        self.setup, self.replay, self.ghost, self.sources = setup, replay, ghost, sources
        self.pygame, self.screen = open_display(size, f"puppet - {setup.interface.name}",
                                                 headless_hint(replay))
        pygame = self.pygame
        self.gamepads = Gamepads(pygame)
        self.feeder = self.recorder = None
        self.slowdown = slowdown = slowdown or setup.interface.slowdown
        if replay is not None:  # events come from a log; the devices only drive the window
            from puppet.timeline.replay import new_session

            self.session = session = new_session(replay, setup)
        else:
            self.session = session = Session(setup)
        self.clock = clock = SimClock(session.sim.dt, slowdown)
        if replay is not None:  # the recorded speed keys change the slowdown as they did
            from puppet.timeline.replay import LogFeeder

            self.feeder = LogFeeder(session, replay, until_step,
                                    on_action=None if slowdown_chosen else clock.apply)
        if replay is None and not no_record:
            from puppet.timeline.log import Recorder, default_path

            path = record or default_path(setup.interface.name)
            self.recorder = Recorder(session, path, slowdown=slowdown,
                                     script=script_text if script is not None else None)
            print(f"recording to {path}")
        self.player = None
        if script is not None and replay is None:  # timed events and rules, on the clock
            from puppet.timeline.reactive import ScriptPlayer

            self.player = ScriptPlayer(session, script, None, lambda: clock.slowdown,
                                       clock.apply)
        from puppet.session.history import Scrubber

        self.scrub = Scrubber(session)
        info = HudInfo(replaying=Path(replay.path).name if replay is not None else "",
                       overlay=overlay)
        # the frame is drawn as headless runs draw it, into the screen
        self.renderer = FrameRenderer(session, surface=self.screen, info=info)
        self.camera, self.info = self.renderer.camera, info
        self.font, self.small = self.renderer.font, self.renderer.small
        self.camera.follow(subject_of(session), None)
        from puppet.timeline.playtest.store import figure_line, last_for

        self.info.playtest = figure_line(last_for(setup.interface.name))  # how forgiving
        self.reloader = None
        self.reload_error = ""  # shown until the file is valid again
        if self.feeder is None:  # hot reload: saving the interface file applies it at once
            from puppet.app.reloader import Reloader

            self.reloader = Reloader(setup.interface_path, self.check_text,
                                     now=time.perf_counter())
        from puppet.app.gestures import GestureRecorder

        self.gestures = GestureRecorder()
        if note:
            session.say(note)
        self.held_at: set = set()  # pointer positions (pixels) that are not input
        self.start_pointer: dict = {}  # interface version -> where the mouse holds the pose
        self.pressed: dict[str, str] = {}  # key name -> chord it was pressed as
        self.dragging = False
        self.last_mouse = None
        self.pad = None  # --virtual-pad: the mouse and a few keys are a gamepad
        if virtual_pad and self.feeder is None:
            from puppet.app.virtual_pad import HELP, VirtualPad

            self.pad = VirtualPad()
            w, h = self.screen.get_size()
            pygame.mouse.set_pos((w // 2, h // 2))  # the stick at rest
            taken = VirtualPad.clashes(setup.interface)
            session.say(HELP + (f" (the layout's own {', '.join(taken)} do not reach it)"
                                if taken else ""))
            print(f"puppet play: {HELP}", file=sys.stderr)
        elif self.feeder is None and self.hold_pose():  # where the mouse holds the pose
            session.say("the pointer starts where the mouse holds the start pose")
        self.frames = pygame.time.Clock()
        self.start = time.perf_counter()

    # -- the loop --------------------------------------------------------------------
    def run(self) -> int:
        """Frames until the user quits; then the recording is closed."""
        running = True
        while running:
            wall_dt = self.frames.tick(60) / 1000.0
            running = self.poll_events()
            self.poll_reload()
            self.step(wall_dt)
            self.draw(wall_dt)
        self.scrub.release()
        if self.recorder is not None:
            self.recorder.close()
            print(f"recorded {self.recorder.path}")
        self.pygame.quit()
        return 0

    # -- events and input --------------------------------------------------------------
    def ctrl_held(self) -> bool:
        return bool(self.pygame.key.get_mods() & self.pygame.KMOD_CTRL)

    def mods(self) -> list[str]:
        pygame = self.pygame
        m = pygame.key.get_mods()
        return [n for n, flag in (("ctrl", pygame.KMOD_CTRL), ("shift", pygame.KMOD_SHIFT),
                                  ("alt", pygame.KMOD_ALT)) if m & flag]

    def poll_events(self) -> bool:
        """The devices' events of this frame, into the session; False means quit."""
        pygame, session, pad = self.pygame, self.session, self.pad
        running = True
        for event in pygame.event.get():
            translated = device_events(pygame, event, self.gamepads, session.interface.gamepad)
            consumed = False
            if pad is not None:  # mouse buttons and the pad's keys are the pad's
                translated, consumed = pad_events(pygame, pad, event, translated)
            for one in translated:
                running = self.app_action(self.handle(one)) and running
            if consumed:  # a key of the pad: not a key of the layout too
                continue
            if event.type == pygame.QUIT:
                running = False
            elif event.type == pygame.WINDOWRESIZED or event.type == pygame.VIDEORESIZE:
                self.camera.resize(*self.screen.get_size())
            elif event.type == pygame.KEYDOWN:
                running = self.key_down(event) and running
            elif event.type == pygame.KEYUP:
                name = pygame.key.name(event.key)
                if name in self.pressed:
                    chord = self.pressed.pop(name)
                    if session.app_action_of(chord) in ("rewind", "forward"):
                        self.scrub.release()  # play on from the snapshot shown
                    self.handle(ev.key(chord, False))
            elif event.type == pygame.MOUSEBUTTONDOWN and event.button == 1 \
                    and pygame.key.get_mods() & pygame.KMOD_CTRL:
                picked = _pick(session, self.camera, event.pos)
                if picked is not None:
                    link, local = picked
                    self.handle(ev.drag_start(link, local, self.camera.to_world(event.pos)))
                    self.dragging = True
            elif event.type == pygame.MOUSEBUTTONUP and event.button == 1 and self.dragging:
                self.handle(ev.drag_end())
                self.dragging = False
            elif event.type == pygame.MOUSEMOTION and self.dragging:
                self.handle(ev.drag_move(self.camera.to_world(event.pos)))
        if not self.clock.paused:
            self.send_mouse()
            if self.feeder is None:
                for source in self.sources:  # live streams and clips (on the sim clock)
                    for event_ in source.drain(session.time):
                        self.handle(event_)
        return running

    def key_down(self, event) -> bool:
        """A key pressed (a recorded gesture's key, or a chord); False means quit."""
        name = self.pygame.key.name(event.key)
        if name in MODIFIER_KEYS or not name:
            return True
        chord = key_chord(name, self.mods())
        session = self.session
        if self.gestures.binding:  # the key a recorded gesture goes on
            event_, text = self.gestures.bind(chord, session.interface,
                                              session.app_keys["save_gestures"])
            if event_ is not None:
                self.handle(event_)
            session.say(text)
            return True
        self.pressed[name] = chord
        return self.app_action(self.handle(ev.key(chord, True)))

    def handle(self, event) -> str | None:
        """Send an input event to the session (not while replaying or scrubbing)."""
        session = self.session
        if self.feeder is not None:  # replaying: only the window's own keys do anything
            if event["type"] == "key" and event["down"]:
                action = session.app_action_of(event["key"])
                return action if action not in ("rewind", "forward") else None
            return None
        if self.scrub.active and event["type"] in ("mouse", "drag"):
            return None
        action = session.app_action_of(event["key"]) if event["type"] == "key" else None
        if action in ("rewind", "forward"):  # the window's own: the scrub commits
            return action if event["down"] else None  # with a logged rewind action
        if self.scrub.active and self.scrub.moved:
            self.scrub.commit()  # a key while scrubbing acts at the step shown, in the log
            if event["type"] == "key":  # too; its owner there (the states may differ)
                action = session.app_action_of(event["key"])
        reset = event["type"] == "key" and event["down"] and action == "reset"
        action = session.handle(event)
        if reset and self.pad is None and self.hold_pose(after_reset=True):
            session.say("reset: the pointer is back where the mouse holds the start pose")
        return action

    def send_mouse(self) -> None:
        """The pointer's position to the session if it moved. Not while paused: moving
        the mouse to the keys would be new input, branching away the future that the
        scrub keys can still move through; it acts when the simulation steps again."""
        pygame = self.pygame
        if self.dragging or self.ctrl_held() or not pygame.mouse.get_focused():
            return  # Ctrl is the drag's: the mouse does not drive the maps meanwhile
        w, h = self.screen.get_size()
        mx, my = pygame.mouse.get_pos()
        if self.held_at:
            if (mx, my) in self.held_at:
                return  # holding the pose until the user moves the mouse
            self.held_at.clear()
        pos = (min(1.0, max(0.0, mx / max(1, w - 1))),
               min(1.0, max(0.0, 1.0 - my / max(1, h - 1))))
        if self.pad is not None:  # the mouse is a stick
            for event_ in self.pad.mouse(*pos):
                self.handle(event_)
            self.last_mouse = pos
        elif pos != self.last_mouse:
            self.handle(ev.mouse(*pos))
            self.gestures.add(self.session.time, *pos)
            self.last_mouse = pos

    def start_pose_pointer(self):
        """The pointer (0..1) at which the live interface's mouse maps hold the start
        pose (None if no mouse map drives a joint): found on a fresh session of the
        same interface, so it holds after a hot reload too."""
        session = self.session
        version = session.version
        if version not in self.start_pointer:
            import dataclasses

            fresh = Session(dataclasses.replace(self.setup, interface=session.interface))
            self.start_pointer[version] = fresh.runtime.pointer_for_pose()
        return self.start_pointer[version]

    def hold_pose(self, after_reset: bool = False) -> bool:
        """Put the pointer where the mouse maps hold the start pose, and send no mouse
        input until the user moves it, so the first mouse event does not throw the
        character out of its pose. After a reset the maps are first given that
        position (a logged mouse event: the reset re-applies the last inputs, which
        threw the lamp). If the pointer cannot be moved (some systems refuse), the
        pose is still held until the mouse moves. False if no mouse map drives a joint."""
        pygame = self.pygame
        rest = self.start_pose_pointer()
        if rest is None:
            return False
        if after_reset:
            self.session.handle(ev.mouse(*rest))
            self.last_mouse = rest
        self.held_at.clear()
        self.held_at.add(tuple(pygame.mouse.get_pos()))
        w, h = self.screen.get_size()
        target = (round(rest[0] * (w - 1)), round((1.0 - rest[1]) * (h - 1)))
        pygame.mouse.set_pos(target)
        self.held_at.add(target)
        return True

    # -- app actions -----------------------------------------------------------------
    def app_action(self, name: str | None) -> bool:
        """Do a window-side app action; False means quit."""
        clock, info, session, feeder = self.clock, self.info, self.session, self.feeder
        if name == "quit":
            return False
        if clock.apply(name):  # slower, faster, an interface key's slowdown
            return True
        if name in ("rewind", "forward"):
            self.scrub.start(forward=name == "forward")
        if name == "pause":
            clock.toggle_pause()
        elif name == "step":
            if clock.paused and feeder is not None:
                feeder.advance(1)  # the log's events due there act first
            elif clock.paused:
                self.send_mouse()
                session.advance(1)
        elif name == "help":
            info.show_help = not info.show_help
        elif name == "balance":
            info.overlay = not info.overlay
        elif name == "branches":
            self.next_branch()
        elif name == "take_branch" and feeder is None:
            self.take_branch()
        elif name == "export_branch" and feeder is None:
            self.export_branch()
        elif name == "record_gesture" and feeder is None:
            session.say(self.gestures.toggle(session.time, self.last_mouse,
                                             session.app_keys["record_gesture"]))
        elif name == "save_gestures" and self.reloader is not None:
            session.say(self.save_gestures())
        return True

    # -- hot reload and gestures -------------------------------------------------------
    def check_text(self, text: str) -> None:
        """Raise a ``DataError`` if ``text`` is not a valid interface file for this setup."""
        from puppet.data.catalog import parse_interface_text

        setup = self.setup
        parse_interface_text(text, str(setup.interface_path), setup.character,
                             setup.character_path, setup.scene)

    def poll_reload(self) -> None:
        """Apply the interface file if it was saved (valid), else show its error."""
        if self.reloader is None or self.scrub.active:
            return
        change = self.reloader.poll(time.perf_counter())
        if change is not None and not change.ok:
            self.reload_error = change.error  # the last good version keeps running
            print(f"puppet play: {change.error} (the last valid version keeps "
                  "running)", file=sys.stderr, flush=True)  # the whole line, to copy
        elif change is not None:
            self.reload_error = ""
            path = self.setup.interface_path
            self.handle(ev.reload(change.text, str(path)))
            for event_ in self.gestures.rebind_after_reload(self.session.interface):
                self.handle(event_)  # bound since the last save: keep them
            self.session.say(f"reloaded {path}")

    def save_gestures(self) -> str:
        """Write the live interface's gestures into its file (the reload follows)."""
        from puppet.data.errors import DataError
        from puppet.data.gesture_file import replace_gestures
        from puppet.data.yamlfile import read_text

        if self.reload_error:
            return "the interface file has an error: fix it before saving gestures"
        path = self.setup.interface_path
        gestures = self.session.interface.gestures
        try:
            text = replace_gestures(read_text(path), gestures)
            self.check_text(text)
            path.write_text(text, encoding="utf-8")
        except (DataError, OSError) as exc:
            return f"gestures not saved: {exc}"
        self.gestures.unsaved.clear()
        return f"saved {len(gestures)} gesture(s) into {path}"

    # -- branches ----------------------------------------------------------------------
    def next_branch(self) -> None:
        """Select the next branch near the step shown (past the last: none)."""
        info, session = self.info, self.session
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

    def selected_branch(self):
        session = self.session
        history = session.history
        if self.info.branch is None or self.info.branch >= len(history.branches):
            session.say(f"choose a branch first: {session.app_keys['branches']} lists them")
            return None
        return history.branches[self.info.branch]

    def take_branch(self) -> None:
        """Take up the selected branch: a logged "take" action (a replay does the same)."""
        chosen = self.selected_branch()
        if chosen is None:
            return
        history = self.session.history
        if not history.oldest() <= chosen.fork <= history.head:
            self.session.say("that branch forks before the history kept", error=True)
            return
        self.scrub.commit()
        self.handle(ev.action("take") | {"branch": self.info.branch})
        self.info.branch = None

    def export_branch(self) -> None:
        """Write the selected branch, from step 0, as a log of its own."""
        from puppet.timeline.log import default_path, record_events

        session, setup = self.session, self.setup
        chosen = self.selected_branch()
        if chosen is None:
            return
        events = session.branch_events(self.info.branch)
        if events is None:
            session.say("the history no longer reaches back to the start: cannot export",
                        error=True)
            return
        path = default_path(f"{setup.interface.name}-branch")
        at = chosen.fork * session.sim.dt
        fresh = Session(setup, dt=session.sim.dt,
                        checkpoint_interval=session.checkpoint_interval)
        record_events(fresh, events, chosen.head, path, slowdown=self.slowdown,
                      description=f"a branch of {setup.interface.name} from t={at:.2f} s")
        session.say(f"exported the branch to {path}")

    # -- the frame: step, then draw ------------------------------------------------------
    def step(self, wall_dt: float) -> None:
        """Advance the simulation by this frame's wall time: the scrub, the replayed
        log, the script or the live session."""
        clock, session, feeder = self.clock, self.session, self.feeder
        steps = clock.steps_for(wall_dt)
        if self.scrub.active:
            shift = bool(self.pygame.key.get_mods() & self.pygame.KMOD_SHIFT)
            self.scrub.update(wall_dt, forward=shift)
        elif feeder is not None:
            feeder.advance(steps)
            if feeder.finished and not clock.paused:
                from puppet.timeline.report import finished_message

                clock.toggle_pause()
                done = finished_message(session, self.replay)
                session.say(done, error="DIFFERENT" in done)
        elif self.player is not None:
            self.player.advance(steps)
        else:
            session.advance(steps)
        if session.halted and not clock.paused and not self.scrub.active:
            clock.toggle_pause()  # even the start blew up: pause on its one message

    def draw(self, wall_dt: float) -> None:
        """The HUD's figures, then the frame (``FrameRenderer``: the world under the
        panels and the HUD, as headless runs draw it) on screen."""
        info, session, clock = self.info, self.session, self.clock
        info.follow_messages(session, time.perf_counter())
        if self.reload_error:
            info.message, info.message_error = self.reload_error, True
        info.scrubbing = self.scrub.active
        clock.sample(time.perf_counter() - self.start, session.time)
        info.slowdown = clock.slowdown
        info.measured = clock.measured_slowdown()
        info.fps = self.frames.get_fps() or None
        info.sources = [s.hud_line() if hasattr(s, "hud_line") else s.status()
                        for s in self.sources]  # a live stream's line is the short one
        info.paused = clock.paused
        ghost = self.ghost
        world = not session.sim.blown_up()  # else (until the next health check recovers
        if world and ghost is not None:      # it) the last world drawn stays
            ghost.sync(session)
        self.renderer.render(session, wall_dt=wall_dt,
                             ghost=ghost.session if ghost is not None else None,
                             hold_camera=self.dragging or self.ctrl_held(), world=world)
        self.pygame.display.flip()


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

