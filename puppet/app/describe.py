"""Human-readable lines for what an interface binds: the HUD's and the key map's text."""

from __future__ import annotations

from puppet.data.actions import ActionSpec
from puppet.data.interfaces import MAIN_MACHINE, InterfaceSpec
from puppet.data.keys import APP_KEYS, normalize_key


def _fmt(v: float) -> str:
    return f"{v:+.0f}"


# What an input is, to a player: its name on the HUD and the words for its two ends.
_AXES = {"x": ("left-right", "left", "right"), "y": ("up-down", "bottom", "top")}
_STICKS = {"left_x": ("left stick left-right", "left", "right"),
           "left_y": ("left stick up-down", "bottom", "top"),
           "right_x": ("right stick left-right", "left", "right"),
           "right_y": ("right stick up-down", "bottom", "top"),
           "left_trigger": ("left trigger", "released", "pulled"),
           "right_trigger": ("right trigger", "released", "pulled")}


def input_words(name: str) -> tuple[str, str, str]:
    """(what the input is, its low end, its high end) in a player's words:
    mouse.x -> ("mouse left-right", "left", "right")."""
    device, _, part = name.partition(".")
    if device == "pointer" and part in _AXES:
        what, lo, hi = _AXES[part]
        return f"mouse or stick {what}", lo, hi
    if device == "mouse" and part in _AXES:
        what, lo, hi = _AXES[part]
        return f"mouse {what}", lo, hi
    if device == "mouse":
        return f"{part} mouse button", "up", "pressed"
    if device == "gamepad" and part in _STICKS:
        return _STICKS[part]
    if device == "gamepad" and part.startswith("axis"):
        return f"gamepad axis {part[4:]}", "low", "high"
    if device == "gamepad":
        return f"gamepad {part.removeprefix('button')} button", "up", "pressed"
    if device == "sensor":
        return f"(balance) {_sensor_words(part)}", "low", "high"
    return name, "low", "high"


def _sensor_words(sensor: str) -> str:
    """A sensor in a player's words: com.vx -> "body's speed forward"."""
    fixed = {"com.vx": "body's speed forward", "com.vy": "body's speed up",
             "com.x": "body's position", "com.y": "body's height", "lean": "body's lean",
             "root.angle": "tilt", "com.dx.support": "body ahead of the feet",
             "com.fall_time": "time left in the air", "com.spin": "body's spin"}
    if sensor in fixed:
        return fixed[sensor]
    kind, _, what = sensor.partition(".")
    if sensor.startswith("com.dx."):
        return f"body ahead of the {sensor[7:].replace('_', ' ')}"
    if sensor.startswith("lead."):
        link, _, other = sensor[5:].partition(".")
        return f"{link.replace('_', ' ')} ahead of the {other.replace('_', ' ')}"
    words = {"angle": "tilt of the", "spin": "spin of the", "height": "height of the",
             "joint": "angle of the", "contact": "touch of the"}
    return f"{words.get(kind, kind)} {what.replace('_', ' ')}"


def input_label(names) -> str:
    """The HUD's name for a map's inputs: "mouse" for mouse x and y together."""
    names = list(names)
    devices = {n.partition(".")[0] for n in names}
    if len(names) > 1 and devices == {"mouse"}:
        return "mouse"
    if len(names) > 1 and devices == {"gamepad"} and all("_" in n for n in names):
        sticks = {n.partition(".")[2].rsplit("_", 1)[0] for n in names}
        if len(sticks) == 1:
            return f"{sticks.pop()} stick"
    return ", ".join(input_words(n)[0] for n in names)


def joint_words(joints) -> str:
    """hip_near, knee_near -> "near hip and knee"; ankle -> "ankle"."""
    joints = list(joints)
    stems = {j.rpartition("_")[0] for j in joints}
    if len(joints) > 1 and len(stems) == 1 and "" not in stems:  # hip_near, hip_far
        return f"{stems.pop().replace('_', ' ')}s (both sides)"
    sides = {j.rpartition("_")[2] for j in joints if "_" in j}
    if len(sides) == 1 and all("_" in j for j in joints):
        side = sides.pop()
        names = [j.rpartition("_")[0].replace("_", " ") for j in joints]
        return f"{side} " + _and(names)
    return _and([j.replace("_", " ") for j in joints])


