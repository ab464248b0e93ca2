"""A Session plays one interface on one character in one scene.

It is the only code path from input events to physics: the window, headless play,
replay and the tests all feed events into ``handle`` and call ``advance``. Events
act at the current step; nothing here reads a clock.
"""

from __future__ import annotations

import dataclasses
import json
from collections.abc import Callable

from puppet.data.catalog import Setup, parse_interface_text
from puppet.data.interfaces import InterfaceSpec, with_gesture
from puppet.interface.app_keys import SIM_ACTIONS, AppAction
from puppet.interface.events import Event
from puppet.interface.runtime import InterfaceRuntime
from puppet.physics.simulation import Simulation, step_of
from puppet.session.history import History, Snapshot
from puppet.session.playback import play
from puppet.session.stepping import MAX_SPEED2, feed, idle_for, recorded

FRAME_SECONDS = 1 / 60  # the cheap leaving-the-world check runs this often (a frame)
WORLD_MARGIN = 1.0  # m below the lowest ground point, or past the ground's ends: gone


def world_box(scene) -> tuple[float, float, float, float]:
    """(x min, x max, y min, y max) the root link must stay inside: the ground's
    extent widened by WORLD_MARGIN (y max: 10 km above its highest point)."""
    xs = [x for g in scene.ground for x, _ in g.points]
    ys = [y for g in scene.ground for _, y in g.points]
    return (min(xs) - WORLD_MARGIN, max(xs) + WORLD_MARGIN, min(ys) - WORLD_MARGIN,
            max(ys) + 10000.0)


