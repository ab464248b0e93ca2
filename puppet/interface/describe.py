"""Human-readable lines for what an interface binds: the HUD's and the key map's text."""

from __future__ import annotations

from puppet.data.interfaces import InterfaceSpec
from puppet.interface.app_keys import APP_KEYS


def _fmt(v: float) -> str:
    return f"{v:+.0f}"


def interface_lines(spec: InterfaceSpec) -> list[tuple[str, str]]:
    """(input, what it does) for the interface's own controls."""
    lines: list[tuple[str, str]] = []
    for m in spec.maps:
        lines.append((m.input, f"{m.joint} {_fmt(m.to[0])}..{_fmt(m.to[1])} deg"))
    for k in spec.keys:
        parts = [f"{j}={_fmt(v)}" for j, v in k.set.items()]
        parts += [f"{j}{_fmt(v)}" for j, v in k.adjust.items()]
        lines.append((k.key, k.description or " ".join(parts)))
    return lines


def app_lines(spec: InterfaceSpec) -> list[tuple[str, str]]:
    """(key, what it does) for the app's keys as this interface binds them."""
    table = spec.app_key_table()
    return [(table[action], text) for action, (_, text) in APP_KEYS.items()]
