"""Mechanics libraries for the network tests, and an independent reading of their rows.

- :func:`mechanics_library`: ONE small real library per test session (the mechanics through
  python-fcl: held roll {0, 1} x pitch {-1, 0, 1} x phases 0:330:30 of the 1/4-20 pair),
  built with :func:`threadmate.library.sweep` on 2 workers the first time a test asks for
  it and shared by every test module afterwards.
- :func:`synthetic_library`: a library of known structure written with the public
  :func:`threadmate.library.write_library` (a cycle that never snaps, a jump, an error
  start, a start already in phase, a snap beyond one turn, a turning leg whose work is
  negative), for the graph logic.
- :func:`walk_starts`, :func:`expected_weight`, :func:`setting_figures`: what the network
  and the recommendation should say, recomputed from the Parquet rows with pandas alone
  (no networkx, no threadmate.network).
"""

from __future__ import annotations

import math
from collections import defaultdict
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from threadmate.contact import Compliance, blank_row, state_id, state_schema
from threadmate.geometry import spec_from_designation
from threadmate.library import Grid, load, sweep, write_library

#: The thread of the shared real library (a designation, so that ``threadmate run`` with the
#: same grid can reuse the library), with the thesis's flat parts (``--point flat
#: --no-countersink``).
DESIGNATION = "1/4-20 UNC-2A/2B"
#: The shared real library's grid (held roll, held pitch, phases).
REAL_GRID = {"roll": "0,1", "pitch": "-1:1:1", "phase": "0:330:30"}
#: The synthetic libraries' grid.
SYNTH_GRID = {"roll": [0.0, 1.0], "pitch": [-1.0, 0.0, 1.0], "phase": [0.0, 90.0, 180.0, 270.0]}
#: Compliance of the synthetic libraries (force in N).
SYNTH_COMPLIANCE = Compliance(force=10.0)
INCH = 0.0254  # metres

_BUILT: dict[str, Path] = {}


def mechanics_library(tmp_path_factory: Any) -> Path:
    """The session's real mechanics library (built once, on 2 workers)."""
    if "real" not in _BUILT:
        out = tmp_path_factory.mktemp("mechanics-library") / "library"
        sweep(
            spec_from_designation(DESIGNATION, point="flat", countersink=False),
            REAL_GRID["roll"],
            REAL_GRID["pitch"],
            REAL_GRID["phase"],
            out=out,
            workers=2,
        )
        _BUILT["real"] = out
    return _BUILT["real"]


