"""What the chamfered point and the countersink change: snap share, turn and click.

Run:  python docs/scripts/ends_study.py [--workers 2] [--work DIR] [--out docs/figures/ends.png]

For 1/4-20 UNC-2A/2B and M6x1-6g/6H at mean material, default compliance (10 N, 1 N m/rad,
held laterally, friction 0.15), two pairs of parts each: the thesis's flat tip and flat,
sharp-edged bore, and the standard ends a designation gets (a 45-degree chamfer to 0.1
pitch below the minor diameter, a 120-degree countersink of the standard nut's diameter;
docs/conventions.md, "Ends"). Each is swept on the grid of ``threadmate run`` (held roll
and pitch -2..2 by 1 degree, start phases every 20 degrees), its network built, and every
start's passive search to the snap read off (``threadmate.network.start_outcomes``).
Prints the Markdown table of docs/validation.md, "Flat ends against the standard ends"
(``python docs/scripts/validation.py --ends FILE`` reads this output), and writes the
figure.
Libraries are kept in ``--work`` (resumable).
"""

from __future__ import annotations

import argparse
import json
import math
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from threadmate.geometry import spec_from_designation  # noqa: E402
from threadmate.library import sweep  # noqa: E402
from threadmate.network import from_library, start_outcomes  # noqa: E402

PAIRS = ("1/4-20 UNC-2A/2B", "M6x1-6g/6H")
PARTS = {"flat (thesis)": {"point": "flat", "countersink": False}, "chamfer + countersink": {}}
GRID = ("-2:2:1", "-2:2:1", "0:340:20")


def _summary(outcomes, thread_pitch: float) -> dict[str, float]:
    ok = outcomes[~outcomes["failed"]]
    snapped = ok[ok["snapped"]]
    size = np.hypot(ok["held_roll"], ok["held_pitch"])
    upright = ok[size < 1e-9]
    return {
        "starts": int(len(outcomes)),
        "failed": int(outcomes["failed"].sum()),
        "share_snap": float(ok["snapped"].mean()),
        "share_snap_upright": float(upright["snapped"].mean()) if len(upright) else math.nan,
        "share_snap_2deg": float(ok[size >= 2 - 1e-9]["snapped"].mean()),
        "turn_mean": float(snapped["turn"].mean()),
        "turn_worst": float(snapped["turn"].max()),
        "click_mean": float(snapped["click"].mean()),
        "click_mean_pitches": float(snapped["click"].mean() / thread_pitch),
        "work_mean": float(snapped["work"].mean()),
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--work", default="ends-study")
    parser.add_argument("--out", default="docs/figures/ends.png")
    args = parser.parse_args()
    work = Path(args.work)
    rows = []
    for designation in PAIRS:
        for label, parts in PARTS.items():
            spec = spec_from_designation(designation, **parts)
            lib = work / f"{designation.split('-')[0].replace('/', '_')}-{label.split()[0]}"
            sweep(spec, *GRID, out=lib, workers=args.workers)
            outcomes = start_outcomes(from_library(lib))
            row = {"pair": designation, "parts": label, "units": spec.units}
            row.update(_summary(outcomes, spec.pitch))
            rows.append(row)
            print(json.dumps(row), flush=True)

    print()
    print(
        "| pair | parts | snap within a turn | upright | at 2 deg | turn mean / worst (deg) "
        "| click mean | work mean (mJ) |"
    )
    print("|---|---|---|---|---|---|---|---|")
    for r in rows:
        print(
            f"| {r['pair']} | {r['parts']} | {r['share_snap']:.0%} | "
            f"{r['share_snap_upright']:.0%} | {r['share_snap_2deg']:.0%} | "
            f"{r['turn_mean']:.0f} / {r['turn_worst']:.0f} | "
            f"{r['click_mean']:.4g} {r['units']} ({r['click_mean_pitches']:.2f} P) | "
            f"{r['work_mean']:.1f} |"
        )

    fig, axes = plt.subplots(1, 3, figsize=(11, 3.4))
    x = np.arange(len(PAIRS))
    width = 0.38
    for k, label in enumerate(PARTS):
        sel = [r for r in rows if r["parts"] == label]
        for ax, key, scale in (
            (axes[0], "share_snap", 100.0),
            (axes[1], "turn_mean", 1.0),
            (axes[2], "click_mean_pitches", 1.0),
        ):
            ax.bar(x + (k - 0.5) * width, [r[key] * scale for r in sel], width, label=label)
    for ax, title in zip(
        axes,
        (
            "starts that snap within a turn (%)",
            "mean turn to the snap (deg)",
            "mean click (pitches)",
        ),
        strict=True,
    ):
        ax.set_xticks(x, PAIRS)
        ax.set_title(title, fontsize=10)
    axes[0].legend(fontsize=8, loc="lower left")
    fig.suptitle(
        "Flat ends (the thesis) against a chamfered point and a countersunk nut", fontsize=11
    )
    fig.tight_layout()
    Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(args.out, dpi=120)
    print(f"figure: {args.out}")


if __name__ == "__main__":
    main()
