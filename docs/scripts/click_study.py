"""The click and the turn to the snap against the size and direction of the tilt.

Run:  python docs/scripts/click_study.py [--spec DESIGNATION] [--sizes 0,0.5,1,2,3,4]
          [--directions 4] [--start 30] [--out docs/figures/click.png]

A designation (default 1/4-20 UNC-2A/2B) with the thesis's flat parts at mean material,
default compliance (10 N, 1 N m/rad, held laterally, friction 0.15). For each held tilt
of the given sizes toward each of ``--directions`` directions evenly spread from +X (4:
+X, +Y, -X and -Y; the direction of the tilt relative to the nut's thread start, which a
robot rarely knows), the counter-clockwise search from the start phase is simulated for
one turn. Prints one JSON row per search and the Markdown table (``python
docs/scripts/validation.py --click FILE``, or ``--small-tilts FILE`` for the published
observation's 1/2-in bolt, reads this output), and writes the figure.
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

SIZES = "0,0.5,1,2,3,4"
NAMED = {0.0: "+X", 90.0: "+Y", 180.0: "-X", 270.0: "-Y"}


def _direction_name(angle: float) -> str:
    return NAMED.get(angle, f"{angle:g} deg")


def main() -> None:
    parser = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    parser.add_argument("--spec", default="1/4-20 UNC-2A/2B", help="designation")
    parser.add_argument("--sizes", default=SIZES, help="held tilts (deg), comma list")
    parser.add_argument(
        "--directions", type=int, default=4, help="directions evenly spread from +X"
    )
    parser.add_argument("--start", type=float, default=30.0, help="start phase (deg)")
    parser.add_argument("--out", default="docs/figures/click.png")
    args = parser.parse_args()
    spec = spec_from_designation(args.spec, point="flat", countersink=False)
    sizes = [float(v) for v in args.sizes.split(",")]
    directions = [360.0 * k / args.directions for k in range(args.directions)]
    clearance = spec.axial_clearance
    mech = Mechanics(spec, Compliance())
    rows = []
    for size in sizes:
        for direction in directions:
            if size == 0 and direction != directions[0]:
                continue
            roll = size * math.cos(math.radians(direction))
            pitch = size * math.sin(math.radians(direction))
            run = search(mech, roll, pitch, args.start, turns=1.0, step=5.0)
            rows.append(
                {
                    "designation": args.spec,
                    "units": spec.units,
                    "clearance": clearance,
                    "start": args.start,
                    "size": size,
                    "direction": _direction_name(direction) if size else "-",
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
    print(f"\naxial clearance (pitch-diameter difference / sqrt 3): {clearance:.5f} {spec.units}\n")
    print(
        f"| tilt (deg) | toward | turn to snap (deg) | click ({spec.units}) | "
        "click / clearance | axis jump at snap (deg) | other jumps | driver's work (mJ) |"
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
    for direction in directions:
        name = _direction_name(direction)
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
    ax1.set_title(f"{args.spec}, 10 N, 1 N m/rad: the snap against the tilt")
    ax1.legend(fontsize=8, ncol=2 if len(directions) > 4 else 1)
    ax2.set_ylabel(f"turn to snap from {args.start:g} deg (deg)")
    ax2.set_xlabel("held tilt (deg)")
    Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    fig.tight_layout()
    fig.savefig(args.out, dpi=120)


if __name__ == "__main__":
    main()
