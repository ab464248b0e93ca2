"""What the bench measures: every shipped character with the interfaces that drive it
(``Subject``), and the input a frame of play gets (``gesture``: a figure-of-eight mouse
path and key taps, as a player's would be)."""

from __future__ import annotations

import math
from pathlib import Path

from puppet.commands.bench.config import FRAME_HZ


def characters_and_interfaces() -> list[tuple[str, list[str]]]:
    """(character name, every valid interface that drives it, by file name)."""
    from puppet.data.catalog import find, folder
    from puppet.data.errors import DataError
    from puppet.data.interfaces import parse_interface
    from puppet.data.yamlfile import load_file

    users: dict[Path, list[str]] = {}
    for path in sorted(folder("interface").glob("*.yaml")):
        try:
            spec = parse_interface(load_file(path))
            char_path = find("character", spec.character).resolve()
        except DataError:
            continue  # an invalid interface is `puppet check`'s business, not ours
        users.setdefault(char_path, []).append(path.stem)
    return [(path.stem, users.get(path.resolve(), []))
            for path in sorted(folder("character").glob("*.yaml"))]


def gesture(frames: int, interface_spec) -> list[list[dict]]:
    """The input of each frame: a figure-of-eight mouse path, and key taps."""
    from puppet.data.keys import normalize_key
    from puppet.interface import events as ev

    # Keys that change the world itself (gravity, friction, random kicks, shoves, and the
    # app's checkpoint / restore / reset a layout may bind) are left out: the bare run
    # replays servo changes only, and those are not the control layer's cost (a
    # checkpoint's and a rewind's are measured on their own).
    keys = [normalize_key(k.key) for k in (interface_spec.keys if interface_spec else [])
            if k.gravity is None and k.friction is None and k.perturb is None
            and k.push is None and k.app is None]
    per_tap = max(1, round(0.5 * FRAME_HZ))
    out = []
    for f in range(frames):
        t = f / FRAME_HZ
        batch = [ev.mouse(0.5 + 0.35 * math.sin(2 * math.pi * 0.6 * t),
                          0.5 + 0.35 * math.sin(2 * math.pi * 1.2 * t))]
        if keys and f % per_tap == 0:
            tap = f // per_tap
            batch.append(ev.key(keys[(tap // 2) % len(keys)], tap % 2 == 0))
        out.append(batch)
    return out


class Subject:
    """One character with its interface (or a bare Simulation), ready to build runs."""

    def __init__(self, character: str, interface: str | None, scene: str | None = None):
        from puppet.data.catalog import find, load_character_named, load_scene_named, load_setup
        from puppet.physics.simulation import step_of

        self.character = character
        self.interface = interface
        if interface is not None:
            self.setup = load_setup(interface, scene)
            self.character_spec, self.scene_spec = self.setup.character, self.setup.scene
            self.scene = self.setup.scene_path.stem
            self.interface_spec = self.setup.interface
        else:
            self.setup = None
            self.character_spec, _ = load_character_named(character)
            try:
                find("scene", "flat")
                self.scene = "flat"
            except Exception:  # noqa: BLE001 - any shipped scene will do
                from puppet.data.catalog import list_kind
                self.scene = list_kind("scene")[0][0]
            self.scene_spec, _ = load_scene_named(self.scene)
            self.interface_spec = None
        self.dt = step_of(self.character_spec)  # the character's step, as a session's
        self.steps_per_frame = max(1, round(1.0 / (FRAME_HZ * self.dt)))

    def frames(self, seconds: float) -> int:
        return max(1, round(seconds * FRAME_HZ))

    def session(self, keyframes: bool = True):
        """A fresh Session (or, without an interface, a fresh Simulation)."""
        if self.setup is not None:
            from puppet.session import Session

            return Session(self.setup, self.dt, keyframes=keyframes)
        from puppet.physics.simulation import Simulation

        return Simulation(self.character_spec, self.scene_spec, self.dt)

    @staticmethod
    def sim_of(obj):
        return getattr(obj, "sim", obj)