class Session:
    def __init__(self, setup: Setup, dt: float | None = None,
                 checkpoint_interval: float | None = None, keyframes: bool = True):
        """``dt``: the simulation step, s (default: the character's, ``step_of``; a
        replay passes its log's). ``checkpoint_interval``: seconds between automatic
        checkpoints (default: the interface's ``checkpoint_every``). ``keyframes=False``
        turns them off (rewinds then reach back to manual checkpoints and the start
        only): the benchmark uses it to weigh the control layer apart from the timeline."""
        if dt is None:
            dt = step_of(setup.character)
        if checkpoint_interval is None:
            checkpoint_interval = setup.interface.checkpoint_every
        self.setup = setup
        self.sim = Simulation(setup.interface.start_character(setup.character), setup.scene, dt)
        self.runtime = InterfaceRuntime(setup.interface, self.sim.character, self.sim)
        self._bind_app_keys(setup.interface)
        # Every interface this session has run (hot reloads): snapshots name theirs by
        # index, so a rewind across a reload restores the interface of that time.
        self.versions: list[InterfaceSpec] = [setup.interface]
        self._version_of: dict = {}  # reload text (or other key) -> index in versions
        self.version = 0
        self.checkpoint_interval = checkpoint_interval
        # Called with (step, event) for every event handled, before it acts (recording).
        self.listener: Callable[[int, Event], None] | None = None
        self.message = ""  # the last thing the user should be told (e.g. a blow-up)
        self.message_serial = 0  # bumped on every new message
        self.message_error = False  # the message says something went wrong
        self.last_take: tuple[int, int] = (0, 0)  # (how many takes, the last one's fork)
        self.blowups = 0
        self.blowup_messages: list[str] = []  # what each recovery said (headless runs print them)
        # Blow-up recovery: (step it happened, step of the checkpoint restored) of the last
        # one, to go further back when that checkpoint fails again; ``halted``: the message
        # once even the start failed (the physics stands still until a reset, restore or
        # rewind; the step count goes on, so a replay ends where the recording did).
        self._recovery: tuple[int, int] | None = None
        self.halted: str | None = None
        self.halted_at: float | None = None  # s: when it halted (the end line says it)
        self._frame_every = max(1, round(FRAME_SECONDS / dt))
        self._world = world_box(setup.scene)
        self._root_name = self.sim.character.link_order[0]
        self._advance_constants = (self._frame_every, self._root_name, *self._world)
        self._frame = (*self._advance_constants, MAX_SPEED2)  # (the kernel's loop checks it)
        self._idle = idle_for(self._frame)  # (the steps where nothing is due, in C)
        start = self._snapshot()  # re-seated, like every checkpoint
        self._start = start.sim
        self.history = History(dt, checkpoint_interval, keyframes=keyframes)
        self.history.set_start(start)
        self._rebuilding = False  # re-simulating recorded history (rewind): record nothing

    @property
    def character(self):
        return self.sim.character

    @property
    def time(self) -> float:
        return self.sim.time

    @property
    def steps(self) -> int:
        return self.sim.steps

    def handle(self, event: Event) -> str | None:
        """Apply an input event at the current step. Returns the app action a key
        stands for when that action is the window's business (pause, quit...)."""
        kind = event["type"]
        if kind == "channels" or kind == "mouse" or kind == "gamepad":  # the frequent
            runtime = self.runtime  # events: recorded, then the runtime's fast paths
            if not self._rebuilding:
                recorded(self, self.history, self.sim.steps, event)
            if kind == "channels":  # a stream's frame (mocap)
                runtime._on_channels(event["values"])
                return None
            if kind == "mouse":
                return runtime.on_event(event)  # (which runs pending channel maps first)
            action = runtime.on_event(event)  # a gamepad's button may ask for an action
            if action in SIM_ACTIONS:
                self.perform(action)
                return None
            return action
        if self.runtime._pending:
            self.runtime.flush()  # channel maps act before anything after them
        # a key's owner, resolved once for this press (interface.bindings decides)
        resolved = self.runtime.resolve(event["key"]) if kind == "key" else None
        if not self._rebuilding:
            if self.listener is not None:
                self.listener(self.sim.steps, event)  # logged, all of it (speed keys too)
            if not (kind == "action" and event.get("name") in ("rewind", "restore", "take")
                    or kind == "key" and resolved.app is not None
                    and resolved.app not in SIM_ACTIONS):  # the window's business (help,
                # pause...), not input: it does not rewrite the future, so scrubbing back,
                # pressing it and scrubbing forward again works
                if self.sim.steps < self.history.head:
                    self.history.branch(self.sim.steps)  # new input: the future is rewritten
                self.history.record(self.sim.steps, event)
        if kind == "key" and event["down"]:
            app_action = resolved.app
            if app_action is not None:
                if app_action in SIM_ACTIONS:
                    self.perform(app_action)
                    return None
                return app_action
        if kind == "action":
            self.perform(event["name"], event.get("to_step"), event.get("branch"))
            return None
        if kind == "reload":
            self.reload(event["text"], event.get("path"))
            return None
        if kind == "gesture":
            self.bind_gesture(event["key"], event["path"], event.get("description", ""))
            return None
        if kind == "push":
            self.sim.push(event["link"], tuple(event["impulse"]), event.get("point"))
            self.runtime.tracker.impact(self.steps)  # a performer's figure reacts
            return None
        if kind == "drag":
            phase = event["phase"]
            if phase == "start":
                if event["link"] not in self.character.link_order:
                    raise ValueError(f"drag: unknown link {event['link']!r}; the character "
                                     f"has: {', '.join(self.character.link_order)}")
                self.sim.start_drag(event["link"], tuple(event["point"]), tuple(event["target"]))
                self.runtime.tracker.impact(self.steps)
            elif phase == "move":
                self.sim.move_drag(tuple(event["target"]))
                self.runtime.tracker.impact(self.steps)  # still pulled: still reacting
            else:
                self.sim.end_drag()
            return None
        tracker = self.runtime.tracker
        was_tracking = tracker.mode
        action = self.runtime.on_event(event, resolved)  # an interface key may ask for an
        # app action
        if kind == "key" and was_tracking == "off" and tracker.mode != "off" \
                and not self._rebuilding \
                and not any(c in self.runtime.channels for c in tracker.joints.values()):
            self.say(f"{event['key']}: no motion capture stream (start with --mocap CLIP)")
        if action in SIM_ACTIONS:
            self.perform(action)
            return None
        return action

    def app_action_of(self, chord: str) -> AppAction | None:
        """The app action ``chord`` stands for now, or None when it is the interface's
        input or nobody's (decided in ``interface.bindings``; asked here)."""
        return self.runtime.resolve(chord).app

    def perform(self, name: str, to_step: int | None = None,
                branch: int | None = None) -> None:
        if name == "reset":
            self.reset()
        elif name == "checkpoint":
            self.checkpoint()
        elif name == "restore":
            self.restore_checkpoint()
        elif name == "rewind":
            if to_step is None:
                raise ValueError("the rewind action needs 'to_step'")
            self.rewind_to(int(to_step))
        elif name == "take":
            if branch is None:
                raise ValueError("the take action needs 'branch'")
            self.take_branch(int(branch))
        else:
            raise ValueError(f"unknown simulation action '{name}'")

    def reset(self) -> None:
        """Back to the start pose; the time line goes on (reset is an event, not a rewind)."""
        steps = self.sim.steps
        self.sim.restore(self._start)
        self.sim.steps = steps
        self.runtime.reset()
        self._recovery, self.halted = None, None

    # -- hot reload ---------------------------------------------------------------------
    @property
    def interface(self) -> InterfaceSpec:
        return self.versions[self.version]

    def reload(self, text: str, path: str | None = None) -> None:
        """Run the interface in ``text`` from now on (the "reload" event). It is parsed
        and checked against this session's character and scene exactly like ``puppet
        check`` does (DataError if invalid: the window checks before sending); the new
        runtime takes over input state and what is running (``InterfaceRuntime.adopt``),
        the physics and the servo targets are untouched."""
        key = ("text", text)
        index = self._version_of.get(key)
        if index is None:
            spec = parse_interface_text(text, path or str(self.setup.interface_path),
                                        self.setup.character, self.setup.character_path,
                                        self.setup.scene)[0]
            index = self._add_version(key, spec)
        self._run_version(index, adopt=True)

    def bind_gesture(self, key: str, path, description: str = "") -> None:
        """Bind a recorded mouse path to a key (the "gesture" event): the live interface
        is the current one with that gesture (ValueError if the key is taken or the
        path is invalid; the window checks first)."""
        vkey = ("gesture", self.version, key, json.dumps(path), description)
        index = self._version_of.get(vkey)
        if index is None:
            index = self._add_version(vkey, with_gesture(self.interface, key, path, description))
        self._run_version(index, adopt=True)

    def _add_version(self, key, spec: InterfaceSpec) -> int:
        self.versions.append(spec)
        self._version_of[key] = len(self.versions) - 1
        return len(self.versions) - 1

    def _run_version(self, index: int, adopt: bool) -> None:
        """Switch to interface version ``index``: with ``adopt``, continuing what the
        current runtime does; without, touching nothing (a snapshot's state follows)."""
        spec = self.versions[index]
        runtime = InterfaceRuntime(spec, self.sim.character, self.sim, start=False)
        if adopt:
            runtime.adopt(self.runtime)
        self.runtime = runtime
        self.version = index
        self.setup = dataclasses.replace(self.setup, interface=spec)
        self._bind_app_keys(spec)

    def _bind_app_keys(self, spec: InterfaceSpec) -> None:
        """The app's keys as ``spec`` binds them, both ways round."""
        self.app_keys = spec.app_key_table()
        self.key_to_app = {key: AppAction(action) for action, key in self.app_keys.items()}

    def _runtime_state(self) -> dict:
        state = self.runtime.get_state()
        state["interface_version"] = self.version
        state["recovery"] = self._recovery  # so a rewind re-lives the same recoveries
        return state

    def advance(self, steps: int = 1) -> None:
        """Step the physics, taking the history's snapshots at their step boundaries
        (and recovering from a blow-up there), so the result does not depend on how
        the steps are split between calls (``stepping.feed``: the one stepping loop,
        which the replays also run, with their events)."""
        if steps > 0:
            feed(self, (), 0, None, self.sim.steps + steps, steps)

    # -- history: checkpoints, rewind, blow-up recovery --------------------------------
    def _snapshot(self) -> Snapshot:
        """The state now, continuing on a restored copy (``Simulation.checkpoint``), so
        that restoring this snapshot and feeding the same inputs is bit-identical to
        never restoring: a rewind shows exactly what was played, and going back to any
        checkpoint, automatic or manual, replays exactly. (pymunk's copies lose part of
        the solver's warm start; a plain snapshot would restore a past that drifts by
        up to centimetres from the one played.) The price: the run depends on where the
        checkpoints fall, which the log records (the interval; checkpoint actions), so
        a replay takes the same ones at the same steps and reaches the same bits."""
        return Snapshot(self.sim.steps, self.sim.keep(), self._runtime_state())

    def _restore(self, snap: Snapshot, keep_interface: bool = False) -> None:
        """Restore a snapshot, with the interface version it was taken under; with
        ``keep_interface`` the current version then takes over again (as a reload
        would), so going back to a checkpoint does not undo a hot reload."""
        current = self.version
        index = snap.runtime.get("interface_version", 0)
        if index != self.version:
            self._run_version(index, adopt=False)
        self.sim.restore(snap.sim)
        self.runtime.set_state(snap.runtime)
        self._recovery = snap.runtime.get("recovery")
        self.halted = None
        if keep_interface and self.version != current:
            self._run_version(current, adopt=True)

    def left_world(self) -> bool:
        """The root link is below the lowest ground point by WORLD_MARGIN, or past the
        ground's ends (or not a finite position)."""
        x, y = self.sim.character.bodies[self._root_name].position
        x0, x1, y0, y1 = self._world
        return not (x0 < x < x1 and y0 < y < y1)

    def _at_boundary(self) -> None:
        if self.sim.blown_up() or self.left_world():
            self._recover()
            return
        if not self._rebuilding and self.history.keyframe_due(self.sim.steps):
            self.history.add(self._snapshot())

    def _recover(self) -> None:
        """Back to the last good checkpoint's state; the time line goes on (like reset).
        If the checkpoint restored last time fails again before the run has gone as far
        past it as it had (plus a checkpoint interval), the one before it is tried, and
        so on back to the start; if the start fails too, the physics halts with one
        message (``halted``) until a reset, restore or rewind. It never loops."""
        steps = self.sim.steps
        what = "left the world" if not self.sim.blown_up() and self.left_world() \
            else "blew up"
        before = steps
        last = self._recovery
        if last is not None and steps - last[0] <= (last[0] - last[1]) \
                + self.history.checkpoint_every:
            before = last[1]  # that checkpoint failed again: one further back
        start = self.history.start
        if last is not None and before == last[1] and last[1] <= start.step:
            self.halted_at = steps * self.sim.dt
            self.halted = (f"the simulation {what} at t={steps * self.sim.dt:.2f} s again "
                           f"after going back to the start; stopped (reset, rewind or "
                           f"change the interface)")
            if not self._rebuilding:
                self.blowups += 1
                self.say(self.halted)
                self.blowup_messages.append(self.message)
            return
        snap = self.history.last_checkpoint(before)
        self._restore(snap, keep_interface=True)
        self.sim.steps = steps
        self._recovery = (steps, snap.step)
        if self._rebuilding:
            return  # re-simulating history (a rewind): this one was counted when it happened
        self.blowups += 1
        self.say(f"the simulation {what} at t={steps * self.sim.dt:.2f} s; "
                 f"restored the checkpoint of t={snap.step * self.sim.dt:.2f} s", error=True)
        self.blowup_messages.append(self.message)

    def say(self, text: str, error: bool = False) -> None:
        """A message for the screen; ``error``: something went wrong (drawn in red)."""
        self.message = text
        self.message_error = error
        self.message_serial += 1

    def checkpoint(self) -> Snapshot:
        """A manual checkpoint here (the "restore" action goes back to it)."""
        snap = self._snapshot()
        if not self._rebuilding:  # re-simulating: re-seat the same way, keep the original
            self.history.add_manual(snap)
            self.say(f"checkpoint at t={snap.step * self.sim.dt:.2f} s")
        return snap

    def restore_checkpoint(self) -> None:
        """Back to the last manual checkpoint (else the last automatic one)."""
        steps = self.sim.steps
        snap = self.history.last_manual(steps) or self.history.last_checkpoint(steps)
        self._restore(snap, keep_interface=True)
        self.history.branch(snap.step)
        if not self._rebuilding:
            self.say(f"back to the checkpoint of t={snap.step * self.sim.dt:.2f} s")

    def rewind_to(self, step: int) -> None:
        """Back (or forward, within a rewound history) to ``step``: restore the last
        keyframe at or before it and re-simulate the recorded input up to it. The
        history is kept until new input (or stepping on) branches it."""
        history = self.history
        if not history.oldest() <= step <= history.head:
            raise ValueError(f"cannot rewind to step {step}: no snapshot there (the history "
                             f"spans steps {history.oldest()}..{history.head})")
        snap = history.keyframe_before(step)
        self._restore(snap)
        self._rebuilding = True
        try:
            play(self, history.events_after(snap, step), until_step=None, end_step=step)
        finally:
            self._rebuilding = False

    def take_branch(self, index: int) -> None:
        """Take up an abandoned future again (the "take" action, logged with the
        branch's index): back to where it forked (an exact rewind), the present future
        kept as a branch in its turn, then the branch's input re-played up to its end,
        with its keyframes taken as they were: the very run that was abandoned."""
        history = self.history
        if not 0 <= index < len(history.branches):
            raise ValueError(f"no branch {index} (there are {len(history.branches)})")
        chosen = history.branches[index]
        if chosen.fork < history.oldest() or chosen.fork > history.head:
            raise ValueError(f"branch {index} forks at step {chosen.fork}, outside the "
                             f"history kept (steps {history.oldest()}..{history.head})")
        self.rewind_to(chosen.fork)
        self.last_take = (self.last_take[0] + 1, chosen.fork)  # a trajectory drops the rest
        del history.branches[index]
        history.branch(chosen.fork)  # the present future: a branch in its turn
        listener, self.listener = self.listener, None  # the log has the take action
        try:
            play(self, [(step, e) for _, step, e in chosen.events], until_step=None,
                 end_step=chosen.head)
        finally:
            self.listener = listener
        if not self._rebuilding:
            self.say(f"took up the branch from t={chosen.fork * self.sim.dt:.2f} s "
                     f"({chosen.steps * self.sim.dt:.1f} s)")

    def branch_events(self, index: int) -> list[tuple[int, Event]] | None:
        """The whole input of branch ``index`` from step 0, as one linear history: the
        kept events up to its fork, then its own (None if the history no longer reaches
        back to step 0: only the last minutes are kept)."""
        history = self.history
        chosen = history.branches[index]
        if history.oldest() > 0:
            return None
        before = [(step, e) for _, step, e in history.events if step < chosen.fork]
        return before + [(step, e) for _, step, e in chosen.events]

    def preview(self, step: int) -> None:
        """Show the snapshot at ``step`` while scrubbing (the window commits the
        scrub with a logged "rewind" action when the key is released)."""
        self.rewind_to(step)