def _and(words: list[str]) -> str:
    return words[0] if len(words) == 1 else ", ".join(words[:-1]) + " and " + words[-1]


def map_line(m) -> tuple[str, str]:
    """(input, what it does) in plain words, e.g. ("mouse", "near hip and knee: blends 6
    poses") or ("mouse left-right", "ankle +80 deg at the left .. -80 at the right").
    A map's own ``description`` is what it does, when the file gives one."""
    if getattr(m, "add", None) is not None:  # a constant offset while it is active
        gains = m.gains()
        who = joint_words(gains) if len(gains) > 1 else next(iter(gains)).replace("_", " ")
        return "(balance) offset", m.description or f"{who} {m.add:+g} deg while active"
    if getattr(m, "description", ""):
        names = (m.x, m.y) if getattr(m, "grid", None) is not None else (m.input,)
        return input_label(names), _unprefixed(m.description, names)
    if getattr(m, "grid", None) is not None:
        rows, cols = len(m.grid), len(m.grid[0])
        who = joint_words(m.joints) if m.joints else "the poses' joints"
        text = f"{who}: blends {rows * cols} poses"
        if set(m.mirror) == {"x", "y"}:
            text += ", half a cycle apart"
        elif m.mirror:
            flipped = input_words(m.x if m.mirror == ["x"] else m.y)[0]
            text += f", {flipped} reversed"
        return input_label((m.x, m.y)), text
    what, lo, hi = input_words(m.input)
    gains = m.gains()
    who = joint_words(gains) if len(gains) > 1 else next(iter(gains)).replace("_", " ")
    if m.frame != "joint":
        link = "in the world" if m.frame == "world" else f"from the {m.frame.replace('_', ' ')}"
        who = f"{who} (its {'upper' if m.hold == 'parent' else 'lower'} link, {link})"
    if m.combine == "add":
        who = f"adds to {who}"
    a, b = m.to
    if tuple(m.from_) not in ((0.0, 1.0), (-1.0, 1.0)):
        return what, f"{who} {_fmt(a)} deg at {m.from_[0]:g} .. {_fmt(b)} at {m.from_[1]:g}"
    return what, f"{who} {_fmt(a)} deg at the {lo} .. {_fmt(b)} at the {hi}"


def _unprefixed(text: str, names) -> str:
    """A description without the input it opens with, which the HUD's key column shows
    already: "mouse x: the swing thigh ..." -> "the swing thigh ...", "mouse x (run):
    the thigh ..." -> "run: the thigh ..."."""
    if len(names) != 1 or "." not in names[0]:
        return text
    device, _, part = names[0].partition(".")
    head = f"{device} {part}"
    if text.startswith(head + ": "):
        return text[len(head) + 2:]
    if text.startswith(head + " (") and "): " in text:
        inner, _, rest = text[len(head) + 2:].partition("): ")
        return f"{inner}: {rest}"
    return text


def compact_lines(lines: list[tuple[str, str]], more: str,
                  limit: int = 6) -> list[tuple[str, str]]:
    """The HUD's short list: the maps on one input merged into one row ("4 maps"), at
    most ``limit`` rows; ``more`` says where the full list is (e.g. "f1: all")."""
    count: dict[str, int] = {}
    for key, _ in lines:
        count[key] = count.get(key, 0) + 1
    out: list[tuple[str, str]] = []
    for key, text in lines:
        if count[key] > 1:
            if all(k != key for k, _ in out):
                out.append((key, f"{count[key]} maps ({more})"))
            continue
        out.append((key, text))
    if len(out) > limit:
        out = out[:limit - 1] + [("...", f"{len(out) - limit + 1} more ({more})")]
    return out


def action_text(k) -> str:
    """A short summary of what an action does (its description if it has one)."""
    if k.description:
        return k.description
    parts = []
    if k.pose:
        parts.append(f"pose: {k.pose.replace('_', ' ')}")
    if k.sequence:
        parts.append(f"moves: {k.sequence.replace('_', ' ')}")
    parts += [f"{j.replace('_', ' ')} to {v:.0f} deg" for j, v in k.set.items()]
    parts += [f"{j.replace('_', ' ')} {_fmt(v)} deg" for j, v in k.adjust.items()]
    if k.stiffness or k.damping:
        parts.append("stiffer" + (" while held" if k.while_held else ""))
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


