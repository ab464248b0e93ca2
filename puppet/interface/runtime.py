"""Run an interface file: input state in, PD targets and gains out.

The runtime is event driven: targets change only when an input changes, so between
events the physics steps at full speed with nothing to do in Python.
"""

from __future__ import annotations

import math

from puppet.data.interfaces import InterfaceSpec
from puppet.interface import maps
from puppet.interface.app_keys import normalize_key
from puppet.interface.events import Event
from puppet.physics.character import Character


class InterfaceRuntime:
    def __init__(self, spec: InterfaceSpec, character: Character):
        self.spec = spec
        self.character = character
        self.inputs: dict[str, float] = {}
        self.held: set[str] = set()
        self.bindings = {normalize_key(k.key): k for k in spec.keys}
        self.apply_gains()

    def apply_gains(self) -> None:
        """Interface gains override the character's defaults."""
        for name, servo in self.character.servos.items():
            k, d, t = servo.default_gains
            gain = self.spec.gains.get(name)
            if gain is not None:
                k = gain.stiffness if gain.stiffness is not None else k
                d = gain.damping if gain.damping is not None else d
                t = gain.max_torque if gain.max_torque is not None else t
            servo.stiffness, servo.damping, servo.max_torque = k, d, t

    def handles_key(self, chord: str) -> bool:
        return chord in self.bindings

    def on_event(self, event: Event) -> None:
        kind = event["type"]
        if kind == "mouse":
            self.inputs["mouse.x"] = event["x"]
            self.inputs["mouse.y"] = event["y"]
            self.apply_maps()
        elif kind == "key":
            chord = event["key"]
            if event["down"]:
                self.held.add(chord)
                binding = self.bindings.get(chord)
                if binding is not None:
                    self._key_action(binding)
            else:
                self.held.discard(chord)

    def apply_maps(self) -> None:
        servos = self.character.servos
        for m in self.spec.maps:
            value = self.inputs.get(m.input)
            if value is not None:
                servos[m.joint].target = maps.linear(m, value)

    def _key_action(self, binding) -> None:
        servos = self.character.servos
        for joint, deg in binding.set.items():
            servos[joint].target = math.radians(deg)
        for joint, deg in binding.adjust.items():
            servos[joint].target += math.radians(deg)

    def reset(self) -> None:
        """After the character is reset: start-pose targets, then the current inputs."""
        start = self.character.start_joint_angles()
        for name, servo in self.character.servos.items():
            servo.target = start.get(name, 0.0)
        self.apply_gains()
        self.apply_maps()

    # The runtime's own state rides along with physics snapshots.
    def get_state(self) -> dict:
        return {"inputs": dict(self.inputs), "held": sorted(self.held)}

    def set_state(self, state: dict) -> None:
        self.inputs = dict(state["inputs"])
        self.held = set(state["held"])
