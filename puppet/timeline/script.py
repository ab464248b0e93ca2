"""Scripted performances: timed key presses and mouse paths written as YAML.

A script is how a performance is authored without hands: each entry acts at ``t``
seconds of simulated time. It compiles to ``(step, event)`` pairs, the same form a
recorded log replays from.

    events:
      - {t: 0.0, mouse: [0.5, 0.5]}              # jump the mouse there
      - {t: 1.0, mouse: [0.9, 0.1], over: 0.2}   # glide there from where it was, in 0.2 s
      - {t: 2.0, key: space}                     # press and release
      - {t: 2.5, key: a, hold: 0.4}              # hold for 0.4 s
      - {t: 3.0, action: reset}
      - {t: 4.0, drag: {link: base, point: [0, 0], to: [1.0, 0.5], over: 0.5}}
      - {t: 5.0, gamepad: {left_x: 0.8, left_y: -0.5}, over: 0.2}   # glide a stick
      - {t: 5.5, key: gamepad.a}                 # a pad button, pressed and released

It may also hold *rules*, for a performance played by watching rather than by the
clock: when a condition (in the interface language's sensor and state vocabulary)
becomes true, an action follows after a reaction delay of real time
(``puppet.timeline.reactive`` plays them):

    rules:
      - {when: {sensor: contact.swing_foot, is: true}, after: 0.25, key: space}
      - {when: {state: crouch}, after: 0.2, mouse: [0.6, 0.4], over: 0.15}
"""

from __future__ import annotations

from typing import Annotated

from puppet.data.actions import ConditionSpec
from puppet.data.keys import (
    GAMEPAD_BUTTONS,
    GAMEPAD_STICKS,
    GAMEPAD_TRIGGERS,
    key_problem,
    normalize_key,
)
from puppet.data.ranges import Duration, Num, Time, WorldXY
from puppet.data.validate import Meta, Spec, field, validate
from puppet.data.yamlfile import Located, load_file
from puppet.interface import events as ev
from puppet.interface.app_keys import SIM_ACTIONS
from puppet.interface.events import Event

Vec2 = WorldXY
GLIDE_RATE = 240.0  # Hz: how often a gliding mouse reports, like a gaming mouse
DEFAULT_SECONDS = 5.0  # a scripted run's length when neither the caller nor the script says


class DragSpec(Spec, kw_only=True):
    link: str
    point: tuple[Num("model_xy"), Num("model_xy")] = (0.0, 0.0)  # on the link, model frame, m
    to: Vec2  # world target, m
    start: Vec2 | None = None  # world target at start; default: 'to'
    over: Duration = 0.0
    hold: Duration = 0.0


class PushSpec(Spec, kw_only=True):
    """A shove: an impulse (N*s) at a point of a link (the character file's coordinates)."""

    link: str
    impulse: Vec2  # N*s, world x and y
    point: Vec2 | None = None  # model frame, m; default the link's centre of mass


def gamepad_problem(name: str, value: float) -> str | None:
    """Why a script's ``gamepad: {name: value}`` cannot be sent, or None: a stick reads
    -1..1, a trigger 0..1, a button 0 or 1 (raw ``axisN`` -1..1, ``buttonN`` 0 or 1)."""
    if name in GAMEPAD_STICKS or (name.startswith("axis") and name[4:].isdigit()):
        low, high = -1.0, 1.0
    elif name in GAMEPAD_TRIGGERS:
        low, high = 0.0, 1.0
    elif name in GAMEPAD_BUTTONS or (name.startswith("button") and name[6:].isdigit()):
        if value not in (0.0, 1.0):
            return f"gamepad button '{name}' is 0 (up) or 1 (pressed), got {value:g}"
        return None
    else:
        return (f"unknown gamepad input '{name}'; expected a stick ({', '.join(GAMEPAD_STICKS)}"
                f"), a trigger ({', '.join(GAMEPAD_TRIGGERS)}), a button ("
                f"{', '.join(GAMEPAD_BUTTONS)}), axisN or buttonN")
    if not low <= value <= high:
        return f"gamepad '{name}' reads {low:g}..{high:g}, got {value:g}"
    return None


def _analog(name: str) -> bool:
    return not (name in GAMEPAD_BUTTONS or name.startswith("button"))


