"""A load-time warning for a world-frame hold that cannot hold: the joint holds one of
its links at an angle in the world by turning against the links on its other side, and
when that other side is light and free (off the ground) it is the one that turns.

A servo's torque acts on both sides of the joint alike; each side turns in inverse
proportion to its moment of inertia about the hinge. Holding the pelvis upright
through the stance hip works because the thigh below it stands on the foot; holding a
kangaroo's body through its tail, held in the air, turns the tail. So, in the pose the
interface starts in: if the side the hold pushes against touches nothing (no link of it
at the floor) and its moment about the hinge is less than the held side's, say so,
once per hold, at its place in the file (``file:line:col: warning: ...``). A hold that
acts later (a key's pose) is judged so only when that side is a single link: a limb
may have its hand or foot on the ground by then (a handstand's arms), a tail or a head
never carries the body.
"""

from __future__ import annotations

import math
from collections.abc import Iterator

import pymunk

from puppet.data.actions import FrameTargetSpec
from puppet.data.characters import CharacterSpec
from puppet.physics.character import Character
from puppet.physics.kinematics import beyond

GROUNDED = 0.01  # m: a link whose lowest point is this close to the body's lowest touches


def frame_holds(spec) -> Iterator[tuple[tuple, str, str]]:
    """(location, joint or role, 'child' or 'parent') of every target in the world frame:
    the poses', the actions' ``set``s and the maps' with ``frame: world``."""
    from puppet.data.interface_refs import actions, all_maps

    for name, pose in spec.poses.items():
        for joint, target in pose.joints.items():
            if isinstance(target, FrameTargetSpec) and target.world is not None:
                yield ("poses", name, "joints", joint), joint, target.hold
    for loc, action in actions(spec):
        for joint, target in action.set.items():
            if isinstance(target, FrameTargetSpec) and target.world is not None:
                yield loc + ("set", joint), joint, target.hold
    for loc, m in all_maps(spec):
        if getattr(m, "frame", "joint") == "world":
            for joint in m.gains():
                yield loc + (("joint",) if m.joint is not None else ("joints", joint)), \
                    joint, m.hold


def _moment(character: Character, links, about) -> float:
    """The links' moment of inertia about the point ``about`` (kg*m^2)."""
    total = 0.0
    for name in links:
        body = character.bodies[name]
        c = body.local_to_world(body.center_of_gravity)
        total += body.moment + body.mass * ((c.x - about[0]) ** 2 + (c.y - about[1]) ** 2)
    return total


def hold_warnings(spec, character_spec: CharacterSpec, located) -> list[str]:
    """``file:line:col: warning: ...`` for each world-frame hold whose other side is
    too light to carry it, in the interface's start pose (``spec.start_character``)."""
    holds = list(frame_holds(spec))
    if not holds:
        return []
    start = spec.start_character(character_spec)
    character = Character(start)
    space = pymunk.Space()  # (pymunk sums a body's mass from its shapes in a space; the
    character.add_to(space)  # space is kept while its bodies are read)
    standing = _grounded(character, character_spec)  # its feet, in its own start pose
    grounded = _grounded(character, start)  # in the interface's start pose
    joints = {j.name for j in start.joints}
    out, said = [], set()
    for loc, name, hold in holds:
        for joint in _meanings(spec, name):
            if joint not in joints or (loc, joint) in said:
                continue
            said.add((loc, joint))
            j = start.joint(joint)
            child_side = set(beyond(start, joint))
            held = child_side if hold == "child" else set(character.link_order) - child_side
            base = set(character.link_order) - held
            if base & grounded:
                continue  # it pushes against the floor: it can hold
            if not _at_start(spec, loc) and (len(base) > 1 or base & standing):
                continue  # a limb or a foot, used later: it may be down by then
            hinge = character.bodies[j.parent].local_to_world(j.anchor)
            i_base, i_held = _moment(character, base, hinge), _moment(character, held, hinge)
            if i_base >= i_held:
                continue
            link = j.child if hold == "child" else j.parent
            other = j.parent if hold == "child" else j.child
            mass = sum(character.bodies[n].mass for n in base)
            held_mass = sum(character.bodies[n].mass for n in held)
            where = located.where(loc)
            at = f"{located.path}:{where[0]}:{where[1]}" if where else str(located.path)
            role = f" ('{name}' here)" if name != joint else ""
            out.append(f"{at}: warning: joint '{joint}'{role} holds '{link}' in the world "
                       f"by turning against '{other}', whose side ({mass:.3g} kg, "
                       f"{i_base:.2g} kg*m^2 about the hinge) is lighter than the side it "
                       f"holds ({held_mass:.3g} kg, {i_held:.2g} kg*m^2) and touches "
                       f"nothing in the start pose: '{other}' will turn instead; hold "
                       f"'{link}' through a joint whose other side is on the ground or "
                       f"heavier")
    del space
    return out


def _grounded(character: Character, spec: CharacterSpec) -> set[str]:
    """The links at the floor with the character built in ``spec``'s start pose."""
    character.place(0.0, 0.0, math.radians(spec.start.angle),
                    {n: math.radians(v) for n, v in spec.start.joints.items()})
    bottoms = {name: min(s.cache_bb().bottom for s in shapes)
               for name, shapes in character.shapes.items()}
    lowest = min(bottoms.values())
    return {name for name, b in bottoms.items() if b - lowest <= GROUNDED}


def _at_start(spec, loc: tuple) -> bool:
    """Whether the hold at ``loc`` acts from the start, in the pose whose contacts are
    known: the start pose, the top level's maps, the start mode's, each machine's first
    state's maps and entry. (Another hold acts in a pose and a place the file does not
    say, so only a side that is one free link - a tail, a head - is judged there.)"""
    if loc[0] == "poses":
        return loc[1] == spec.start_pose
    if loc[0] == "maps":
        return True
    if loc[0] == "modes":
        return loc[1] == spec.start_mode
    machines = spec.state_machines()
    if loc[0] == "machines":
        machine, rest = machines.get(loc[1]), loc[2:]
    else:
        machine, rest = machines.get("main"), loc
    return (machine is not None and len(rest) > 2 and rest[0] == "states"
            and rest[1] == machine.start_state and rest[2] in ("maps", "enter"))


def _meanings(spec, name: str) -> list[str]:
    """The joints ``name`` means: itself, or a role's joint in each binding."""
    if name in spec.roles:
        return list(dict.fromkeys(spec.roles[name].values()))
    return [name]


def setup_hold_warnings(setup):
    """``setup`` (a catalog Setup) with its interface's hold warnings added to its
    ``warnings`` (what ``puppet play`` prints and shows)."""
    import dataclasses

    from puppet.data.yamlfile import load_text

    if not any(True for _ in frame_holds(setup.interface)):
        return setup
    try:
        text = setup.interface_path.read_text(encoding="utf-8")
    except OSError:
        return setup
    said = hold_warnings(setup.interface, setup.character,
                         load_text(text, str(setup.interface_path)))
    return dataclasses.replace(setup, warnings=tuple(setup.warnings) + tuple(said)) \
        if said else setup
