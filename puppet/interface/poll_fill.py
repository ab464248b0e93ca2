"""Writing a machine's rows into the ``pk_poll`` table (``PollPlan``'s fill).

``PollPlan.ready`` decides whether the work due is the kernel's and fills the plan
again only when what it holds changed; ``fill`` is that write: the state's polled
transitions (``poll_table``'s rows, those an input rules out left out, a running
sequence step's ``until`` first), the blend's travelling targets, the held frame
targets, the states table armed (``poll_states``) and the centre of mass's arguments;
``held_again`` rewrites only the held frame targets' angles. Apart from ``poll_plan``
so that the plan's deciding and running read apart from the row-by-row writing.
"""

from __future__ import annotations

from puppet.interface.controllers import feedback_kernel as _fk
from puppet.interface.poll_states import States
from puppet.interface.poll_table import LIVE_INPUT, NEVER, sequence_until
from puppet.interface.poll_track import VELOCITY

MAX_CONDITIONS = 32  # the plan's arrays (transitions, conditions, blends, frame targets)


def held_again(plan, held: dict) -> bool:
    """The same joints held in the same frames, at new angles: written into the
    plan's rows (False: held otherwise, the plan must be filled again)."""
    rows = plan._frame_rows
    if rows is None or len(rows) != len(held):
        return False
    angle = plan.plan.f_angle
    for n, ((joint, (target, _)), (was, ref, hold_parent)) in enumerate(zip(held.items(),
                                                                             rows)):
        if joint != was or target.ref != ref or target.hold_parent != hold_parent:
            return False
        angle[n] = target.angle
    return True

_ARRAYS = ("first", "period", "hold", "since", "cond0", "n_cond", "kind", "want", "lo", "hi",
           "body_a", "body_b", "spring", "start", "to", "b_first", "b_last", "f_parent",
           "f_child", "f_ref", "f_spring", "f_angle", "f_hold_parent", "f_blend")


def _arrays(plan) -> tuple:
    """The plan's row arrays, each looked up once (``p.first`` makes a new cdata at each
    read; an entry's fill writes some sixty rows: the walkers fill at every state)."""
    got = plan.__dict__.get("_fill_arrays")
    if got is None:
        p = plan.plan
        got = plan._fill_arrays = tuple(getattr(p, name) for name in _ARRAYS)
    return got


def _pointers(plan, bodies) -> dict:
    """The kernel's pointers of the bodies and springs the rows name, per binding of
    the bodies (a re-seat makes new ones): (condition kind, name) and (joint, ref)
    -> their pointers, made at a first fill."""
    got = plan.__dict__.get("_fill_pointers")
    if got is None or got[0] is not bodies:
        got = plan._fill_pointers = (bodies, {})
    return got[1]


