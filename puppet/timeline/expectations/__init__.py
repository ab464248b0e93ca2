"""What a replayed log must show: checked by ``puppet replay --check`` and test suites.

Expectations live in the log header (``"expect": [...]``) or in a sidecar file
``LOG.expect.yaml`` next to the log (``expect:`` then a list of ``- KIND: settings``
entries). Every kind, with its settings, an example and its margin, is documented in
docs/expectations.md (a test holds that page and the classes together).

The package: one class per kind (its settings, ``describe``, ``evaluate``) in theme
modules - ``position``, ``posture``, ``contacts``, ``flight``, ``grasps``, ``states`` -
registered in ``base.KINDS``; the entry and list structs in ``entry``; where they are
read from in ``files``; the shared ways of reading a sampled run in ``measure``; and
what a check found in ``outcome`` (an ``Outcome``: verdict, words, numeric margin).
The run itself is ``puppet.timeline.trajectory.Trajectory``.
"""

from __future__ import annotations

from puppet.timeline.expectations.base import KINDS, Check, Checking
from puppet.timeline.expectations.entry import Expectation, Expectations, ExpectFile
from puppet.timeline.expectations.files import (
    load_expectations,
    parse_expectations,
    sidecar_path,
    validate_expect_file,
)
from puppet.timeline.expectations.outcome import NOTHING, Outcome

__all__ = ["KINDS", "Check", "Checking", "ExpectFile", "Expectation", "Expectations",
           "NOTHING", "Outcome", "evaluate", "evaluate_all", "load_expectations",
           "parse_expectations", "sidecar_path", "validate_expect_file"]


def evaluate(e: Expectation, traj, final_hash: str) -> Outcome:
    """Check one expectation against a sampled trajectory (see ``Trajectory``)."""
    outcome = e.value.evaluate(traj, Checking(e, final_hash))
    outcome.kind = e.kind
    return outcome


def evaluate_all(items: list[Expectation], traj, final_hash: str) -> list[Outcome]:
    return [evaluate(e, traj, final_hash) for e in items]