# -- synthetic libraries ------------------------------------------------------------------
class _Rows:
    """Rows of the state record, written by hand."""

    def __init__(self) -> None:
        self.rows: dict[str, dict[str, Any]] = {}
        self.serial: dict[tuple[float, float], int] = defaultdict(int)
        self.grid = Grid.parse(SYNTH_GRID["roll"], SYNTH_GRID["pitch"], SYNTH_GRID["phase"])

    def config(self, r: float, p: float, ph: float) -> int:
        g = self.grid
        return g.config_id(g.roll.index(r), g.pitch.index(p), g.phase.index(ph % 360.0))

    def add(
        self,
        r: float,
        p: float,
        ph: float,
        role: str,
        cls: str,
        *,
        cid: int,
        z: float,
        torque: float = math.nan,
        error: str = "",
    ) -> str:
        sid = state_id(r, p, ph, self.serial[(r, p)])
        self.serial[(r, p)] += 1
        row = blank_row(state_schema())
        row.update(
            config_id=cid,
            state_id=sid,
            held_roll=r,
            held_pitch=p,
            phase=ph % 360.0,
            role=role,
            classification=cls,
            engaged=cls == "in-phase",  # every in-phase state here is a proved snap
            roll=r,
            pitch=p,
            origin_z=z - 0.2,
            centre_z=z,
            centre_x=0.0,
            centre_y=0.0,
            origin_x=0.0,
            origin_y=0.0,
            rotation=[1.0, 0, 0, 0, 1.0, 0, 0, 0, 1.0],
            potential=10.0 * z,
            driver_torque=torque,
            friction_torque=torque,
            error=error,
            n_contacts=0 if cls == "error" else 2,
            region_combination="" if cls == "error" else "flank/flank + crest/root",
            contact_regions=[] if cls == "error" else ["flank/flank", "crest/root"],
            contact_forces=[] if cls == "error" else [6.0, 4.0],
            contact_points=[] if cls == "error" else [0.1, 0, 0, -0.1, 0, 0.01],
            contact_normals=[] if cls == "error" else [0, 0, 1.0, 0, 0.6, 0.8],
        )
        self.rows[sid] = row
        return sid

    def link(
        self,
        a: str,
        b: str,
        kind: str,
        label: str,
        *,
        turn: float = 0.0,
        wf: float = 0.0,
        wp: float = 0.0,
        peak: float = math.nan,
    ) -> None:
        self.rows[a].update(
            next_id=b,
            transition=kind,
            transition_label=label,
            transition_turn=turn,
            work_friction=wf,
            work_potential=wp,
            torque_peak=peak,
            drop=self.rows[a]["centre_z"] - self.rows[b]["centre_z"],
            tilt_change=0.1,
        )

    def drop(self, r: float, p: float, ph: float, cls: str, z: float, torque: float = 0.004) -> str:
        """A start: its first contact (2 thousandths above), settling to the rest state."""
        cid = self.config(r, p, ph)
        first = self.add(r, p, ph, "first-contact", "unstable", cid=cid, z=z + 0.002)
        rest = self.add(r, p, ph, "start", cls, cid=cid, z=z, torque=torque)
        self.link(first, rest, "settling", "unstable")
        return rest

    def snap_after(self, sid: str, at: float) -> None:
        """Turn from ``sid`` to a fold at phase ``at``, then snap into the thread."""
        row = self.rows[sid]
        r, p, ph, cid = row["held_roll"], row["held_pitch"], row["phase"], row["config_id"]
        before = self.add(
            r,
            p,
            at,
            "before-jump",
            "quasi-stable",
            cid=cid,
            z=row["centre_z"] - 0.0002,
            torque=0.005,
        )
        after = self.add(
            r,
            p,
            at + 0.01,
            "after-jump",
            "in-phase",
            cid=cid,
            z=row["centre_z"] - 0.0052,
            torque=0.006,
        )
        self.link(
            sid,
            before,
            "turning",
            "quasi-stable",
            turn=(at - ph) % 360.0,
            wf=0.4,
            wp=0.05,
            peak=0.0045,
        )
        self.link(before, after, "snap", "unstable", turn=0.01)


