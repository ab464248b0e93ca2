"""Cross-references in an interface file, checked at load time with file:line:col.

The types check each value on its own; this module checks that names point at things
that exist (poses, sequences, modes, states, chains; joints and links of the character),
that every state can be reached, and that values fit the character (pose angles within
joint limits). A mistake is reported where it was written, with a did-you-mean.
"""

from __future__ import annotations

from collections.abc import Iterator

from puppet.data.actions import ActionSpec, check_input_name
from puppet.data.characters import CharacterSpec
from puppet.data.errors import DataError
from puppet.data.interfaces import MAIN_MACHINE
from puppet.data.yamlfile import Located

FIXED_SENSORS = ("root.angle", "lean", "com.x", "com.y", "com.vx", "com.vy", "com.fall_time",
                 "com.spin")
JOINT_SENSORS = ("joint", "torque")
LINK_SENSORS = ("angle", "height", "contact", "spin", "com.dx")


def _period(rate: float) -> int:
    """Steps between control steps at ``rate`` on the simulation's 1/480 s step
    (``interface.control_rate.control_period`` at ``physics.simulation.DEFAULT_DT``)."""
    return max(1, round(1.0 / (rate * (1.0 / 480.0))))

def unknown(kind: str, name: str, known, owner: str = "") -> str:
    """Message for a name that is not one of ``known``, with a did-you-mean."""
    import difflib  # only for a mistake (process start)

    known = list(known)
    close = difflib.get_close_matches(str(name), known, n=1)
    hint = f"; did you mean '{close[0]}'? " if close else "; "
    listing = ", ".join(known) if known else "none defined"
    return f"unknown {kind} '{name}'{owner}{hint}expected one of: {listing}"


def machine_locs(spec) -> Iterator[tuple[str, tuple, object]]:
    """(machine name, location of its states' parent, machine spec) for every machine."""
    for name, machine in spec.state_machines().items():
        yield name, (() if name == MAIN_MACHINE else ("machines", name)), machine


def actions(spec) -> Iterator[tuple[tuple, ActionSpec]]:
    """Every action in the file with its location: keys, state entries, state keys,
    any_state keys, in every machine."""
    for a in machine_actions(spec):
        yield a[1], a[2]


def machine_actions(spec) -> Iterator[tuple[str | None, tuple, ActionSpec]]:
    """(machine or None for top-level keys, location, action) of every action."""
    for i, k in enumerate(spec.keys):
        yield None, ("keys", i), k
    for mname, where, machine in machine_locs(spec):
        for name, state in machine.states.items():
            if state.enter is not None:
                yield mname, where + ("states", name, "enter"), state.enter
            for i, k in enumerate(state.keys):
                yield mname, where + ("states", name, "keys", i), k
        for i, k in enumerate(machine.any_state.keys):
            yield mname, where + ("any_state", "keys", i), k
    tracking = spec.tracking
    if tracking is not None:  # what tracking runs: when lost, found, after a fall
        for name in ("lost", "found"):
            if getattr(tracking, name) is not None:
                yield None, ("tracking", name), getattr(tracking, name)


def transitions(spec) -> Iterator[tuple[str, str | None, tuple, object]]:
    """(machine, state or None for any_state, location, transition) of every transition."""
    for mname, where, machine in machine_locs(spec):
        for name, state in machine.states.items():
            for i, t in enumerate(state.transitions):
                yield mname, name, where + ("states", name, "transitions", i), t
        for i, t in enumerate(machine.any_state.transitions):
            yield mname, None, where + ("any_state", "transitions", i), t


def all_maps(spec) -> Iterator[tuple[tuple, object]]:
    for i, m in enumerate(spec.maps):
        yield ("maps", i), m
    for mode, maps in spec.modes.items():
        for i, m in enumerate(maps):
            yield ("modes", mode, i), m
    for _, where, machine in machine_locs(spec):
        for name, state in machine.states.items():
            for i, m in enumerate(state.maps):
                yield where + ("states", name, "maps", i), m


