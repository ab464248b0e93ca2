"""Several state machines in one ``pk_poll`` table (``PollPlan`` with more than one).

``pk_poll`` stops at the first step where any polled transition holds, and Python's
tick there runs every machine's ``due`` in its order, so the machines' transitions
can stand in one table: each machine's current state's rows (``poll_table.state_table``),
machine after machine, their first steps counted from the first machine's entry (the
plan's fill, ``poll_fill``, adds that back), a ``for``'s index as (the machine's place, its
index). Only when every machine polls at the same period, none is device-only (a
quiet machine's polls are the one-machine plan's) and every state's table is the
kernel's; else Python's ticks, as before.
"""

from __future__ import annotations

from puppet.interface.poll_table import state_table


def joint_table(plan) -> list | None:
    """The machines' current states' transitions as one table (kept while no machine
    moves: the same list, so the plan is not filled again), or None."""
    rt = plan.runtime
    machines = rt._machine_list
    key = (tuple((m.current, m.entered, m.every) for m in machines), rt.roles.binding)
    if key == plan._joint_key:
        return plan._joint
    first, rows = machines[0], []
    for n, m in enumerate(machines):
        table = None if m.device_only or m.every != first.every else state_table(plan, m)
        if table is None:
            rows = None
            break
        shift = m.entered - first.entered
        rows.extend((shift + after, conditions, hold, (n, index))
                    for after, conditions, hold, index in table)
    plan._joint_key, plan._joint = key, rows
    return rows


def since_into(plan) -> None:
    """The `for`s' starts, as each machine has them now, into the plan."""
    machines, since = plan.runtime._machine_list, plan.plan.since
    for k, (n, index) in plan._held:
        since[k] = machines[n]._since.get(index, -1)


def since_back(plan) -> None:
    """The `for`s' starts the run leaves, handed back to their machines."""
    machines, since = plan.runtime._machine_list, plan.plan.since
    back: dict = {}
    for k, (n, index) in plan._held:
        got = back.setdefault(n, {})
        if since[k] >= 0:
            got[index] = since[k]
    for n, got in back.items():
        machines[n]._since = got


def quiet_now(machine, step: int) -> bool:
    """A state polling device inputs alone, stirred by an input event, polls them at
    ``step`` (a tick is due there, this one or Python's: ``PollPlan.ready``): when none
    holds, it is quiet until the next event (what ``StateMachine.due`` finds and sets;
    no step changes an input)."""
    since = step - machine.entered
    if step % machine.every or since < machine._polled:
        return False
    for _, after, read, test, lo, hi in machine._transitions:
        if since < after:
            continue
        if read is None or ((lo < read() < hi) if test is None else test(read())):
            return False  # a timer due, or a transition fires: Python's tick
    machine.quiet = True
    return True