def synthetic_rows() -> pd.DataFrame:
    """The hand-made library (every held tilt of :data:`SYNTH_GRID`):

    - (0, -1): four quasi-stable starts, each turning to the next (the 90 -> 180 leg has
      negative work: its weight is clipped at 0), the snap at 290 (turns 290.01, 200.01,
      110.01, 20.01);
    - (1, -1): the same, but the start at 180 failed (an error row); the continuation
      from 90 reaches a *continued* state at 180 instead;
    - (0, 0): the drops at 0 and 90 land in phase; 180 -> 270 -> snap at 290;
    - (1, 0): from 0 a jump (unstable, dropping) at 40, then on to 90, 180, 270, snap at 290;
    - (0, +1): a cycle 0 -> 90 -> 180 -> 270 -> 0 that never snaps;
    - (1, +1): 0 lands in phase; 90 goes round a second sheet of continued states and
      snaps at 110 after 380.01 degrees (reaches the snap, but not within one turn); 180
      and 270 join that sheet and snap within the turn.

    Rest heights differ by held tilt so that active moves lift or drop.
    """
    b = _Rows()
    z0 = {
        (0.0, -1.0): 0.010,
        (1.0, -1.0): 0.011,
        (0.0, 0.0): 0.009,
        (1.0, 0.0): 0.012,
        (0.0, 1.0): 0.013,
        (1.0, 1.0): 0.008,
    }
    phases = SYNTH_GRID["phase"]
    # (0, -1)
    r, p = 0.0, -1.0
    s = [b.drop(r, p, ph, "quasi-stable", z0[r, p]) for ph in phases]
    b.link(s[0], s[1], "turning", "quasi-stable", turn=90, wf=0.9, wp=0.1, peak=0.006)
    b.link(s[1], s[2], "turning", "quasi-stable", turn=90, wf=0.5, wp=-0.8, peak=0.003)
    b.link(s[2], s[3], "turning", "stable", turn=90, wf=1.2, wp=0.3, peak=0.007)
    b.snap_after(s[3], 290.0)
    # (1, -1): the start at 180 failed
    r, p = 1.0, -1.0
    s0 = b.drop(r, p, 0.0, "quasi-stable", z0[r, p])
    s1 = b.drop(r, p, 90.0, "quasi-stable", z0[r, p])
    bad = b.add(
        r,
        p,
        180.0,
        "start",
        "error",
        cid=b.config(r, p, 180.0),
        z=math.nan,
        error="RuntimeError: the drop found no contact",
    )
    s3 = b.drop(r, p, 270.0, "quasi-stable", z0[r, p])
    c2 = b.add(
        r,
        p,
        180.0,
        "continued",
        "quasi-stable",
        cid=b.rows[s1]["config_id"],
        z=z0[r, p],
        torque=0.004,
    )
    b.link(s0, s1, "turning", "quasi-stable", turn=90, wf=1.0, wp=0.0, peak=0.005)
    b.link(s1, c2, "turning", "quasi-stable", turn=90, wf=1.1, wp=0.2, peak=0.0052)
    b.link(c2, s3, "turning", "quasi-stable", turn=90, wf=0.7, wp=0.1, peak=0.0049)
    b.snap_after(s3, 290.0)
    assert bad
    # (0, 0): two drops straight in phase
    r, p = 0.0, 0.0
    b.drop(r, p, 0.0, "in-phase", z0[r, p] - 0.005, torque=0.0065)
    b.drop(r, p, 90.0, "in-phase", z0[r, p] - 0.005, torque=0.0065)
    s2 = b.drop(r, p, 180.0, "quasi-stable", z0[r, p])
    s3 = b.drop(r, p, 270.0, "quasi-stable", z0[r, p])
    b.link(s2, s3, "turning", "quasi-stable", turn=90, wf=0.8, wp=0.1, peak=0.0051)
    b.snap_after(s3, 290.0)
    # (1, 0): a jump on the way
    r, p = 1.0, 0.0
    s = [b.drop(r, p, ph, "quasi-stable", z0[r, p]) for ph in phases]
    cid = b.rows[s[0]]["config_id"]
    fold = b.add(
        r, p, 40.0, "before-jump", "quasi-stable", cid=cid, z=z0[r, p] + 0.0003, torque=0.008
    )
    land = b.add(
        r, p, 40.005, "after-jump", "quasi-stable", cid=cid, z=z0[r, p] - 0.0007, torque=0.004
    )
    b.link(s[0], fold, "turning", "quasi-stable", turn=40, wf=0.5, wp=0.2, peak=0.0095)
    b.link(fold, land, "jump", "unstable", turn=0.005)
    b.link(land, s[1], "turning", "quasi-stable", turn=49.995, wf=0.6, wp=-0.1, peak=0.005)
    b.link(s[1], s[2], "turning", "quasi-stable", turn=90, wf=1.0, wp=0.1, peak=0.005)
    b.link(s[2], s[3], "turning", "quasi-stable", turn=90, wf=1.0, wp=0.1, peak=0.005)
    b.snap_after(s[3], 290.0)
    # (0, +1): a cycle that never snaps
    r, p = 0.0, 1.0
    s = [b.drop(r, p, ph, "quasi-stable", z0[r, p]) for ph in phases]
    for i, peak in enumerate((0.0058, 0.0051, 0.0053, 0.005)):  # the largest on 0 -> 90
        b.link(s[i], s[(i + 1) % 4], "turning", "quasi-stable", turn=90, wf=1.0, wp=0.0, peak=peak)
    # (1, +1): a second sheet; the snap beyond one turn from 90
    r, p = 1.0, 1.0
    b.drop(r, p, 0.0, "in-phase", z0[r, p] - 0.005, torque=0.0065)
    s1 = b.drop(r, p, 90.0, "quasi-stable", z0[r, p])
    s2 = b.drop(r, p, 180.0, "quasi-stable", z0[r, p])
    s3 = b.drop(r, p, 270.0, "quasi-stable", z0[r, p])
    cid = b.rows[s1]["config_id"]
    sheet = [
        b.add(r, p, ph, "continued", "quasi-stable", cid=cid, z=z0[r, p] + 0.001, torque=0.004)
        for ph in (180.0, 270.0, 0.0, 90.0)
    ]
    b.link(s1, sheet[0], "turning", "quasi-stable", turn=90, wf=1.0, wp=0.5, peak=0.006)
    for u, v in zip(sheet, sheet[1:], strict=False):
        b.link(u, v, "turning", "quasi-stable", turn=90, wf=1.0, wp=0.0, peak=0.006)
    b.snap_after(sheet[3], 110.0)
    b.link(s2, sheet[1], "turning", "quasi-stable", turn=90, wf=0.9, wp=0.0, peak=0.0061)
    b.link(s3, sheet[2], "turning", "quasi-stable", turn=90, wf=0.9, wp=0.0, peak=0.0062)
    return pd.DataFrame(list(b.rows.values()))


