"""A stage's script entries for one set of parameter values.

The stage's ``let:`` values are worked out in order, then its ``events`` (once), its
``repeat`` (cycle by cycle, ``cycle`` = 0, 1, ...) and its ``then`` entries (after the
cycles: ``cycles_end``), each number evaluated and every time moved by the stage's
start. Numbers are rounded to 0.1 ms / 1e-4 (what the written script shows, so the
script and the searched run are the same input), a mouse point is held inside the
window, a glide or hold is never negative.
"""

from __future__ import annotations

from puppet.data.errors import DataError
from puppet.timeline.tuning.expr import Expr, ExprError
from puppet.timeline.tuning.spec import MAX_CYCLES, EntryTemplate, Loaded, StageSpec

NUMBER_FIELDS = ("t", "over", "hold")


def r4(value: float) -> float:
    return round(float(value), 4)


def _expr(value) -> Expr:
    return Expr(value)


class StageTemplate:
    """Stage ``index`` of a spec, its expressions parsed (``checks`` made sure each
    names only what it may)."""

    def __init__(self, loaded: Loaded, index: int):
        self.loaded = loaded
        self.index = index
        self.spec: StageSpec = loaded.spec.stages[index]
        self.loc = ("stages", index)
        s = self.spec
        self.lets = [(name, _expr(v)) for name, v in s.let.items()]
        self.events = [_entry(e) for e in s.events]
        self.repeat = None
        if s.repeat is not None:
            r = s.repeat
            self.repeat = (_expr(r.every), None if r.times is None else _expr(r.times),
                           None if r.for_ is None else _expr(r.for_), _expr(r.start),
                           [_entry(e) for e in r.events])
        self.then = [_entry(e) for e in s.then]
        self.length = _expr(s.length)
        self.at = None if s.at is None else _expr(s.at)
        self.script: list[dict] = []
        if s.script is not None:
            self.script = script_entries(loaded, index)

    def values(self, params: dict) -> dict:
        """The parameters with the ``let:`` values added."""
        values = dict(params)
        for name, e in self.lets:
            values[name] = self._eval(e, values, ("let", name))
        return values

    def _eval(self, e: Expr, values: dict, sub: tuple) -> float:
        try:
            return e(values)
        except ExprError as exc:
            shown = ", ".join(f"{k} = {v:g}" for k, v in values.items()
                              if isinstance(v, float) and k in e.names)
            with_values = f" (with {shown})" if shown else ""
            raise self.loaded.error(self.loc + sub, f"{exc}{with_values}") from None

    def entries(self, params: dict, t0: float) -> tuple[list[dict], float]:
        """(script entries at absolute times, the stage's length in s) for ``params``
        with the stage starting at ``t0`` s."""
        values = self.values(params)
        out: list[dict] = [dict(e, t=r4(t0 + e["t"])) for e in self.script]
        for i, e in enumerate(self.events):
            out.append(self._one(e, values, t0, ("events", i)))
        if self.repeat is not None:
            every, times, until, start, events = self.repeat
            loc = ("repeat",)
            step = self._eval(every, values, loc + ("every",))
            first = self._eval(start, values, loc + ("start",))
            if times is not None:
                n = int(round(self._eval(times, values, loc + ("times",))))
            else:
                limit = self._eval(until, values, loc + ("for",))
                if step <= 0:
                    raise self.loaded.error(self.loc + loc + ("every",),
                                            f"'every' is {step:g} s: expected more than 0")
                n = 0
                while first + n * step < limit - 1e-9 and n <= MAX_CYCLES:
                    n += 1
            if not 0 <= n <= MAX_CYCLES:
                raise self.loaded.error(self.loc + loc, f"{n} cycles: expected 0..{MAX_CYCLES}")
            for k in range(n):
                cyc = dict(values, cycle=float(k))
                offset = first + k * step
                for i, e in enumerate(events):
                    out.append(self._one(e, cyc, t0 + offset, loc + ("events", i)))
            values["cycles_end"] = first + n * step
        for i, e in enumerate(self.then):
            out.append(self._one(e, values, t0, ("then", i)))
        length = self._eval(self.length, values, ("length",))
        if length < 0:
            raise self.loaded.error(self.loc + ("length",),
                                    f"the stage's length is {length:g} s: expected 0 or more")
        return out, r4(length)

    def _one(self, e: dict, values: dict, t0: float, sub: tuple) -> dict:
        loc = sub

        def num(key, expr):
            return self._eval(expr, values, loc + (key,))

        out: dict = {"t": r4(t0 + max(0.0, num("t", e["t"])))}
        if "mouse" in e:
            x, y = (num("mouse", v) for v in e["mouse"])
            out["mouse"] = [r4(min(1.0, max(0.0, x))), r4(min(1.0, max(0.0, y)))]
            over = num("over", e["over"])
            if over > 0:
                out["over"] = r4(over)
        elif "key" in e:
            key = e["key"]
            if key.startswith("$"):
                key = values[key[1:]]
            out["key"] = str(key)
            hold = num("hold", e["hold"])
            if hold > 0:
                out["hold"] = r4(hold)
        elif "action" in e:
            out["action"] = e["action"]
        elif "drag" in e:
            d = e["drag"]
            drag = {"link": d["link"], "point": [r4(num("drag", v)) for v in d["point"]],
                    "to": [r4(num("drag", v)) for v in d["to"]]}
            if d["start"] is not None:
                drag["start"] = [r4(num("drag", v)) for v in d["start"]]
            drag["over"] = r4(max(0.0, num("drag", d["over"])))
            drag["hold"] = r4(max(0.0, num("drag", d["hold"])))
            out["drag"] = drag
        else:
            p = e["push"]
            push = {"link": p["link"], "impulse": [r4(num("push", v)) for v in p["impulse"]]}
            if p["point"] is not None:
                push["point"] = [r4(num("push", v)) for v in p["point"]]
            out["push"] = push
        return out


