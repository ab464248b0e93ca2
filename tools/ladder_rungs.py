"""Shared by the ladder search tools (tune_ladder.py, tune_gymnast_climb.py): which rung
of the ladder scene a hand or foot holds."""

from __future__ import annotations


def rung(sim, name: str) -> int:
    """The number of the rung ``name`` holds (0: none)."""
    held = sim.grasps.get(name)
    if held is None or held[1] is None:
        return 0
    point = sim.props[held[1]].nearest(sim.grasp_point(name))[2]
    return int(point[4:]) if point else 0
