"""What only the whole spec can say, checked when it is read (``load_tune_spec``): each
name an expression reads, each ``$key``, each ``first:`` value, each generator, each
interface number's place, each expectation's bounds. One DataError, file:line:col.
"""

from __future__ import annotations

from puppet.data.keys import key_problem
from puppet.interface.app_keys import SIM_ACTIONS
from puppet.timeline.expectations import Expectations
from puppet.timeline.tuning.expr import FUNCTIONS, Expr, ExprError
from puppet.timeline.tuning.spec import Loaded, params_of
from puppet.timeline.tuning.template import template_exprs

RESERVED = {"cycle", "cycles_end", "pi", *FUNCTIONS}


def check_spec(loaded: Loaded) -> None:
    spec = loaded.spec
    if spec.feat is not None:
        Expectations(spec.feat.expect, loaded.located, ("feat", "expect"))
    for i in range(len(spec.stages)):
        _check_stage(loaded, i)
    for i, stage in enumerate(spec.stages):
        if stage.generator is not None:
            from puppet.timeline.tuning.generators import GENERATORS

            if stage.generator not in GENERATORS:
                raise loaded.error(("stages", i, "generator"),
                                   f"no candidate generator '{stage.generator}'; the "
                                   f"generators: {', '.join(sorted(GENERATORS))}")
            if spec.mocap is not None:
                raise loaded.error(("stages", i, "generator"),
                                   "a generator plays its own input from the session; with "
                                   "'mocap' the clip's samples would not be merged into it: "
                                   "expected the stage's 'events' (or 'repeat') instead")
    if any(p.interface for ps in loaded.params for p in ps):
        _check_interface_places(loaded)


def _names(loaded: Loaded, loc: tuple, value, known: set[str]) -> None:
    try:
        e = Expr(value)
        e.check(known)
    except ExprError as exc:
        raise loaded.error(loc, str(exc)) from None