class ScriptEntry(Spec, kw_only=True):
    t: Time  # s of simulated time
    mouse: tuple[Num("mouse"), Num("mouse")] | None = None
    over: Duration = 0.0
    key: str | None = None
    hold: Duration = 0.0
    action: str | None = None
    drag: DragSpec | None = None
    push: PushSpec | None = None
    # gamepad inputs by name (left_x: -1..1, right_trigger: 0..1, a: 0/1): sticks and
    # triggers glide there with 'over'; with 'hold', all go back to rest after it
    gamepad: dict[str, Num("input")] | None = None

    def __post_init__(self):
        given = [n for n in ("mouse", "key", "action", "drag", "push", "gamepad")
                 if getattr(self, n) is not None]
        if len(given) != 1:
            raise ValueError("each entry needs exactly one of mouse, key, action, drag, push, "
                             f"gamepad; got {', '.join(given) or 'none'}")
        for name, value in (self.gamepad or {}).items():
            problem = gamepad_problem(name, value)
            if problem:
                raise ValueError(problem)
        if self.gamepad is not None and not self.gamepad:
            raise ValueError("'gamepad' names no input; expected e.g. {left_x: 0.5}")
        if self.action is not None and self.action not in SIM_ACTIONS:
            raise ValueError(f"unknown action '{self.action}'; a script can perform "
                             f"{', '.join(sorted(SIM_ACTIONS))} (window actions such as "
                             "pause or slowdown have no meaning in a headless run)")
        if self.key is not None and key_problem(self.key):
            raise ValueError(key_problem(self.key))
        if self.mouse is not None and not all(0.0 <= v <= 1.0 for v in self.mouse):
            raise ValueError(f"mouse position must be within [0, 1] x [0, 1], got "
                             f"{list(self.mouse)}")


class WhenSpec(Spec, kw_only=True):
    """What a rule watches for: a sensor condition (as a state machine's transition
    writes it: ``sensor`` with ``above``/``below``, or ``is`` for a contact), the
    interface being in a state (``state``: NAME or MACHINE.NAME, or a list: any of
    them) or a mode (``mode``). A rule's ``when`` is one of these or a list of them
    (all must hold); the rule fires when it *becomes* true."""

    sensor: str | None = None
    above: Num("sensor") | None = None
    below: Num("sensor") | None = None
    is_: bool | None = field(name="is", default=None)
    state: str | list[str] | None = None
    mode: str | None = None

    def __post_init__(self):
        given = [n for n in ("sensor", "state", "mode") if getattr(self, n) is not None]
        if len(given) != 1:
            raise ValueError("'when' needs exactly one of sensor (with above / below / is), "
                             f"state or mode; got {', '.join(given) or 'none'}")
        if self.sensor is None and (self.above is not None or self.below is not None
                                    or self.is_ is not None):
            raise ValueError("above, below and is go with 'sensor'")
        if isinstance(self.state, list) and not self.state:
            raise ValueError("'state' needs at least one state name")
        if self.sensor is not None:
            self.condition()  # ConditionSpec's own checks (is for contacts...)

    @property
    def states(self) -> list[str]:
        return [] if self.state is None else [self.state] if isinstance(self.state, str) \
            else list(self.state)

    def condition(self) -> ConditionSpec:
        return ConditionSpec(sensor=self.sensor, above=self.above, below=self.below,
                             is_=self.is_)


class RuleSpec(Spec, kw_only=True):
    """When ``when`` becomes true (and has held for ``for`` s of real time: a foot
    settled, not a touch), ``after`` s of *real* time later (a person's reaction delay,
    which a playtest's noise varies), press ``key`` (for ``hold`` real s) or move the
    mouse to ``mouse`` (gliding ``over`` real s). ``from`` / ``until`` (simulated s)
    arm it for a window; ``times``: it fires at most so often."""

    when: WhenSpec | Annotated[list[WhenSpec], Meta(min_length=1, max_length=16)]
    for_: Duration = field(name="for", default=0.0)  # real s the condition must hold first
    after: Duration
    key: str | None = None
    hold: Duration = 0.0
    mouse: tuple[Num("mouse"), Num("mouse")] | None = None
    over: Duration = 0.0
    from_: Time = field(name="from", default=0.0)
    until: Time | None = None
    times: Annotated[int, Meta(ge=1, le=1000000)] | None = None

    def __post_init__(self):
        given = [n for n in ("key", "mouse") if getattr(self, n) is not None]
        if len(given) != 1:
            raise ValueError("each rule needs exactly one action, key or mouse; got "
                             f"{', '.join(given) or 'none'}")
        if self.key is not None and key_problem(self.key):
            raise ValueError(key_problem(self.key))
        if self.mouse is not None and not all(0.0 <= v <= 1.0 for v in self.mouse):
            raise ValueError(f"mouse position must be within [0, 1] x [0, 1], got "
                             f"{list(self.mouse)}")
        if isinstance(self.when, WhenSpec):
            self.when = [self.when]  # (one condition or several: all must hold)
        if self.until is not None and self.until < self.from_:
            raise ValueError(f"'until' ({self.until:g} s) is before 'from' ({self.from_:g} "
                             "s): the rule would never fire")


