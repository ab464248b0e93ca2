"""A script's player: its timed events, and its rules that react to what happens.

A rule (``script.RuleSpec``) watches a condition in the interface language's own
vocabulary - a sensor condition as a state machine's transition writes it
(``puppet.interface.conditions`` reads it, roles resolved as the interface binds them
now), or the interface entering a state or a mode - and when it *becomes* true, acts
``after`` a reaction delay of real time: at the slowdown in force that is
``after / slowdown`` simulated seconds, rounded to steps, as for a person watching a
slowed-down run. Conditions are polled at the interface's control rate, on steps that
are multiples of the control period (as the state machines poll theirs), so where
``advance`` is cut does not change the run. A rule does not fire again while its
reaction is pending.

The player feeds the session through ``Session.handle`` like any device, so a
recording of the run holds the events the rules made and replays bit-identically with
no script. The same class plays in the window (``puppet play --input SCRIPT``),
headless, and in a playtest, where ``noise`` moves the timed events as it moves a
log's (``playtest.noise.perturb``) and varies every reaction's delay, hold, aim and
tremor, so that the presses follow the condition, not the clock. Without noise the
player is deterministic.
"""

from __future__ import annotations

import heapq
import zlib
from collections.abc import Callable

from puppet.data.keys import normalize_key
from puppet.data.playtest import REFERENCE_WINDOW, Noise
from puppet.interface import events as ev
from puppet.interface.conditions import compile_test, reader
from puppet.interface.events import Event
from puppet.session import Session
from puppet.timeline.script import GLIDE_RATE, RuleSpec, ScriptSpec, compile_script


class _Rule:
    """A rule compiled against a session: its test and what it last read."""

    def __init__(self, index: int, spec: RuleSpec, dt: float):
        self.index, self.spec = index, spec
        # never at step 0: before the first step pymunk has found no contacts yet, and a
        # foot standing on the ground would read as landing at the next poll
        self.first = max(1, round(spec.from_ / dt))
        self.last = None if spec.until is None else round(spec.until / dt)
        self.was: bool | None = None  # the condition at the last poll (None: not read yet)
        self.since: int | None = None  # the step it became true (None: false, or acted on)
        self.fired = 0
        self.busy_until = -1  # a reaction pending until this step
        self.tests = [compile_test(w.condition()) if w.sensor is not None else None
                      for w in spec.when]
        self._readers: dict[tuple, Callable[[], float]] = {}

    def holds(self, session: Session) -> bool:
        """Whether every condition of the rule holds now."""
        runtime = session.runtime
        for k, w in enumerate(self.spec.when):
            if w.mode is not None:
                ok = runtime.mode == w.mode
            elif w.state is not None:
                ok = False
                for name in w.states:
                    where = session.interface.resolve_goto(name)
                    machine = runtime.machines.get(where[0]) if where else None
                    if machine is not None and machine.current == where[1]:
                        ok = True
                        break
            else:
                sensor = w.sensor if w.sensor.startswith("held.") \
                    else runtime.roles.sensor(w.sensor)  # a role as the binding means now
                key = (id(runtime), sensor)
                read = self._readers.get(key)
                if read is None:
                    read = self._readers[key] = reader(sensor, session.character,
                                                       runtime.channels, runtime.inputs,
                                                       lambda name: session.sim.grasp_point(name))
                ok = self.tests[k](read())
            if not ok:
                return False
        return True