def script_entries(loaded: Loaded, index: int) -> list[dict]:
    """The events of the script a stage names (``script:``), as plain entries."""
    import msgspec

    from puppet.data.catalog import find
    from puppet.timeline.script import load_script

    name = loaded.spec.stages[index].script
    try:
        spec = load_script(find("script", name, (loaded.path.resolve().parent,)))
    except DataError as exc:
        raise loaded.error(("stages", index, "script"), f"{name}: {exc.message}") from None
    out = []
    for e in spec.events:
        d = {k: v for k, v in msgspec.to_builtins(e).items()
             if v is not None and not (k in ("over", "hold") and v == 0)}
        out.append(d)
    return out


def _entry(e: EntryTemplate) -> dict:
    """An entry's expressions parsed once."""
    out: dict = {"t": _expr(e.t)}
    if e.mouse is not None:
        out["mouse"] = [_expr(v) for v in e.mouse]
        out["over"] = _expr(e.over)
    elif e.key is not None:
        out["key"] = e.key
        out["hold"] = _expr(e.hold)
    elif e.action is not None:
        out["action"] = e.action
    elif e.drag is not None:
        d = e.drag
        out["drag"] = {"link": d.link, "point": [_expr(v) for v in d.point],
                       "to": [_expr(v) for v in d.to],
                       "start": None if d.start is None else [_expr(v) for v in d.start],
                       "over": _expr(d.over), "hold": _expr(d.hold)}
    else:
        p = e.push
        out["push"] = {"link": p.link, "impulse": [_expr(v) for v in p.impulse],
                       "point": None if p.point is None else [_expr(v) for v in p.point]}
    return out


def template_exprs(e: EntryTemplate) -> list[tuple[tuple, object]]:
    """(sub-path, written value) of every number of an entry, for the checks."""
    out = [(("t",), e.t)]
    if e.mouse is not None:
        out += [(("mouse", i), v) for i, v in enumerate(e.mouse)] + [(("over",), e.over)]
    elif e.key is not None:
        out.append((("hold",), e.hold))
    elif e.drag is not None:
        d = e.drag
        out += [(("drag", "point", i), v) for i, v in enumerate(d.point)]
        out += [(("drag", "to", i), v) for i, v in enumerate(d.to)]
        if d.start is not None:
            out += [(("drag", "start", i), v) for i, v in enumerate(d.start)]
        out += [(("drag", "over"), d.over), (("drag", "hold"), d.hold)]
    elif e.push is not None:
        p = e.push
        out += [(("push", "impulse", i), v) for i, v in enumerate(p.impulse)]
        if p.point is not None:
            out += [(("push", "point", i), v) for i, v in enumerate(p.point)]
    return out


__all__ = ["StageTemplate", "r4", "script_entries", "template_exprs"]
