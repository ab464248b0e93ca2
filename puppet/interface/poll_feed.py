"""Feedback's add maps in the states table of the kernel's loop (``poll_states``): the
states whose maps are add maps on sensors the kernel reads are entered and left there
too, their rows switched into the loop's ``pk_feedback`` (``physics.kernel_poll_feed``).

A Luxo flip's ``tucked`` and ``landed`` (the tuck loosened by the fall time left, the
arm swung against the base's tilt and spin) each cost Python's ticks: the entry, the
entry's blend arriving, the exit, and the tick after it that takes the additions back
(``Feedback.tick`` with no maps), 40-60 us each, at most 15 physics steps. Here the
table is armed with feedback busy or idle, when every active map is an add map that
``FeedbackKernel.plan`` compiles with sensors the kernel reads (no support polygon:
right after a restore that one is Python's), and a state's maps are its rows
(``e_fb``). ``Feedback`` keeps its ``base`` and ``last`` in the kernel's arrays the
while (``_in_c``: pushed here when they are the dicts'). After a call ``fed_back``
hands back the sensors' readings of each state's rows that ran, in order, and
Feedback's state as Python's ticks leave it. Without the kernel there is no plan.
"""

from __future__ import annotations


def add_only(maps) -> bool:
    """Every map an add map on sensors (``sensor.*``: Feedback's, at the control rate)."""
    return all(m.feedback and getattr(m, "combine", "set") == "add" for m in maps)


def state_plan(rt, mode, state: str):
    """The compiled add maps active in ``state`` and ``mode`` (the whole active set:
    the interface's, the mode's, the state's): None without maps, False when one is
    not the loop's to run (a device map, a sensor map that sets, a sensor read in
    Python, the support polygon), else ``FeedbackKernel.plan``'s ``Plan``."""
    fk = rt.feedback._fk
    got = rt.__dict__.get("_refreshed", {}).get((rt.roles.binding, mode, (state,)))
    if fk is None or got is None:  # (made for each mode and state: prime_maps)
        return False
    active, compiled, _ = got
    if not active:
        return None
    readers, setters, adders = compiled[1]
    if setters or not adders or not add_only(active):
        return False
    plan = fk.plan(readers, adders)
    if plan is None or plan.given or plan.support:
        return False
    return plan


def runs(feedback) -> bool:
    """Feedback busy with what the loop runs: the compiled plan of its add maps (its
    sensors the kernel's), or only additions to take back (no maps)."""
    if feedback._fk is None or feedback.setters:
        return False
    plan = feedback._plan
    if plan is None:
        return not feedback.adders
    return not plan.given and not plan.support


def usable(rt) -> bool:
    """The active maps and feedback allow the states table (``States.usable``): none,
    or add maps the loop runs."""
    return (not rt.active_maps or (rt.feedback._fk is not None and add_only(rt.active_maps))) \
        and (not rt.feedback.busy or runs(rt.feedback))


def templates(ffi, plans: list, keep: list):
    """Per state its rows as a ``pk_feedback`` (only the rows' fields; NULL: no maps)."""
    out = ffi.new("pk_feedback *[]", max(1, len(plans)))
    keep.append(out)
    for k, plan in enumerate(plans):
        if not plan:
            continue
        t = ffi.new("pk_feedback *")
        keep.append(t)
        t.n_sensors, t.kind, t.a, t.b, t.values = plan.count, plan.kind, plan.a, plan.b, \
            plan.values
        t.n_rows, t.sensor, t.clamp, t.slot = plan.n_rows, plan.sensor, plan.clamp, plan.slot
        t.x0, t.inv, t.lo, t.span, t.gain = plan.x0, plan.inv, plan.lo, plan.span, plan.gain
        out[k] = t
    return out


def wire(rt, plans: list, st, current: int) -> bool:
    """The loop's feedback ready for a call armed at state ``current``: every state's
    rows bound to the bodies of now, the kernel's arrays holding ``base`` and ``last``,
    the rows the current state's (Python's plan); False when Python's plan is another."""
    feedback = rt.feedback
    fk, plan = feedback._fk, feedback._plan
    if plan is not (plans[current] or None):
        return False
    bodies, f = rt.character.bodies, fk.f
    for p in plans:  # (links, and the centre of mass's bodies: FeedbackKernel._bind)
        if p and (p.bound is not bodies or fk._bodies is not bodies):
            fk.prepare(p)
    if fk._bodies is not bodies:  # (no state's plan prepared: the first one's bodies)
        return False
    if plan is None:
        f.n_sensors = f.n_rows = 0
        fk._plan = None
    elif fk._plan is not plan:
        fk.prepare(plan)
    f.gravity = -fk._space.gravity[1]  # (conditions._fall_time's g, as prepare's)
    if not feedback._in_c:  # (Feedback.compiled's push)
        fk.push(feedback.base, feedback.last)
        feedback._in_c = True
    st.fb_state, st.fb_ran, st.fb_at = current, 0, -1
    return True


def feed(feedback, space):
    """At each ``ready`` of a plan armed with feedback's rows: the kernel's arrays
    holding ``base`` and ``last`` (a Python tick or a snapshot may have taken them
    back into the dicts), the gravity of now; the struct."""
    fk = feedback._fk
    if not feedback._in_c:
        fk.push(feedback.base, feedback.last)
        feedback._in_c = True
    f = fk.f
    f.gravity = -space.gravity[1]
    return f


def fed_back(rt, plans: list, st, log: list, stop: int) -> None:
    """After a call: each state's rows that ran handed back (their sensors' last
    readings into the inputs, in order: kind 4 in the log, then the rows of now),
    the kernel's ``pk_feedback`` rows noted, ``Feedback`` as Python's ticks leave it
    (no maps: its dicts pulled, not busy once the additions are taken back), and an
    add made at ``stop`` before entries the kernel could not finish (Python's tick
    there does not add again: ``Feedback.done_at``)."""
    feedback = rt.feedback
    fk, inputs = feedback._fk, rt.inputs
    for kind, arg in log:
        if kind == 4 and plans[arg]:
            fk.hand_back(plans[arg], inputs)
    if st.fb_ran:
        st.fb_ran = 0
        plan = plans[st.fb_state]
        if plan:
            fk.hand_back(plan, inputs)
    fk._plan = plans[st.fb_state] or None  # (the rows pk_feedback has)
    if feedback._plan is None:
        feedback._pull()
        feedback.busy = bool(feedback.setters or feedback.adders or feedback.last)
    if st.fb_at == stop:
        feedback.done_at = stop
