"""A state's transitions (and a sequence step's ``until``) as ``pk_poll``'s rows read them.

``PollPlan`` asks here what a machine's current state polls, once per state and binding
(``plan._tables``): each transition as a timer or as conditions in the kernel's codes
(``condition_kind``: a link's contact, angle, spin or height, a joint's angle, the
centre of mass's), a device input or channel as its reader (no step changes it), a
mouse's as its ``in_val`` slot (``LIVE``); None where one cannot be read there, which
leaves the state to Python's ticks. Apart from ``poll_plan`` because reading the
interface's conditions is one idea and writing the kernel's table (``poll_fill``) and
running it (``poll_plan``) are others; ``poll_states`` and ``poll_machines`` read the
same tables.
"""

from __future__ import annotations

from puppet.interface.conditions import INPUT, compile_bounds, reader
from puppet.interface.controllers import feedback_kernel as _fk

NEVER = 1 << 62  # no timer, no arrival: a run ends at its call's end, an event or a boundary

# sensor kind -> the kernel's code (PK_S_*, kernel_control's pk_sensor): a link's
# contact, its angle within a turn, a joint's angle, a link's spin, its height; and
# the centre of mass's (COM: its place, velocity, fall time, the body's spin; com.dx
# from a link)
KINDS = {"contact": _fk.CONTACT, "angle": _fk.ANGLE, "joint": _fk.JOINT, "spin": _fk.SPIN,
         "height": _fk.HEIGHT}
COM = _fk.COM  # the centre of mass's (its position, velocity, fall time; the body's spin)
OFFLINE = ("channel.", INPUT)  # sensors no step changes: read once, when the plan is made
# a device input a mouse move sets, read by pk_poll's conditions from the plan's in_val
# (PK_S_INPUT + its slot): written at each ``ready``, and by the kernel's event runs
LIVE_INPUT = 100
LIVE = {"mouse.x": 0, "mouse.y": 1, "pointer.x": 2, "pointer.y": 3}


def condition_kind(sensor: str, root: str) -> tuple[int, str] | None:
    """(pk_poll's code, the link or joint) for a sensor ``pk_poll`` reads, else None."""
    if sensor == "root.angle":
        return KINDS["angle"], root
    if sensor in COM:
        return COM[sensor], None
    if sensor.startswith("com.dx."):  # from a link (the support polygon: Python's)
        name = sensor[len("com.dx."):]
        return None if name == "support" or "." in name else (_fk.COM_DX, name)
    kind, _, name = sensor.partition(".")
    if kind in KINDS and name and "." not in name:
        return KINDS[kind], name
    return None


def state_table(plan, machine, current: str | None = None):
    """The current state's transitions as ``pk_poll`` can poll them, in ``due``'s
    order: ``(after, None, 0, index)`` a timer, ``(after, conditions, for, index)``
    a polled one (``for`` in steps, 0 without; ``index``: the machine's), each
    condition ``(code or None, name or reader, lo, hi, want)`` (``None``: a device
    input or channel, its reader); None when one cannot be polled there."""
    rt = plan.runtime
    current = machine.current if current is None else current  # (prime: each state)
    key = (machine.name, current, rt.role_binding)
    if key in plan._tables:
        return plan._tables[key]
    rename = rt.roles.sensor
    spec, name = machine.spec, machine.name
    state = spec.states[current]
    shared = [t for t in spec.any_state.transitions
              if rt.spec.resolve_goto(t.to, name) != (name, current)]
    table = []
    for index, t in enumerate([*state.transitions, *shared]):
        after = round((t.after or 0.0) / machine.dt)
        if not t.conditions:
            table.append((after, None, 0, index))
            continue
        hold = round((t.held or 0.0) / machine.dt)  # (StateMachine._hold_steps)
        if hold and any(rename(c.sensor).startswith(OFFLINE) for c in t.conditions):
            table = None  # (a `for` left out when an input rules it out: Python's)
            break
        conditions = polled_conditions(plan, t.conditions)
        if conditions is None:
            table = None
            break
        table.append((after, conditions, hold, index))
    plan._tables[key] = table
    return table

def polled_conditions(plan, conditions) -> list | None:
    """A transition's or an ``until``'s conditions as ``pk_poll`` reads them:
    ``(code or None, name or reader, lo, hi, want)``; None if one cannot be."""
    rt = plan.runtime
    rename, root = rt.roles.sensor, rt.character.spec.root
    out = []
    for c in conditions:
        sensor = rename(c.sensor)
        bounds = compile_bounds(c)
        lo, hi = bounds if bounds is not None else (0.0, 0.0)
        want = -1 if bounds is not None else int(bool(c.is_))
        if sensor.startswith(OFFLINE):
            slot = LIVE.get(sensor[len(INPUT):]) if sensor.startswith(INPUT) else None
            if slot is not None and (slot < 2 or rt._pointer):  # (pointer: the mouse's)
                out.append((LIVE_INPUT + slot, None, lo, hi, want))
                continue
            out.append((None, reader(sensor, rt.character, rt.channels, rt.inputs),
                        lo, hi, want))
            continue
        kind = condition_kind(sensor, root)
        if kind is None or (kind[0] == _fk.COM_DX and kind[1] not in rt.character.bodies):
            return None  # (a name no link has: Python's reader says so)
        out.append((*kind, lo, hi, want))
    return out

def sequence_until(plan, name: str, index: int):
    """A sequence step's ``until`` (``compile_untils``): (after in steps, its
    conditions), None without one, False when ``pk_poll`` cannot read it."""
    key = ("sequence", name, index, plan.runtime.roles.binding)
    if key not in plan._tables:
        spec = plan.runtime.sequences.specs[name][index]
        found = None
        if spec.until is not None:
            conditions = polled_conditions(plan, spec.conditions)
            found = False if conditions is None else \
                (round((spec.after or 0.0) / plan.runtime.dt), conditions)
        plan._tables[key] = found
    return plan._tables[key]