def check_names(spec, located: Located) -> None:
    """Names of poses, sequences, modes, states and chains used must be defined."""
    def need(loc, kind, name, known, prefer_key=False):
        if name not in known:
            raise located.error(loc, unknown(kind, name, known), prefer_key=prefer_key)

    for seq, steps in spec.sequences.items():
        for i, step in enumerate(steps):
            need(("sequences", seq, i, "pose"), "pose", step.pose, spec.poses)
    if spec.mode is not None:
        need(("mode",), "mode", spec.mode, spec.modes)
    if spec.initial is not None:
        need(("initial",), "state", spec.initial, spec.states)
    if spec.start_pose is not None:
        need(("start_pose",), "pose", spec.start_pose, spec.poses)
        for joint, value in spec.poses[spec.start_pose].joints.items():
            if not isinstance(value, (int, float)):
                raise located.error(("poses", spec.start_pose, "joints", joint),
                                    "a start pose's targets are joint angles (degrees), "
                                    "not frame targets")
    bindings = spec.bindings
    if spec.binding is not None:
        need(("binding",), "role binding", spec.binding, bindings)
    for _, where, machine in machine_locs(spec):
        for name, state in machine.states.items():
            if state.roles is not None:
                need(where + ("states", name, "roles"), "role binding", state.roles, bindings)
            rate = state.control_rate
            if rate is not None and rate <= spec.control_rate:
                raise located.error(where + ("states", name, "control_rate"),
                                    f"a state's control_rate makes the control steps faster "
                                    f"while it is active: {rate:g} is not above the "
                                    f"interface's {spec.control_rate:g} (drop it, or raise it)")
            if rate is not None and _period(rate) >= _period(spec.control_rate):
                raise located.error(where + ("states", name, "control_rate"),
                                    f"a state's control_rate makes the control steps faster "
                                    f"while it is active: at 1/480 s {rate:g} a second is "
                                    f"one in {_period(rate)} steps, as the interface's "
                                    f"{spec.control_rate:g} (drop it, or raise it)")
    if spec.states and MAIN_MACHINE in spec.machines:
        raise located.error(("machines", MAIN_MACHINE),
                            f"machine name '{MAIN_MACHINE}' is the top-level 'states'; name "
                            "this machine otherwise", prefer_key=True)
    for mname, machine in spec.machines.items():
        if machine.initial is not None:
            need(("machines", mname, "initial"), "state", machine.initial, machine.states)
    for loc, m in all_maps(spec):
        grid = getattr(m, "grid", None)
        if grid is None:
            continue
        joints = None
        for r, row in enumerate(grid):
            for c, pose in enumerate(row):
                need(loc + ("grid", r, c), "pose", pose, spec.poses)
                these = set(spec.poses[pose].joints)
                if joints is None:
                    joints, first = these, pose
                elif these != joints:
                    raise located.error(loc + ("grid", r, c),
                                        f"grid pose '{pose}' sets joints "
                                        f"{sorted(these)} but '{first}' sets "
                                        f"{sorted(joints)}; grid poses must set the same joints")
        for i, joint in enumerate(getattr(m, "joints", None) or []):
            if joint not in joints:
                raise located.error(loc + ("joints", i),
                                    unknown("joint", joint, sorted(joints),
                                            " among the grid poses' joints"))
    def need_state(loc, name, machine):
        if spec.resolve_goto(name, machine) is None:
            every = [f"{m}.{st}" if m != MAIN_MACHINE else st
                     for m, ms in spec.state_machines().items() for st in ms.states]
            owners = [m for m, ms in spec.state_machines().items() if name in ms.states]
            if len(owners) > 1:
                raise located.error(loc, f"state '{name}' is in machines "
                                         f"{', '.join(owners)}; write MACHINE.{name}")
            raise located.error(loc, unknown("state", name, every))

    for machine, loc, a in machine_actions(spec):
        if a.goto is not None:
            need_state(loc + ("goto",), a.goto, machine)
        if a.reach is not None and a.reach.point is not None and a.reach.point.of is not None:
            need(loc + ("reach", "point", "of"), "chain", a.reach.point.of, spec.chains)
    for loc, a in actions(spec):
        if a.pose is not None:
            need(loc + ("pose",), "pose", a.pose, spec.poses)
        if a.sequence is not None:
            need(loc + ("sequence",), "sequence", a.sequence, spec.sequences)
        if a.mode is not None:
            need(loc + ("mode",), "mode", a.mode, spec.modes)
        if a.reach is not None:
            need(loc + ("reach", "chain"), "chain", a.reach.chain, spec.chains)
        if a.grasp is not None:
            need(loc + ("grasp", "chain"), "chain", a.grasp.chain, spec.chains)
        if a.release is not None and a.release != "all":
            need(loc + ("release",), "chain", a.release, list(spec.chains) + ["all"])
        if a.while_held and not (a.stiffness or a.damping):
            raise located.error(loc + ("while_held",), "'while_held' undoes stiffness/damping "
                                                       "changes, but this action sets none")
        if a.while_held and loc[0] == "states" and loc[2] == "enter":
            raise located.error(loc + ("while_held",), "'while_held' needs a key")
    for machine, _, loc, t in transitions(spec):
        need_state(loc + ("to",), t.to, machine)
        other = spec.resolve_goto(t.to, machine)[0]
        if other != machine:  # it would fire again at every step: its machine stays put
            raise located.error(loc + ("to",), f"a transition moves its own machine "
                                               f"'{machine}', but '{t.to}' is a state of "
                                               f"machine '{other}'; to move '{other}', "
                                               f"goto it from a state's enter or a key")
    _check_reachable(spec, located)


