"""Running reaches in ``pk_poll``'s table (``ReachController.tick`` at every step).

A reach ticks at every step while it runs (``ReachController.next_wakeup``): its aim,
its two-link solve and its writes, and for one that grasps on arrival, ``try_grasp``'s
test. With the kernel those are already two compiled calls a step (``pk_reach_aim``,
``pk_reach_set``), but the step still went through Python's tick. Here the reaches
the kernel can run are written into the plan (``pk_poll_plan``'s ``r_*`` rows), and
``pk_poll`` does them at every step after the state's polls, before a blend's, frame
targets' and feedback's writes (the runtime's controllers' order). It stops for
Python's tick where a reach's end comes (``until``) and at a step where a grasping
reach's end is within its tolerance of its goal, or nearly (Python's tick there makes
the grasp, or finds it does not; nothing the kernel wrote at that step).
What stays Python's: a steered target, a chain of other than two links, more than
``MAX_REACHES`` reaches, a reach that owns neither joint (its tick ends it).
"""

from __future__ import annotations

MAX_REACHES = 4  # (pk_poll_plan's r_* arrays)


def fill_reaches(plan, rt, never: int) -> int | None:
    """Write the runtime's running reaches into ``plan``'s table (``PollPlan``): the
    step the first one ends at (``never``: none ends), or None when one is not the
    kernel's to run."""
    reaching = rt.reaching
    p = plan.plan
    reaches = reaching.reaches
    if not reaches:
        p.n_reach = 0
        return never
    if len(reaches) > MAX_REACHES or reaching._pk is None:
        return None
    rows = reaching._plan
    bodies = rt.character.bodies
    if rows is None or rows[0] is not bodies:
        rows = reaching._plan = reaching._planned()
    if rows[1] is None:  # a chain of other than two links
        return None
    table, sim, chains = rt.owners.table, rt.sim, reaching.chains
    pointer, null = plan.pointer, reaching._pk[2]  # (the kernel's NULL: a world point)
    until = never
    for j, (name, reach, owner, j0, j1, start, args, params, spring0, spring1) in \
            enumerate(rows[1]):
        if args is None:  # a steered target: its point read at each step (Python's)
            return None
        own0, own1 = table.get(j0) == owner, table.get(j1) == owner
        if not (own0 or own1):
            return None
        parent, ax, ay, goal, gx, gy, p0x, p0y, steps, _ = args
        p.r_parent[j] = pointer(parent)
        p.r_goal[j] = null if goal is null else pointer(goal)
        p.r_ax[j], p.r_ay[j], p.r_gx[j], p.r_gy[j] = ax, ay, gx, gy
        p.r_p0x[j], p.r_p0y[j], p.r_steps[j], p.r_start[j] = p0x, p0y, steps, start
        p.r_params[j] = params
        p.r_spring0[j] = pointer(spring0) if own0 else null
        p.r_spring1[j], p.r_own1[j] = pointer(spring1), own1
        if reach.grasp and sim is not None and name not in sim.grasps:
            chain = chains[name]
            p.r_end[j] = pointer(bodies[chain.end_link]._body)
            p.r_ex[j], p.r_ey[j] = chain.end
            p.r_tol[j] = reach.tolerance
        else:
            p.r_end[j] = null
        end = reach.end
        if end is not None and end < until:
            until = end
    p.n_reach = len(rows[1])
    return until


MAX_PLACES = 64  # (pk_poll_plan's a_p* and a_s* arrays)


def fill_grasps(plan, rt, never: int) -> int | None:
    """Write the runtime's armed grasps into ``plan``'s table: each chain's end, its
    tolerance, where it let go (``skip_released``) and its places in the world (its
    points, or its static props' points and segments: ``Prop._placed``'s, which stay
    while the prop stands); the step the first one runs out at (``never``: none), or
    None when one is not the kernel's to try (a chain that holds already, whose tick
    disarms it at once; a dynamic prop; too many)."""
    grasping = rt.grasping
    p = plan.plan
    armed = grasping.armed
    if not armed:
        p.n_armed = 0
        return never
    sim = rt.sim
    if sim is None or len(armed) > MAX_REACHES:
        return None
    bodies, props, held = rt.character.bodies, sim.props, sim.grasps
    # what the table is made of: the armed grasps (a new list each arm), the chains
    # that hold, where each let go, the bodies and the seat (a re-seat or a restore
    # makes new ones; a static prop stands still between them)
    key = (bodies, sim.space, sim.seats, tuple((n, id(a)) for n, a in armed.items()),
           tuple(held), tuple(grasping.released.items()))
    kept = plan.__dict__.get("_grasps_kept")
    if kept is not None and kept[0] == key and kept[2] is armed:
        p.n_armed = len(armed)
        return kept[1]
    plan._grasps_kept = None
    until = never
    n_p = n_s = 0
    for j, (name, (points, prop, tolerance, ends, _, _, skip)) in enumerate(armed.items()):
        if name in held:
            return None
        chain = grasping.chains[name]
        p.a_end[j] = plan.pointer(bodies[chain.end_link]._body)
        p.a_ex[j], p.a_ey[j] = chain.end
        p.a_tol[j] = tolerance
        skip = grasping.released_point(name) if skip else None
        p.a_skip[j] = skip is not None
        if skip is not None:
            p.a_sx[j], p.a_sy[j] = skip
        p.a_p0[j], p.a_s0[j] = n_p, n_s
        if points is not None:
            places, segments = [(None, x, y) for x, y in points], []
        else:
            places, segments = [], []
            for name_ in (props if prop == "any" else [prop]):
                got = props.get(name_)
                if got is None or not got._static():
                    return None
                here = got._placed()
                places += here[0]
                segments += here[1]
        if n_p + len(places) > MAX_PLACES or n_s + len(segments) > MAX_PLACES:
            return None
        for _, x, y in places:
            p.a_px[n_p], p.a_py[n_p] = x, y
            n_p += 1
        for ax, ay, vx, vy, vv in segments:
            p.a_sax[n_s], p.a_say[n_s], p.a_svx[n_s], p.a_svy[n_s], p.a_svv[n_s] = \
                ax, ay, vx, vy, vv
            n_s += 1
        p.a_p1[j], p.a_s1[j] = n_p, n_s
        if ends is not None and ends < until:
            until = ends
    p.n_armed = len(armed)
    plan._grasps_kept = (key, until, armed, tuple(armed.values()))  # (the lists kept
    # alive: their ids are not taken by new ones)
    return until
