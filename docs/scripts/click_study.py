"""The click and the turn to the snap against the size and direction of the tilt.

Run:  python docs/scripts/click_study.py [--start 30] [--out docs/figures/click.png]

1/4-20 UNC-2A/2B at mean material, default compliance (10 N, 1 N m/rad, held laterally,
friction 0.15). For each held tilt of size 0 to 4 degrees toward +X, +Y, -X and -Y (the
direction of the tilt relative to the nut's thread start, which a robot rarely knows),
the counter-clockwise search from the start phase is simulated for one turn. Prints the
Markdown table of docs/validation.md, "The click against the tilt" (``python
docs/scripts/validation.py --click FILE`` reads this output), and writes the figure.
"""

from __future__ import annotations

import argparse
import json
import math
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from threadmate.contact import Compliance, Mechanics, search  # noqa: E402
from threadmate.geometry import spec_from_designation  # noqa: E402

SIZES = (0.0, 0.5, 1.0, 2.0, 3.0, 4.0)
DIRECTIONS = {"+X": 0.0, "+Y": 90.0, "-X": 180.0, "-Y": 270.0}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--start", type=float, default=30.0, help="start phase (deg)")
    parser.add_argument("--out", default="docs/figures/click.png")
    args = parser.parse_args()
    spec = spec_from_designation("1/4-20 UNC-2A/2B", point="flat", countersink=False)
    mech = Mechanics(spec, Compliance())
    rows = []
    for size in SIZES:
        for name, direction in DIRECTIONS.items():
            if size == 0 and name != "+X":
                continue
            roll = size * math.cos(math.radians(direction))
            pitch = size * math.sin(math.radians(direction))
            run = search(mech, roll, pitch, args.start, turns=1.0, step=5.0)
            rows.append(
                {
                    "size": size,
                    "direction": name if size else "-",
                    "roll": roll,
                    "pitch": pitch,
                    "snap_turn": run.snap_turn,
                    "click": None if run.snap is None else run.snap.click,
                    "tilt_change": None if run.snap is None else run.snap.tilt_change,
                    "work": run.work,
                    "events": len(run.events),
                    "jumps": sum(e.kind == "jump" for e in run.events),
                }
            )
            print(json.dumps(rows[-1]), flush=True)
    clearance = spec.axial_clearance
    print(f"\naxial clearance (pitch-diameter difference / sqrt 3): {clearance:.5f} in\n")
    print(
        "| tilt (deg) | toward | turn to snap (deg) | click (in) | click / clearance | "
        "axis jump at snap (deg) | other jumps | driver's work (mJ) |"
    )
    print("|---|---|---|---|---|---|---|---|")
    for r in rows:
        snap = "no snap in 1 turn" if r["snap_turn"] is None else f"{r['snap_turn']:.2f}"
        click = "-" if r["click"] is None else f"{r['click']:.5f}"
        ratio = "-" if r["click"] is None else f"{r['click'] / clearance:.2f}"
        jump = "-" if r["tilt_change"] is None else f"{r['tilt_change']:.2f}"
        others = r["jumps"]
        print(
            f"| {r['size']:g} | {r['direction']} | {snap} | {click} | {ratio} | {jump} | "
            f"{others} | {r['work']:.2f} |"
        )
    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(6.4, 6.4), sharex=True)
    for name in DIRECTIONS:
        pts = [r for r in rows if r["direction"] in (name, "-")]
        xs = [r["size"] for r in pts if r["click"] is not None]
        ax1.plot(
            xs,
            [r["click"] / clearance for r in pts if r["click"] is not None],
            "o-",
            label=f"toward {name}",
        )
        ax2.plot(
            xs,
            [r["snap_turn"] for r in pts if r["click"] is not None],
            "o-",
            label=f"toward {name}",
        )
    ax1.axhline(1.0, color="0.6", lw=0.8, ls="--")
    ax1.set_ylabel("click / axial clearance")
    ax1.set_title("1/4-20 UNC-2A/2B, 10 N, 1 N m/rad: the snap against the tilt")
    ax1.legend(fontsize=8)
    ax2.set_ylabel(f"turn to snap from {args.start:g} deg (deg)")
    ax2.set_xlabel("held tilt (deg)")
    Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    fig.tight_layout()
    fig.savefig(args.out, dpi=120)


if __name__ == "__main__":
    main()
