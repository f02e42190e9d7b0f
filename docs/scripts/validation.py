"""Write docs/validation.md: the measured figures the documentation rests on.

Run:  python docs/scripts/validation.py [--sections NAMES] [--dynamics FILE] [--click FILE]
          [--small-tilts FILE] [--ends FILE] [--run DIR] [--bench NAME=FILE ...]
          [--out docs/validation.md]

The other pages (mechanics.md, network.md, stages.md) say what threadmate computes and
why; every figure measured on a run of it is on this page, each section stamped with the
date, the commit and the machine it was measured on and the command that measures it
again. Sections, in page order, by where their figures come from:

- **computed here** (``--sections``, a comma list of ``closed-forms``, ``screw-in``,
  ``window``, ``thesis``; ``all``, the default, or ``none``), a minute in all:

  - closed forms (docs/mechanics.md, "Limits with closed forms"): the flat 1/4-20
    UNC-2A/2B pair upright and stiffly held (1e2 N m/rad) snaps where the in-phase window
    opens, ``360 (1 - c / (2 lead))``, and drops by the axial flank clearance
    ``c = (nut pd - bolt pd) / sqrt(3)``; held through 1 N m/rad it snaps at the same edge;
  - the snap proved by screwing in: the tilted landing of the flat pair held (0, -3) from
    30 degrees, pinched between the nut's flank below and the edge of its thread start
    above, screwed in half a turn: the descent per turn against the lead, the tilt at the
    end;
  - the snap's window: the standard parts (chamfered point, countersunk nut) held (1, 1)
    from 0 degrees;
  - the thesis's examples (``docs/scripts/thesis_examples.py``): its four named poses
    under its fixed-pivot procedure and under the mechanics;

- **read from a study's output** (the studies take minutes to hours):

  - ``--dynamics FILE``: the JSON of ``docs/scripts/dynamics_check.py --json FILE``,
    MuJoCo's snap phase and click against the quasi-static search's, start by start;
  - ``--click FILE``: what ``python docs/scripts/click_study.py > FILE`` prints, the click
    and the turn to the snap against the tilt;
  - ``--small-tilts FILE``: the same study of a 1/2-in pair at a degree and less
    (``click_study.py --spec '1/2-13 UNC-2A/2B' --sizes 0,0.25,0.5,1 --directions 8``),
    against a published observation of the click;
  - ``--ends FILE``: what ``python docs/scripts/ends_study.py > FILE`` prints, flat ends
    against the standard point and countersink;
  - ``--run DIR``: a ``threadmate run -o DIR`` folder on the built-in default, its counts
    read from the report it wrote;
  - ``--bench NAME=FILE`` (repeatable): what ``python benchmarks/bench_NAME.py`` prints,
    NAME one of ``mechanics``, ``sweep``, ``network``, ``mesh``, ``contact``, given whole;

- **recorded**: measurements with no script input here (the continuation's step, the
  thread starts' sensitivity, the rules' measured effects), each stamped with the commit
  it was measured at.

A section that a run does not compute or read is carried over unchanged from the page at
``--out`` as it stands, with its own stamp: ``--sections none`` with no input rewrites
only the page's header. Timings on a shared host are comparable only within one run; the
stamp gives the host's load (``uptime``) when the section was measured.
"""

from __future__ import annotations

import argparse
import contextlib
import datetime
import io
import json
import math
import os
import platform
import subprocess
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from threadmate.contact import Compliance, Continuation, Mechanics, search
from threadmate.geometry import spec_from_designation

ROOT = Path(__file__).resolve().parents[2]
SCRIPTS = Path(__file__).resolve().parent
TITLE = "# Validation: the measured figures"


def _load() -> str:
    try:
        return ", ".join(f"{v:.2f}" for v in os.getloadavg())
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


def _machine() -> str:
    """The host in a few words: system, processor, cores, Python."""
    cpu = platform.processor() or platform.machine()
    try:
        for line in Path("/proc/cpuinfo").read_text(encoding="utf-8").splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    return (
        f"{platform.system()} {platform.machine()}, {cpu}, {os.cpu_count()} cores, "
        f"Python {platform.python_version()}"
    )


