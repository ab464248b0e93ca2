"""State transitions inside the kernel's loop: the poll plan's states table
(``physics.kernel_poll_states``) and the hand-back of what a call entered.

``poll_fill.fill`` arms it (``arm``) when the runtime's work between ticks is one
machine's polls and plain travelling targets, nothing else busy (no device maps
active, no sequence, frame targets, reach or grasp; sensor add maps the kernel runs
may be: ``poll_feed``). Then a transition into a state the loop can enter - its table
the kernel's with no device input decided when filled (a `for` kept in the plan's
rows, its start handed back), no roles, no maps but sensor add maps (their rows
switched with it: ``poll_feed``), its own control rate the loop's too, its entry
nothing, a ``set`` of plain angles with ``over`` or a pose put on at once
(``poll_poses``), no press kept that acts there but one ``poll_poses`` runs - is taken
in the loop, with the states chained after it and the targets' arrivals; any other
ends the call for Python's tick, as a timer does. After the call
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
from puppet.interface.poll_poses import hand_back, kept, kept_action, pose_rows, presses, takes_kept
from puppet.interface.poll_table import state_table
from puppet.physics.kernel_poll_poses import setters

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
        self.poses: list = []  # per state: its pose's target joints (poll_poses) or ()
        self.kept: tuple = ()  # the kept chords the table armed last was made for
        self.presses: tuple = ()  # and the presses kept then, with their steps
        self.spent: list = []  # per state: the targets a kept press's pose takes, or None
        self.held: list = []  # per state: its rows with a `for` (row, transition index)
        self.plans: list = []  # per state: its add maps' Plan, None, False (poll_feed)
        self.fb_on = False  # the armed table switches feedback's rows (poll_feed)

    def _enterable(self, rt, machine, name: str, mode, every: int, plan,
                   chords: tuple = ()):
        """``(targets, steps)`` of a state the loop can enter (its entry's blend; a
        pose put on at once: none, ``poll_poses``), else None, in ``mode`` at the
        period ``every`` (``plan``: its add maps', poll_feed), with ``chords`` kept
        for a later state."""
        spec = machine.spec.states[name]
        table = state_table(self.plan, machine, name)
        if table is None or spec.roles is not None or plan is False \
                or (chords and takes_kept(rt, machine, name, chords)
                    and kept_action(rt, machine, name, chords, mode) is None):
            return None  # (a press kept that acts here: poll_poses, when the loop's)
        if any(cs and any(c[0] is None for c in cs) for _, cs, *_ in table):
            return None
        a = spec.enter
        if a is None or (a.set == {} and blend_only(a, mode)):
            return [], 1
        if not blend_only(a, mode):
            return ([], 1) if pose_rows(rt, a, mode) is not None else None
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
                for chords in ((), *((c,) for c in sorted(rt.buffer.keys))):
                    key = (rt.roles.binding, mode, every, chords)
                    if key not in self._made:
                        self._made[key] = self._build(rt, machine, mode, every, chords)

    def _build(self, rt, machine, mode, every: int, chords: tuple = ()) -> tuple:
        """The table for the binding, mode, period and kept chords of now: (the
        states' names, their entries, per state its transitions' states, the struct,
        what its conditions and entries point at, whether one reads the centre of
        mass, the seat, the pose rows' joints, per state its pose's target joints)."""
        ffi, plan, spec = self.ffi, self.plan, machine.spec
        names = list(spec.states)
        index = {n: k for k, n in enumerate(names)}
        plans = [poll_feed.state_plan(rt, mode, n) if rt.feedback._fk is not None
                 else None if not spec.states[n].maps else False for n in names]
        entries = [self._enterable(rt, machine, n, mode, every, plan, chords)
                   for n, plan in zip(names, plans)]
        poses = [pose_rows(rt, spec.states[n].enter, mode)
                 if e is not None and spec.states[n].enter is not None else None
                 for n, e in zip(names, entries)]
        acts = [None] * len(names)  # per state: a kept press it acts on (poll_poses)
        for b, name in enumerate(names):
            act = entries[b] and chords and kept_action(rt, machine, name, chords, mode)
            if act:  # (its goto's state entered with a pose or nothing; this one too)
                g = index.get(act[0], -1)
                if g < 0 or entries[g] is None or entries[g][0] or entries[b][0] \
                        or takes_kept(rt, machine, act[0], chords):
                    entries[b] = None
                else:
                    acts[b] = (g, *act[1:])
        targets = {}
        t0, t1, after, per, target, c0, nc, holds = [], [], [], [], [], [], [], []
        kind, src, lo, hi, want = [], [], [], [], []
        e0, e1, springs, eto, esteps = [], [], [], [], []
        w0, w1, wjoints, what, wvalue = [], [], [], [], []
        k_goto, k_window = [], []
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
            for a_, cs, hold_, i in state_table(plan, machine, name) if entry else ():
                after.append(a_)
                holds.append(hold_)
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
            w0.append(len(wjoints))
            for joint, w, value in poses[index[name]] or ():
                wjoints.append(joint), what.append(w), wvalue.append(value)
            w1.append(len(wjoints))
        for act in acts:  # (the kept presses' writes: rows n + b)
            w0.append(len(wjoints))
            for joint, w, value in act[2] if act else ():
                wjoints.append(joint), what.append(w), wvalue.append(value)
            w1.append(len(wjoints))
            k_goto.append(act[0] if act else -1)
            k_window.append(act[1] if act else 0)
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
        st.w0, st.w1 = arr("int", w0), arr("int", w1)
        st.w_spring, st.w_what = arr("void *", None, len(wjoints)), arr("int", what)
        st.w_value = arr("double", wvalue)
        st.f_stiffness, st.f_max_force = setters(plan.kernel)
        st.n_state = len(names)
        st.k_goto, st.k_window = arr("int", k_goto), arr("int", k_window)
        st.fb_on = fb_on = any(plans)
        st.e_fb = poll_feed.templates(ffi, plans if fb_on else [], keep)
        uses_com = any(k in _fk.USES_COM for k in kind)
        targets_of = [tuple(j for j, w, _ in rows if w == 0) if rows else () for rows in poses]
        spent = [tuple(j for j, w, _ in act[2] if w == 0) if act else None for act in acts]
        held = [[(k, i) for k, (_, _, h, i) in enumerate(state_table(plan, machine, n) or ())
                 if h] for n in names]
        return [names, entries, targets, st, keep, src, springs, uses_com, None, wjoints,
                targets_of, spent, held, plans]

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
        for w, joint in enumerate(made[9]):
            st.w_spring[w] = plan.pointer(servos[joint].spring._constraint)

    @staticmethod
    def usable(rt) -> bool:
        """Nothing but the machine's polls and plain travelling targets busy: asked
        before the plan is filled (a plan armed has its timers as rows)."""
        return not (not poll_feed.usable(rt) or rt.frames.held or rt._pending
                    or rt.tracker.mode != OFF
                    or rt.reaching.reaches or rt.grasping.armed
                    or len(rt._machine_list) != 1 or len(rt.blends.moving) > MAX_ROWS
                    or any(m[4] is not None for m in rt.blends.moving.values()))

    def held_rows(self) -> list:
        """The `for`s of the state the last call entered: (plan row, transition index)
        (``pk_enter`` writes a state's rows in its table's order)."""
        return self.held[self.names.index(self.plan.machine.current)]

    def stale(self, rt):
        """The table armed last is not the one to use now (other work; other presses
        kept: ``poll_poses``): what differs, so that ``ready``'s key tells one such
        moment from the next; False when it is the one."""
        now = presses(rt)
        if self.usable(rt) and now == self.presses:
            return False
        return self.usable(rt), now

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
        chords = kept(rt)
        key = (rt.roles.binding, rt.mode, machine.every, chords)
        made = self._made.get(key)
        if made is None:
            made = self._made[key] = self._build(rt, machine, rt.mode, machine.every, chords)
        seat = (rt.character.bodies, rt.sim.seats, rt.sim.space)
        if made[8] != seat:
            self._seat(rt, made)
            made[8] = seat
        self.names, self.entries, targets, st = made[:4]
        self.uses_com, self.poses, self.kept = made[7], made[10], chords
        self.spent, self.held, self.presses = made[11], made[12], presses(rt)
        st.kept_live = bool(chords)  # (the press's step: InputBuffer.due's age)
        st.kept_at = rt.buffer.unused[chords[0]] if chords else 0
        self.plans = made[13]
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
            if kind == 4:  # a state's feedback rows ran (poll_feed.fed_back)
                continue
            if kind == 0:  # an arrival (BlendController._write)
                joint = rows[arg]
                del row_of[joint]
                del moving[joint]
                del table[joint]
                continue
            if kind == 2:  # a kept press spent as state arg was entered (poll_poses:
                rt.buffer.unused.pop(self.kept[0], None)  # InputBuffer.due, run_action)
                hand_back(rt, self.spent[arg])
                continue
            if kind == 1:  # (3: its binding's goto, not one of the tick's chain)
                chain = chain + 1 if last is not None and last[1] == step else 1
            last = arg, step  # InterfaceRuntime._enter_state, its entry's blend
            targets, steps = entries[arg]
            if self.poses[arg]:  # (a pose put on: poll_poses)
                hand_back(rt, self.poses[arg])
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