def fill(plan, table, machine, every: int, seq, states: bool = True) -> int | None:
    """Write the plan: the state's polled transitions (those an input rules out
    left out), the blend's travelling targets; the step a timer or an arrival is
    due (NEVER: none), or None when there is nothing to do or it does not fit.
    ``states``: the loop may take transitions and arrivals (``poll_states``: the
    timers are rows then, the arrivals the loop's; armed if all else fits)."""
    rt = plan.runtime
    p, until = plan.plan, NEVER
    p.states, plan._armed, rows = plan.ffi.NULL, False, []
    states = states and seq is None and not plan._many and not any(
        c[0] is None for _, cs, *_ in table if cs for c in cs) and States.usable(rt)
    character = rt.character
    bodies, joints = character.bodies, character.spec
    (a_first, a_period, a_hold, _, a_cond0, a_ncond, a_kind, a_want, a_lo, a_hi, a_body_a,
     a_body_b, a_spring, a_start, a_to, a_bfirst, a_blast, a_fparent, a_fchild, a_fref,
     a_fspring, a_fangle, a_fhold, a_fblend) = _arrays(plan)
    pointers = _pointers(plan, bodies)
    k = i = 0
    entered = machine.entered
    plan._held = held = []  # (the plan's transition, the machine's) with a `for`
    plan._frame_rows = None
    uses_com = inputs = plan._inputs = False
    moves = 0
    if seq is not None:  # a running sequence: its step's end, its ``until``
        name, step_index, ends, began, _ = seq
        found = sequence_until(plan, name, step_index)
        if found is False:
            return None
        until = ends  # (the next step's pose: Python's tick)
        if found is not None:
            plan._offline = plan._offline or any(c[0] is None for c in found[1])
            table = [((began or 0) + found[0] - entered, found[1], 0, -1, 1), *table]
    quiet = machine.quiet and not plan._live
    for after, conditions, hold, index, *period in table:
        first = entered + after
        if conditions is None and states and k < MAX_CONDITIONS:  # a timer: a row
            a_first[k], a_cond0[k], a_ncond[k], a_hold[k], a_period[k] = first, i, 0, 0, 1
            rows.append(index)
            k += 1
            continue
        if conditions is None:  # a timer: Python's tick fires it
            until = first if first < until else until
            continue
        if quiet:  # (a device-only state between input events: no polls; the
            continue  # mouse's alone: the kernel's, see waits)
        c0 = i
        for kind, name, lo, hi, want in conditions:
            if kind is None:  # no step changes it: decided now
                value = name()
                if not (lo < value < hi if want < 0 else (value > 0.5) == bool(want)):
                    break
                continue
            if i >= MAX_CONDITIONS:
                plan._inputs = inputs
                return None
            if kind == _fk.JOINT:
                got = pointers.get((kind, name))
                if got is None:
                    joint = joints.joint(name)
                    got = pointers[(kind, name)] = (plan.pointer(bodies[joint.child]._body),
                                                    plan.pointer(bodies[joint.parent]._body))
                a_body_a[i], a_body_b[i] = got
            elif name is not None:
                got = pointers.get(name)
                if got is None:
                    got = pointers[name] = plan.pointer(bodies[name]._body)
                a_body_a[i] = got
            uses_com = uses_com or kind in _fk.USES_COM
            if kind in VELOCITY:  # (1: a machine's, 2: a sequence's until's)
                moves |= 2 if index == -1 else 1
            inputs = inputs or kind >= LIVE_INPUT
            a_kind[i], a_lo[i], a_hi[i], a_want[i] = kind, lo, hi, want
            i += 1
        else:
            if k >= MAX_CONDITIONS:
                plan._inputs = inputs
                return None
            a_first[k], a_cond0[k], a_ncond[k], a_hold[k] = first, c0, i - c0, hold
            a_period[k] = period[0] if period else every
            if hold:
                held.append((k, index))
            if states:
                rows.append(index if index >= 0 else None)
            k += 1
            continue
        i = c0  # an input condition that does not hold: the transition cannot fire
    plan._inputs = inputs
    p.n_trans = k
    n, servos, null = 0, character.servos, plan.ffi.NULL
    plan._travelling = travelling = {}  # joint -> its travel (a frame target's)
    for joint, (start, to, first, last, target) in rt.blends.moving.items():
        if n >= MAX_CONDITIONS:
            return None
        if target is None:
            a_spring[n] = plan.pointer(servos[joint].spring._constraint)
        else:  # (its angle: the frame loop's)
            a_spring[n] = null
            travelling[joint] = n
        a_start[n], a_to[n], a_bfirst[n], a_blast[n] = start, to, first, last
        until = last if last < until and not states else until  # (the loop's, armed)
        n += 1
    p.n_blend, p.every = n, every
    n, frame_joints, frame_rows = 0, rt.frames.joints, []
    for joint, (target, _) in rt.frames.held.items():  # (FrameTargets.tick's order)
        if n >= MAX_CONDITIONS:
            return None
        ref = target.ref
        frame_rows.append((joint, ref, target.hold_parent))
        got = pointers.get((joint, ref))
        if got is None:  # (parent, child, ref, spring)
            spec = frame_joints[joint]
            got = pointers[(joint, ref)] = (
                plan.pointer(bodies[spec.parent]._body), plan.pointer(bodies[spec.child]._body),
                null if ref is None else plan.pointer(bodies[ref]._body),
                plan.pointer(servos[joint].spring._constraint))
        a_fparent[n], a_fchild[n], a_fref[n], a_fspring[n] = got
        a_fangle[n], a_fhold[n] = target.angle, target.hold_parent
        a_fblend[n] = travelling.get(joint, -1)
        n += 1
    p.n_frame, plan._frame_rows = n, frame_rows
    if states:
        if not plan._states.arm(rt, machine, seq, rows):
            return fill(plan, table, machine, every, seq, False)
        plan._armed = True
        uses_com = uses_com or plan._states.uses_com
    if uses_com:  # Character._com_kernel's arguments, for these bodies
        args = plan._com_args = character._com_bound(plan.kernel)[2]  # (kept alive)
        p.com_bodies, p.com_mass, p.com_gx, p.com_gy, p.com_n, p.com_total = args[:6]
    plan._velocity = moves
    plan._com = uses_com  # (nothing to do between the steps: the loop steps on, and
    return until  # goes on after an input event, which Python's would tick at)