class ScriptSpec(Spec, kw_only=True):
    description: str = ""
    interface: str | None = None
    scene: str | None = None
    seconds: Time | None = None  # default run length, s
    events: list[ScriptEntry] | None = None  # required unless there are rules
    rules: list[RuleSpec] = field(default_factory=list)

    def __post_init__(self):
        if self.events is None:
            if not self.rules:
                raise ValueError("a script needs 'events' (timed input) and/or 'rules' "
                                 "(input that reacts to what happens)")
            self.events = []


def run_seconds(spec: ScriptSpec | None, seconds: float | None = None) -> float:
    """How long a scripted run lasts: ``seconds`` if given, else the script's, else
    DEFAULT_SECONDS. One rule for ``puppet play --headless`` and ``record_script``."""
    if seconds is None and spec is not None:
        seconds = spec.seconds
    return DEFAULT_SECONDS if seconds is None else seconds


def entry_end(e: ScriptEntry) -> float:
    """When an entry has done all it does, s: a glide's or drag's end, a key's release."""
    if e.mouse is not None:
        return e.t + e.over
    if e.key is not None:
        return e.t + e.hold
    if e.gamepad is not None:
        return e.t + e.over + e.hold
    if e.drag is not None:
        return e.t + e.drag.over + e.drag.hold
    return e.t


def late_note(spec: ScriptSpec, seconds: float, dt: float, given: bool = False,
              clip: bool = False) -> str | None:
    """What to say when some of a script's entries come after the run's end (they never
    act) or run past it (a glide or hold cut short), counted as the user wrote them
    (entries, not the mouse samples of a glide or a key's press and release), with how
    long the script runs, so that ``--seconds`` or ``seconds:`` can be chosen; None
    when every entry is done by the end. ``given``: ``seconds`` came from --seconds;
    ``clip``: else a mocap clip's length sets it, unless the script says.
    An entry at the end's own step still acts (``play``)."""
    end = round(seconds / dt)
    late = [e for e in spec.events if round(e.t / dt) > end]
    cut = [e for e in spec.events if round(e.t / dt) <= end < round(entry_end(e) / dt)]
    if not late and not cut:
        return None
    n = len(spec.events)
    one = len(late) == 1
    told = [f"{len(late)} of the script's {n} entries start{'s' if one else ''} after the run "
            f"ends and never act{'s' if one else ''}" if late else "",
            f"{len(cut)} {'is' if len(cut) == 1 else 'are'} cut short by the end (a glide or "
            "hold that goes on past it)" if cut else ""]
    last = max(spec.events, key=lambda e: e.t)
    done = max(entry_end(e) for e in spec.events)
    source = ("--seconds" if given else "the script's 'seconds:'" if spec.seconds is not None
              else "the --mocap clip's length" if clip
              else "the default: neither --seconds nor 'seconds:' in the script says")
    return (f"{', '.join(t for t in told if t)}: the run ends at {seconds:g} s ({source}); "
            f"the script's last entry is at t = {last.t:g} s"
            + (f" and it is done at {done:g} s" if done > last.t else ""))


