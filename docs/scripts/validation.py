"""Write docs/validation.md: what threadmate's mechanics measures against independent answers.

Run:  python docs/scripts/validation.py [--dynamics FILE] [--run DIR] [--out docs/validation.md]

Every figure on the page is computed by this script when it runs (nothing is copied from
an earlier run), each beside the independent answer it is checked against:

- **Closed forms** (docs/mechanics.md, "Limits with closed forms"): the flat 1/4-20
  UNC-2A/2B pair upright and stiffly held (1e2 N m/rad) snaps where the in-phase window
  opens, ``360 (1 - c / (2 lead))``, and drops by the axial flank clearance
  ``c = (nut pd - bolt pd) / sqrt(3)``; held through 1 N m/rad it snaps at the same edge.
- **The snap proved** by screwing in: the tilted landing of the flat pair held (0, -3)
  from 30 degrees, pinched between the nut's flank below and the edge of its thread start
  above, screwed in half a turn: the descent per turn against the lead, the tilt at the
  end.
- **The snap's window**: the standard parts (chamfered point, countersunk nut) held (1, 1)
  from 0 degrees.
- **An independent dynamics simulation** (``--dynamics FILE``: the JSON that
  ``docs/scripts/dynamics_check.py --json FILE`` writes): MuJoCo's snap phase and click
  against the quasi-static search's, start by start.
- **The default run** (``--run DIR``: a ``threadmate run`` directory): its counts, read
  from the files it wrote.

The page records the date, the commit and the host's load (``uptime``): timings on a
shared host are comparable only within one run.
"""

from __future__ import annotations

import argparse
import datetime
import json
import math
import os
import subprocess
import sys
import time
from pathlib import Path

from threadmate.contact import Compliance, Continuation, Mechanics, search
from threadmate.geometry import spec_from_designation

ROOT = Path(__file__).resolve().parents[2]


def _load() -> str:
    try:
        return os.getloadavg().__repr__()
    except OSError:  # pragma: no cover - not on every platform
        return "unknown"


def _commit() -> str:
    try:
        out = subprocess.run(
            ["git", "-C", str(ROOT), "rev-parse", "--short", "HEAD"],
            capture_output=True,
            text=True,
            check=True,
        )
        dirty = subprocess.run(
            ["git", "-C", str(ROOT), "status", "--porcelain", "--untracked-files=no"],
            capture_output=True,
            text=True,
            check=True,
        )
    except (OSError, subprocess.CalledProcessError):
        return "unknown"
    return out.stdout.strip() + (" (with uncommitted changes)" if dirty.stdout.strip() else "")


def _tilt(roll: float, pitch: float) -> float:
    """Angle of the bolt axis off the nut's (degrees)."""
    c = math.cos(math.radians(roll)) * math.cos(math.radians(pitch))
    return math.degrees(math.acos(max(-1.0, min(1.0, c))))


def closed_forms(lines: list[str]) -> None:
    spec = spec_from_designation("1/4-20 UNC-2A/2B", point="flat", countersink=False)
    c = (spec.nut.pitch_diameter - spec.bolt.pitch_diameter) / math.sqrt(3.0)
    edge = 360.0 * (1.0 - c / (2.0 * spec.lead))
    lines += [
        "## Closed forms: the upright bolt",
        "",
        "Flat 1/4-20 UNC-2A/2B (flat tip, flat bore edge), upright, from phase 40 degrees, "
        "10 N, frictionless. The closed form: the snap where the in-phase window opens, "
        f"{edge:.3f} degrees, by the axial flank clearance c = {c:.6f} in.",
        "",
        "| stiffness (N m/rad) | snap (deg) | closed form (deg) | click (in) | c (in) | time (s) |",
        "|---:|---:|---:|---:|---:|---:|",
    ]
    for k in (100.0, 1.0):
        t = time.process_time()
        run = search(spec, 0.0, 0.0, 40.0, compliance=Compliance(stiffness=k, friction=0.0))
        took = time.process_time() - t
        snap = run.snap
        if snap is None:
            lines.append(f"| {k:g} | none | {edge:.3f} | - | {c:.6f} | {took:.1f} |")
        else:
            lines.append(
                f"| {k:g} | {snap.phase:.3f} | {edge:.3f} | {snap.drop:.6f} | {c:.6f} | "
                f"{took:.1f} |"
            )
    lines += [
        "",
        "Held through 1 N m/rad the bolt tips a little as it rides onto the edge where the "
        "nut's thread starts, and lands on that edge: its click is less than c.",
        "",
    ]


def pinched_screw_in(lines: list[str]) -> None:
    spec = spec_from_designation("1/4-20 UNC-2A/2B", point="flat", countersink=False)
    mech = Mechanics(spec, Compliance(friction=0.0))
    t = time.process_time()
    run = search(mech, 0.0, -3.0, 30.0)
    lines += [
        "## The snap proved: a tilted landing screwed in",
        "",
        "Flat 1/4-20 held (0, -3) degrees from 30 degrees, 10 N, 1 N m/rad, frictionless. "
        "The landing is pinched as it is screwed in (the tip on the nut's flank below, the "
        "edge of the nut's thread start over the bolt's crest); the bolt must right itself "
        "to go on.",
        "",
    ]
    if run.snap is None or run.snap.engagement is None:
        lines += ["No snap within the turn.", ""]
        return
    landing = run.states[-1]
    walk = Continuation(mech, 0.0, -3.0, contact_changes=False, sense="tighten")
    _, events, states = walk.advance(landing, run.snap.phase, 180.0)
    took = time.process_time() - t
    proof = run.snap.engagement
    jumps = [e for e in events if abs(e.drop) > spec.pitch / 40]
    lines += [
        "| snap (deg) | click (in) | descent per turn (in) | lead (in) | tilt at landing "
        "(deg) | tilt after half a turn (deg) | jumps in the screw-in | time (s) |",
        "|---:|---:|---:|---:|---:|---:|---:|---:|",
        f"| {run.snap.phase:.3f} | {run.snap.drop:.6f} | {proof.descent:.5f} | "
        f"{spec.lead:.5f} | {_tilt(landing.roll, landing.pitch):.3f} | "
        f"{_tilt(states[-1].roll, states[-1].pitch):.3f} | {len(jumps)} | {took:.1f} |",
        "",
    ]


