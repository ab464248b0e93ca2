"""Interface files (``interfaces/*.yaml``): how input drives a character.

The vocabulary follows the paper's action semantics: continuous maps from devices
to joint targets, key actions that set or adjust targets, and rebindable app keys.
"""

from __future__ import annotations

from typing import Literal

from pydantic import Field, NonNegativeFloat, PositiveFloat, model_validator

from puppet.data.characters import CharacterSpec
from puppet.data.validate import Spec, validate
from puppet.data.yamlfile import Located, load_file
from puppet.interface.app_keys import APP_KEYS, normalize_key

CONTINUOUS_INPUTS = ("mouse.x", "mouse.y")


class GainSpec(Spec):
    stiffness: NonNegativeFloat | None = None
    damping: NonNegativeFloat | None = None
    max_torque: PositiveFloat | None = None


class LinearMapSpec(Spec):
    """target = to[0] + (input - from[0]) / (from[1] - from[0]) * (to[1] - to[0])."""

    input: str = Field(description="mouse.x (0 left .. 1 right) or mouse.y (0 bottom .. 1 top)")
    joint: str
    from_: tuple[float, float] = Field((0.0, 1.0), alias="from")
    to: tuple[float, float] = Field(description="joint target, degrees, at from[0] and from[1]")
    clamp: bool = True

    @model_validator(mode="after")
    def _check(self):
        if self.input not in CONTINUOUS_INPUTS:
            raise ValueError(f"unknown input '{self.input}'; expected one of: "
                             f"{', '.join(CONTINUOUS_INPUTS)}")
        if self.from_[0] == self.from_[1]:
            raise ValueError("'from' must be two different input values")
        return self


class KeyActionSpec(Spec):
    """What a key does: set targets absolutely and/or adjust them relatively (degrees)."""

    key: str
    set: dict[str, float] = Field(default_factory=dict)
    adjust: dict[str, float] = Field(default_factory=dict)
    description: str = ""


class InterfaceSpec(Spec):
    name: str
    description: str
    character: str
    scene: str = "flat"
    slowdown: float = Field(1.0, ge=1.0, le=100.0)
    app_keys: dict[str, str] = Field(default_factory=dict,
                                     description="rebind the app's keys: action -> key")
    gains: dict[str, GainSpec] = Field(default_factory=dict)
    maps: list[LinearMapSpec] = Field(default_factory=list)
    keys: list[KeyActionSpec] = Field(default_factory=list)

    def app_key_table(self) -> dict[str, str]:
        """App action -> key, after this interface's rebinding."""
        table = {action: key for action, (key, _) in APP_KEYS.items()}
        table.update({a: normalize_key(k) for a, k in self.app_keys.items()})
        return table


def _check_keys(spec: InterfaceSpec, located: Located) -> None:
    for action in spec.app_keys:
        if action not in APP_KEYS:
            raise located.error(("app_keys", action),
                                f"unknown app action '{action}'; expected one of: "
                                f"{', '.join(APP_KEYS)}", prefer_key=True)
    app_table = spec.app_key_table()
    by_key: dict[str, str] = {}
    for action, key in app_table.items():
        if key in by_key:
            raise located.error(("app_keys",), f"app actions '{by_key[key]}' and '{action}' "
                                               f"are both on key '{key}'")
        by_key[key] = f"app:{action}"
    for i, binding in enumerate(spec.keys):
        key = normalize_key(binding.key)
        if key in by_key:
            owner = by_key[key]
            if owner.startswith("app:"):
                action = owner[4:]
                raise located.error(("keys", i, "key"),
                                    f"key '{key}' is the app's '{action}' key; bind another key "
                                    f"or move the app's with app_keys: {{{action}: <key>}}")
            raise located.error(("keys", i, "key"), f"key '{key}' is bound twice "
                                                     f"(also keys[{owner}])")
        by_key[key] = str(i)


def check_against_character(spec: InterfaceSpec, character: CharacterSpec,
                            located: Located) -> None:
    """Joint names used by the interface must exist (and be actuated) in its character."""
    actuated = [j.name for j in character.actuated]

    def need(loc: tuple, name: str, prefer_key: bool = False) -> None:
        if name not in actuated:
            raise located.error(loc, f"unknown joint '{name}' for character "
                                     f"'{character.name}'; expected one of: "
                                     f"{', '.join(actuated)}", prefer_key=prefer_key)

    for name in spec.gains:
        need(("gains", name), name, True)
    for i, m in enumerate(spec.maps):
        need(("maps", i, "joint"), m.joint)
    for i, k in enumerate(spec.keys):
        for field in ("set", "adjust"):
            for name in getattr(k, field):
                need(("keys", i, field, name), name, True)


def parse_interface(located: Located) -> InterfaceSpec:
    spec = validate(located, InterfaceSpec)
    _check_keys(spec, located)
    return spec


def load_interface(path) -> tuple[InterfaceSpec, Located]:
    located = load_file(path)
    return parse_interface(located), located
