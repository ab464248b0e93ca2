"""A Session plays one interface on one character in one scene.

It is the only code path from input events to physics: the window, headless play,
replay and the tests all feed events into ``handle`` and call ``advance``. Events
act at the current step; nothing here reads a clock.
"""

from __future__ import annotations

from puppet.data.catalog import Setup
from puppet.interface.app_keys import SIM_ACTIONS
from puppet.interface.events import Event
from puppet.interface.runtime import InterfaceRuntime
from puppet.physics.simulation import DEFAULT_DT, Simulation


class Session:
    def __init__(self, setup: Setup, dt: float = DEFAULT_DT):
        self.setup = setup
        self.sim = Simulation(setup.character, setup.scene, dt)
        self.runtime = InterfaceRuntime(setup.interface, self.sim.character)
        self.app_keys = setup.interface.app_key_table()
        self.key_to_app = {key: action for action, key in self.app_keys.items()}
        self._start = self.sim.checkpoint()

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
        if kind == "key" and event["down"]:
            app_action = self.key_to_app.get(event["key"])
            if app_action is not None and not self.runtime.handles_key(event["key"]):
                if app_action in SIM_ACTIONS:
                    self.perform(app_action)
                    return None
                return app_action
        if kind == "action":
            self.perform(event["name"])
            return None
        if kind == "drag":
            phase = event["phase"]
            if phase == "start":
                self.sim.start_drag(event["link"], tuple(event["point"]), tuple(event["target"]))
            elif phase == "move":
                self.sim.move_drag(tuple(event["target"]))
            else:
                self.sim.end_drag()
            return None
        self.runtime.on_event(event)
        return None

    def perform(self, name: str) -> None:
        if name == "reset":
            self.reset()
        else:
            raise ValueError(f"unknown simulation action '{name}'")

    def reset(self) -> None:
        """Back to the start pose; the time line goes on (reset is an event, not a rewind)."""
        steps = self.sim.steps
        self.sim.restore(self._start)
        self.sim.steps = steps
        self.runtime.reset()

    def advance(self, steps: int = 1) -> None:
        self.sim.step(steps)
