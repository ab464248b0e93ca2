"""State transitions inside the kernel's loop: the poll plan's states table
(``physics.kernel_poll_states``) and the hand-back of what a call entered.

``poll_fill.fill`` arms it (``arm``) when the runtime's work between ticks is one
machine's polls and plain travelling targets, nothing else busy (no device maps
active, no sequence, frame targets, reach, grasp or kept key press; sensor add maps
the kernel runs may be: ``poll_feed``). Then a transition into a state the loop can
enter - its table the kernel's with no device input decided when filled, no roles,
no maps but sensor add maps (their rows switched with it: ``poll_feed``), its entry
nothing or a ``set`` of plain angles with ``over``; its own control rate and `for`s
are the loop's too - is taken in the loop, with the states chained after it and the
targets' arrivals; any other ends the call for Python's tick, as a timer does. After the call
``handed_back`` replays the log on the runtime: the machine's state (``enter``), the
maps refreshed and activated as ``_enter_state`` does, the owners and the blend's
travelling targets (each from the rest angle the kernel read), so that the runtime is
what Python's ticks would have left, to the bit. Without the kernel there is no
plan, and every transition is Python's.
"""

from __future__ import annotations

import math

from puppet.interface import poll_feed
from puppet.interface.actions import MAX_CHAINED_GOTOS
from puppet.interface.controllers import feedback_kernel as _fk
from puppet.interface.controllers.tracking import OFF
from puppet.interface.ownership import BLEND
from puppet.interface.poll_table import state_table

MAX_LOG = 256
MAX_VAL = 1024
MAX_ROWS = 32  # the plan's rows (poll_fill.MAX_CONDITIONS)
_DEFAULT_NONE = ("pose", "sequence", "repeat", "goto", "reach", "grasp", "release",
                 "app", "slowdown", "gravity", "friction", "perturb", "push", "track",
                 "kinematic")
_DEFAULT_EMPTY = ("adjust", "stiffness", "damping")


def blend_only(a, mode) -> bool:
    """An entry that only starts plain targets travelling (``set`` of angles with
    ``over``), or does nothing (``mode`` already the runtime's: ``run_action``)."""
    return (a.over is not None or not a.set) and not a.while_held \
        and (a.mode is None or a.mode == mode) \
        and all(getattr(a, f) is None for f in _DEFAULT_NONE) \
        and all(not getattr(a, f) for f in _DEFAULT_EMPTY) \
        and all(isinstance(v, (int, float)) for v in a.set.values())