def live_keys(spec: InterfaceSpec, state: str | None = None,
              scene: str | None = None) -> list[ActionSpec]:
    """The key actions live in ``state`` (default: the start state): the state's own keys,
    then the top level's it does not rebind. The order ``InterfaceRuntime.binding``
    looks them up in, so the HUD and the key map show what a key would do. ``scene``
    (a scene's name): a key meant for other scenes (``scenes:``) is left out."""
    keys = [k for k in spec.keys if k.plays_on(scene)]
    if not spec.states:
        return keys
    own = [k for k in spec.states[state if state is not None else spec.start_state].keys
           if k.plays_on(scene)]
    bound = {normalize_key(k.key) for k in own}
    return list(own) + [k for k in keys if normalize_key(k.key) not in bound]


def where_line(spec: InterfaceSpec, state: str | None, mode: str | None,
               states: dict[str, str] | None = None) -> str:
    """"state upright, mode walk": which bindings are live now ("" if neither exists);
    with several state machines (``states``: machine -> state), each one's state."""
    parts = []
    if states and len(states) > 1:
        parts += [f"{m} {st}" if m != MAIN_MACHINE else f"state {st}" for m, st in states.items()]
    elif spec.states:
        parts.append(f"state {state if state is not None else spec.start_state}")
    if spec.modes:
        parts.append(f"mode {mode if mode is not None else spec.start_mode}")
    return ", ".join(parts)


def app_lines(spec: InterfaceSpec) -> list[tuple[str, str]]:
    """(key, what it does) for the app's keys as this interface binds them."""
    table = spec.app_key_table()
    return [(table[action], text) for action, (_, text) in APP_KEYS.items()] + [
        ("ctrl+drag", "pull a body with a spring (the mouse maps and the camera wait)")]


def reads_sensors(m) -> bool:
    """A map driven by the body's own sensors (balance feedback), or a constant offset,
    not by the player: it acts by itself."""
    return any(n.startswith("sensor.") for n in m.inputs) or getattr(m, "add", None) is not None


def _live_maps(spec: InterfaceSpec, state: str | None, mode: str | None) -> list:
    maps = list(spec.maps)
    mode = mode if mode is not None else spec.start_mode
    if mode is not None:
        maps += spec.modes[mode]
    if spec.states:
        maps += spec.states[state if state is not None else spec.start_state].maps
    return maps


def _goto_state(spec: InterfaceSpec, k) -> str | None:
    """The main machine's state a key's ``goto`` leads to (None: none, or another machine's)."""
    if k.goto is None or not spec.states:
        return None
    to = spec.resolve_goto(k.goto, MAIN_MACHINE)
    return to[1] if to is not None and to[0] == MAIN_MACHINE else None


def _state_mode(spec: InterfaceSpec, name: str) -> str | None:
    enter = spec.states[name].enter
    return enter.mode if enter is not None else None


def _where_else(spec: InterfaceSpec, state: str | None, mode_name: str | None,
                state_name: str | None) -> str:
    """Where maps that are not live now apply, in a player's words: "for 0.3 s after
    space" when a key live now leads to the state that has them (or enters their
    mode) and a timed transition leaves it, "after space", else "in mode stepping"."""
    keys, timed = [], []
    for k in live_keys(spec, state):
        to = _goto_state(spec, k)
        if state_name is not None:
            here = to == state_name
        else:
            here = k.mode == mode_name or to is not None and _state_mode(spec, to) == mode_name
        if not here or k.key in keys:
            continue
        keys.append(k.key)
        if to is not None:  # left again by time, for a state without these maps
            left = [t.after for t in spec.states[to].transitions
                    if t.after is not None and t.when is None and t.to in spec.states
                    and (state_name is not None or _state_mode(spec, t.to) != mode_name)]
            if left:
                timed.append(min(left))
    if keys:
        after = "after " + " or ".join(keys)
        return f"for {max(timed):g} s {after}" if len(timed) == len(keys) else after
    return f"in mode {mode_name}" if mode_name is not None else f"in state {state_name}"


