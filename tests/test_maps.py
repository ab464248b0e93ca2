"""Interface maps: clamped ranges, pose grids over the mouse, channels and roles, ``add``
maps on one joint, mouse buttons read as 1 and 0."""

from __future__ import annotations

import math
import textwrap

import pytest
from helpers import session_of

from puppet.data.catalog import load_setup
from puppet.interface import events as ev
from puppet.session import Session

LUXO_HEADER = "name: t\ndescription: a test interface\ncharacter: luxo\n"


def luxo_session(tmp_path, body: str) -> Session:
    path = tmp_path / "iface.yaml"
    path.write_text(LUXO_HEADER + textwrap.dedent(body))
    return Session(load_setup(str(path)))


def deg(s) -> dict[str, float]:
    return {n: round(math.degrees(sv.target), 6) for n, sv in s.character.servos.items()}


CAT_GRID = """
name: t
description: grid maps on channels
character: cat
poses:
  low: {joints: {hip_near: 0, knee_near: -40}}
  high: {joints: {hip_near: 40, knee_near: -80}}
  back: {joints: {shoulder_near: -40}}
  front: {joints: {shoulder_near: 20}}
maps:
  - {grid: [[high], [low]], x: channel.gx, y: channel.gy}
  - {grid: [[back, front], [back, front]], x: mouse.x, y: channel.gy}
"""


def test_a_clamped_map_gives_its_end_values_outside_its_from_range(tmp_path):
    maps = """
    maps:
      - {{input: mouse.y, joint: knee, from: [0.4, 0.6], to: [10, 30]{extra}}}
    """
    clamped = luxo_session(tmp_path, maps.format(extra=""))
    free = luxo_session(tmp_path, maps.format(extra=", clamp: false"))
    for y, end, line in ((1.0, 30, 70), (0.0, 10, -30), (0.5, 20, 20), (0.6, 30, 30)):
        for s in (clamped, free):
            s.handle(ev.mouse(0.5, y))
        assert deg(clamped)["knee"] == pytest.approx(end), y
        assert deg(free)["knee"] == pytest.approx(line), y  # clamp: false extrapolates


def test_a_mouse_button_reads_1_while_down_and_0_when_up(tmp_path):
    s = luxo_session(tmp_path, """
    maps:
      - {input: mouse.left, joint: knee, to: [0, 40], clamp: false}
    """)
    s.handle(ev.mouse_button("left", True))
    assert s.runtime.read_input("mouse.left") == 1.0
    assert deg(s)["knee"] == pytest.approx(40)
    s.handle(ev.mouse_button("left", False))
    assert s.runtime.read_input("mouse.left") == 0.0
    assert deg(s)["knee"] == pytest.approx(0)


def test_a_grid_map_on_two_channels_blends_its_poses_as_the_channels_say(tmp_path):
    s = session_of(tmp_path, CAT_GRID)
    for gy, hip, knee in ((0.25, 10, -50), (1.0, 40, -80), (0.5, 20, -60)):
        s.handle(ev.channels({"gx": 0.3, "gy": gy}))
        s.advance(1)
        assert (deg(s)["hip_near"], deg(s)["knee_near"]) == pytest.approx((hip, knee)), gy


def test_a_grid_map_on_the_mouse_and_a_channel_reads_both(tmp_path):
    s = session_of(tmp_path, CAT_GRID)
    s.handle(ev.channels({"gx": 0.0, "gy": 0.5}))
    for x, shoulder in ((0.75, 5), (0.0, -40), (0.5, -10)):
        s.handle(ev.mouse(x, 0.9))
        s.advance(1)
        assert deg(s)["shoulder_near"] == pytest.approx(shoulder), x


def test_a_grid_map_of_roles_drives_the_joints_of_the_binding_in_force(tmp_path):
    s = session_of(tmp_path, """
    name: t
    description: a grid map through roles
    character: cat
    roles:
      leg_hip: {a: hip_near, b: hip_far}
    poses:
      low: {joints: {leg_hip: 0}}
      high: {joints: {leg_hip: 40}}
    maps:
      - {grid: [[high], [low]], x: channel.gx, y: channel.gy, joints: [leg_hip]}
    binding: b
    """)
    near = deg(s)["hip_near"]
    s.handle(ev.channels({"gx": 0.5, "gy": 0.75}))
    s.advance(1)
    assert deg(s)["hip_far"] == pytest.approx(30)
    assert deg(s)["hip_near"] == near  # not the other binding's joint


def test_two_add_maps_on_one_joint_add_up(tmp_path):
    s = session_of(tmp_path, """
    name: t
    description: two contributions to the knee
    character: luxo
    maps:
      - {input: channel.a, joint: knee, from: [0, 1], to: [0, 20], combine: add}
      - {input: channel.b, joint: knee, from: [0, 1], to: [0, 10], combine: add}
    """)
    base = deg(s)["knee"]
    s.handle(ev.channels({"a": 1.0, "b": 0.5}))
    s.advance(1)
    assert deg(s)["knee"] == pytest.approx(base + 25)


def _grid_by_corners(spec, pose_targets, x, y) -> dict[str, float]:
    """A grid map's targets as the general applier sums them: corner by corner."""
    from puppet.interface.maps import _grid_corners

    rows, cols = len(spec.grid), len(spec.grid[0])
    acc: dict[str, float] = {}
    for r, c, w in _grid_corners(rows, cols, spec.mirror, x, y):
        for joint, angle in pose_targets[spec.grid[r][c]].items():
            if spec.joints is None or joint in spec.joints:
                acc[joint] = acc.get(joint, 0.0) + w * angle
    return acc


def test_a_grid_whose_poses_give_every_joint_sums_them_to_the_bit():
    """The cat's grids (every pose has each leg joint) take the unrolled applier: the
    same sums, corner by corner from 0.0, for any input, in or out of range, mirrored
    or not."""
    import random

    import msgspec

    from puppet.data.interfaces import GridMapSpec
    from puppet.interface.active_maps import every_map
    from puppet.interface.maps import compile_map

    session = Session(load_setup("cat-trot"))
    runtime, servos = session.runtime, session.character.servos
    grids = [m for m in every_map(runtime.spec) if isinstance(m, GridMapSpec)]
    assert grids
    rng = random.Random(7)
    inputs = [(0.0, 0.0), (1.0, 1.0), (0.5, 0.5), (-0.3, 1.4), (1.0, 0.0)] + [
        (rng.uniform(-0.2, 1.2), rng.uniform(-0.2, 1.2)) for _ in range(150)]
    for spec in grids:
        for mirror in ([], ["x"], ["y"], ["x", "y"]):
            grid = msgspec.structs.replace(spec, mirror=mirror)
            apply = compile_map(grid, servos, runtime.pose_targets)
            assert apply.__name__ == "apply_full_grid"
            for x, y in inputs:
                written = apply({grid.x: x, grid.y: y})
                got = {j: servos[j].target for j in written}
                assert got == _grid_by_corners(grid, runtime.pose_targets, x, y), (x, y)
