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
