"""The runtime's life beyond a step: reset, checkpoints and hot reload.

Kept apart from the arbiter (``interface.runtime``) because none of it runs while a
performance steps: a reset starts control again, a snapshot saves and restores the
runtime's plain-data state beside the physics (``physics.snapshot``), and ``adopt``
hands a running performance over to a reloaded interface file.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from puppet.interface.runtime import InterfaceRuntime


class RuntimeState:
    """Mixed into ``InterfaceRuntime``: its reset, snapshot state and hot reload."""

    # -- reset and snapshots -------------------------------------------------------
    def reset(self) -> None:
        """After the character is reset: start-pose targets, then the current inputs."""
        start = self.character.start_joint_angles()
        for name, servo in self.character.servos.items():
            servo.target = start.get(name, 0.0)
        for controller in self.controllers:  # the restored space has no grasp joints either
            controller.stop()
        self.owners.table = {}
        self.gain_holds = {}
        self.buffer.set_state(None)
        self.chained = None
        self.mode = self.spec.start_mode
        self._use_binding(self.spec.start_binding)
        self.apply_gains()
        self._start_control()
        self.apply_maps()

    # The runtime's own state rides along with physics snapshots (plain data).
    def get_state(self) -> dict:
        if self._pending:
            self.flush()
        return {"inputs": dict(self.inputs), "channels": dict(self.channels),
                "held": sorted(self.held), "mode": self.mode,
                "owners": self.owners.get_state(),
                "controllers": [c.get_state() for c in self.controllers],
                "machines": {n: m.get_state() for n, m in self.machines.items()},
                "gain_holds": _copy_holds(self.gain_holds), "binding": self.role_binding,
                "next_wakeup": self.next_wakeup, "buffer": self.buffer.get_state()}

    def set_state(self, state: dict) -> None:
        self.inputs.clear()
        self.inputs.update(state["inputs"])
        self.channels.clear()
        self.channels.update(state["channels"])
        self.held = set(state["held"])
        self.mode = state["mode"]
        self.owners.set_state(state["owners"])
        for controller, s in zip(self.controllers, state["controllers"]):
            controller.set_state(s)
        for name, s in state["machines"].items():
            if name in self.machines:
                self.machines[name].set_state(s)
        self._follow_rate()  # the period follows from the states (saved)
        self.gain_holds = _copy_holds(state["gain_holds"])
        self.buffer.set_state(state.get("buffer"))
        if state["binding"] != self.role_binding:
            self._use_binding(state["binding"])
        self._pending = []
        self.chained = None  # (a chain's count is the tick's at the step it stopped)
        if self.poll is not None:
            self.poll.resume = -1  # (the tick at a restored step is Python's)
        self._refresh_active_maps()
        self._reschedule(self.step_now())
        self.next_wakeup = state["next_wakeup"]

    # -- hot reload ----------------------------------------------------------------------
    def adopt(self, old: InterfaceRuntime) -> None:
        """Take over from ``old``, the runtime of the interface this one replaces (a hot
        reload): the physics and the servo targets stay as they are, so nothing moves
        until an input changes or a key is pressed; input values and held keys carry
        over; so does what is running (sequence, gesture, reaches, grasps, gain holds,
        states, mode, random motion) where the new interface defines it the same way.
        The rest ends, leaving its joints' targets where they are."""
        now = old.step_now()
        self.now = old.now
        self.inputs.update(old.inputs)
        self.channels.update(old.channels)
        for _, values in old._pending:  # stored, as old's flush would (its maps are gone)
            self.channels.update(values)
        self.held = set(old.held)
        self.buffer.set_state(old.buffer.get_state())
        spec, was = self.spec, old.spec
        self.mode = old.mode if old.mode in spec.modes else spec.start_mode
        if old.role_binding in spec.bindings:
            self._use_binding(old.role_binding)

        def same(kind: str, name: str) -> bool:
            if kind == "sequence":
                return (name in spec.sequences and spec.sequences[name] == was.sequences.get(name)
                        and all(spec.poses.get(p.pose) == was.poses.get(p.pose)
                                for p in spec.sequences[name]))
            if kind == "chain":
                return name in spec.chains and spec.chains[name] == was.chains.get(name)
            if kind == "tracking":
                return spec.tracking == was.tracking
            return spec.perturbation == was.perturbation

        kept = set()
        for mine, theirs in zip(self.controllers, old.controllers):
            kept |= mine.adopt(theirs, same, now)
        self.owners.table = dict(old.owners.table)
        self.owners.keep_only(kept)
        if spec.gains == was.gains:
            self.gain_holds = _copy_holds(old.gain_holds)
        else:
            self.apply_gains()
            if self.tracker.scaled:  # still tracking under KD: its gains again
                self.tracker.scale_gains(list(self.tracker.scaled))
        fresh = []
        for name, machine in self.machines.items():
            theirs = old.machines.get(name)
            if theirs is not None and theirs.current in machine.spec.states:
                machine.set_state(theirs.get_state())
            else:  # a new state machine (or its state is gone): start it
                machine.enter(machine.initial, now)
                fresh.append(name)
        self._follow_rate()
        self._refresh_active_maps()
        for name in fresh:
            self._run_entry(name, now, 0)
        self._reschedule(now)


def _copy_holds(holds: dict) -> dict:
    """A deep copy of gain holds (chord -> joint -> [stiffness, damping])."""
    return {c: {j: list(v) for j, v in h.items()} for c, h in holds.items()}
