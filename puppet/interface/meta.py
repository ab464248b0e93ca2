"""Meta actions on the world rather than on joint targets: gravity and friction (the
paper's "modify physical parameters"). They change the pymunk space, so checkpoints
capture them. Random motion is a controller (``controllers/perturbation.py``).
"""

from __future__ import annotations


def set_gravity(sim, gravity: tuple[float, float]) -> None:
    sim.space.gravity = tuple(gravity)


def set_friction(sim, friction: float) -> None:
    """Friction of every ground segment (the character's own links keep theirs)."""
    for segment in sim.ground:
        segment.friction = friction
