"""A state's entry that puts on a pose at once, and presses kept for a state, in the
kernel's loop (``poll_states``' table; ``physics.kernel_poll_poses``).

The cat's stride (cat-bound, cat-gap) is a machine whose every entry is a ``pose:``
without ``over``: targets and gains written at once (``poses.pose_writer``). Each was
a Python tick, the plan's ``ready`` and a new ``pk_poll`` call (about 120 a replay, as
much as the rest of the cat's Python). Here such an entry becomes rows the loop
writes in ``pose_writer``'s order - each target (``SET_TARGET``), stiffness
(``SET_STIFFNESS``) and torque cap (``SET_MAX_FORCE``) - when the pose has no frame
targets and no damping (``Servo.damping`` converts for the step: Python's) and the
action does nothing else. The hand-back takes the targets' joints back from their
owners as ``run_action`` does (``owners.take``); the loop leaves to Python an entry
whose target would take a joint from a travelling blend.

A press kept for a later state (``buffer: S``) used to keep the loop from entering
states at all. The runtime asks the buffer only when a state is entered
(``_enter_state``), so with presses kept the loop may still enter any state in which
no kept chord finds a binding with a ``buffer`` (``takes_kept``; its table is made per
set of kept chords). With one press kept, the state that takes it is the loop's too
when its binding only goes to a state of the machine and writes stiffnesses and a
pose (``kept_action``; the cat's push, ctrl+a, pressed as the cat lands and acted on
as it is gathered): the loop checks the press's age as ``InputBuffer.due`` does,
enters the goto's state, writes the binding's rows and logs the press spent
(``pk_enter_kept``), which the hand-back takes out of the buffer. A press too old
for its buffer leaves the entry to Python's tick, where it stays kept.
"""

from __future__ import annotations

TARGET, STIFFNESS, MAX_FORCE = 0, 1, 2  # a row's write (pk_pose_write's codes)
# the action's parts that must be empty for its pose to be the loop's to put on
_NONE = ("over", "sequence", "repeat", "goto", "reach", "grasp", "release", "app",
         "slowdown", "gravity", "friction", "perturb", "push", "track", "kinematic")
_EMPTY = ("set", "adjust", "stiffness", "damping")


def pose_only(a, mode) -> bool:
    """An entry that only puts on a named pose at once (``mode``: the runtime's, which
    an entry may name again: ``run_action`` does nothing then)."""
    return a.pose is not None and not a.while_held and (a.mode is None or a.mode == mode) \
        and all(getattr(a, f) is None for f in _NONE) \
        and all(not getattr(a, f) for f in _EMPTY)


def pose_rows(rt, a, mode) -> list | None:
    """The rows of a pose-only entry, ``(joint, what, value)`` in ``pose_writer``'s
    order (its targets, stiffnesses, torque caps); None when it is not the loop's."""
    return named_pose(rt, a.pose) if pose_only(a, mode) else None


def named_pose(rt, name: str) -> list | None:
    """A pose's rows (``pose_rows``), or None (frame targets, damping)."""
    pose = rt.poses.get(name)
    if pose is None or pose.frames or pose.damping:
        return None
    rows = [(j, TARGET, v) for j, v in pose.targets.items()]
    rows += [(j, STIFFNESS, k) for j, k in pose.stiffness.items()]
    rows += [(j, MAX_FORCE, t) for j, t in pose.max_torque.items()]
    servos = rt.character.servos
    if any(j not in servos for j, _, _ in rows):
        return None
    return rows


def kept(rt) -> tuple:
    """The chords kept for a later state now (the states table is made per set)."""
    unused = rt.buffer.unused
    return tuple(sorted(unused)) if unused else ()


def presses(rt) -> tuple:
    """The presses kept now, with their steps (a table armed for others is stale: a
    press spent by the loop, or made again since, is not the one it holds)."""
    unused = rt.buffer.unused
    return tuple(sorted(unused.items())) if unused else ()


def _binding(rt, machine, state: str, chord: str):
    """(the binding ``chord`` finds in ``state``, its machine): ``KeyBindings.lookup``
    with one machine in ``state``."""
    bindings = rt.key_bindings
    found = bindings.state[(machine.name, state)].get(chord)
    if found is None:
        found = bindings.any[machine.name].get(chord)
    if found is not None:
        return found, machine.name
    return bindings.top.get(chord), None


def takes_kept(rt, machine, state: str, chords: tuple) -> bool:
    """A kept chord would act on entering ``state`` (``InputBuffer.due``: the binding
    it finds there has a ``buffer``; how old the press is does not matter here)."""
    for chord in chords:
        found = _binding(rt, machine, state, chord)[0]
        if found is not None and getattr(found, "buffer", None) is not None:
            return True
    return False


def kept_action(rt, machine, state: str, chords: tuple, mode):
    """The one kept chord's binding in ``state``, when the loop can run it as the
    state is entered (``_enter_state``'s ``buffer.due``, then ``run_action``): its
    ``goto`` (a state of this machine, entered first), then its stiffnesses and its
    pose, nothing else. ``(state to go to, the buffer in steps, rows)`` or None."""
    if len(chords) != 1:
        return None
    a, owner = _binding(rt, machine, state, chords[0])
    if a is None or a.buffer is None or a.goto is None or a.while_held \
            or a.mode not in (None, mode) \
            or any(getattr(a, f) is not None for f in _NONE if f != "goto") \
            or a.set or a.adjust or a.damping:
        return None
    to = rt.spec.resolve_goto(a.goto, owner)
    if to is None or to[0] != machine.name:
        return None
    rename, servos = rt.roles.rename, rt.character.servos
    rows = [(rename(j), STIFFNESS, k) for j, k in a.stiffness.items()]
    if a.pose is not None:
        pose = named_pose(rt, a.pose)
        if pose is None:
            return None
        rows += pose
    if any(j not in servos for j, _, _ in rows):
        return None
    return to[1], round(a.buffer / rt.buffer.dt), rows


def hand_back(rt, joints: tuple) -> None:
    """A pose entered by the loop, on the runtime: its targets' joints taken back
    (``owners.take``; the loop wrote the values)."""
    table = rt.owners.table
    if table:
        for joint in joints:
            table.pop(joint, None)
