"""What one check found: ``Outcome``, a verdict with its words and its margin.

The margin is the number a tool reads instead of the words: how far inside (+) or
outside (-) its bound the run was, in the check's own unit (``unit``: 'm', 's', 'deg',
'turns'...). Searches score tries by it, so they never parse the text.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

NOTHING = -math.inf  # the margin of a failure with no distance to measure


@dataclass
class Outcome:
    expectation: str  # what was expected, one line
    passed: bool
    measured: str  # what was measured, one line
    # the expectation's kind (its key: 'never_fell', 'flight_phases'...; 'same_end' for
    # the recorded end state a closed log adds)
    kind: str = ""
    # how far inside (+) or outside (-) the bound, in ``unit``: passed is margin >= 0
    # (to a rounding); -inf for a failure with nothing to measure (never in the air, no
    # sample in the window, a hash that differs). None: 0 if passed, else -inf
    margin: float | None = None
    unit: str = ""  # the margin's unit ('m', 's', 'deg', 'm/s', 'turns', 'flights'...)

    def __post_init__(self):
        if self.margin is None:
            self.margin = 0.0 if self.passed else NOTHING
        self.margin = float(self.margin)

    def __str__(self) -> str:
        return f"{'ok  ' if self.passed else 'FAIL'} {self.expectation}: {self.measured}"
