"""The active maps of an interface runtime: which continuous maps the current mode and
states make active, what they compile to (once per binding and set of active maps),
and the feedback maps the control rate runs.

A mixin of ``puppet.interface.runtime.InterfaceRuntime``, which holds the state these
methods read (its inputs, channels, owners, roles, controllers)."""

from __future__ import annotations

import math

from puppet.data.interfaces import InterfaceSpec
from puppet.data.keys import POINTER
from puppet.interface import maps as mapping
from puppet.interface.conditions import map_reader
from puppet.interface.ownership import FEEDBACK


class ActiveMaps:
    """The maps part of the runtime (see the module docstring)."""

    def _refresh_active_maps(self) -> None:
        if self._pending:
            self.flush()  # with the maps that were active when their events came
        # What the active maps compile to depends on the binding, the mode and each
        # machine's state alone (a gait enters a state every few control steps): worked
        # out once for each (the appliers are plain functions of the inputs)
        binding = self.roles.binding
        where = (binding, self.mode, tuple([m.current for m in self.machines.values()]))
        cache = self.__dict__.get("_refreshed")
        if cache is None:
            cache = self._refreshed = {}
        got = cache.get(where)
        if got is None:
            got = cache[where] = self._active_now(binding)
        self.active_maps, compiled, self._input_maps = got
        self._mouse_maps, (readers, setters, adders), joints, self._channel_maps = compiled
        self.feedback.set_maps(readers, setters, adders)
        self.gestures.mouse_maps = self._mouse_maps  # what a gesture plays through
        self.gestures.mouse_joints = joints  # (read only)

    def prime_maps(self) -> None:
        """What ``_refresh_active_maps`` finds for each mode and state of a one-machine
        interface, made ahead (each state's first entry in a replay made it between
        the steps; the compiled maps are plain functions of the inputs)."""
        if len(self.machines) != 1:
            return
        (machine,) = self.machines.values()
        binding, kept = self.roles.binding, self.__dict__.get("active_maps")
        cache = self.__dict__.setdefault("_refreshed", {})
        try:
            for mode in [None, *self.spec.modes]:
                for state in machine.spec.states:
                    where = (binding, mode, (state,))
                    if where not in cache:
                        cache[where] = self._active_now(binding, mode, (state,))
                    readers, setters, adders = cache[where][1][1]
                    fk = self.feedback._fk  # (Feedback.set_maps's compiled plan)
                    if fk is not None and adders and not setters:
                        fk.plan(readers, adders)
        finally:
            if kept is None:  # (a runtime not started: none yet)
                self.__dict__.pop("active_maps", None)
            else:
                self.active_maps = kept

    def _active_now(self, binding, mode=False, states=None) -> tuple:
        """(the active maps, what they compile to, an empty ``_input_maps``), in the mode
        and states of now (or those given: ``prime_maps``)."""
        spec = self.spec
        active = list(spec.maps)
        mode = self.mode if mode is False else mode
        if mode is not None:
            active += spec.modes[mode]
        if states is None:
            states = [machine.current for machine in self.machines.values()]
        for machine, state in zip(self.machines.values(), states):
            active += machine.spec.states[state].maps
        self.active_maps = active
        key = (binding, tuple(map(id, active)))
        compiled = self._active_cache.get(key)
        if compiled is None:
            joints: set[str] = set()
            for m in active:
                if any(n in ("mouse.x", "mouse.y") + POINTER for n in m.inputs):
                    joints |= self._map_joints(m)
            compiled = self._active_cache[key] = (
                mapping.fused(self._compiled(("mouse.x", "mouse.y") + POINTER)),
                self._feedback_maps(active), frozenset(joints), {})
        return active, compiled, {}  # (binding, input names) -> apply_maps' appliers

    def _compiled(self, inputs) -> list:
        """Compiled appliers of the active device maps reading any of ``inputs``, in
        order (feedback maps run at the control rate instead)."""
        return [self._applier(m) for m in self.active_maps
                if not m.feedback and any(i in inputs for i in m.inputs)]

    def _feedback_maps(self, active) -> tuple:
        """The active feedback maps (sensor inputs, ``add``) as their controller takes
        them: (readers, setters, adders)."""
        readers, setters, adders = {}, [], []
        for m in active:
            if not m.feedback:
                continue
            for name in self.roles.map(m).inputs:
                if name.startswith("sensor.") and name not in readers:
                    read = self._readers.get(name)
                    if read is None:
                        read = self._readers[name] = map_reader(name[7:], self.character)
                    readers[name] = read
            if getattr(m, "combine", "set") == "add":
                adders.append(self._applier(m))
            else:
                setters.append((self._applier(m), tuple(sorted(self._map_joints(m)))))
        return tuple(readers.items()), tuple(setters), tuple(adders)

    def _map_joints(self, m) -> set[str]:
        m = self.roles.map(m)
        if getattr(m, "grid", None) is not None:
            these = {j for row in m.grid for p in row for j in self.pose_targets[p]}
            return these if m.joints is None else these & set(m.joints)
        return set(m.gains())

    def _applier(self, m):
        """The compiled form of map ``m`` (compiled once per runtime)."""
        key = (id(m), self.role_binding)
        applier = self._map_cache.get(key)
        if applier is None:
            m = self.roles.map(m)
            if getattr(m, "combine", "set") == "add":
                applier = mapping.compile_contribution(m, self.channels)
            else:
                applier = mapping.compile_map(m, self.character.servos, self.pose_targets,
                                              self.channels, self.frames,
                                              FEEDBACK if m.feedback else None)
            self._map_cache[key] = applier
        return applier

    def pointer_for_pose(self, tolerance_deg: float = 2.0) -> tuple[float, float] | None:
        """The mouse position (x, y in 0..1) at which the active mouse maps give the
        targets the joints have now (at the start: the start pose), or None if no
        position comes within ``tolerance_deg`` on every joint they drive. The window
        puts the pointer there when it opens, so its first mouse event does not snap
        the character out of its pose (the middle of luxo-mouse throws Luxo over).
        A grid search, then a pattern search; the targets are left as they were."""
        if self._pending:
            self.flush()
        mouse_joints = self.gestures.mouse_joints
        if not self._mouse_maps or not mouse_joints:
            return None
        servos = self.character.servos
        want = {j: servos[j].target for j in mouse_joints}
        values = dict(self.inputs)

        def score(x: float, y: float) -> tuple[float, float]:
            values["mouse.x"], values["mouse.y"] = x, y
            values["pointer.x"], values["pointer.y"] = x, y
            for apply in self._mouse_maps:
                apply(values)  # written straight to the servos; put back below
            error = max(abs(servos[j].target - t) for j, t in want.items())
            return error, abs(x - 0.5) + abs(y - 0.5)  # ties: nearer the middle

        try:
            n = 20
            best, x, y = min((score(i / n, k / n), i / n, k / n)
                             for i in range(n + 1) for k in range(n + 1))
            step = 1.0 / n
            while step > 1e-4:
                moves = [(min(1.0, max(0.0, x + dx * step)), min(1.0, max(0.0, y + dy * step)))
                         for dx in (-1, 0, 1) for dy in (-1, 0, 1) if dx or dy]
                found = min((score(*p), *p) for p in moves)
                if found[0] < best:
                    best, x, y = found
                else:
                    step /= 2
        finally:
            for joint, target in want.items():
                servos[joint].target = target
        return (x, y) if best[0] <= math.radians(tolerance_deg) else None

    def apply_maps(self, inputs=None) -> None:
        """Re-evaluate the active maps that read ``inputs`` (default: all inputs)."""
        if type(inputs) is not tuple:  # (a stick event's: a tuple already)
            inputs = tuple(self.input_names() if inputs is None else inputs)
        key = (self.roles.binding, inputs)  # (a button or stick event: the same few names)
        compiled = self._input_maps.get(key)
        if compiled is None:
            compiled = self._input_maps[key] = self._compiled(set(inputs))
        values, table = self.inputs, self.owners.table
        for apply in compiled:  # (owners.take, called only when it has work)
            written = apply(values)
            if table and written:
                self.owners.take(written)

    def _activate(self, maps) -> None:
        """Maps that just became active (a mode or state entered) act at once with the
        inputs as they are; the maps that were active already leave their joints be. A
        sensor map takes its joints, and writes them at the next control step."""
        key = (id(maps), self.roles.binding)  # (each list of maps is the spec's, or
        cache = self.__dict__.get("_activations")  # _role_maps's: kept, so ids stay)
        if cache is None:
            cache = self._activations = {}
        got = cache.get(key)
        if got is None or got[0] is not maps:  # what each map does, worked out once
            got = cache[key] = (maps, [
                (self._applier(m), None) if not m.feedback else (None, self._map_joints(m))
                for m in maps if not m.feedback or getattr(m, "combine", "set") != "add"])
        inputs, take = self.inputs, self.owners.take
        for apply, joints in got[1]:
            if apply is not None:
                take(apply(inputs))
            else:
                self.feedback.claim(joints)

    def _role_maps(self) -> list:
        """The active device maps that drive a joint through a role (they act again
        when the roles re-bind), worked out once for each list of active maps."""
        active = self.active_maps
        cache = self.__dict__.get("_role_maps_of")
        if cache is None:
            cache = self._role_maps_of = {}
        got = cache.get(id(active))
        if got is None or got[0] is not active:
            got = cache[id(active)] = (active, [m for m in active if not m.feedback
                                                and self.roles.names_role(m)])
        return got[1]



def every_map(spec: InterfaceSpec):
    """Every map of an interface: the top level's, each mode's, each state's."""
    from puppet.data.interface_refs import all_maps

    return (m for _, m in all_maps(spec))