def snap_window(lines: list[str]) -> None:
    spec = spec_from_designation("1/4-20 UNC-2A/2B")
    t = time.process_time()
    run = search(spec, 1.0, 1.0, 0.0)
    took = time.process_time() - t
    lines += [
        "## The snap's window",
        "",
        "Standard 1/4-20 parts (chamfered point, countersunk nut) held (1, 1) from 0 "
        "degrees, default compliance.",
        "",
    ]
    if run.snap is None or run.snap_window is None:
        lines += ["No snap within the turn.", ""]
        return
    lo, hi = run.snap_window
    lines += [
        "| snap (deg) | window (deg) | click (in) | time (s) |",
        "|---:|---:|---:|---:|",
        f"| {run.snap.phase:.3f} | {lo:.2f} to {hi:.2f} | {run.snap.drop:.6f} | {took:.1f} |",
        "",
    ]


def dynamics(lines: list[str], path: Path) -> None:
    rows = json.loads(path.read_text(encoding="utf-8"))
    lines += [
        "## Against an independent dynamics simulation",
        "",
        f"From `{path.name}` (`docs/scripts/dynamics_check.py --json`): MuJoCo with convex "
        "pieces from the exact profile, frictionless, turned slowly and heavily damped, "
        "against `threadmate search` on the same compliance.",
        "",
        "The click is the last jump's drop; the whole fall runs from the last state of "
        "the smooth ride to the landing (a sensor sees it whole where the jumps come "
        "within a fraction of a degree).",
        "",
        "| case | snap (deg): threadmate | simulated | difference | click: threadmate | "
        "simulated | whole fall: threadmate | simulated | difference |",
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]

    def num(v: float | None, fmt: str) -> str:
        return "-" if v is None else format(v, fmt)

    for r in rows:
        a, b = r.get("threadmate_snap_phase"), r.get("sim_snap_phase")
        fa, fb = r.get("threadmate_fall"), r.get("sim_fall")
        held = f"held ({r['held_roll']:g}, {r['held_pitch']:g}) from {r['start_phase']:g}"
        lines.append(
            f"| {r['case']}: {held}, {r['stiffness']:g} N m/rad | {num(a, '.2f')} | "
            f"{num(b, '.2f')} | {'-' if a is None or b is None else f'{b - a:+.2f}'} | "
            f"{num(r.get('threadmate_click'), '.6f')} | {num(r.get('sim_click'), '.6f')} | "
            f"{num(fa, '.6f')} | {num(fb, '.6f')} | "
            f"{'-' if not fa or fb is None else f'{(fb - fa) / fa:+.1%}'} |"
        )
    lines.append("")


def default_run(lines: list[str], run_dir: Path) -> None:
    report = run_dir / "report.md"
    lines += ["## The default run", ""]
    if not report.is_file():
        lines += [f"No report in `{run_dir.name}`.", ""]
        return
    text = report.read_text(encoding="utf-8").splitlines()
    wanted = ("- **Pre-tilt", "- With it,", "Starts:", "**")
    keep = [ln for ln in text if ln.startswith(wanted) and "did not reach" not in ln[:40]]
    not_at_rest = [ln for ln in text if "did not reach a rest state" in ln]
    lines += [
        "`threadmate run` on the built-in default (its report's lines):",
        "",
        *(ln if ln.startswith("-") else f"- {ln}" for ln in keep[:3]),
        *(f"- {ln.split(':', 1)[0].strip('*')}" for ln in not_at_rest[:1]),
        "",
    ]


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--dynamics", type=Path, help="dynamics_check.py's JSON")
    parser.add_argument("--run", type=Path, help="a threadmate run directory")
    parser.add_argument("--out", type=Path, default=ROOT / "docs" / "validation.md")
    args = parser.parse_args(argv)
    started = time.time()
    lines = [
        "# Validation: the mechanics against independent answers",
        "",
        "Generated by `python docs/scripts/validation.py` "
        f"on {datetime.date.today().isoformat()} at commit {_commit()}; host load "
        f"(1, 5, 15 min) {_load()} at the start. Times are CPU seconds of this process.",
        "",
    ]
    for step in (closed_forms, pinched_screw_in, snap_window):
        print(f"validation: {step.__name__}", file=sys.stderr, flush=True)
        step(lines)
    if args.dynamics is not None:
        dynamics(lines, args.dynamics)
    if args.run is not None:
        default_run(lines, args.run)
    lines += [f"Load at the end {_load()}; {time.time() - started:.0f} s wall.", ""]
    tmp = args.out.with_suffix(".md.tmp")
    tmp.write_text("\n".join(lines), encoding="utf-8")
    tmp.replace(args.out)
    print(f"validation: wrote {args.out}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