@dataclass(frozen=True)
class Stamp:
    """When, at which commit and on which machine this run measures."""

    date: str
    commit: str
    machine: str

    def measured(self, how: str) -> str:
        """The stamp line of a section computed by this run."""
        return (
            f"*Measured {self.date} at commit {self.commit} on {self.machine}; host load "
            f"(1, 5, 15 min) {_load()} at the start; by {how}.*"
        )

    def read(self, path: Path, how: str) -> str:
        """The stamp line of a section read from a study's output file."""
        written = datetime.date.fromtimestamp(path.stat().st_mtime).isoformat()
        return (
            f"*From `{path.name}`, written {written} by {how}; read {self.date} at commit "
            f"{self.commit} on {self.machine}.*"
        )


def _tilt(roll: float, pitch: float) -> float:
    """Angle of the bolt axis off the nut's (degrees)."""
    c = math.cos(math.radians(roll)) * math.cos(math.radians(pitch))
    return math.degrees(math.acos(max(-1.0, min(1.0, c))))


def _here() -> str:
    return "`python docs/scripts/validation.py`; times are CPU seconds of this process"


def closed_forms(stamp: Stamp) -> list[str]:
    spec = spec_from_designation("1/4-20 UNC-2A/2B", point="flat", countersink=False)
    c = (spec.nut.pitch_diameter - spec.bolt.pitch_diameter) / math.sqrt(3.0)
    edge = 360.0 * (1.0 - c / (2.0 * spec.lead))
    lines = [
        stamp.measured(_here()),
        "",
        "Flat 1/4-20 UNC-2A/2B (flat tip, flat bore edge), upright, from phase 40 degrees, "
        "10 N, frictionless. The closed form: the snap where the in-phase window opens, "
        f"{edge:.3f} degrees, by the axial flank clearance c = {c:.6f} in.",
        "",
        "| stiffness (N m/rad) | snap (deg) | closed form (deg) | drop (in) | c (in) | time (s) |",
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
        "nut's thread starts, and lands on that edge: its drop is less than c.",
    ]
    return lines


def pinched_screw_in(stamp: Stamp) -> list[str]:
    spec = spec_from_designation("1/4-20 UNC-2A/2B", point="flat", countersink=False)
    mech = Mechanics(spec, Compliance(friction=0.0))
    t = time.process_time()
    run = search(mech, 0.0, -3.0, 30.0)
    lines = [
        stamp.measured(_here()),
        "",
        "Flat 1/4-20 held (0, -3) degrees from 30 degrees, 10 N, 1 N m/rad, frictionless. "
        "The landing is pinched as it is screwed in (the tip on the nut's flank below, the "
        "edge of the nut's thread start over the bolt's crest); the bolt must right itself "
        "to go on.",
        "",
    ]
    if run.snap is None or run.snap.engagement is None:
        return [*lines, "No snap within the turn."]
    landing = run.states[-1]
    walk = Continuation(mech, 0.0, -3.0, contact_changes=False, sense="tighten")
    _, events, states = walk.advance(landing, run.snap.phase, 180.0)
    took = time.process_time() - t
    proof = run.snap.engagement
    jumps = [e for e in events if abs(e.drop) > spec.pitch / 40]
    return [
        *lines,
        "| snap (deg) | drop (in) | descent per turn (in) | lead (in) | tilt at landing "
        "(deg) | tilt after half a turn (deg) | jumps in the screw-in | time (s) |",
        "|---:|---:|---:|---:|---:|---:|---:|---:|",
        f"| {run.snap.phase:.3f} | {run.snap.drop:.6f} | {proof.descent:.5f} | "
        f"{spec.lead:.5f} | {_tilt(landing.roll, landing.pitch):.3f} | "
        f"{_tilt(states[-1].roll, states[-1].pitch):.3f} | {len(jumps)} | {took:.1f} |",
    ]


def snap_window(stamp: Stamp) -> list[str]:
    spec = spec_from_designation("1/4-20 UNC-2A/2B")
    t = time.process_time()
    run = search(spec, 1.0, 1.0, 0.0)
    took = time.process_time() - t
    lines = [
        stamp.measured(_here()),
        "",
        "Standard 1/4-20 parts (chamfered point, countersunk nut) held (1, 1) from 0 "
        "degrees, default compliance.",
        "",
    ]
    if run.snap is None or run.snap_window is None:
        return [*lines, "No snap within the turn."]
    lo, hi = run.snap_window
    return [
        *lines,
        "| snap (deg) | window (deg) | drop (in) | time (s) |",
        "|---:|---:|---:|---:|",
        f"| {run.snap.phase:.3f} | {lo:.2f} to {hi:.2f} | {run.snap.drop:.6f} | {took:.1f} |",
    ]