class ScriptPlayer:
    """Plays a script into ``session`` until step ``until`` (``advance``, like
    ``replay.LogFeeder``). ``slowdown()``: the slowdown in force now (the window's
    clock; headless, ``Speed``); ``on_action`` gets the app actions the events it
    sends ask for (a slowdown key...). ``noise``, ``seed``, ``try_index``: a
    playtest's try (None: the script as written). ``timed``: the timed events to play
    (default the script's own, compiled; a mocap clip's frames may be merged in)."""

    def __init__(self, session: Session, spec: ScriptSpec, until: int | None,
                 slowdown: Callable[[], float], on_action=None, noise: Noise | None = None,
                 seed: int = 0, try_index: int = 0,
                 timed: list[tuple[int, Event]] | None = None):
        self.session, self.spec, self.until = session, spec, until
        self.slowdown, self.on_action = slowdown, on_action
        self.noise, self.seed, self.try_index = noise, seed, try_index
        dt = session.sim.dt
        self.dt = dt
        timed = compile_script(spec, dt) if timed is None else list(timed)
        if noise is not None and timed:
            from puppet.timeline.playtest.noise import perturb

            end = until if until is not None else max(s for s, _ in timed)
            timed = perturb(timed, [slowdown()] * len(timed), dt, end, noise, seed,
                            try_index, session.interface.app_key_table()).pairs
        self.timed = timed
        self.i = 0  # the next timed event
        self.rules = [_Rule(i, r, dt) for i, r in enumerate(spec.rules)]
        self._rngs: dict[int, object] = {}
        self.pending: list[tuple[int, int, Event]] = []  # heap of (step, order, event)
        self._order = 0
        self._polled = -1  # the step last polled
        self._seen = session.steps  # time going back (a restore) resets the rules

    # -- when ------------------------------------------------------------------------
    def _every(self) -> int:
        return max(1, round(1.0 / (self.session.interface.control_rate * self.dt)))

    def _next_poll(self, now: int) -> int | None:
        if not self.rules:
            return None
        every = self._every()
        at = now if self._polled < now else now + 1
        return -(-at // every) * every

    def _steps(self, real_seconds: float) -> int:
        return max(0, round(real_seconds / self.slowdown() / self.dt))

    def _next(self, now: int) -> int | None:
        """The next step something is due at (None: nothing more)."""
        due = [s for s in (self.timed[self.i][0] if self.i < len(self.timed) else None,
                           self.pending[0][0] if self.pending else None,
                           self._next_poll(now)) if s is not None]
        if self.until is not None:
            due.append(self.until)
        return min(due) if due else None

    @property
    def finished(self) -> bool:
        now = self.session.steps
        if self.until is not None:
            return now >= self.until and not self._due(now)
        return self.i >= len(self.timed) and not self.pending

    def _due(self, now: int) -> bool:
        return ((self.i < len(self.timed) and self.timed[self.i][0] <= now)
                or bool(self.pending and self.pending[0][0] <= now)
                or (self.rules and self._polled < now and now % self._every() == 0
                    and (self.until is None or now < self.until)))

    # -- what ------------------------------------------------------------------------
    def _send(self, event: Event) -> None:
        action = self.session.handle(event)
        if action is not None and self.on_action is not None:
            self.on_action(action)

    def _schedule(self, step: int, event: Event) -> None:
        heapq.heappush(self.pending, (step, self._order, event))
        self._order += 1

    def _rng(self, rule: _Rule):
        rng = self._rngs.get(rule.index)
        if rng is None:
            import numpy as np

            rng = self._rngs[rule.index] = np.random.default_rng(
                [self.seed, self.try_index, 1 << 20, zlib.crc32(f"rule:{rule.index}".encode())])
        return rng

    def _react(self, rule: _Rule, now: int) -> None:
        """The rule's condition became true at ``now``: schedule its action."""
        r, noise = rule.spec, self.noise
        rng = self._rng(rule) if noise is not None else None

        def err() -> float:  # a real-time error, s
            return 0.0 if rng is None else float(rng.uniform(-1.0, 1.0)) * noise.timing_ms / 1e3

        start = now + self._steps(r.after + err())
        if r.key is not None:
            chord = normalize_key(r.key)
            release = start + max(1, self._steps(r.hold + err()) if r.hold else 1)
            self._schedule(start, ev.key(chord, True))
            self._schedule(release, ev.key(chord, False))
            rule.busy_until = release
        else:
            aim = tremor = (0.0, 0.0)
            n = max(1, round(r.over * GLIDE_RATE)) if r.over > 0 else 1
            if rng is not None:
                ax, ay = rng.uniform(-1.0, 1.0, 2)
                aim = (ax * noise.aim_px / REFERENCE_WINDOW[0],
                       ay * noise.aim_px / REFERENCE_WINDOW[1])
            inputs = self.session.runtime.inputs
            x0, y0 = inputs.get("mouse.x", 0.5), inputs.get("mouse.y", 0.5)
            x1, y1 = r.mouse[0] + aim[0], r.mouse[1] + aim[1]
            tempo = 1.0 + (float(rng.uniform(-1.0, 1.0)) * noise.tempo if rng is not None
                           else 0.0)
            for i in range(1, n + 1):
                u = i / n
                if rng is not None:
                    tx, ty = rng.uniform(-1.0, 1.0, 2)
                    tremor = (tx * noise.tremor_px / REFERENCE_WINDOW[0],
                              ty * noise.tremor_px / REFERENCE_WINDOW[1])
                at = start + (self._steps(u * r.over * tempo) if r.over > 0 else 0)
                x = min(1.0, max(0.0, x0 + u * (x1 - x0) + tremor[0]))
                y = min(1.0, max(0.0, y0 + u * (y1 - y0) + tremor[1]))
                self._schedule(at, ev.mouse(x, y))
                rule.busy_until = at
        rule.fired += 1

    def _poll(self, now: int) -> None:
        self._polled = now
        for rule in self.rules:
            if now < rule.first or (rule.last is not None and now > rule.last):
                rule.was = rule.since = None  # out of its window: read afresh when back in
                continue
            holds = rule.holds(self.session)
            if holds and rule.was is False:
                rule.since = now  # it became true: it acts once it has held 'for'
            elif not holds:
                rule.since = None
            rule.was = holds
            if rule.since is not None and now - rule.since >= self._steps(rule.spec.for_) \
                    and now > rule.busy_until and (rule.spec.times is None
                                                   or rule.fired < rule.spec.times):
                rule.since = None  # once per time it becomes true
                self._react(rule, now)

    def _rewound(self, now: int) -> None:
        """Time went back (a restore, a reset does not): pending reactions are dropped
        and the rules read afresh."""
        self.pending.clear()
        self._polled = now - 1
        for rule in self.rules:
            rule.was, rule.since, rule.busy_until = None, None, -1

    def advance(self, steps: int) -> None:
        """Run up to ``steps`` steps; what is due at the step reached acts too."""
        budget = steps
        session = self.session
        while True:
            now = session.steps
            if now < self._seen:
                self._rewound(now)
            self._seen = now
            if self.until is not None and now > self.until:
                return
            acted = False
            if self.rules and self._polled < now and now % self._every() == 0 \
                    and (self.until is None or now < self.until):
                self._poll(now)
            if self.i < len(self.timed) and self.timed[self.i][0] <= now:
                event = self.timed[self.i][1]
                self.i += 1
                self._send(event)
                acted = True
            elif self.pending and self.pending[0][0] <= now:
                self._send(heapq.heappop(self.pending)[2])
                acted = True
            if acted:
                continue
            target = self._next(now)
            if target is None or target <= now or budget <= 0:
                return
            k = min(budget, target - now)
            session.advance(k)
            budget -= k

    def run(self) -> None:
        """Play to the end (headless)."""
        while not self.finished:
            before = self.session.steps
            self.advance(1 << 30)
            if self.session.steps == before and not self._due(before):
                return


def play_script(session: Session, player: ScriptPlayer, every: int = 0,
                on_tick: Callable[[Session], None] | None = None) -> None:
    """Run ``player`` to its end, calling ``on_tick`` every ``every`` steps (frames),
    as ``playback.play`` does for a list of events."""
    if not every or on_tick is None:
        player.run()
        return
    while not player.finished:
        before = session.steps
        player.advance(every - session.steps % every)
        if session.steps % every == 0 and session.steps != before:
            on_tick(session)
        elif session.steps == before:
            return


class Speed:
    """The slowdown in force for a run with no window: the run's, changed by the
    actions the events ask for as the window's clock changes it (``SimClock.apply``)."""

    def __init__(self, slowdown: float):
        from puppet.data.bounds import nearest_slowdown_index

        self.value = float(slowdown)
        self.index = nearest_slowdown_index(self.value)

    def __call__(self) -> float:
        return self.value

    def apply(self, action) -> None:
        from puppet.data.bounds import (
            MAX_SLOWDOWN,
            MIN_SLOWDOWN,
            nearest_slowdown_index,
            stepped_slowdown,
        )
        from puppet.interface.app_keys import SetSlowdown

        if action in ("slower", "faster"):
            self.value, self.index = stepped_slowdown(self.value, self.index,
                                                      action == "slower")
        elif isinstance(action, SetSlowdown):
            self.value = min(MAX_SLOWDOWN, max(MIN_SLOWDOWN, float(action.value)))
            self.index = nearest_slowdown_index(self.value)
