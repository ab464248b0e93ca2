"""Bounds the command line checks as well as the data files (slowdown, checkpoint
interval), in a module of their own so that ``puppet`` can parse its arguments without
importing the data files' models (process start)."""

CHECKPOINT_EVERY = 3.0  # s of simulated time between automatic checkpoints (keyframes)
CHECKPOINT_MIN, CHECKPOINT_MAX = 0.5, 600.0  # s; the interval is a multiple of 0.5 s
MIN_SLOWDOWN, MAX_SLOWDOWN = 0.1, 100.0  # wall s per simulated s; 0.1: ten times faster