def synthetic_library(
    out: Path,
    spec: Any,
    rows: pd.DataFrame | None = None,
    roll: list[float] | None = None,
    pitch: list[float] | None = None,
) -> Path:
    """Write the hand-made rows (or a subset: ``rows`` on the held rolls ``roll`` and
    pitches ``pitch``) as a library with the public writer."""
    rows = synthetic_rows() if rows is None else rows
    roll, pitch = roll or SYNTH_GRID["roll"], pitch or SYNTH_GRID["pitch"]
    # Renumber the configurations for the subset's grid (the readers check that they fit).
    full = Grid.parse(SYNTH_GRID["roll"], SYNTH_GRID["pitch"], SYNTH_GRID["phase"])
    sub = Grid.parse(roll, pitch, SYNTH_GRID["phase"])
    renumber = {}
    for cid in rows["config_id"].unique():
        r, p, ph = full.configuration(int(cid))
        renumber[cid] = sub.config_id(sub.roll.index(r), sub.pitch.index(p), sub.phase.index(ph))
    rows = rows.assign(config_id=rows["config_id"].map(renumber))
    return write_library(
        rows, out, spec, roll, pitch, SYNTH_GRID["phase"], compliance=SYNTH_COMPLIANCE
    )


# -- the independent reading --------------------------------------------------------------
def metres(length: float, units: str) -> float:
    return length * (INCH if units == "in" else 1e-3)


def expected_weight(row: pd.Series | dict[str, Any], jump_penalty: float = 0.0) -> float:
    """The weight of the transition leaving ``row``, by the documented formula."""
    kind = row["transition"]
    if kind == "turning":
        return max(0.0, float(row["work_friction"]) + float(row["work_potential"]))
    if kind == "jump":
        return jump_penalty
    assert kind in ("settling", "snap"), kind
    return 0.0


