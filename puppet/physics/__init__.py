"""Physics: characters and scenes built from their specs into pymunk, stepped at a fixed rate."""

from puppet.physics import pymunk_setattr as _pymunk_setattr  # noqa: F401 - see its docstring
