"""``flight_phases``'s ``min_clearance``: a flight counts only if the lowest point of the
links rose that far above where it was as the flight began (a run's flight you can see,
not a foot skimming the ground), on made-up trajectories whose answers are known."""

import numpy as np

from puppet.timeline.expectations import evaluate_all, parse_expectations
from puppet.timeline.trajectory import Trajectory


def _traj(contact_rows, lowest_rows):
    contact = np.array(contact_rows, dtype=bool)[:, None]
    n = len(contact)
    z = np.zeros((n, 1))
    return Trajectory(links=["base"], joints=[], step=np.arange(n) * 4,
                      t=np.arange(n) / 120.0, x=z.copy(), y=z.copy(), angle=z.copy(),
                      lowest=np.array(lowest_rows, dtype=float)[:, None], contact=contact,
                      com=np.zeros((n, 2)), root_angle=np.zeros(n),
                      joint_angle=np.zeros((n, 0)), joint_target=np.zeros((n, 0)),
                      joint_channel=np.zeros((n, 0)),
                      state=np.array([None] * n, dtype=object),
                      mode=np.array([None] * n, dtype=object), state_names=[],
                      mode_names=[])


def _said(traj, entry):
    return [str(o) for o in evaluate_all(parse_expectations([entry]).items, traj, "")][0]


def test_only_flights_clear_enough_count():
    # two flights of 4 samples: the first skims (1 cm up), the second rises 6 cm
    traj = _traj([1, 1, 0, 0, 0, 0, 1, 1, 0, 0, 0, 0, 1],
                 [0, 0, .002, .01, .012, .005, 0, 0, .003, .04, .063, .02, 0])
    both = {"flight_phases": {"min_count": 2, "min_seconds": 0.03}}
    assert _said(traj, both).startswith("ok   flight_phases at least 2 of 0.03 s or more "
                                        "(no link touching)")
    clear = {"flight_phases": {"min_count": 2, "min_seconds": 0.03, "min_clearance": 0.05}}
    assert _said(traj, clear) == (
        "FAIL flight_phases at least 2 of 0.03 s or more, 5 cm clear or more (no link "
        "touching) from 0 s to the end: 1 flights of 0.03 s or more and 5 cm clear (2 in "
        "all, the longest 0.033 s, the highest 6.0 cm clear)")
    clear["flight_phases"]["min_count"] = 1
    assert _said(traj, clear).startswith("ok   ")