def _check_stage(loaded: Loaded, i: int) -> None:
    stage = loaded.spec.stages[i]
    loc = ("stages", i)
    params = {p.name: p for p in params_of(stage)}
    for name, written in stage.vary.items():
        if isinstance(written, tuple) and written[1] < written[0]:
            raise loaded.error(loc + ("vary", name),
                               f"range [{written[0]:g}, {written[1]:g}]: the high end is "
                               "under the low one; expected [low, high]")
        if name in RESERVED or not name.isidentifier():
            raise loaded.error(loc + ("vary", name),
                               f"'{name}' cannot name a parameter (expected a name of "
                               f"letters, digits and _, not one of {', '.join(sorted(RESERVED))})")
    for name, value in stage.first.items():
        p = params.get(name)
        if p is None:
            raise loaded.error(loc + ("first", name),
                               f"'{name}' is not a parameter of the stage; its parameters: "
                               f"{', '.join(params) or 'none'}")
        if p.choose is not None and value not in p.choose:
            raise loaded.error(loc + ("first", name),
                               f"{value!r} is not one of {name}'s choices {p.choose}")
        if p.range is not None and (isinstance(value, str)
                                    or not p.range[0] <= value <= p.range[1]):
            raise loaded.error(loc + ("first", name),
                               f"{value!r} is outside {name}'s range [{p.range[0]:g}, "
                               f"{p.range[1]:g}]")
    numeric = {n for n, p in params.items() if p.choose is None
               or all(not isinstance(c, str) for c in p.choose)}
    known = set(numeric)
    for name, value in stage.let.items():
        if name in RESERVED or name in params or not name.isidentifier():
            raise loaded.error(loc + ("let", name),
                               f"'{name}' cannot name a value here (a parameter's or a "
                               "reserved name, or not a name)")
        _names(loaded, loc + ("let", name), value, known)
        known.add(name)
    if stage.at is not None:
        _names(loaded, loc + ("at",), stage.at, set())
    choices = {n for n, p in params.items() if p.choose is not None}

    def entries(where: tuple, items, names: set[str]) -> None:
        for j, e in enumerate(items):
            for sub, value in template_exprs(e):
                _names(loaded, loc + where + (j,) + sub, value, names)
            if e.key is not None:
                if e.key.startswith("$"):
                    name = e.key[1:]
                    if name not in choices:
                        raise loaded.error(loc + where + (j, "key"),
                                           f"'{e.key}': '{name}' is not a 'choose' parameter "
                                           "of the stage (those: "
                                           f"{', '.join(sorted(choices)) or 'none'})")
                    for option in params[name].choose:
                        if problem := key_problem(str(option)):
                            raise loaded.error(loc + ("vary", name), problem)
                elif problem := key_problem(e.key):
                    raise loaded.error(loc + where + (j, "key"), problem)
            if e.action in ("checkpoint", "restore"):
                raise loaded.error(loc + where + (j, "action"),
                                   f"a stage's entries may not {e.action}: each stage begins "
                                   "at a checkpoint of its own (the search restores it)")
            if e.action is not None and e.action not in SIM_ACTIONS:
                raise loaded.error(loc + where + (j, "action"),
                                   f"unknown action '{e.action}'; a script can perform "
                                   f"{', '.join(sorted(SIM_ACTIONS))}")

    entries(("events",), stage.events, known)
    if stage.script is not None:
        from puppet.timeline.tuning.template import script_entries

        for j, e in enumerate(script_entries(loaded, i)):
            if e.get("action") in ("checkpoint", "restore"):
                raise loaded.error(loc + ("script",), f"{stage.script}: its entry {j + 1} "
                                   f"is a {e['action']}: a stage begins at a checkpoint of "
                                   "its own, and its input may not checkpoint or restore")
    after = set(known)
    if stage.repeat is not None:
        r = stage.repeat
        for key, value in (("every", r.every), ("times", r.times), ("for", r.for_),
                           ("start", r.start)):
            if value is not None:
                _names(loaded, loc + ("repeat", key), value, known)
        entries(("repeat", "events"), r.events, known | {"cycle"})
        after.add("cycles_end")
    entries(("then",), stage.then, after)
    _names(loaded, loc + ("length",), stage.length, after)
    if stage.until:
        Expectations(stage.until, loaded.located, loc + ("until",))
    for j, term in enumerate(stage.score):
        Expectations([term.expect], loaded.located, loc + ("score", j, "expect"))
    if stage.search.grid:
        for p in params.values():
            if p.choose is None and p.step is None:
                raise loaded.error(loc + ("vary", p.name),
                                   f"a grid search ('search: {{grid: true}}') needs a 'step' "
                                   f"for '{p.name}' (or a 'choose' list)")
    judges_feat = stage.feat or (stage.feat is None and i == len(loaded.spec.stages) - 1
                                 and loaded.spec.feat is not None)
    if params and not stage.score and not judges_feat:
        raise loaded.error(loc, f"stage '{stage.name}' varies {', '.join(params)} but "
                                    "has no 'score:' (and does not judge the feat): nothing "
                                    "tells its tries apart; expected a 'score:' list")


def _check_interface_places(loaded: Loaded) -> None:
    """Every interface number's place is a number in the interface file."""
    from puppet.data.catalog import find
    from puppet.data.yamlfile import load_file
    from puppet.timeline.tuning.interface_values import lookup

    spec = loaded.spec
    where = (loaded.path.resolve().parent,)
    name = spec.interface
    if name is None:
        raise loaded.error(("start",), "interface numbers to vary need the spec's "
                                       "'interface:' named (not only a start log's)")
    path = find("interface", name, where)
    located = load_file(path)
    for i, params in enumerate(loaded.params):
        for p in params:
            for j, place in enumerate(p.interface):
                problem = lookup(located.data, place)[1]
                if problem:
                    raise loaded.error(("stages", i, "vary", p.name, "interface", j),
                                       f"{place}: {problem} in {path.name}")
