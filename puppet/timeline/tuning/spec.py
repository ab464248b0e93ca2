"""A tuning spec (``assets/tune/NAME.yaml``): what ``puppet tune`` searches, as data.

Read like every data file: YAML through ``puppet.data.yamlfile`` (file:line:col for
each value), checked by msgspec structs, and then by what only the whole spec can say
(an expression naming an unknown parameter, a ``$key`` that is no choice, an interface
number that is not in the file): one line, ``file:line:col: what, what was expected``.
docs/tuning.md describes every field with an example.
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Literal

from puppet.data.playtest_bar import LevelName
from puppet.data.ranges import Seed
from puppet.data.validate import Meta, Spec, field, validate
from puppet.data.yamlfile import Located, load_file
from puppet.timeline.expectations import Expectation, ExpectFile
from puppet.timeline.script import ScriptEntry
from puppet.timeline.tuning.expr import Expr, ExprError

Number = float | str  # a number, or arithmetic on the stage's names (``expr.Expr``)
Whole = Annotated[int, Meta(ge=0, le=100000)]
Share = Annotated[float, Meta(ge=0.0, le=1.0)]
Positive = Annotated[float, Meta(gt=0.0, le=1e6)]
MAX_CYCLES = 10000  # a repeat's cycles, at most (a runaway 'every' near 0)


class ParamSpec(Spec, kw_only=True):
    """One number (or choice) to vary: ``range`` (uniform in it; with ``step`` on its
    grid) or ``choose`` (one of a list); ``interface``: the places in the interface
    file it is written (dotted paths, list items by index), for a number of the
    interface rather than of the performance."""

    range: tuple[float, float] | None = None
    step: Positive | None = None
    choose: Annotated[list[float | str], Meta(min_length=1, max_length=100)] | None = None
    interface: list[str] = field(default_factory=list)

    def __post_init__(self):
        if (self.range is None) == (self.choose is None):
            raise ValueError("a parameter has a 'range: [low, high]' or a 'choose: [...]' "
                             "list, not both")
        if self.range is not None and self.range[1] < self.range[0]:
            raise ValueError(f"range [{self.range[0]:g}, {self.range[1]:g}]: the high end "
                             "is under the low one; expected [low, high]")
        if self.step is not None and self.range is None:
            raise ValueError("'step' goes with 'range'")
        if self.interface and self.range is None:
            raise ValueError("an interface number has a 'range'")


class DragTemplate(Spec, kw_only=True):
    link: str
    point: tuple[Number, Number] = (0.0, 0.0)
    to: tuple[Number, Number]
    start: tuple[Number, Number] | None = None
    over: Number = 0.0
    hold: Number = 0.0


class PushTemplate(Spec, kw_only=True):
    link: str
    impulse: tuple[Number, Number]
    point: tuple[Number, Number] | None = None


class EntryTemplate(Spec, kw_only=True):
    """A script entry (``puppet.timeline.script``) whose numbers may be arithmetic on
    the stage's names and whose key may be ``$NAME``, a ``choose`` parameter. ``t`` is
    seconds from the stage's start."""

    t: Number
    mouse: tuple[Number, Number] | None = None
    over: Number = 0.0
    key: str | None = None
    hold: Number = 0.0
    action: str | None = None
    drag: DragTemplate | None = None
    push: PushTemplate | None = None

    def __post_init__(self):
        given = [n for n in ("mouse", "key", "action", "drag", "push")
                 if getattr(self, n) is not None]
        if len(given) != 1:
            raise ValueError("each entry needs exactly one of mouse, key, action, drag, push; "
                             f"got {', '.join(given) or 'none'}")


class RepeatSpec(Spec, kw_only=True):
    """The stage's rhythm: ``events`` once per cycle, cycle k at ``start + k * every``
    (``cycle`` is k in them), ``times`` cycles or as many as begin before ``for`` s."""

    every: Number
    times: Number | None = None
    for_: Number | None = field(name="for", default=None)
    start: Number = 0.0
    events: Annotated[list[EntryTemplate], Meta(min_length=1)]

    def __post_init__(self):
        if (self.times is None) == (self.for_ is None):
            raise ValueError("a repeat has 'times: N' or 'for: SECONDS', one of them")