def walk_starts(rows: pd.DataFrame, jump_penalty: float = 0.0) -> pd.DataFrame:
    """Follow ``next_id`` from every start row with pandas: the passive search's outcome.

    One row per start, indexed by state id: ``held_roll``, ``held_pitch``, ``phase``,
    ``classification``, ``failed``, ``reaches``, ``snapped`` (an in-phase row within 360
    deg), ``turn`` (sum of ``transition_turn``), ``work`` (sum of the weights),
    ``click`` (drop of the snap), ``snap_phase``, ``torque_peak`` (largest of the start's
    driver torque and every transition's peak), ``passes_unstable``, ``path`` (ids).
    """
    by_id = rows.set_index("state_id")
    out = []
    for sid, start in by_id[by_id["role"] == "start"].iterrows():
        path, seen = [sid], {sid}
        turn = work = 0.0
        click, unstable, reaches = 0.0, False, False
        peaks = [start["driver_torque"]]
        node = start
        while True:
            if node["classification"] == "in-phase":
                reaches = True
                break
            nxt = node["next_id"]
            if not nxt:
                break
            peaks.append(node["torque_peak"])
            if nxt in seen:  # a cycle: the driver turns round it for ever, never snapping
                unstable = unstable or node["transition_label"] == "unstable"
                break
            turn += node["transition_turn"]
            work += expected_weight(node, jump_penalty)
            if node["transition"] == "snap":
                # the fall a sensor sees, recorded with the snap (a hand-built row has
                # none: its drop)
                click = node["click"] if np.isfinite(node["click"]) else node["drop"]
            elif node["transition_label"] == "unstable":
                unstable = True
            path.append(nxt)
            seen.add(nxt)
            node = by_id.loc[nxt]
        finite = [float(t) for t in peaks if np.isfinite(t)]
        out.append(
            {
                "node": sid,
                "held_roll": start["held_roll"],
                "held_pitch": start["held_pitch"],
                "phase": start["phase"],
                "classification": start["classification"],
                "failed": start["classification"] == "error",
                "reaches": reaches,
                "snapped": reaches and turn <= 360.0 + 1e-9,
                "turn": turn if reaches else math.nan,
                "work": work if reaches else math.nan,
                "click": click if reaches else math.nan,
                "snap_phase": by_id.loc[path[-1], "phase"] if reaches else math.nan,
                "torque_peak": max(finite) if finite else math.nan,
                "passes_unstable": unstable,
                "path": path,
            }
        )
    return pd.DataFrame(out).set_index("node")


def setting_figures(
    walked: pd.DataFrame, held_pitch: float, roll_spread: float = math.inf
) -> dict[str, float | None]:
    """The recommendation's figures of one held pitch, from :func:`walk_starts`."""
    sel = walked[
        (walked["held_pitch"] == held_pitch)
        & (walked["held_roll"].abs() <= roll_spread)
        & ~walked["failed"]
    ]
    ok = sel[sel["snapped"]]
    clicks = ok.loc[ok["turn"] > 0, "click"]

    def agg(values: pd.Series, how: str) -> float | None:
        values = [float(v) for v in values if np.isfinite(v)]
        if not values:
            return None
        return sum(values) / len(values) if how == "mean" else max(values)

    return {
        "starts": len(sel),
        "share_snap": len(ok) / len(sel),
        "turn_mean": agg(ok["turn"], "mean"),
        "turn_worst": agg(ok["turn"], "max"),
        "work_mean": agg(ok["work"], "mean"),
        "work_worst": agg(ok["work"], "max"),
        "click_mean": agg(clicks, "mean"),
        "torque_peak": agg(sel["torque_peak"], "max"),
        "share_unstable": float(sel["passes_unstable"].mean()),
    }


def library_rows(path: Path) -> pd.DataFrame:
    """The library's rows, read with pandas (pyarrow) straight from the Parquet parts."""
    parts = sorted(Path(path).glob("part-*.parquet"))
    return pd.concat([pd.read_parquet(p) for p in parts], ignore_index=True)


def compliance_of(path: Path) -> Compliance:
    """The compliance the library's metadata records."""
    c = load(path, columns=["config_id"]).attrs["threadmate"]["compliance"]
    return Compliance(
        force=c["force"],
        stiffness=(c["stiffness"]["roll"], c["stiffness"]["pitch"]),
        lateral_stiffness=c["lateral_stiffness"],
        compliance_z=c["compliance_z"],
        friction=c["friction"],
    )
