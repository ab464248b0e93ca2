"""Playtests: a simulated player replays a log many times with a human's imprecision
and counts how often the feat still comes off (``puppet playtest``).

- ``noise``: a log's input moved as a person would move it (the human model's numbers
  are ``puppet.data.playtest``);
- ``slowdown``: the slowdown in force at each event (real-time errors scale with it);
- ``trial``: one try, replayed headless and judged by the log's feat expectations;
- ``runner``: N tries of many logs, in one process or several.
"""

from puppet.data.playtest import LEVELS, Noise, noise_at
from puppet.data.playtest_bar import PlaytestBar
from puppet.timeline.playtest.noise import Perturbation, perturb
from puppet.timeline.playtest.runner import LogPlaytest, Plan, load_bar, playtest, run
from puppet.timeline.playtest.trial import (
                                            TryResult,
                                            judge,
                                            perturbation,
                                            perturbed_log,
                                            prepare,
                                            run_try,
)

__all__ = ["LEVELS", "LogPlaytest", "Noise", "Perturbation", "Plan", "PlaytestBar",
           "TryResult", "judge", "load_bar", "noise_at", "perturb", "perturbation",
           "perturbed_log", "playtest", "prepare", "run", "run_try"]