class TermSpec(Spec, kw_only=True):
    """One graded expectation: ``points`` if it holds, plus ``weight`` per unit of its
    margin, the margin counted between ``floor`` and ``cap`` (-inf, nothing measured,
    counts as ``floor``). ``over``: the stage's stretch (its times from the stage's
    start) or the whole run so far. ``required``: a try that misses it is not kept;
    ``margin``: with ``required``, the margin it must reach (more than just holding:
    ``never_fell`` with margin 30 is never more than 60 deg from upright on the ground)."""

    expect: Expectation
    over: Literal["stage", "run"] = "stage"
    points: float = 10.0
    weight: float = 1.0
    cap: float = 0.0
    floor: float = -100.0
    required: bool = False
    margin: float = 0.0

    def __post_init__(self):
        if self.margin and not self.required:
            raise ValueError("'margin' is what a required term must reach: it goes with "
                             "'required: true'")
        if self.cap < self.floor:
            raise ValueError(f"'cap' ({self.cap:g}) is under 'floor' ({self.floor:g})")


class PhysicsVariant(Spec, kw_only=True):
    """Other physics settings a playtest term also plays its tries on: ``solver_passes``
    (constraint-solver iterations a step) and/or ``step`` (s, or "1/240")."""

    solver_passes: Annotated[int, Meta(ge=1, le=200)] | None = None
    step: float | str | None = None

    def __post_init__(self):
        if self.solver_passes is None and self.step is None:
            raise ValueError("a physics entry changes 'solver_passes', 'step' or both")
        if self.step is not None:
            from puppet.timeline.other_physics import parse_step

            parse_step(self.step)  # ValueError: said at the entry's line

    def other(self):
        """The ``OtherPhysics`` it names."""
        from puppet.timeline.other_physics import OtherPhysics, parse_step

        return OtherPhysics(iterations=self.solver_passes,
                            dt=None if self.step is None else parse_step(self.step))


class PlaytestTerm(Spec, kw_only=True):
    """A try that is kept is also played ``tries`` times by the simulated player at
    ``noise`` (from the stage's checkpoint), and as many again on each of ``physics``
    (cheaper settings the feat must survive); ``weight`` points for a pass rate of 1
    over them all."""

    noise: LevelName = "human"
    tries: Annotated[int, Meta(ge=1, le=200)] = 8
    weight: float = 20.0
    physics: Annotated[list[PhysicsVariant], Meta(max_length=8)] = field(default_factory=list)


class SearchSpec(Spec, kw_only=True):
    """How a stage's tries are drawn: ``tries`` in ``rounds`` (the first try is the
    stage's ``first``; a share ``around`` of the others near the best so far - Gaussian
    steps of ``sigma`` of each range - the rest anywhere), then ``climbs`` hill climbs of
    ``refine`` tries each from the best; ``grid``: every point of the parameters' grid
    instead (each a ``choose`` or a ``range`` with ``step``)."""

    tries: Whole = 60
    rounds: Annotated[int, Meta(ge=1, le=1000)] = 1
    around: Share = 0.5
    sigma: Annotated[float, Meta(gt=0.0, le=1.0)] = 0.15
    climbs: Whole = 1
    refine: Whole = 40
    grid: bool = False


class StageSpec(Spec, kw_only=True):
    """One stretch of the performance, searched from a checkpoint at its start."""

    name: str
    at: Number | None = None  # s from the performance's start (default: the last's end)
    vary: dict[str, tuple[float, float] | ParamSpec] = field(default_factory=dict)
    first: dict[str, float | str] = field(default_factory=dict)
    let: dict[str, Number] = field(default_factory=dict)
    events: list[EntryTemplate] = field(default_factory=list)
    repeat: RepeatSpec | None = None
    then: list[EntryTemplate] = field(default_factory=list)
    script: str | None = None  # a script's events, played from the stage's start
    generator: str | None = None
    length: Number
    lookahead: Annotated[float, Meta(ge=0.0, le=60.0)] = 0.0
    lookahead_repeats: Annotated[int, Meta(ge=0, le=20)] = 0
    times: Annotated[int, Meta(ge=1, le=1000)] = 1
    until: list[Expectation] = field(default_factory=list)
    alternatives: Annotated[int, Meta(ge=0, le=20)] = 0
    feat: bool | None = None  # the spec's feat judged here (default: the last stage)
    search: SearchSpec = field(default_factory=SearchSpec)
    score: list[TermSpec] = field(default_factory=list)
    playtest: PlaytestTerm | None = None