def _elsewhere(spec: InterfaceSpec, state: str | None,
               mode: str | None) -> list[tuple[str, str, str]]:
    """(input, where, what it does) for the maps on the player's own inputs that are
    not live in ``state`` and ``mode`` but are in another mode or state."""
    live = {map_line(m) for m in _live_maps(spec, state, mode)}
    mode = mode if mode is not None else spec.start_mode
    state = state if state is not None else (spec.start_state if spec.states else None)
    places = [(m, None) for m in spec.modes if m != mode]
    places += [(None, s) for s in spec.states if s != state]
    out: list[tuple[str, str, str]] = []
    seen = set(live)
    for mode_name, state_name in places:
        maps = spec.modes[mode_name] if mode_name is not None else spec.states[state_name].maps
        mine = [m for m in maps if not reads_sensors(m) and map_line(m) not in seen]
        if not mine:
            continue
        where = _where_else(spec, state, mode_name, state_name)
        for m in mine:
            key, text = map_line(m)
            seen.add((key, text))
            out.append((key, where, text))
    return out


def _compact_elsewhere(spec: InterfaceSpec, state: str | None, mode: str | None,
                       live_inputs: set[str], more: str) -> list[tuple[str, str]]:
    """The compact list's rows for inputs that do nothing now but will: one row per
    input, what its one map does, or how many maps it drives and from when."""
    rows: dict[str, list[tuple[str, str]]] = {}
    for key, where, text in _elsewhere(spec, state, mode):
        if key not in live_inputs:
            rows.setdefault(key, []).append((where, text))
    out = []
    for key, found in rows.items():
        if len(found) == 1:
            out.append((key, f"{found[0][0]}: {found[0][1]}"))
            continue
        wheres = list(dict.fromkeys(w for w, _ in found))
        where = wheres[0] if len(wheres) == 1 else wheres[0].split(" s ", 1)[-1] \
            if wheres[0].startswith("for ") else wheres[0]
        out.append((key, f"{where}: {len(found)} maps ({more})"))
    return out


SENSORS = "sensors"  # the key column of the sensor maps' folded row


def control_rows(spec: InterfaceSpec, state: str | None = None, mode: str | None = None,
                 more: str | None = None, scene: str | None = None) -> list[tuple[str, str]]:
    """The HUD's controls: the player's maps live now, then the player's maps of the
    other modes and states (with when they apply), the keys and gestures, and last the
    maps on the body's own sensors. ``more`` (e.g. "f1: all"): the compact list (maps
    on one input in one row, the sensor maps in one row); None: all of them, the sensor
    maps under a heading of their own. ``scene``: the scene's name (its keys only)."""
    maps = _live_maps(spec, state, mode)
    user = [map_line(m) for m in maps if not reads_sensors(m)]
    sensed = [map_line(m) for m in maps if reads_sensors(m)]
    keys = [(k.key, action_text(k)) for k in live_keys(spec, state, scene)]
    keys += [(g.key, g.description or f"gesture {g.duration:.1f} s") for g in spec.gestures]
    if more is not None:
        later = _compact_elsewhere(spec, state, mode, {k for k, _ in user}, more)
        rows = compact_lines(user, more) + later
        rows = compact_lines(rows + keys, more, limit=8)
        if sensed:
            rows.append((SENSORS, f"{len(sensed)} map{'s' if len(sensed) > 1 else ''} "
                                  f"acting by themselves ({more})"))
        return rows
    groups: dict[tuple[str, str], list[str]] = {}  # (input, where) -> what each map does
    for key, where, text in _elsewhere(spec, state, mode):
        groups.setdefault((key, where), []).append(text)
    later = []
    for (key, where), texts in groups.items():  # a whole other mode's maps: counted
        later += [(key, f"{where}: {text}") for text in texts] if len(texts) <= 2 else \
            [(key, f"{where}: {len(texts)} maps")]
    rows = user + later + keys
    if sensed:
        rows += [("by themselves, from the body's sensors", "")]
        rows += [("", f"{k.removeprefix('(balance) ')}: {t}") for k, t in sensed]
    return rows
