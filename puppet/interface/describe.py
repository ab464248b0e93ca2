"""Human-readable lines for what an interface binds: the HUD's and the key map's text."""

from __future__ import annotations

from puppet.data.actions import ActionSpec
from puppet.data.interfaces import InterfaceSpec
from puppet.interface.app_keys import APP_KEYS, normalize_key


def _fmt(v: float) -> str:
    return f"{v:+.0f}"


def map_line(m) -> tuple[str, str]:
    if getattr(m, "grid", None) is not None:
        rows, cols = len(m.grid), len(m.grid[0])
        extra = "".join(f" {a}-mirrored" for a in m.mirror)
        if m.joints:
            extra += " -> " + ", ".join(m.joints)
        return f"{m.x}, {m.y}", f"pose grid {rows}x{cols}{extra}"
    joints = ", ".join(m.gains()) if len(m.gains()) > 1 else next(iter(m.gains()))
    return m.input, f"{joints} {_fmt(m.to[0])}..{_fmt(m.to[1])} deg"


def action_text(k) -> str:
    """A short summary of what an action does (its description if it has one)."""
    if k.description:
        return k.description
    parts = []
    if k.pose:
        parts.append(f"pose {k.pose}")
    if k.sequence:
        parts.append(f"sequence {k.sequence}")
    parts += [f"{j}={_fmt(v)}" for j, v in k.set.items()]
    parts += [f"{j}{_fmt(v)}" for j, v in k.adjust.items()]
    if k.stiffness or k.damping:
        parts.append("gains" + (" while held" if k.while_held else ""))
    for name in ("mode", "goto", "app", "slowdown", "gravity", "friction", "perturb",
                 "release"):
        value = getattr(k, name)
        if value is not None:
            parts.append(f"{name} {value}")
    if k.reach is not None:
        parts.append(f"reach {k.reach.chain}")
    if k.grasp is not None:
        parts.append(f"grasp {k.grasp.chain}")
    return " ".join(parts)


def live_keys(spec: InterfaceSpec, state: str | None = None) -> list[ActionSpec]:
    """The key actions live in ``state`` (default: the start state): the state's own keys,
    then the top level's it does not rebind. The order ``InterfaceRuntime.binding``
    looks them up in, so the HUD and the key map show what a key would do."""
    keys = list(spec.keys)
    if not spec.states:
        return keys
    own = spec.states[state if state is not None else spec.start_state].keys
    bound = {normalize_key(k.key) for k in own}
    return list(own) + [k for k in keys if normalize_key(k.key) not in bound]


def interface_lines(spec: InterfaceSpec, state: str | None = None,
                    mode: str | None = None) -> list[tuple[str, str]]:
    """(input, what it does) for the interface's own controls (in a state and mode)."""
    lines: list[tuple[str, str]] = [map_line(m) for m in spec.maps]
    mode = mode if mode is not None else spec.start_mode
    if mode is not None:
        lines += [map_line(m) for m in spec.modes[mode]]
    if spec.states:
        state = state if state is not None else spec.start_state
        lines += [map_line(m) for m in spec.states[state].maps]
    for k in live_keys(spec, state):
        lines.append((k.key, action_text(k)))
    for g in spec.gestures:  # recorded mouse paths
        lines.append((g.key, g.description or f"gesture {g.duration:.1f} s"))
    return lines


def where_line(spec: InterfaceSpec, state: str | None, mode: str | None) -> str:
    """"state upright, mode walk": which bindings are live now ("" if neither exists)."""
    parts = []
    if spec.states:
        parts.append(f"state {state if state is not None else spec.start_state}")
    if spec.modes:
        parts.append(f"mode {mode if mode is not None else spec.start_mode}")
    return ", ".join(parts)


def app_lines(spec: InterfaceSpec) -> list[tuple[str, str]]:
    """(key, what it does) for the app's keys as this interface binds them."""
    table = spec.app_key_table()
    return [(table[action], text) for action, (_, text) in APP_KEYS.items()] + [
        ("ctrl+drag", "pull a body with a spring (the mouse maps and the camera wait)")]