class StartSpec(Spec, kw_only=True):
    """Begin from a log: its events up to ``until`` s, or up to its ``checkpoint``-th
    checkpoint (1 the first), or all of it."""

    log: str
    until: float | None = None
    checkpoint: Annotated[int, Meta(ge=1)] | None = None

    def __post_init__(self):
        if self.until is not None and self.checkpoint is not None:
            raise ValueError("a start has 'until' or 'checkpoint', not both")


class MocapSpec(Spec, kw_only=True):
    """A clip that plays along every try (``puppet play --mocap CLIP [--mapping M]
    [--loop]``): a performer's channels beside the searched keys and mouse."""

    clip: str
    mapping: str | None = None
    loop: bool = False


class TuneSpec(Spec, kw_only=True):
    description: str = ""
    interface: str | None = None
    scene: str | None = None
    seed: Seed = 0
    start: StartSpec | None = None
    events: list[ScriptEntry] = field(default_factory=list)
    stages: Annotated[list[StageSpec], Meta(min_length=1, max_length=200)]
    feat: ExpectFile | None = None
    max_backtracks: Whole = 30
    mocap: MocapSpec | None = None

    def __post_init__(self):
        if self.interface is None and self.start is None:
            raise ValueError("a spec names its 'interface' (or a 'start: {log: ...}' to "
                             "take it from)")
        if self.mocap is not None and self.start is not None:
            raise ValueError("'mocap' plays a clip from the performance's first step: a "
                             "spec with it starts from the scene (its 'interface' and "
                             "'events'), not from a log")


class Param:
    """A parameter as the search uses it (from ``vary``)."""

    def __init__(self, name: str, spec: ParamSpec | tuple):
        self.name = name
        if isinstance(spec, ParamSpec):
            self.range, self.step, self.choose = spec.range, spec.step, spec.choose
            self.interface = list(spec.interface)
        else:  # written [low, high]
            self.range, self.step, self.choose, self.interface = tuple(spec), None, None, []

    @property
    def span(self) -> float:
        return 0.0 if self.range is None else self.range[1] - self.range[0]

    def grid(self) -> list:
        if self.choose is not None:
            return list(self.choose)
        lo, hi = self.range
        if self.step is None:
            raise ValueError(f"parameter '{self.name}' has no 'step': a grid search needs "
                             "one on every range")
        n = int((hi - lo) / self.step + 1e-9)
        return [round(lo + k * self.step, 6) for k in range(n + 1)]

    def clamp(self, value: float) -> float:
        lo, hi = self.range
        value = min(hi, max(lo, value))
        if self.step is not None:
            value = lo + round((value - lo) / self.step) * self.step
            value = min(hi, max(lo, value))
        return round(value, 4)

    def middle(self):
        return self.choose[0] if self.choose is not None else self.clamp(
            (self.range[0] + self.range[1]) / 2)


def params_of(stage: StageSpec) -> list[Param]:
    out = []
    for name, p in stage.vary.items():
        out.append(Param(name, p))
    return out


class Loaded:
    """A validated spec with where it came from (for errors found later)."""

    def __init__(self, spec: TuneSpec, located: Located, path: Path):
        self.spec = spec
        self.located = located
        self.path = path
        self.name = path.name.removesuffix(".yaml").removesuffix(".yml")
        self.text = located.text or ""
        self.params = [params_of(s) for s in spec.stages]
        self.exprs: dict[tuple, Expr] = {}  # data path of a number -> its expression

    def error(self, loc: tuple, message: str):
        return self.located.error(loc, message)


def load_tune_spec(path: str | Path) -> Loaded:
    """Read and check a spec; DataError (one line, file:line:col) at the first problem."""
    from puppet.timeline.tuning.checks import check_spec

    located = load_file(path)
    spec = validate(located, TuneSpec)
    loaded = Loaded(spec, located, Path(path))
    check_spec(loaded)
    return loaded


__all__ = ["EntryTemplate", "Expr", "ExprError", "Loaded", "MocapSpec", "Param", "ParamSpec",
           "PhysicsVariant", "PlaytestTerm", "RepeatSpec", "SearchSpec", "StageSpec",
           "StartSpec", "TermSpec", "TuneSpec", "load_tune_spec", "params_of"]
