"""Gestures: a recorded mouse path bound to a key, played back through the active
mouse maps in sim time, as a sequence plays its poses.

It owns the joints the active mouse maps drive (taken back like a sequence's: by a
pose, a moving mouse, a new sequence) and writes only those it still owns.
"""

from __future__ import annotations

from puppet.data.keys import normalize_key
from puppet.interface.ownership import GESTURE, JointOwners, Owner


class GestureController:
    BUSY = "running"

    def __init__(self, specs, servos, owners: JointOwners, dt: float):
        # key -> [(step offset, x, y)]: recorded mouse paths, replayed in sim time
        self.paths = {normalize_key(g.key): [(round(t / dt), x, y) for t, x, y in g.path]
                      for g in specs}
        self.servos = servos
        self.owners_table = owners
        self.running: list | None = None  # [key, start step, index of the next point]
        # Set by the runtime whenever the active maps change (what a gesture drives):
        self.mouse_maps: list = []
        self.mouse_joints: set[str] = set()
        self.inputs: dict[str, float] = {}

    def start(self, chord: str, now: int) -> None:
        self.owners_table.drop(GESTURE)
        self.owners_table.claim(self.mouse_joints, GESTURE)
        self.running = [chord, now, 0]
        self.tick(now)

    def tick(self, step: int) -> None:
        """Feed the gesture's points due by ``step`` through the mouse maps, writing
        only the joints it still owns; end it when done or when it owns none."""
        if self.running is None:
            return
        chord, start, index = self.running
        path = self.paths[chord]
        owned = self.owners_table.owned(GESTURE)
        if owned:
            servos = self.servos
            others = [(servos[j], servos[j].target) for j in self.mouse_joints - owned]
            values = dict(self.inputs)
            pointer = "pointer.x" in values  # the layout reads the mouse as the pointer
            while index < len(path) and start + path[index][0] <= step:
                values["mouse.x"], values["mouse.y"] = path[index][1], path[index][2]
                if pointer:
                    values["pointer.x"], values["pointer.y"] = path[index][1], path[index][2]
                for apply in self.mouse_maps:
                    apply(values)
                index += 1
            for servo, target in others:  # joints taken back by later actions
                servo.target = target
        if index >= len(path) or not owned:
            self.owners_table.drop(GESTURE)
            self.running = None
        else:
            self.running[2] = index

    def next_wakeup(self, earliest: int) -> int | None:
        if self.running is None:
            return None
        chord, start, index = self.running
        return start + self.paths[chord][index][0]

    def owners(self) -> set[Owner]:
        return {GESTURE} if self.running is not None else set()

    def get_state(self):
        return list(self.running) if self.running else None

    def set_state(self, state) -> None:
        self.running = list(state) if state else None

    def adopt(self, old: GestureController, same, now: int) -> set[Owner]:
        g = old.running
        if g is not None and self.paths.get(g[0]) == old.paths.get(g[0]):
            self.running = list(g)
            return {GESTURE}
        return set()

    def stop(self) -> None:
        self.running = None