def _check_reachable(spec, located: Located) -> None:
    """Every state of every machine can be reached from its machine's initial state
    (through gotos from anywhere that lead into the machine, its own states' keys,
    entries and transitions, and its any_state rules)."""
    edges: dict[tuple[str, str], set[tuple[str, str]]] = {}
    anywhere: set[tuple[str, str]] = set()  # reachable from any state of any machine
    for machine, loc, a in machine_actions(spec):
        if a.goto is None:
            continue
        to = spec.resolve_goto(a.goto, machine)
        if machine is None or loc[len(loc) - 3:len(loc) - 1] == ("any_state", "keys"):
            anywhere.add(to)
        else:
            state = loc[loc.index("states") + 1]
            if to[0] == machine:
                edges.setdefault((machine, state), set()).add(to)
            else:
                anywhere.add(to)  # a key in one machine moving another: live while there
    for machine, state, _loc, t in transitions(spec):
        to = spec.resolve_goto(t.to, machine)
        if state is None:
            anywhere.add(to)
        else:
            edges.setdefault((machine, state), set()).add(to)
    for mname, where, ms in machine_locs(spec):
        start = (mname, ms.start_state)
        seen, todo = {start}, [start]
        while todo:
            for nxt in edges.get(todo.pop(), set()) | anywhere:
                if nxt[0] == mname and nxt not in seen:
                    seen.add(nxt)
                    todo.append(nxt)
        for name in ms.states:
            if (mname, name) not in seen:
                raise located.error(where + ("states", name),
                                    f"state '{name}' is unreachable from the initial state "
                                    f"'{ms.start_state}': no key 'goto', transition or entry "
                                    "leads to it", prefer_key=True)


