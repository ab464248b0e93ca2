"""Where a search begins: the scene's start with the spec's own fixed ``events``, or a
log played up to a time or one of its checkpoints. It gives the session's make (the
interface and scene, or the log's), the input before the first stage and when the first
stage may start, and the interface text that interface parameters change.
"""

from __future__ import annotations

import hashlib

from puppet.physics.simulation import step_of
from puppet.timeline.expectations import Expectations
from puppet.timeline.script import ScriptSpec, compile_script, entry_end
from puppet.timeline.tuning.interface_values import interface_values, with_values
from puppet.timeline.tuning.spec import Loaded
from puppet.timeline.tuning.trial import _setup


class Start:
    def __init__(self, loaded: Loaded):
        spec = loaded.spec
        self.log_path: str | None = None
        self.entries: list[dict] | None = [_plain(e) for e in spec.events]
        folder = str(loaded.path.resolve().parent)
        if spec.start is not None:
            self._from_log(loaded)
        else:
            self.setup_from = ("names", spec.interface, spec.scene, folder)
            self.setup = _setup(self.setup_from)
            self.dt = step_of(self.setup.character)  # a new session's step
            self.interval = self.setup.interface.checkpoint_every
            script = ScriptSpec(events=list(spec.events)) if spec.events else None
            self.pairs = compile_script(script, self.dt) if script else []
            self.t0 = 0.0
            first = spec.stages[0]
            if first.at is None and spec.events:
                self.t0 = max(entry_end(e) for e in spec.events)
            elif first.at is not None:
                from puppet.timeline.tuning.expr import Expr

                self.t0 = round(Expr(first.at)({}), 4)
            for i, e in enumerate(spec.events):
                if entry_end(e) > self.t0 + 1e-9:
                    raise loaded.error(("events", i),
                                       f"this entry goes on to {entry_end(e):g} s, after the "
                                       f"first stage starts ({self.t0:g} s): the fixed events "
                                       "come before the stages")
        self.interface_path = self.setup.interface_path
        self._interface_text = None
        self.performer = None
        if spec.mocap is not None:  # the clip's samples before the first stage, merged
            self.performer = _performer(loaded, self.setup, self.dt)
            from puppet.timeline.tuning.performer import merged

            self.pairs = merged(self.pairs, self.performer.between(0, round(self.t0 / self.dt)))

    def _from_log(self, loaded: Loaded) -> None:
        from puppet.timeline.log import read_log
        from puppet.timeline.replay import find_log, require_end

        spec = loaded.spec
        s = spec.start
        try:
            path = find_log(s.log)
            log = read_log(path)
            require_end(log, allow_truncated=False)
        except Exception as exc:  # DataError: said at the spec's start
            message = getattr(exc, "message", str(exc))
            raise loaded.error(("start", "log"), f"{s.log}: {message}") from None
        self.log_path = path
        self.setup_from = ("log", path)
        self.setup = _setup(self.setup_from)
        self.dt = float(log.header["dt"])
        self.interval = float(log.header["checkpoint_interval"])
        events = log.pairs()
        if s.checkpoint is not None:
            marks = [i for i, (_, e) in enumerate(events)
                     if e["type"] == "action" and e.get("name") == "checkpoint"]
            if len(marks) < s.checkpoint:
                raise loaded.error(("start", "checkpoint"),
                                   f"{s.log} has {len(marks)} checkpoint(s); expected a "
                                   f"number 1..{len(marks)}" if marks else
                                   f"{s.log} has no checkpoint")
            cut_index = marks[s.checkpoint - 1]
            cut = events[cut_index][0]
            events = events[:cut_index + 1]
        else:
            cut = log.last_step if s.until is None else round(s.until / self.dt)
            if not 0 <= cut <= log.last_step:
                raise loaded.error(("start", "until"),
                                   f"{s.until:g} s is outside the log "
                                   f"(0..{log.last_step * self.dt:.2f} s)")
            kept = []
            for step, e in events:
                if step > cut:
                    break
                kept.append((step, e))
            events = kept
        self.pairs = events
        self.t0 = round(cut * self.dt, 4)
        self.entries = None  # a log's input is not script entries: no script is written
        if spec.stages[0].at is not None:
            from puppet.timeline.tuning.expr import Expr

            self.t0 = round(Expr(spec.stages[0].at)({}), 4)

    def interface_text(self, params: list, values: dict) -> str | None:
        """The interface with the stage's interface numbers set (None: it has none)."""
        places = interface_values(params, values)
        if not places:
            return None
        if self._interface_text is None:
            self._interface_text = self.interface_path.read_text(encoding="utf-8")
        return with_values(self._interface_text, str(self.interface_path), places)

    def current(self, params: list) -> dict:
        """The interface file's own value of each interface parameter (its first
        place's, rounded as the parameter is): where a search of them starts."""
        from puppet.data.yamlfile import load_text
        from puppet.timeline.tuning.interface_values import lookup

        if self._interface_text is None:
            self._interface_text = self.interface_path.read_text(encoding="utf-8")
        data = load_text(self._interface_text, str(self.interface_path)).data
        out = {}
        for p in params:
            if p.interface:
                value = lookup(data, p.interface[0])[0]
                out[p.name] = p.clamp(-value if p.interface[0].startswith("-") else value)
        return out

    def fingerprint(self) -> str:
        """What the results depend on besides the spec: the interface, scene and
        character files' text, the start log, the clip and its mapping (``mocap``),
        puppet's version and this package's code."""
        h = hashlib.sha1()
        for p in (self.setup.interface_path, self.setup.character_path,
                  getattr(self.setup, "scene_path", None), self.log_path):
            if p:
                try:
                    with open(p, "rb") as f:
                        h.update(f.read())
                except OSError:
                    h.update(str(p).encode())
        if self.performer is not None:
            h.update(self.performer.fingerprint())
        from puppet import __version__

        h.update(__version__.encode())
        from pathlib import Path

        for source in sorted(Path(__file__).parent.glob("*.py")):  # how tries are scored
            h.update(source.read_bytes())
        return h.hexdigest()[:16]

    def check_names(self, loaded: Loaded, terms: list) -> None:
        """DataError at an expectation naming a link the character lacks."""
        links = [link.name for link in self.setup.character.links]
        spec = loaded.spec
        if spec.feat is not None:
            Expectations(spec.feat.expect, loaded.located, ("feat", "expect")).check_links(links)
        for i, stage in enumerate(spec.stages):
            for j, t in enumerate(stage.score):
                Expectations([t.expect], loaded.located,
                             ("stages", i, "score", j, "expect")).check_links(links)
            if stage.until:
                Expectations(stage.until, loaded.located, ("stages", i, "until")).check_links(links)


def _performer(loaded: Loaded, setup, dt: float):
    """The spec's ``mocap`` clip through its mapping (as ``puppet play --mocap`` takes
    them); a clip or mapping that cannot play is said at the spec's ``mocap`` line."""
    from puppet.data.errors import DataError
    from puppet.timeline.tuning.performer import Performer

    mocap = loaded.spec.mocap
    try:
        performer = Performer(mocap, setup, dt)
    except DataError as exc:
        raise loaded.error(("mocap", "clip"), str(exc)) from None
    from puppet.data.tracking import interface_mapping_problem

    problem = interface_mapping_problem(setup.interface, setup.character, performer.mapping)
    if problem:
        raise loaded.error(("mocap",), f"{problem} ({performer.mapping_where})")
    return performer


def _plain(e) -> dict:
    """A script entry as the written script shows it."""
    import msgspec

    out = {k: v for k, v in msgspec.to_builtins(e).items() if v is not None}
    for k in ("over", "hold"):
        if out.get(k) == 0:
            del out[k]
    return out
