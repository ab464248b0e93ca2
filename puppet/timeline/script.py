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
"""

from __future__ import annotations

from puppet.data.keys import key_problem, normalize_key
from puppet.data.ranges import Duration, Num, Time, WorldXY
from puppet.data.validate import Spec, validate
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


class ScriptEntry(Spec, kw_only=True):
    t: Time  # s of simulated time
    mouse: tuple[Num("mouse"), Num("mouse")] | None = None
    over: Duration = 0.0
    key: str | None = None
    hold: Duration = 0.0
    action: str | None = None
    drag: DragSpec | None = None
    push: PushSpec | None = None

    def __post_init__(self):
        given = [n for n in ("mouse", "key", "action", "drag", "push")
                 if getattr(self, n) is not None]
        if len(given) != 1:
            raise ValueError("each entry needs exactly one of mouse, key, action, drag, push; "
                             f"got {', '.join(given) or 'none'}")
        if self.action is not None and self.action not in SIM_ACTIONS:
            raise ValueError(f"unknown action '{self.action}'; a script can perform "
                             f"{', '.join(sorted(SIM_ACTIONS))} (window actions such as "
                             "pause or slowdown have no meaning in a headless run)")
        if self.key is not None and key_problem(self.key):
            raise ValueError(key_problem(self.key))
        if self.mouse is not None and not all(0.0 <= v <= 1.0 for v in self.mouse):
            raise ValueError(f"mouse position must be within [0, 1] x [0, 1], got "
                             f"{list(self.mouse)}")


class ScriptSpec(Spec, kw_only=True):
    description: str = ""
    interface: str | None = None
    scene: str | None = None
    seconds: Time | None = None  # default run length, s
    events: list[ScriptEntry]


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
        elif e.key is not None:
            chord = normalize_key(e.key)
            add(e.t, ev.key(chord, True))
            add(e.t + max(e.hold, dt), ev.key(chord, False))
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


def check_links(path, spec: ScriptSpec, links: list[str]) -> None:
    """DataError at the entry for a drag or push of a link the character played does
    not have (the script is valid on its own; a link is only known with a character)."""
    for i, e in enumerate(spec.events):
        for kind, what in (("drag", e.drag), ("push", e.push)):
            if what is not None and what.link not in links:
                from puppet.data.interface_refs import unknown

                raise load_file(path).error(("events", i, kind, "link"),
                                            unknown("link", what.link, links))