def sensor_problem(sensor: str, character: CharacterSpec, roles=None) -> str | None:
    """Why a condition's sensor name is wrong for this character, or None. A joint or
    link in it may be a role (``roles``: role -> binding -> name), checked per binding."""
    if sensor in FIXED_SENSORS:
        return None
    if sensor.startswith("held."):  # timeline/reactive.py's, not a state machine's
        return f"'{sensor}': held.CHAIN is read by a script's rules only, not here"
    if sensor.startswith("channel."):  # an input channel (a mocap plugin's): any name
        return None if len(sensor) > len("channel.") else "a channel sensor needs a " \
            "name: channel.NAME"
    if sensor.startswith("input."):  # a device input (the mouse, a gamepad's stick)
        name = sensor[len("input."):]
        try:
            if name.startswith(("channel.", "sensor.")):
                raise ValueError(f"'{name}' is not a device input; write it as a sensor "
                                 "of its own (channel.NAME, or the sensor's name)")
            check_input_name(name)
        except ValueError as exc:
            return str(exc)
        return None
    if sensor.startswith("lead."):  # lead.LINK.OTHER: either may be a role
        return _lead_problem(sensor, character, roles)
    for role, targets in (roles or {}).items():
        if sensor.endswith("." + role):
            for name in targets.values():
                problem = sensor_problem(sensor[:-len(role)] + name, character)
                if problem:
                    return f"role '{role}': {problem}"
            return None
    kind, _, name = sensor.partition(".")
    if sensor.startswith("com.dx."):
        kind, name = "com.dx", sensor[len("com.dx."):]
        if name == "support":  # from the middle of the support polygon
            return None
    joints = [j.name for j in character.joints]
    links = [link.name for link in character.links]
    if kind in JOINT_SENSORS and name:
        return None if name in joints else unknown("joint", name, joints,
                                                    f" for character '{character.name}'")
    if kind in LINK_SENSORS and name:
        return None if name in links else unknown("link", name, links,
                                                  f" for character '{character.name}'")
    forms = list(FIXED_SENSORS) + [f"{k}.JOINT" for k in JOINT_SENSORS] + \
        [f"{k}.LINK" for k in LINK_SENSORS] + ["lead.LINK.LINK", "channel.NAME", "input.INPUT"]
    return unknown("sensor", sensor, forms)


def _lead_problem(sensor: str, character: CharacterSpec, roles=None) -> str | None:
    """``lead.LINK.OTHER``: two link names (or link roles), each checked."""
    parts = sensor.split(".")[1:]
    if len(parts) != 2 or not all(parts):
        return f"'{sensor}': write lead.LINK.OTHER (how far LINK is ahead of OTHER), two links"
    links = [link.name for link in character.links]
    roles = roles or {}
    for part in parts:
        names = list(roles[part].values()) if part in roles else [part]
        for name in names:
            if name not in links:
                where = f" (role '{part}')" if part in roles else ""
                return unknown("link", name, links, f" for character '{character.name}'{where}")
    return None