def compile_script(spec: ScriptSpec, dt: float) -> list[tuple[int, Event]]:
    """(step, event) pairs in the order they act."""
    out: list[tuple[int, int, Event]] = []  # (step, entry order, event)
    mouse = (0.5, 0.5)
    pad: dict[str, float] = {}  # each gamepad input's last value (at rest: 0)
    order = 0

    def add(t: float, event: Event) -> None:
        nonlocal order
        out.append((round(t / dt), order, event))
        order += 1

    for e in sorted(spec.events, key=lambda e: e.t):
        if e.mouse is not None:
            if e.over > 0:
                n = max(1, round(e.over * GLIDE_RATE))
                for i in range(1, n + 1):
                    u = i / n
                    add(e.t + u * e.over, ev.mouse(mouse[0] + u * (e.mouse[0] - mouse[0]),
                                                   mouse[1] + u * (e.mouse[1] - mouse[1])))
            else:
                add(e.t, ev.mouse(*e.mouse))
            mouse = e.mouse
        elif e.key is not None and normalize_key(e.key).startswith("gamepad."):
            button = normalize_key(e.key)[len("gamepad."):]  # as a pad sends it: an input
            add(e.t, ev.gamepad(button, 1.0))  # that also acts as a key
            add(e.t + max(e.hold, dt), ev.gamepad(button, 0.0))
            pad[button] = 0.0
        elif e.key is not None:
            chord = normalize_key(e.key)
            add(e.t, ev.key(chord, True))
            add(e.t + max(e.hold, dt), ev.key(chord, False))
        elif e.gamepad is not None:
            glide = [n for n in e.gamepad if _analog(n)] if e.over > 0 else []
            for name, value in e.gamepad.items():
                if name not in glide:
                    add(e.t, ev.gamepad(name, value))
            n = max(1, round(e.over * GLIDE_RATE))
            for i in range(1, n + 1) if glide else ():
                u = i / n
                for name in glide:
                    start = pad.get(name, 0.0)
                    add(e.t + u * e.over, ev.gamepad(name, start + u * (e.gamepad[name] - start)))
            pad.update(e.gamepad)
            if e.hold > 0:  # then every input it named back at rest
                for name in e.gamepad:
                    add(e.t + e.over + e.hold, ev.gamepad(name, 0.0))
                    pad[name] = 0.0
        elif e.action is not None:
            add(e.t, ev.action(e.action))
        elif e.push is not None:
            add(e.t, ev.push(e.push.link, e.push.impulse, e.push.point))
        else:
            d = e.drag
            start = d.start if d.start is not None else None
            add(e.t, ev.drag_start(d.link, d.point, start if start is not None else d.to))
            if d.over > 0:
                s0 = start if start is not None else d.to
                n = max(1, round(d.over * GLIDE_RATE))
                for i in range(1, n + 1):
                    u = i / n
                    add(e.t + u * d.over, ev.drag_move((s0[0] + u * (d.to[0] - s0[0]),
                                                        s0[1] + u * (d.to[1] - s0[1]))))
            add(e.t + d.over + max(d.hold, dt), ev.drag_end())
    out.sort(key=lambda item: (item[0], item[1]))
    return [(step, event) for step, _, event in out]


def parse_script(located: Located) -> ScriptSpec:
    return validate(located, ScriptSpec)


def load_script(path) -> ScriptSpec:
    return parse_script(load_file(path))


def _when_problem(w: WhenSpec, interface, character) -> tuple[str | None, tuple]:
    """What is wrong with a condition's names for this interface and character, and
    where (the field's path under the condition)."""
    from puppet.data.interface_refs import sensor_problem

    if w.sensor is not None and w.sensor.startswith("held."):  # held.CHAIN: a chain's grasp
        chain = w.sensor[len("held."):]
        return (None if chain in interface.chains else
                f"'{w.sensor}': the interface '{interface.name}' has no chain '{chain}'; its "
                f"chains: {', '.join(interface.chains) or 'none'}"), ("sensor",)
    if w.sensor is not None:
        return sensor_problem(w.sensor, character, interface.roles), ("sensor",)
    if w.mode is not None and w.mode not in interface.modes:
        return (f"the interface '{interface.name}' has no mode '{w.mode}'; its modes: "
                f"{', '.join(interface.modes) or 'none'}"), ("mode",)
    for j, name in enumerate(w.states):
        if interface.resolve_goto(name) is None:
            states = sorted({n for m in interface.state_machines().values() for n in m.states})
            return (f"the interface '{interface.name}' has no state '{name}' (or it is in "
                    f"two machines: write MACHINE.STATE); its states: "
                    f"{', '.join(states) or 'none'}"), \
                ("state",) + ((j,) if isinstance(w.state, list) else ())
    return None, ()


def _listed(located, path, rule: int) -> bool:
    """Whether the rule's ``when`` was written as a list (its errors then name the item)."""
    data = (located or load_file(path)).data
    try:
        return isinstance(data["rules"][rule]["when"], list)
    except (KeyError, IndexError, TypeError):
        return False


def check_links(path, spec: ScriptSpec, links: list[str], interface=None,
                character=None, located: Located | None = None) -> None:
    """DataError at the entry for a drag or push of a link the character played does
    not have (the script is valid on its own; a link is only known with a character);
    with the ``interface`` and ``character`` (specs) played, also at a rule whose
    sensor, state or mode they do not have. ``located``: the script's text as read
    (default: ``path`` read again for the error's line)."""
    if interface is not None and character is not None:
        for i, r in enumerate(spec.rules):
            for k, w in enumerate(r.when):
                problem, what = _when_problem(w, interface, character)
                if problem:
                    loc = ("rules", i, "when") + ((k,) if _listed(located, path, i) else ())
                    raise (located or load_file(path)).error(loc + what, problem)
    for i, e in enumerate(spec.events):
        for kind, what in (("drag", e.drag), ("push", e.push)):
            if what is not None and what.link not in links:
                from puppet.data.interface_refs import unknown

                raise (located or load_file(path)).error(("events", i, kind, "link"),
                                            unknown("link", what.link, links))
