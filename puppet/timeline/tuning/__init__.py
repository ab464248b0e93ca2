"""``puppet tune SPEC.yaml``: a performance searched stage by stage from checkpoints.

The paper's users built long performances segment by segment: play a little, set a
checkpoint, try the next stretch until it works, keep it, go on. A tuning spec
(``assets/tune/*.yaml``; docs/tuning.md) says that search as data: an interface, a
start, stages (each a time window with the input it may play and the numbers it may
vary), and the score (expectations with their margins, optionally the simulated
player's pass rate). The modules, each using only those above it in this list:

- ``expr``: the arithmetic a spec may write for a number;
- ``spec``: the file's structs and ``load_tune_spec``; ``checks``: what only the whole
  spec can say; ``interface_values``: an interface's numbers changed in place;
- ``template``: a stage's script entries for some parameter values;
- ``candidates``: which values a stage tries (draws, grid, hill-climb neighbours);
- ``scoring``: a try's score from expectations' margins;
- ``generators``: stages written by Python where a spec cannot say it (the extension
  point);
- ``trial``: one try, wherever it runs; ``start``: where the search begins;
- ``state``: the tries played, on disk, to resume; ``search``: the stage loop,
  backtracking included; ``writer``: the log, sidecar, script and interface files.

Tries run through ``puppet.timeline.executor`` (here, local processes, or Dask).
"""

from __future__ import annotations

from puppet.timeline.tuning.search import Interrupted, Reporter, Search, TuneResult
from puppet.timeline.tuning.spec import load_tune_spec

__all__ = ["Interrupted", "Reporter", "Search", "TuneResult", "load_tune_spec"]