def check_character_refs(spec, character: CharacterSpec, located: Located) -> None:
    """Joint and link names must exist (joints driven by servos must be actuated) and
    pose angles must be within the joints' limits."""
    actuated = [j.name for j in character.actuated]
    owner = f" for character '{character.name}'"
    links = [link.name for link in character.links]
    joint_roles, link_roles = _check_roles(spec, character, located, actuated, links)

    def need(loc, name, prefer_key=False):
        if name not in actuated and name not in joint_roles:
            raise located.error(loc, unknown("joint", name, actuated + joint_roles, owner),
                                prefer_key=prefer_key)

    def need_link(loc, name):
        if name not in links and name not in link_roles:
            raise located.error(loc, unknown("link", name, links + link_roles, owner))

    def in_limits(loc, name, deg):
        if not isinstance(deg, (int, float)):  # a frame target: checked as a link
            if deg.relative_to is not None:
                need_link(loc + ("relative_to",), deg.relative_to)
            return
        for joint in spec.roles.get(name, {None: name}).values():  # each joint a role means
            _in_limits(located, loc, joint, deg, character)

    for name in spec.gains:
        need(("gains", name), name, True)
    for pose_name, pose in spec.poses.items():
        for field in ("joints", "stiffness", "damping", "max_torque"):
            for name in getattr(pose, field):
                need(("poses", pose_name, field, name), name, True)
        for name, deg in pose.joints.items():
            in_limits(("poses", pose_name, "joints", name), name, deg)
    for loc, m in all_maps(spec):
        for field in ("input", "x", "y"):
            name = getattr(m, field, None)
            if isinstance(name, str) and name.startswith("sensor."):
                problem = sensor_problem(name[len("sensor."):], character, spec.roles)
                if name.startswith("sensor.input."):
                    problem = (f"a map reads a device input as itself: write "
                               f"'{name[len('sensor.input.'):]}', not '{name}'")
                if problem:
                    raise located.error(loc + (field,), problem)
        if getattr(m, "grid", None) is not None:
            continue
        if m.joint is not None:
            need(loc + ("joint",), m.joint)
        for name in m.joints:
            need(loc + ("joints", name), name, True)
        if m.frame not in ("joint", "world") and m.frame not in links + link_roles:
            raise located.error(loc + ("frame",), unknown(
                "frame", m.frame, ["joint", "world"] + links,
                " (joint, world or a link)"))
    _check_tracking(spec, character, located, need, need_link)
    for loc, a in actions(spec):
        if a.push is not None:
            need_link(loc + ("push", "link"), a.push.link)
        for field in ("set", "adjust", "stiffness", "damping"):
            for name in getattr(a, field):
                need(loc + (field, name), name, True)
        for name, deg in a.set.items():
            in_limits(loc + ("set", name), name, deg)
    for name, chain in spec.chains.items():
        for i, joint in enumerate(chain.joints):
            need(("chains", name, "joints", i), joint)
        for i, (first, second) in enumerate(zip(chain.joints, chain.joints[1:])):
            first, second = character.joint(first), character.joint(second)
            if second.parent != first.child:
                raise located.error(("chains", name, "joints", i + 1),
                                    f"chain '{name}': joint '{second.name}' must be on link "
                                    f"'{first.child}' (the child of '{first.name}'), but its "
                                    f"parent is '{second.parent}'")
        pts = [tuple(character.joint(j).anchor) for j in chain.joints] + [tuple(chain.end)]
        for i in [i for i in range(len(pts) - 1) if pts[i] == pts[i + 1]][:1]:  # (IK: / length)
            raise located.error(("chains", name) + (("joints", i + 1) if i < len(pts) - 2 else (
                "end",)), f"chain '{name}': its link {i + 1} has no length (two points at "
                f"{pts[i][0]:g}, {pts[i][1]:g}); expected each point apart from the one before")
    for _, _, loc, t in transitions(spec):
        several = isinstance(t.when, list)
        for i, condition in enumerate(t.conditions):
            problem = sensor_problem(condition.sensor, character, spec.roles)
            if problem:
                where = loc + (("when", i, "sensor") if several else ("when", "sensor"))
                raise located.error(where, problem)
    for seq, steps in spec.sequences.items():
        for k, step in enumerate(steps):
            several = isinstance(step.until, list)
            for i, condition in enumerate(step.conditions):
                problem = sensor_problem(condition.sensor, character, spec.roles)
                if problem:
                    where = ("sequences", seq, k) + (("until", i, "sensor") if several
                                                     else ("until", "sensor"))
                    raise located.error(where, problem)


