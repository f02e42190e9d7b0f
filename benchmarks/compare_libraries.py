"""Two mechanics libraries of one sweep compared row by row (a change that must keep them).

Usage::

    python benchmarks/compare_libraries.py OLD_LIBRARY NEW_LIBRARY

Rows are matched by ``state_id``. Every column but the screw-in proof's must be equal
(floats to 1e-12 relative, NaN equal to NaN); the proof's verdict (``engaged``) too, and
whether its note is empty. Its measures may move within the tolerances docs/mechanics.md
states ("The snap proved: screwing in"): ``screw_descent`` within 1 % of the lead,
``screw_tilt`` within 0.05 degree, the phases a note quotes within a degree (a wedge's
within three: where a walk wedges depends on where its steps fall). Prints the
rows compared, every column that differs and by how much; exits 1 when a tolerance is
passed.
"""

from __future__ import annotations

import argparse
import re
import sys

import numpy as np
import pandas as pd

from threadmate.library import load

#: The proof's measures and their tolerances (descent: a share of the lead).
SCREW_DESCENT = 0.01
SCREW_TILT = 0.05
NOTE_PHASE = 1.0
#: A failed proof's note of a wedge, and how far its phase may move (degrees).
WEDGED = "no rest state continues the turn"
WEDGE_PHASE = 3.0
_NUMBER = re.compile(r"-?\d+(?:\.\d+)?(?:e-?\d+)?")


def _same(a: object, b: object) -> bool:
    if isinstance(a, float) and isinstance(b, float):
        return (np.isnan(a) and np.isnan(b)) or bool(np.isclose(a, b, rtol=1e-12, atol=0.0))
    if isinstance(a, np.ndarray | list) or isinstance(b, np.ndarray | list):
        x, y = np.asarray(a), np.asarray(b)
        if x.shape != y.shape:
            return False
        if x.dtype.kind == "f" and y.dtype.kind == "f":
            return bool(np.allclose(x, y, rtol=1e-12, atol=0.0, equal_nan=True))
        return bool(np.array_equal(x, y))
    if a is None or b is None or (isinstance(a, float) and np.isnan(a)):
        return (a is None or (isinstance(a, float) and np.isnan(a))) and (
            b is None or (isinstance(b, float) and np.isnan(b))
        )
    return bool(a == b)


def _count(flags: pd.Series) -> int:
    return int(flags.eq(True).sum())


def _note_numbers(note: str) -> list[float]:
    return [float(x) for x in _NUMBER.findall(note)]


def main() -> None:
    """Compare the libraries named on the command line."""
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("old")
    ap.add_argument("new")
    args = ap.parse_args()
    old, new = load(args.old), load(args.new)
    lead = float(old.attrs["threadmate"]["spec"]["pitch"]) * float(
        old.attrs["threadmate"]["spec"].get("starts", 1)
    )
    old, new = old.set_index("state_id").sort_index(), new.set_index("state_id").sort_index()
    ok = True
    if not old.index.equals(new.index):
        print(
            f"rows differ: {len(old)} old, {len(new)} new; "
            f"only old {sorted(set(old.index) - set(new.index))[:5]}, "
            f"only new {sorted(set(new.index) - set(old.index))[:5]}"
        )
        sys.exit(1)
    print(f"rows compared: {len(old)} ({int(old['role'].eq('start').sum())} starts)")
    screw = {"screw_descent", "screw_tilt", "screw_note"}
    for col in old.columns:
        if col in screw:
            continue
        bad = [i for i in old.index if not _same(old.at[i, col], new.at[i, col])]
        if bad:
            ok = False
            print(
                f"{col}: {len(bad)} rows differ, e.g. {bad[0]}: "
                f"{old.at[bad[0], col]!r} -> {new.at[bad[0], col]!r}"
            )
    proved = old["screw_descent"].notna() | new["screw_descent"].notna()
    print(
        f"proved states: {int(proved.sum())}, engaged {_count(old['engaged'])} old, "
        f"{_count(new['engaged'])} new"
    )
    d_desc = (new["screw_descent"] - old["screw_descent"]).abs()[proved]
    d_tilt = (new["screw_tilt"] - old["screw_tilt"]).abs()[proved]
    print(
        f"screw_descent: {int((d_desc > 0).sum())} rows differ, largest {d_desc.max():.3g} "
        f"({d_desc.max() / lead:.3%} of the lead)"
    )
    print(f"screw_tilt: {int((d_tilt > 0).sum())} rows differ, largest {d_tilt.max():.3g} deg")
    ok &= bool((d_desc <= SCREW_DESCENT * lead).all() and (d_tilt <= SCREW_TILT).all())
    notes = 0
    for i in old.index[proved]:
        a, b = str(old.at[i, "screw_note"] or ""), str(new.at[i, "screw_note"] or "")
        if a == b:
            continue
        notes += 1
        na, nb = _note_numbers(a), _note_numbers(b)
        print(f"screw_note {i}:\n  old: {a}\n  new: {b}")
        if bool(a) != bool(b) or len(na) != len(nb):
            ok = False
        elif a.startswith(WEDGED) and b.startswith(WEDGED):
            # A wedge: the phase where the walk wedges depends on where its steps fall
            # (docs/mechanics.md), the rise it quotes within the descent's tolerance.
            ok &= abs(na[0] - nb[0]) <= WEDGE_PHASE
            ok &= abs(na[1] - nb[1]) <= SCREW_DESCENT * lead + 1e-4
        elif a.split("(it jumps")[0] != b.split("(it jumps")[0]:
            # The descent it quotes: within the descent's tolerance (4 digits printed).
            ok &= all(
                abs(x - y) <= SCREW_DESCENT * lead + 1e-4 for x, y in zip(na, nb, strict=True)
            )
        else:
            ok &= all(abs(x - y) <= NOTE_PHASE for x, y in zip(na, nb, strict=True))
    print(f"screw_note: {notes} rows differ")
    print("within tolerances" if ok else "OUTSIDE TOLERANCES")
    sys.exit(0 if ok else 1)


if __name__ == "__main__":
    main()
