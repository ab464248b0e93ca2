"""Plot a replay's joint targets against the actual joint angles over time.

matplotlib draws it, through its Agg canvas only: no pyplot, no window, no global
backend switch (safe in tests and next to a pygame window).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from puppet.timeline.trajectory import Trajectory

TARGET_COLOR = "#d9822b"
ANGLE_COLOR = "#1f4e8c"


def plot_joints(traj: Trajectory, title: str | None = None,
                limits: dict[str, tuple[float, float]] | None = None):
    """A matplotlib Figure with one subplot per actuated joint (``traj.joints`` order):
    the PD target (dashed) and the actual angle (solid), in degrees, against simulated
    time. ``limits`` (joint -> (lo, hi) degrees) are drawn as faint lines."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    n = max(1, len(traj.joints))
    fig = Figure(figsize=(10, 1.2 + 2.0 * n), dpi=100, layout="constrained")
    FigureCanvasAgg(fig)
    axes = fig.subplots(n, 1, sharex=True, squeeze=False)[:, 0]
    if not traj.joints:
        axes[0].text(0.5, 0.5, "no actuated joints", ha="center", va="center",
                     transform=axes[0].transAxes)
    for j, (ax, name) in enumerate(zip(axes, traj.joints)):
        ax.plot(traj.t, np.degrees(traj.joint_target[:, j]), "--",
                color=TARGET_COLOR, lw=1.4, label="target")
        ax.plot(traj.t, np.degrees(traj.joint_angle[:, j]), "-",
                color=ANGLE_COLOR, lw=1.4, label="angle")
        if limits and name in limits:
            for v in limits[name]:
                ax.axhline(v, color="0.6", lw=0.8, ls=":")
        ax.set_ylabel(f"{name}\n(deg)")
        ax.grid(True, color="0.9")
        ax.legend(loc="upper right", fontsize="small", framealpha=0.8)
    axes[-1].set_xlabel("simulated time (s)")
    if title:
        fig.suptitle(title)
    return fig


def joint_limits(character_spec) -> dict[str, tuple[float, float]]:
    """Joint limits in degrees, by joint name, from a character spec."""
    return {j.name: tuple(j.limits) for j in character_spec.joints if j.limits is not None}


def save_joint_plot(traj: Trajectory, path: str | Path, title: str | None = None,
                    limits: dict[str, tuple[float, float]] | None = None):
    """Write the plot (PNG, or any format matplotlib knows by the extension); returns
    the Figure."""
    fig = plot_joints(traj, title, limits)
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(str(path))
    return fig