def _check_tracking(spec, character, located, need, need_link) -> None:
    """The tracked joints and the pulled links exist; ``track`` needs a ``tracking``
    section, and ``kd`` its ``root`` on the root link."""
    tracking = spec.tracking
    for loc, a in actions(spec):
        if a.track is None and a.kinematic is None:
            continue
        field = "track" if a.track is not None else "kinematic"
        if tracking is None:
            raise located.error(loc + (field,), f"'{field}' needs the interface's "
                                                f"'tracking' section (which channels drive "
                                                f"which joints)")
        if a.track == "kd" and tracking.root is None:
            raise located.error(loc + ("track",), "'track: kd' needs 'tracking.root' (the "
                                                  "channels that place the performed pose)")
    if tracking is None:
        return
    tracked_poses = [(("tracking", "stand"), tracking.stand)] if tracking.stand else []
    get_up = tracking.reaction.get_up if tracking.reaction is not None else None
    if get_up is not None:
        tracked_poses += [(("tracking", "reaction", "get_up", "steps", i, "pose"), s.pose)
                          for i, s in enumerate(get_up.steps)]
        for i, name in enumerate(get_up.hands):
            need_link(("tracking", "reaction", "get_up", "hands", i), name)
    for loc, name in tracked_poses:  # poses KD control stands the figure in: joint angles
        pose = spec.poses.get(name)
        if pose is None:
            raise located.error(loc, unknown("pose", name, list(spec.poses)))
        framed = [j for j, v in pose.joints.items() if not isinstance(v, (int, float))]
        if framed:
            raise located.error(loc, f"pose '{name}' holds {', '.join(framed)} in a frame; "
                                     f"a pose tracking stands the figure in is joint "
                                     f"angles (degrees), as a performer's frame is")
        if tracking.root is None:
            raise located.error(loc, "KD control stands the figure in this pose: it needs "
                                     "'tracking.root'")
    library = tracking.reaction.library if tracking.reaction is not None else None
    if library is not None:
        from puppet.data.motion_library import library_named

        try:
            library_named(library.file, character.name)
        except DataError as exc:
            raise located.error(("tracking", "reaction", "library", "file"),
                                exc.message) from None
        if tracking.root is None:
            raise located.error(("tracking", "reaction", "library"), "a library window is "
                                "placed where the figure is: it needs 'tracking.root'")
    if tracking.walk_in_place is not None:
        _check_walk(tracking, character, located)
    if tracking.contacts is not None:  # intentional contacts: grasp chains of the interface
        for chain in tracking.contacts.hands:
            if chain not in spec.chains:
                raise located.error(("tracking", "contacts", "hands", chain),
                                    unknown("chain", chain, list(spec.chains)))
    if tracking.start == "kd" and tracking.root is None:
        raise located.error(("tracking", "start"), "'start: kd' needs 'tracking.root' (the "
                                                   "channels that place the performed pose)")
    if tracking.joints != "all":
        for i, name in enumerate(tracking.joints):
            need(("tracking", "joints", i), name)
    for name in tracking.channels:
        need(("tracking", "channels", name), name, True)
    for name in tracking.scale:
        need_link(("tracking", "scale", name), name)
    if tracking.root is not None:
        need(("tracking", "root", "at"), tracking.root.at)
        parent = character.joint(tracking.root.at).parent
        if parent != character.root:
            raise located.error(("tracking", "root", "at"),
                                f"joint '{tracking.root.at}' hangs from '{parent}'; "
                                f"expected a joint on the root link '{character.root}' "
                                f"(the hips: its hinge is the root point)")


def _check_walk(tracking, character, located) -> None:
    """walking in place: its library, clip and cycle exist; it needs two feet and the
    root channels."""
    from puppet.data.motion_library import library_named

    walk, at = tracking.walk_in_place, ("tracking", "walk_in_place")
    try:
        library = library_named(walk.library, character.name)
    except DataError as exc:
        raise located.error(at + ("library",), exc.message) from None
    clips = {name: len(frames) for name, frames in library.clips}
    if walk.clip not in clips:
        raise located.error(at + ("clip",), unknown("clip", walk.clip, list(clips),
                                                    f" in motion library '{walk.library}'"))
    end = (clips[walk.clip] - 1) / library.rate
    if not walk.cycle[0] < walk.cycle[1] <= end:
        raise located.error(at + ("cycle",), f"expected from < until <= {end:.2f} s (the "
                                             f"clip's length)")
    for i, name in enumerate(walk.joints):
        if name not in library.channels:
            raise located.error(at + ("joints", i), unknown("channel", name,
                                                            list(library.channels)))
    if tracking.root is None or len(tracking.feet) < 2:
        raise located.error(at, "walking in place reads the performer's feet and places "
                                "the walk: it needs 'tracking.root' and two 'tracking.feet'")
    if not walk.steps[0] < walk.steps[1]:
        raise located.error(at + ("steps",), "expected [shortest, longest] step periods")


def _in_limits(located, loc, name, deg, character) -> None:
    limits = character.joint(name).limits
    if limits is not None and not limits[0] <= deg <= limits[1]:
        raise located.error(loc, f"{deg:g} deg for joint '{name}' is outside its limits "
                                 f"[{limits[0]:g}, {limits[1]:g}]")


