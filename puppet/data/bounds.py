"""Bounds the command line checks as well as the data files (slowdown, checkpoint
interval), in a module of their own so that ``puppet`` can parse its arguments without
importing the data files' models (process start)."""

CHECKPOINT_EVERY = 3.0  # s of simulated time between automatic checkpoints (keyframes)
CHECKPOINT_MIN, CHECKPOINT_MAX = 0.5, 600.0  # s; the interval is a multiple of 0.5 s
MIN_SLOWDOWN, MAX_SLOWDOWN = 0.1, 100.0  # wall s per simulated s; 0.1: ten times faster

# the slowdowns the app's slower / faster keys step through: log-spaced, 1x to 100x
SLOWDOWNS = tuple(round(10 ** (i / 6), 2) for i in range(13))  # 1, 1.47, 2.15 ... 100


def nearest_slowdown_index(value: float) -> int:
    return min(range(len(SLOWDOWNS)), key=lambda i: abs(SLOWDOWNS[i] - value))


def stepped_slowdown(slowdown: float, index: int, slower: bool) -> tuple[float, int]:
    """(slowdown, index) after the app's slower (or faster) key: one step along
    ``SLOWDOWNS``; faster stops at 1x (a chosen fast-forward below it stays). The
    window's clock and a playtest's reading of a log follow this one rule."""
    if slower:
        index = min(index + 1, len(SLOWDOWNS) - 1)
        return SLOWDOWNS[index], index
    if slowdown <= SLOWDOWNS[0]:
        return slowdown, index
    index = max(index - 1, 0)
    return SLOWDOWNS[index], index