def thesis_examples(stamp: Stamp) -> list[str]:
    """The table ``docs/scripts/thesis_examples.py`` prints, run here."""
    sys.path.insert(0, str(SCRIPTS))
    try:
        import thesis_examples as study  # a script beside this one
    finally:
        sys.path.remove(str(SCRIPTS))
    out = io.StringIO()
    t = time.process_time()
    with contextlib.redirect_stdout(out):
        study.main()
    took = time.process_time() - t
    return [
        stamp.measured(
            f"`python docs/scripts/thesis_examples.py`, run by `python "
            f"docs/scripts/validation.py` in {took:.0f} s of CPU"
        ),
        "",
        "1/4-20 UNC-2A/2B with the thesis's flat parts at mean material. The thesis's "
        '(a, b, phi) are its passive `Rx(a) Ry(b) Rz(phi)` (docs/mechanics.md, "The '
        "thesis's examples\"); ours are the same orientation read in threadmate's "
        "composition. The fixed-pivot model is `threadmate contact`; the mechanics "
        "`threadmate settle` at the default compliance (10 N, 1 N m/rad) and a soft one "
        "(0.01 N m/rad).",
        "",
        *out.getvalue().strip().splitlines(),
        "",
        "The thesis's embedding at (4, 0, 185) was measured on the coarse STL and RAPID of "
        "1999 (0.004 in); on meshes within 5e-6 in the fixed pivot's embedding is the one "
        "in the table, which the thesis's criterion compares with the drop.",
    ]


def _num(v: float | None, fmt: str) -> str:
    return "-" if v is None else format(v, fmt)


