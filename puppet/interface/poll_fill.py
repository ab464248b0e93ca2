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
    k = i = 0
    entered = machine.entered
    plan._held = held = []  # (the plan's transition, the machine's) with a `for`
    plan._frame_rows = None
    uses_com = plan._inputs = False
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
    for after, conditions, hold, index, *period in table:
        first = entered + after
        if conditions is None and states and k < MAX_CONDITIONS:  # a timer: a row
            p.first[k], p.cond0[k], p.n_cond[k], p.hold[k], p.period[k] = first, i, 0, 0, 1
            rows.append(index)
            k += 1
            continue
        if conditions is None:  # a timer: Python's tick fires it
            until = first if first < until else until
            continue
        if machine.quiet and not plan._live:  # (a device-only state between input
            continue  # events: no polls; the mouse's alone: the kernel's, see waits)
        c0 = i
        for kind, name, lo, hi, want in conditions:
            if kind is None:  # no step changes it: decided now
                value = name()
                if not (lo < value < hi if want < 0 else (value > 0.5) == bool(want)):
                    break
                continue
            if i >= MAX_CONDITIONS:
                return None
            if kind == _fk.JOINT:
                joint = joints.joint(name)
                p.body_a[i] = plan.pointer(bodies[joint.child]._body)
                p.body_b[i] = plan.pointer(bodies[joint.parent]._body)
            elif name is not None:
                p.body_a[i] = plan.pointer(bodies[name]._body)
            uses_com = uses_com or kind in _fk.USES_COM
            if kind in VELOCITY:  # (1: a machine's, 2: a sequence's until's)
                moves |= 2 if index == -1 else 1
            plan._inputs = plan._inputs or kind >= LIVE_INPUT
            p.kind[i], p.lo[i], p.hi[i], p.want[i] = kind, lo, hi, want
            i += 1
        else:
            if k >= MAX_CONDITIONS:
                return None
            p.first[k], p.cond0[k], p.n_cond[k], p.hold[k] = first, c0, i - c0, hold
            p.period[k] = period[0] if period else every
            if hold:
                held.append((k, index))
            if states:
                rows.append(index if index >= 0 else None)
            k += 1
            continue
        i = c0  # an input condition that does not hold: the transition cannot fire
    p.n_trans = k
    n, servos, null = 0, character.servos, plan.ffi.NULL
    plan._travelling = travelling = {}  # joint -> its travel (a frame target's)
    for joint, (start, to, first, last, target) in rt.blends.moving.items():
        if n >= MAX_CONDITIONS:
            return None
        if target is None:
            p.spring[n] = plan.pointer(servos[joint].spring._constraint)
        else:  # (its angle: the frame loop's)
            p.spring[n] = null
            travelling[joint] = n
        p.start[n], p.to[n], p.b_first[n], p.b_last[n] = start, to, first, last
        until = last if last < until and not states else until  # (the loop's, armed)
        n += 1
    p.n_blend, p.every = n, every
    n, frame_joints, frame_rows = 0, rt.frames.joints, []
    for joint, (target, _) in rt.frames.held.items():  # (FrameTargets.tick's order)
        if n >= MAX_CONDITIONS:
            return None
        spec, ref = frame_joints[joint], target.ref
        frame_rows.append((joint, ref, target.hold_parent))
        p.f_parent[n] = plan.pointer(bodies[spec.parent]._body)
        p.f_child[n] = plan.pointer(bodies[spec.child]._body)
        p.f_ref[n] = null if ref is None else plan.pointer(bodies[ref]._body)
        p.f_spring[n] = plan.pointer(servos[joint].spring._constraint)
        p.f_angle[n], p.f_hold_parent[n] = target.angle, target.hold_parent
        p.f_blend[n] = travelling.get(joint, -1)
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
