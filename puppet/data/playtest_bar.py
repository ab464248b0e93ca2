"""A sidecar's ``playtest:`` bar: how forgiving a feat must be.

    playtest: {noise: human, tries: 20, min_pass: 0.8}

``puppet playtest`` checks it (docs/interfaces.md, section 18.4); the levels are
``puppet.data.playtest``'s.
"""

from __future__ import annotations

import math
from typing import Annotated, Literal

from puppet.data.ranges import Num
from puppet.data.validate import Meta, Spec

LevelName = Literal["steady", "human", "novice"]  # puppet.data.playtest.LEVELS
Tries = Annotated[int, Meta(ge=1, le=10000, extra={
    "message": "tries is a whole number 1..10000"})]


class PlaytestBar(Spec, kw_only=True):
    """At this noise level, at least ``min_pass`` of ``tries`` tries must still meet
    the log's feat expectations."""

    noise: LevelName = "human"
    tries: Tries = 20
    min_pass: Num("fraction")

    def needed(self, tries: int | None = None) -> int:
        """How many of ``tries`` (default the bar's own) must pass."""
        n = self.tries if tries is None else tries
        return math.ceil(self.min_pass * n - 1e-9)