def dynamics(stamp: Stamp, path: Path) -> list[str]:
    rows = json.loads(path.read_text(encoding="utf-8"))
    lines = [
        stamp.read(path, f"`python docs/scripts/dynamics_check.py --json {path.name}`"),
        "",
        "MuJoCo with convex pieces from the exact profile, frictionless, turned slowly and "
        "heavily damped, against `threadmate search` on the same compliance: the flat "
        "1/4-20 UNC-2A/2B pair, and the pairs the cases name (`--spec`, with flat ends; "
        "lengths in each pair's units).",
        "",
        "The click is the fall a sensor sees, measured the same way in both: from the "
        "highest the bolt stands within the last degree of turn before the snap "
        "(`CLICK_SPAN`) to the landing (threadmate's `SearchEvent.click`; on the "
        "simulated trace, a cascade of smaller jumps and a steep stretch before the snap "
        "included). The drop is the last jump's own.",
        "",
        "| case | snap (deg): threadmate | simulated | difference | click: threadmate | "
        "simulated | difference | drop: threadmate | simulated |",
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for r in rows:
        a, b = r.get("threadmate_snap_phase"), r.get("sim_snap_phase")
        ca, cb = r.get("threadmate_click"), r.get("sim_click")
        held = f"held ({r['held_roll']:g}, {r['held_pitch']:g}) from {r['start_phase']:g}"
        u = r.get("units", "in")
        lines.append(
            f"| {r['case']}: {held}, {r['stiffness']:g} N m/rad | {_num(a, '.2f')} | "
            f"{_num(b, '.2f')} | {'-' if a is None or b is None else f'{b - a:+.2f}'} | "
            f"{_num(ca, '.6f')} {u} | {_num(cb, '.6f')} {u} | "
            f"{'-' if not ca or cb is None else f'{(cb - ca) / ca:+.1%}'} | "
            f"{_num(r.get('threadmate_jump_drop'), '.6f')} {u} | "
            f"{_num(r.get('sim_jump_drop'), '.6f')} {u} |"
        )
    return lines


def _json_lines(path: Path) -> list[dict]:
    """The JSON objects a study printed, one a line (its other lines skipped)."""
    rows = []
    for line in path.read_text(encoding="utf-8").splitlines():
        if line.startswith("{"):
            rows.append(json.loads(line))
    if not rows:
        raise SystemExit(f"validation: no JSON rows in {path}")
    return rows


def _click_table(rows: list[dict]) -> list[str]:
    """The click study's rows as a Markdown table (click in the spec's units)."""
    units, clearance = rows[0].get("units", "in"), _clearance(rows[0])
    lines = [
        f"| tilt (deg) | toward | turn to snap (deg) | click ({units}) | click / clearance | "
        "axis jump at snap (deg) | other jumps | driver's work (mJ) |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        snap = "no snap in 1 turn" if r["snap_turn"] is None else f"{r['snap_turn']:.2f}"
        click = "-" if r["click"] is None else f"{r['click']:.5f}"
        ratio = "-" if r["click"] is None else f"{r['click'] / clearance:.2f}"
        jump = "-" if r["tilt_change"] is None else f"{r['tilt_change']:.2f}"
        lines.append(
            f"| {r['size']:g} | {r['direction']} | {snap} | {click} | {ratio} | {jump} | "
            f"{r['jumps']} | {r['work']:.2f} |"
        )
    return lines


def _clearance(row: dict) -> float:
    """The axial clearance of the study's pair (its row, or the default 1/4-20's)."""
    if "clearance" in row:
        return float(row["clearance"])
    spec = spec_from_designation("1/4-20 UNC-2A/2B", point="flat", countersink=False)
    return spec.axial_clearance


def click_study(stamp: Stamp, path: Path) -> list[str]:
    rows = _json_lines(path)
    designation = rows[0].get("designation", "1/4-20 UNC-2A/2B")
    units, clearance = rows[0].get("units", "in"), _clearance(rows[0])
    lines = [
        stamp.read(path, f"`python docs/scripts/click_study.py > {path.name}`"),
        "",
        f"{designation} with the thesis's flat parts, default compliance, one turn from "
        "the study's start phase (30 degrees unless `--start`), held tilts of 0 to 4 "
        "degrees toward +X, +Y, -X and -Y (the direction of the tilt relative to the "
        "nut's thread start). The click is the fall of the compliance centre a sensor "
        "sees at the snap (from the highest the bolt stands within the last degree of "
        f"turn to the landing); the axial clearance (pitch-diameter difference / sqrt 3) "
        f"is {clearance:.5f} {units}. Figure: [figures/click.png](figures/click.png).",
        "",
    ]
    return lines + _click_table(rows)


def small_tilts(stamp: Stamp, path: Path) -> list[str]:
    """The published observation: the click of a 1/2-in pair at tilts of a degree and
    less, whose size is conjectured to shrink as the angle between the axes grows."""
    rows = _json_lines(path)
    designation = rows[0].get("designation", "?")
    units, clearance = rows[0].get("units", "in"), _clearance(rows[0])
    directions = sorted({r["direction"] for r in rows if r["direction"] != "-"})
    sizes = sorted({r["size"] for r in rows})
    lines = [
        stamp.read(
            path,
            f"`python docs/scripts/click_study.py --spec '{designation}' --sizes "
            f"{','.join(f'{s:g}' for s in sizes)} --directions {len(directions)} "
            f"--out small-tilts.png > {path.name}`",
        ),
        "",
        "A published observation: turned in the loosening direction under a light axial "
        "preload, a bolt and nut click once per turn as the thread ends slip past each "
        "other, and the click is conjectured to shrink as the angle between the axes grows "
        "(a 1/2-in bolt, tilts of about a degree and less). What the model says: "
        f"{designation} with flat parts, default compliance, one turn from "
        f"{rows[0].get('start', 30.0):g} degrees, the held tilt toward {len(directions)} "
        "directions relative to the nut's thread start. The click is the fall a sensor "
        "sees at the snap; the axial clearance (pitch-diameter difference / sqrt 3) is "
        f"{clearance:.5f} {units}.",
        "",
        f"| tilt (deg) | snaps | click mean ({units}) | min | max | mean / clearance |",
        "|---:|---:|---:|---:|---:|---:|",
    ]
    for size in sizes:
        at = [r for r in rows if r["size"] == size]
        clicks = [r["click"] for r in at if r["click"] is not None]
        if clicks:
            mean = sum(clicks) / len(clicks)
            lines.append(
                f"| {size:g} | {len(clicks)} of {len(at)} | {mean:.5f} | {min(clicks):.5f} "
                f"| {max(clicks):.5f} | {mean / clearance:.2f} |"
            )
        else:
            lines.append(f"| {size:g} | 0 of {len(at)} | - | - | - | - |")
    return [*lines, "", "Start by start:", "", *_click_table(rows)]


def ends_study(stamp: Stamp, path: Path) -> list[str]:
    rows = _json_lines(path)
    failed = sum(int(r["failed"]) for r in rows)
    lines = [
        stamp.read(path, f"`python docs/scripts/ends_study.py > {path.name}`"),
        "",
        "The grid of `threadmate run` (held roll and pitch -2..2 by 1 degree, 18 start "
        f"phases, {rows[0]['starts']} starts per row), default compliance, the standard "
        "ends of each designation at mean material against the thesis's flat parts. "
        "Figure: [figures/ends.png](figures/ends.png).",
        "",
        "| pair | parts | snap within a turn | upright | at 2 deg | turn mean / worst (deg) "
        "| click mean | work mean (mJ) |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        lines.append(
            f"| {r['pair']} | {r['parts']} | {r['share_snap']:.0%} | "
            f"{r['share_snap_upright']:.0%} | {r['share_snap_2deg']:.0%} | "
            f"{r['turn_mean']:.0f} / {r['turn_worst']:.0f} | "
            f"{r['click_mean']:.4g} {r['units']} ({r['click_mean_pitches']:.2f} P) | "
            f"{r['work_mean']:.1f} |"
        )
    return [
        *lines,
        "",
        '"at 2 deg": the starts held 2 degrees or more from upright; turn, click and work '
        "are means over the starts that snap (a landing in phase counts only when it "
        f"screws in). {'No start' if not failed else f'{failed} starts'} failed.",
    ]


def default_run(stamp: Stamp, run_dir: Path) -> list[str]:
    report = run_dir / "report.md"
    if not report.is_file():
        raise SystemExit(f"validation: no report.md in {run_dir}")
    text = report.read_text(encoding="utf-8").splitlines()
    wanted = ("- **F =", "- Inside it", "- Upright", "- **Pre-tilt", "- With it,", "Starts:")
    keep = [ln for ln in text if ln.startswith(wanted) and "did not reach" not in ln[:40]]
    not_at_rest = [ln for ln in text if "did not reach a rest state" in ln]
    return [
        stamp.read(report, "`threadmate run -o DIR` on the built-in default"),
        "",
        "Its report's lines:",
        "",
        *(ln if ln.startswith("-") else f"- {ln}" for ln in keep[:5]),
        *(f"- {ln.split(':', 1)[0].strip('*- ')}" for ln in not_at_rest[:1]),
    ]


#: Benchmarks whose printed output a section holds whole: name -> (heading, command).
BENCHMARKS = {
    "mechanics": ("Cost: rest states and turns", "python benchmarks/bench_mechanics.py"),
    "sweep": ("Cost: the sweep", "python benchmarks/bench_sweep.py --roll=-4:4:1 --pitch=-4:4:1"),
    "network": ("Cost: the network", "python benchmarks/bench_network.py"),
    "mesh": ("Cost: meshes and queries", "python benchmarks/bench_mesh.py"),
    "contact": ("Cost: the thesis's stages", "python benchmarks/bench_contact.py"),
}


def benchmark(name: str) -> Callable[[Stamp, Path], list[str]]:
    def section(stamp: Stamp, path: Path) -> list[str]:
        command = BENCHMARKS[name][1]
        return [
            stamp.read(path, f"`{command} > {path.name}` (its own arguments as printed)"),
            "",
            "```",
            *path.read_text(encoding="utf-8").rstrip().splitlines(),
            "```",
        ]

    return section


#: Sections computed by this script: name -> (heading, producer).
LIVE: dict[str, tuple[str, Callable[[Stamp], list[str]]]] = {
    "closed-forms": ("Closed forms: the upright bolt", closed_forms),
    "screw-in": ("The snap proved: a tilted landing screwed in", pinched_screw_in),
    "window": ("The snap's window", snap_window),
    "thesis": ("The thesis's examples", thesis_examples),
}
#: Sections read from a study's output: option -> (heading, reader).
READ: dict[str, tuple[str, Callable[[Stamp, Path], list[str]]]] = {
    "dynamics": ("Against an independent dynamics simulation", dynamics),
    "click": ("The click against the tilt", click_study),
    "small_tilts": ("The click at small tilts: a published observation", small_tilts),
    "ends": ("Flat ends against the standard ends", ends_study),
    "run": ("The default run", default_run),
}
#: Sections with no input here: carried over as the page holds them.
RECORDED = (
    "The snap proved where the landing's descent stops short",
    "The snap proved where the thread carries the landing partly",
    "The design's optimum against a finer grid",
    "Against the dynamics simulation, from 3 degrees before the snap",
    "Against the dynamics simulation, the default parts",
    "The snap proved where the bolt follows the helix off the thread",
    "The model's rules, measured",
    "The snap a sensor sees, on the default run",
    "The capture envelope's cost",
    "The continuation's step",
    "Where the thread starts meet",
    "Robustness",
)
#: Every section's heading, in page order.
ORDER = (
    *(h for h, _ in LIVE.values()),
    *(h for h, _ in READ.values()),
    *RECORDED,
    *(h for h, _ in BENCHMARKS.values()),
)


def _sections(text: str) -> dict[str, list[str]]:
    """The page's sections by heading (``## ...``), each its lines after the heading."""
    found: dict[str, list[str]] = {}
    body: list[str] | None = None
    for line in text.splitlines():
        if line.startswith("## "):
            body = found.setdefault(line[3:].strip(), [])
        elif body is not None:
            body.append(line)
    for lines in found.values():
        while lines and not lines[-1].strip():
            lines.pop()
        while lines and not lines[0].strip():
            lines.pop(0)
    return found


def _bench_option(text: str) -> tuple[str, Path]:
    name, sep, file = text.partition("=")
    if not sep or name not in BENCHMARKS:
        raise argparse.ArgumentTypeError(
            f"{text!r}: give NAME=FILE, NAME one of {', '.join(BENCHMARKS)}"
        )
    return name, Path(file)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    parser.add_argument(
        "--sections",
        default="all",
        help=f"sections computed here: all, none or a comma list of {', '.join(LIVE)}",
    )
    parser.add_argument("--dynamics", type=Path, help="dynamics_check.py's JSON")
    parser.add_argument("--click", type=Path, help="click_study.py's printed output")
    parser.add_argument(
        "--small-tilts", type=Path, help="click_study.py's printed output, 1/2-in pair"
    )
    parser.add_argument("--ends", type=Path, help="ends_study.py's printed output")
    parser.add_argument("--run", type=Path, help="a threadmate run directory")
    parser.add_argument(
        "--bench", type=_bench_option, action="append", default=[], help="NAME=FILE"
    )
    parser.add_argument("--out", type=Path, default=ROOT / "docs" / "validation.md")
    args = parser.parse_args(argv)
    names = {"all": list(LIVE), "none": []}.get(args.sections)
    if names is None:
        names = [n.strip() for n in args.sections.split(",") if n.strip()]
        unknown = sorted(set(names) - set(LIVE))
        if unknown:
            parser.error(f"--sections: unknown {', '.join(unknown)}; known: {', '.join(LIVE)}")
    for path in [p for p in (args.dynamics, args.click, args.small_tilts, args.ends) if p] + [
        p for _, p in args.bench
    ]:
        if not path.is_file():
            parser.error(f"no file {path}")

    stamp = Stamp(datetime.date.today().isoformat(), _commit(), _machine())
    old = _sections(args.out.read_text(encoding="utf-8")) if args.out.is_file() else {}
    new: dict[str, list[str]] = {}
    for name in names:
        heading, produce = LIVE[name]
        print(f"validation: {name}", file=sys.stderr, flush=True)
        new[heading] = produce(stamp)
    for option, (heading, read) in READ.items():
        path = getattr(args, option)
        if path is not None:
            new[heading] = read(stamp, path)
    for name, path in args.bench:
        new[BENCHMARKS[name][0]] = benchmark(name)(stamp, path)

    done = ", ".join(f'"{h}"' for h in new) or "none"
    lines = [
        TITLE,
        "",
        "Every figure threadmate's documentation quotes from a run of it is here; the other "
        "pages say what the tool computes and why, and link to these sections. Written by "
        "`python docs/scripts/validation.py` (its docstring lists the sections and their "
        "inputs). Each section is stamped with the date, the commit and the machine it "
        "was measured on and the command that measures it again; a section a run of the "
        "script neither computes nor reads is carried over with its own stamp. Times on a "
        "shared host are comparable only within one stamp.",
        "",
        f"Page last written {stamp.date} at commit {stamp.commit} on {stamp.machine}; "
        f"sections computed or read by that run: {done}.",
        "",
    ]
    extra = [h for h in old if h not in ORDER]
    for heading in (*ORDER, *extra):
        body = new.get(heading, old.get(heading))
        if body is None:
            continue
        lines += [f"## {heading}", "", *body, ""]
    tmp = args.out.with_suffix(".md.tmp")
    tmp.write_text("\n".join(lines), encoding="utf-8")
    tmp.replace(args.out)
    print(f"validation: wrote {args.out}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