def _check_roles(spec, character, located, actuated, links) -> tuple[list, list]:
    """Roles name joints (all of one role's) or links, never clash with a real name,
    and every role has the same bindings. Returns (joint roles, link roles)."""
    joint_roles, link_roles = [], []
    bindings = spec.bindings
    for role, targets in spec.roles.items():
        loc = ("roles", role)
        if role in actuated or role in links or role in [j.name for j in character.joints]:
            raise located.error(loc, f"role '{role}' has the name of a joint or link of "
                                     f"'{character.name}'; name it otherwise",
                                prefer_key=True)
        if list(targets) != bindings:
            raise located.error(loc, f"role '{role}' has bindings {list(targets)}; every "
                                     f"role needs the same ones, in order: {bindings}")
        names = list(targets.values())
        if all(n in actuated for n in names):
            joint_roles.append(role)
        elif all(n in links for n in names):
            link_roles.append(role)
        else:
            bad = next(n for n in names if n not in actuated and n not in links) \
                if any(n not in actuated and n not in links for n in names) else names[0]
            raise located.error(loc, unknown("joint or link", bad, actuated + links,
                                             f" in role '{role}' (a role names actuated "
                                             "joints only, or links only)"))
    return joint_roles, link_roles


def check_scene_refs(spec, scene, located: Located, scene_name: str) -> None:
    """Props named by reaches and grasps must be props of the scene played."""
    props = list(scene.props)
    for loc, a in actions(spec):
        named = []
        if a.reach is not None and a.reach.point is not None:
            named.append((loc + ("reach", "point", "prop"), a.reach.point.prop))
        if a.grasp is not None and a.grasp.prop not in (None, "any"):
            named.append((loc + ("grasp", "prop"), a.grasp.prop))
        for where, prop in named:
            if prop not in props:
                raise located.error(where, unknown("prop", prop, props,
                                                   f" in scene '{scene_name}'"))
            if where[-2] == "point" and not scene.props[prop].grasp_points:
                raise located.error(where, f"prop '{prop}' has no grasp_points to reach for")


def _map_joints(spec, m) -> set[str]:
    grid = getattr(m, "grid", None)
    if grid is None:
        return set(m.gains())
    joints = {j for row in grid for pose in row for j in spec.poses[pose].joints}
    return joints if m.joints is None else joints & set(m.joints)


def map_conflicts(spec, located: Located) -> list[str]:
    """Warnings (``file:line:col: warning: ...``) for two maps that write one joint when
    both are live (the top level's, a mode's, a state's of each machine): the later
    one in the file wins whenever both inputs change, which is seldom what was meant."""
    where = {id(m): loc for loc, m in all_maps(spec)}
    groups: list[tuple[str, list]] = []
    modes = list(spec.modes.items()) or [(None, [])]
    machines = list(spec.state_machines().items())
    states = [(f"state '{s}'" if mname == MAIN_MACHINE else f"state '{mname}.{s}'", st.maps)
              for mname, ms in machines for s, st in ms.states.items()] or [(None, [])]
    for mode, mode_maps in modes:
        for state, state_maps in states:
            label = " and ".join(x for x in (mode and f"mode '{mode}'", state) if x)
            groups.append((label, list(spec.maps) + list(mode_maps) + list(state_maps)))
    out, seen = [], set()
    for label, maps in groups:
        writer: dict[str, object] = {}
        for m in maps:
            if getattr(m, "combine", "set") == "add":
                continue  # adds to the target: combines with any writer, by design
            for joint in sorted(_map_joints(spec, m)):
                first = writer.get(joint)
                if first is not None and (id(first), id(m), joint) not in seen:
                    seen.add((id(first), id(m), joint))
                    a, b = located.where(where[id(first)]), located.where(where[id(m)])
                    line, col = b if b else (None, None)
                    at = f"{located.path}:{line}:{col}" if line else located.path
                    out.append(f"{at}: warning: this map and the one at line "
                               f"{a[0] if a else '?'} both write joint '{joint}'"
                               + (f" in {label}" if label else "")
                               + "; the one that updates last wins (give each joint one map)")
                writer[joint] = m
    return out
