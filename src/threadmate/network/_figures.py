"""Figures read off the network: the click signature along a path, the click against the
tilt over every start."""

from __future__ import annotations

import os
from pathlib import Path

import networkx as nx
import numpy as np
import pandas as pd

from .._figures import Mark, new_figure, save_figure, signature_figure
from ._paths import PathResult

__all__ = ["plot_click_signature", "plot_click_vs_tilt"]


def plot_click_signature(
    graph: nx.DiGraph, result: PathResult, path: str | os.PathLike[str]
) -> Path:
    """What a robot's sensors see along a passive path: the height of the compliance
    centre, the bolt's tilt and the driver torque against the phase turned, with the jumps
    and the snap marked (the states the library holds: grid phases and both sides of each
    jump). The drawing a search's snap signature shares
    (:func:`threadmate.contact.plot_search`)."""
    nodes = [graph.nodes[n] for n in result.path]
    turned = np.concatenate(
        [
            [0.0],
            np.cumsum(
                [
                    graph.edges[u, v]["turn"]
                    for u, v in zip(result.path, result.path[1:], strict=False)
                ]
            ),
        ]
    )
    units = graph.graph.get("units", "in")
    fig = signature_figure(
        turned.tolist(),
        [d["centre_z"] for d in nodes],
        [d["roll"] for d in nodes],
        [d["pitch"] for d in nodes],
        [d["driver_torque"] for d in nodes],
        units=units,
        xlabel=f"turn from the start (deg); start {result.start}",
        title=(
            f"click signature: snap after {result.turn:.1f} deg, click "
            f"{result.snap['click']:.4g} {units}"
        ),
        marks=[
            Mark(turned[i + 1], kind == "snap")
            for i, kind in enumerate(result.kinds)
            if kind in ("jump", "snap")
        ],
        size=(7.0, 6.0),
    )
    return save_figure(fig, path)


def plot_click_vs_tilt(outcomes: pd.DataFrame, path: str | os.PathLike[str], units: str) -> Path:
    """The click (the fall a sensor sees at the snap, within a degree of turn) and the turn
    to it against the held tilt's size, one point per start that snaps within a turn
    (starts already in phase left out), with the mean per size, and each snap's window
    (where the snap may come earlier)."""
    ok = outcomes[outcomes["snapped"] & (outcomes["turn"] > 0)].copy()
    ok["tilt"] = np.hypot(ok["held_roll"], ok["held_pitch"])
    fig = new_figure((7.0, 5.0))
    ax1, ax2 = fig.subplots(2, 1, sharex=True)
    ax1.plot(ok["tilt"], ok["click"], ".", color="#9ecae1", ms=3)
    ax2.plot(ok["tilt"], ok["turn"], ".", color="#9ecae1", ms=3)
    if "snap_window" in ok and bool((ok["snap_window"] > 0).any()):
        # Where the snap is a window, the snap may come anywhere in it: drawn down from
        # the snap's turn to the window's start.
        win = ok[ok["snap_window"] > 0]
        ax2.vlines(
            win["tilt"],
            win["turn"] - win["snap_window"],
            win["turn"],
            color="#fdae6b",
            lw=1.0,
            label="snap window",
        )
        ax2.legend(fontsize=8)
    means = ok.groupby(ok["tilt"].round(6))[["click", "turn"]].mean()
    ax1.plot(means.index, means["click"], "o-", color="#08519c", label="mean")
    ax2.plot(means.index, means["turn"], "o-", color="#08519c")
    ax1.set_ylabel(f"click ({units})")
    ax2.set_ylabel("turn to the snap (deg)")
    ax2.set_xlabel("held tilt size sqrt(roll^2 + pitch^2) (deg)")
    ax1.legend(fontsize=8)
    ax1.set_title("the click against the tilt (every start that snaps within a turn)", fontsize=9)
    return save_figure(fig, path)
