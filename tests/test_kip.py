"""The gymnast's kip (interfaces/biped-kip.yaml): a figure that starts lying on its back."""

from __future__ import annotations

import math

from puppet.data.catalog import load_setup
from puppet.session import Session


def test_start_angle_lays_the_figure_on_its_back_on_the_ground():
    """start_angle: 90 turns the root counter-clockwise (a figure facing +x on its back),
    and the figure is put on the ground, not through it (the root is turned before it
    is placed: pymunk turns a body about its centre of gravity)."""
    session = Session(load_setup("biped-kip", None))
    c = session.sim.character
    assert math.degrees(c.bodies["pelvis"].angle) == 90.0
    assert abs(c.lowest_point() - 0.002) < 1e-9
    chest, pelvis = c.bodies["chest"].position, c.bodies["pelvis"].local_to_world((0, 0))
    assert c.bodies["head"].local_to_world(c.bodies["head"].center_of_gravity).x < pelvis.x
    assert abs(chest.y - pelvis.y) < 1e-9
