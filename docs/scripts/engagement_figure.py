"""The figure of docs/mechanics.md, "In phase: engaged": what in phase means, seen in the
height of the compliance centre as the bolt turns.

Two starts of the thesis's flat 1/4-20 pair (default compliance but frictionless, so that
the heights alone tell the story): the search counter-clockwise to the snap, then the
screw-in that proves it, clockwise from the snap. A state in phase (every load-carrying
contact on the helices) moves along the helix as it turns: its compliance centre rises
or falls the lead, pitch / 360 per degree (the dashed slopes). The second start lands in
phase tilted; screwed in, it is pinched between the nut's flank below and the edge of the
nut's thread start above, and rights itself as it goes in.

    python docs/scripts/engagement_figure.py [--out docs/figures/engagement.png]
"""

from __future__ import annotations

import argparse
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from threadmate.contact import Compliance, Continuation, Mechanics, search  # noqa: E402
from threadmate.geometry import spec_from_designation  # noqa: E402

COLOURS = {
    "stable": "#31a354",
    "quasi-stable": "#fd8d3c",
    "unstable": "0.6",
    "in-phase": "#3182bd",
}
STARTS = [
    ((0.0, 0.0), 40.0, "held upright, from 40 deg: snaps and screws in"),
    ((0.0, -3.0), 30.0, "held pitch -3 deg, from 30 deg: lands tilted, rights itself screwed in"),
]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path, default=Path("docs/figures/engagement.png"))
    args = ap.parse_args()
    spec = spec_from_designation("1/4-20 UNC-2A/2B", point="flat", countersink=False)
    mech = Mechanics(spec, Compliance(friction=0.0))
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.5), sharey=True)
    for ax, ((roll, pitch), phase, title) in zip(axes, STARTS, strict=True):
        # Unproved (screw_in 0), the search stops at the first landing in phase.
        run = search(mech, roll, pitch, phase, screw_in=0.0)
        landing = run.states[-1]
        walk = Continuation(mech, roll, pitch, sense="tighten", contact_changes=False)
        _, _, back = walk.advance(landing, landing.phase, 180.0)
        near = [s for s in run.states if s.phase >= landing.phase - 60.0]
        for states, marker in ((near, "o"), (back, "s")):
            for s in states:
                ax.plot(
                    s.phase,
                    s.centre[2],
                    marker,
                    ms=3.5,
                    color=COLOURS[s.classification],
                    mfc="none" if marker == "s" else COLOURS[s.classification],
                )
        lead = spec.lead / 360.0
        x0, z0 = landing.phase, landing.centre[2]
        ax.plot([x0 - 180, x0 + 20], [z0 - 180 * lead, z0 + 20 * lead], "k--", lw=0.8)
        ax.set_title(title, fontsize="medium")
        ax.set_xlabel("phase [deg] (search: increasing; screw-in, open squares: decreasing)")
        ax.grid(True, color="0.92")
    axes[0].set_ylabel(f"compliance centre height [{spec.units}]")
    handles = [plt.Line2D([], [], marker="o", ls="", color=c, label=k) for k, c in COLOURS.items()]
    handles.append(plt.Line2D([], [], ls="--", color="k", lw=0.8, label="the lead, P/360 per deg"))
    axes[1].legend(handles=handles, fontsize="small", loc="lower right")
    fig.suptitle(
        "In phase is engaged: turning moves the bolt along the helix (1/4-20, flat ends, "
        "F 10 N, k 1 N m/rad, frictionless)",
        fontsize="medium",
    )
    fig.tight_layout()
    args.out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(args.out, dpi=120)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
