"""The envelope's polar figure: tolerated tilt against direction."""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

import numpy as np

from .._figures import new_figure, save_figure
from ._envelope import LEVELS, Envelope, directions_of, levels_of

__all__ = ["plot_envelope"]

_STYLES = {1.0: ("#1f77b4", "-"), 0.95: ("#ff7f0e", "--"), 0.5: ("#2ca02c", ":")}


def plot_envelope(env: Envelope, path: str | os.PathLike[str]) -> Path:
    """The capture envelope on polar axes: for each direction (the azimuth in F from +X
    toward +Y toward which the bolt leans, counter-clockwise from the right), the tilt
    (degrees, radius) up to which every start phase, 95 % and 50 % of them snap within one
    turn; the tolerated misalignment drawn as a circle. Written atomically (.png, .pdf or
    .svg by the suffix)."""
    fig = new_figure((6.0, 6.4))
    ax: Any = fig.add_subplot(projection="polar")  # PolarAxes: set_rlim, set_theta_*
    theta = np.radians(directions_of(env))
    closed = np.append(theta, theta[0] + 2 * np.pi) if len(theta) > 1 else theta
    top = 0.0
    for level in LEVELS:
        r = levels_of(env, level)
        top = max(top, float(r.max()))
        colour, style = _STYLES[level]
        values = np.append(r, r[0]) if len(theta) > 1 else r
        ax.plot(
            closed,
            values,
            style,
            color=colour,
            marker="o",
            ms=3,
            label=f"{100 * level:g} % of phases snap",
        )
    tolerated = env.tolerated_tilt
    ring = np.linspace(0, 2 * np.pi, 181)
    ax.plot(
        ring,
        np.full_like(ring, tolerated),
        color="0.3",
        lw=0.8,
        ls="-.",
        label=f"tolerated: {tolerated:.2f} deg",
    )
    largest = max((x["shares"][-1][0] for x in env.directions if x["shares"]), default=0.0)
    ax.set_rlim(0, max(top, tolerated, largest) * 1.05 or 1.0)
    ax.set_theta_zero_location("E")
    ax.set_theta_direction(1)
    c = env.compliance
    k = c["stiffness"]
    ax.set_title(
        f"capture envelope (tilt, deg) against direction\nF {c['force']:g} N, k "
        f"{k['roll']:g}/{k['pitch']:g} N m/rad, friction {c['friction']:g}; "
        + (f"bisected to {env.tolerance:g} deg" if env.located else "read off the grid"),
        fontsize="medium",
    )
    ax.legend(loc="lower center", bbox_to_anchor=(0.5, -0.2), ncol=2, fontsize=8)
    return save_figure(fig, path)
