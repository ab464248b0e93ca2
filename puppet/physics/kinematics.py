"""Forward kinematics of a character's spec, touching no body: where each link would
be for a root pose and joint angles (a performed pose, before the physics follows it).

Every link's frame is the model frame placed at the link's pose (see ``character``),
so a link's pose is the angle it is turned by and the point the model origin goes to.
"""

from __future__ import annotations

import math

from puppet.data.characters import CharacterSpec


def joint_order(spec: CharacterSpec) -> list:
    """The joints ordered root outward (each parent placed before its children)."""
    placed, order, pending = {spec.root}, [], list(spec.joints)
    while pending:
        ready = [j for j in pending if j.parent in placed]
        if not ready:  # a link no joint reaches from the root: not placed
            break
        for joint in ready:
            order.append(joint)
            placed.add(joint.child)
            pending.remove(joint)
    return order


def link_poses(spec: CharacterSpec, order, origin: tuple[float, float], angle: float,
               joint_angles: dict[str, float]) -> dict[str, tuple[float, float, float]]:
    """link -> (x, y, angle): the model origin's world point and the turn of each link,
    with the root link at ``origin``/``angle`` and the joints at ``joint_angles``
    (radians; a joint not given is 0). ``order``: ``joint_order(spec)``."""
    poses = {spec.root: (origin[0], origin[1], angle)}
    for joint in order:
        px, py, pa = poses[joint.parent]
        ax, ay = joint.anchor
        c, s = math.cos(pa), math.sin(pa)
        wx, wy = px + c * ax - s * ay, py + s * ax + c * ay  # the hinge in the world
        a = pa + joint_angles.get(joint.name, 0.0)
        c, s = math.cos(a), math.sin(a)
        poses[joint.child] = (wx - (c * ax - s * ay), wy - (s * ax + c * ay), a)
    return poses


def beyond(spec: CharacterSpec, joint_name: str) -> list[str]:
    """The links a joint moves: its child and everything hanging from it."""
    children: dict[str, list[str]] = {}
    for j in spec.joints:
        children.setdefault(j.parent, []).append(j.child)
    out, todo = [], [spec.joint(joint_name).child]
    while todo:
        link = todo.pop()
        out.append(link)
        todo += children.get(link, [])
    return out