class States:
    """One plan's states table (made per binding and seat, when first armed)."""

    def __init__(self, plan):
        self.plan = plan
        self.ffi = plan.ffi
        self.st = None  # the pk_states struct armed last
        self._made: dict = {}  # (binding, mode, period) -> its table (_build)
        self.names: list[str] = []
        self.entries: list = []  # per state: (its targets [(joint, to)], steps) or None
        self.targets: dict = {}  # state -> per transition index: the state's index or -1
        self.rows: list = []  # per plan blend row: its joint (the handback's mirror)
        self.row_of: dict = {}  # a travelling joint -> its row
        self.uses_com = False  # a state's conditions read the centre of mass
        self.plans: list = []  # per state: its add maps' Plan, None, False (poll_feed)
        self.fb_on = False  # the armed table switches feedback's rows (poll_feed)

    def _enterable(self, rt, machine, name: str, mode, every: int, plan):
        """``(targets, steps)`` of a state the loop can enter (its entry's), else None,
        in ``mode`` at the period ``every`` (``plan``: its add maps', poll_feed)."""
        spec = machine.spec.states[name]
        table = state_table(self.plan, machine, name)
        if table is None or spec.roles is not None or plan is False:
            return None
        if any(cs and any(c[0] is None for c in cs) for _, cs, *_ in table):
            return None
        a = spec.enter
        if a is None or (a.set == {} and blend_only(a, mode)):
            return [], 1
        if not blend_only(a, mode):
            return None
        rename, servos, targets = rt.roles.rename, rt.character.servos, {}
        for joint, value in a.set.items():  # (BlendController.start_action's order)
            joint = rename(joint)
            if joint not in servos:
                return None
            targets.pop(joint, None)
            targets[joint] = math.radians(value)
        return list(targets.items()), round(a.over / rt.dt)

    def prime(self, rt) -> None:
        """The tables for each mode and period of a one-machine runtime, made when it
        is (as the plan's own: a first build in a replay is between its steps)."""
        if len(rt._machine_list) != 1:
            return
        machine, period = rt._machine_list[0], rt.period
        for mode in {rt.mode, *rt.spec.modes}:
            for every in {period.base, *period.fast.get(machine.name, {}).values()}:
                key = (rt.roles.binding, mode, every)
                if key not in self._made:
                    self._made[key] = self._build(rt, machine, mode, every)

    def _build(self, rt, machine, mode, every: int) -> tuple:
        """The table for the binding, mode and period of now: (the states' names, their
        entries, per state its transitions' states, the struct, what its conditions
        and entries point at, whether one reads the centre of mass, the seat)."""
        ffi, plan, spec = self.ffi, self.plan, machine.spec
        names = list(spec.states)
        index = {n: k for k, n in enumerate(names)}
        plans = [poll_feed.state_plan(rt, mode, n) if rt.feedback._fk is not None
                 else None if not spec.states[n].maps else False for n in names]
        entries = [self._enterable(rt, machine, n, mode, every, plan)
                   for n, plan in zip(names, plans)]
        targets = {}
        t0, t1, after, per, target, c0, nc, holds = [], [], [], [], [], [], [], []
        kind, src, lo, hi, want = [], [], [], [], []
        e0, e1, springs, eto, esteps = [], [], [], [], []
        fast = rt.period.fast.get(machine.name, {})  # (each state's period: its rows',
        periods = [fast.get(n, rt.period.base) for n in names]  # _follow_rate's)
        for name in names:
            shared = [t for t in spec.any_state.transitions
                      if rt.spec.resolve_goto(t.to, machine.name) != (machine.name, name)]
            goes = []
            for t in [*spec.states[name].transitions, *shared]:
                to = rt.spec.resolve_goto(t.to, machine.name)
                k = -1 if to is None or to[0] != machine.name else index.get(to[1], -1)
                goes.append(k if k >= 0 and entries[k] is not None else -1)
            targets[name] = goes
            t0.append(len(after))
            entry = entries[index[name]]
            for a_, cs, hold, i in state_table(plan, machine, name) if entry else ():
                after.append(a_)
                holds.append(hold)
                per.append(periods[index[name]] if cs else 1)  # (a timer: at any step)
                target.append(goes[i])
                c0.append(len(kind))
                nc.append(len(cs or ()))
                for k_, n_, l_, h_, w_ in cs or ():
                    kind.append(k_), src.append((k_, n_))
                    lo.append(l_), hi.append(h_), want.append(w_)
            t1.append(len(after))
            e0.append(len(springs))
            for joint, to in (entry[0] if entry else ()):
                springs.append(joint)
                eto.append(to)
                esteps.append(entry[1])
            e1.append(len(springs))
        keep = []

        def arr(t, values, n=None):
            a = ffi.new(f"{t}[]", values if values else (n or 1))
            keep.append(a)
            return a
        st = ffi.new("pk_states *")
        keep.append(st)
        st.max_chain, st.max_blend, st.max_trans, st.max_cond = \
            MAX_CHAINED_GOTOS, MAX_ROWS, MAX_ROWS, MAX_ROWS
        st.t0, st.t1 = arr("int", t0), arr("int", t1)
        st.r_after, st.r_period, st.r_target = arr("int", after), arr("int", per), \
            arr("int", target)
        st.r_cond0, st.r_ncond = arr("int", c0), arr("int", nc)
        st.r_hold = arr("int", holds)
        st.c_kind, st.c_a, st.c_b = arr("int", kind), arr("void *", None, len(kind)), \
            arr("void *", None, len(kind))
        st.c_lo, st.c_hi, st.c_want = arr("double", lo), arr("double", hi), arr("int", want)
        st.e0, st.e1 = arr("int", e0), arr("int", e1)
        st.e_spring = arr("void *", None, len(springs))
        st.e_to, st.e_steps = arr("double", eto), arr("int", esteps)
        st.e_every = arr("int", periods)
        st.p_target, st.b_live = arr("int", None, MAX_ROWS), arr("int", None, MAX_ROWS)
        st.max_log, st.max_val = MAX_LOG, MAX_VAL
        st.l_step, st.l_kind = arr("int", None, MAX_LOG), arr("int", None, MAX_LOG)
        st.l_arg, st.l_val0 = arr("int", None, MAX_LOG), arr("int", None, MAX_LOG)
        st.l_val = arr("double", None, MAX_VAL)
        st.fb_on = fb_on = any(plans)
        st.e_fb = poll_feed.templates(ffi, plans if fb_on else [], keep)
        uses_com = any(k in _fk.USES_COM for k in kind)
        return [names, entries, targets, st, keep, src, springs, uses_com, None, plans]

    def _seat(self, rt, made: list) -> None:
        """The conditions' links and the entries' springs of the seat of now (a
        re-seat makes new bodies)."""
        character, plan = rt.character, self.plan
        bodies, joints, servos = character.bodies, character.spec, character.servos
        st, src, springs = made[3], made[5], made[6]
        null = self.ffi.NULL
        for c, (k, name) in enumerate(src):
            pa = pb = null
            if k == _fk.JOINT:
                joint = joints.joint(name)
                pa = plan.pointer(bodies[joint.child]._body)
                pb = plan.pointer(bodies[joint.parent]._body)
            elif name is not None:
                pa = plan.pointer(bodies[name]._body)
            st.c_a[c], st.c_b[c] = pa, pb
        for e, joint in enumerate(springs):
            st.e_spring[e] = plan.pointer(servos[joint].spring._constraint)

    @staticmethod
    def usable(rt) -> bool:
        """Nothing but the machine's polls and plain travelling targets busy: asked
        before the plan is filled (a plan armed has its timers as rows)."""
        return not (not poll_feed.usable(rt) or rt.frames.held or rt._pending
                    or rt.tracker.mode != OFF
                    or rt.reaching.reaches or rt.grasping.armed or rt.buffer.unused
                    or len(rt._machine_list) != 1 or len(rt.blends.moving) > MAX_ROWS
                    or any(m[4] is not None for m in rt.blends.moving.values()))

    def arm(self, rt, machine, seq, rows: list) -> bool:
        """The loop may enter states from the plan just filled (``rows``: per plan
        transition, the machine's transition index or None): the table made for this
        binding, mode and period (its pointers for the seat), each row's state, every
        blend row travelling; False (and the plan's ``states`` NULL) when the runtime
        has other work or a row cannot be."""
        p = self.plan.plan
        p.states = self.ffi.NULL
        if seq is not None or not self.usable(rt):
            return False
        moving = rt.blends.moving
        key = (rt.roles.binding, rt.mode, machine.every)
        made = self._made.get(key)
        if made is None:
            made = self._made[key] = self._build(rt, machine, rt.mode, machine.every)
        seat = (rt.character.bodies, rt.sim.seats, rt.sim.space)
        if made[8] != seat:
            self._seat(rt, made)
            made[8] = seat
        self.names, self.entries, targets, st = made[:4]
        self.uses_com, self.plans = made[7], made[9]
        self.fb_on = fb_on = bool(st.fb_on)
        if fb_on:  # (feedback's rows follow the states: poll_feed)
            if not poll_feed.wire(rt, self.plans, st, self.names.index(machine.current)):
                return False
        elif rt.feedback.busy:
            return False
        goes = targets[machine.current]
        for k, i in enumerate(rows):
            if i is None:
                return False  # (a sequence's until, an input decided: not armed)
            st.p_target[k] = goes[i]
        self.rows = rows = list(moving)
        self.row_of = {joint: j for j, joint in enumerate(rows)}
        for j in range(len(rows)):
            st.b_live[j] = 1
        st.started = -1
        self.st = p.states = st
        return True

    def fed_back(self, rt, stop: int) -> None:
        """After a call armed with feedback's rows: ``poll_feed.fed_back``."""
        st, ffi = self.st, self.ffi
        n = st.n_log
        log = list(zip(ffi.unpack(st.l_kind, n), ffi.unpack(st.l_arg, n))) if n else ()
        poll_feed.fed_back(rt, self.plans, st, log, stop)

    def handed_back(self, rt, machine) -> bool:
        """What the call did, on the runtime in its order (see the module's doc);
        True when a state was entered. Only the last state entered is entered here:
        an earlier one leaves nothing the last does not set again (the machine's
        state, the rate, the maps: none active, none of its own), but each entry's and
        arrival's owners and travelling targets are, in order (the blend's dict)."""
        st = self.st
        n = st.n_log
        if not n:
            return False
        moving, table, ffi = rt.blends.moving, rt.owners.table, self.ffi
        rows, row_of, entries = self.rows, self.row_of, self.entries
        last, chain = None, 0
        for step, kind, arg, v in zip(ffi.unpack(st.l_step, n), ffi.unpack(st.l_kind, n),
                                      ffi.unpack(st.l_arg, n), ffi.unpack(st.l_val0, n)):
            if kind == 2:  # a state's feedback rows ran (poll_feed.fed_back)
                continue
            if kind == 0:  # an arrival (BlendController._write)
                joint = rows[arg]
                del row_of[joint]
                del moving[joint]
                del table[joint]
                continue
            chain = chain + 1 if last is not None and last[1] == step else 1
            last = arg, step  # InterfaceRuntime._enter_state, its entry's blend
            targets, steps = entries[arg]
            if not targets:
                continue
            joints = [j for j, _ in targets]
            for joint in joints:  # (owners.take)
                table.pop(joint, None)
            end = step + max(1, steps)
            forget = rt.frames.forget
            for joint, to in targets:
                forget(joint)
                moving[joint] = [st.l_val[v], to, step, end, None]
                v += 1
                if joint not in row_of:  # (the kernel's row: the first free, else new)
                    used = set(row_of.values())
                    j = next(j for j in range(len(rows) + 1) if j not in used)
                    if j == len(rows):
                        rows.append(joint)
                    rows[j] = joint
                    row_of[joint] = j
            rt.owners.claim(joints, BLEND)
        if last is None:
            return False
        rt.chained = (last[1], chain)  # (the tick at that step enters the rest)
        name = self.names[last[0]]
        machine.enter(name, last[1])
        rt._follow_rate()
        rt._refresh_active_maps()
        rt._activate(machine.spec.states[name].maps)
        return True
