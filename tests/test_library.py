"""The sweep stage on the real contact engine (python-fcl): rows, resume, refusal, storage.

The thesis's model (``model="thesis"``): tiny grids at a coarse chord (1e-4 in), rows checked
against the contact analyser called directly in the test process. The mechanics (the
default): two held tilts x 8 phases at the default chord, every start checked against
``Mechanics.settle`` called here, and every passive path read from the Parquet rows against
``threadmate.contact.search`` from the same start.
"""

from __future__ import annotations

import functools
import json
import math
import os
import sys
from collections import Counter
from pathlib import Path

import numpy as np
import pandas as pd
import pyarrow.dataset as ds
import pyarrow.parquet as pq
import pytest

from _fcl import collider
from _poses import axis_angle, leaves_branch
from threadmate import InputError, LibraryError
from threadmate.contact import (
    ROLES,
    STATE_COLUMNS,
    TRANSITION_LABELS,
    TRANSITIONS,
    Compliance,
    ContactAnalyzer,
    Mechanics,
    record_schema,
    search,
)
from threadmate.geometry import ThreadSpec
from threadmate.library import (
    METADATA_FILE,
    Grid,
    SweepInterrupted,
    configurations,
    info,
    load,
    query,
    summary,
    sweep,
    write_figures,
    write_library,
)

CHORD = 1e-4
ROLL, PITCH, PHASE = "-3,0,4", "0,2", "0,185,235"  # 18 configurations


class FlakyAnalyzer(ContactAnalyzer):
    """The real analyser, except that phase 185 raises (to test error rows)."""

    def analyze(self, roll, pitch, phase):
        if phase == 185.0:
            raise RuntimeError("simulated failure at phase 185")
        return super().analyze(roll, pitch, phase)


class KillOnceAnalyzer(ContactAnalyzer):
    """The real analyser, but the first process to reach phase 235 dies (``os._exit``) if
    ``marker`` does not exist yet, creating it: a worker killed mid-sweep, once."""

    def __init__(self, spec, *, marker, **kwargs):
        super().__init__(spec, **kwargs)
        self.marker = marker

    def analyze(self, roll, pitch, phase):
        if phase == 235.0 and not os.path.exists(self.marker):
            open(self.marker, "w").close()
            os._exit(1)
        return super().analyze(roll, pitch, phase)


@pytest.fixture(scope="module")
def analyzer(quarter_20):
    return ContactAnalyzer(quarter_20, chord=CHORD)


@pytest.fixture(scope="module")
def library(quarter_20, tmp_path_factory):
    """One uninterrupted sweep of the thesis's model with a two-process pool."""
    out = tmp_path_factory.mktemp("lib") / "quarter-20"
    sweep(
        quarter_20,
        ROLL,
        PITCH,
        PHASE,
        out=out,
        workers=2,
        chunk_size=4,
        chord=CHORD,
        model="thesis",
    )
    return out


def _same_row(row: pd.Series, rec: dict) -> None:
    for name, value in rec.items():
        got = row[name]
        if isinstance(value, float):
            assert (math.isnan(got) and math.isnan(value)) or got == pytest.approx(
                value, rel=1e-12, abs=1e-15
            ), name
        else:
            assert got == value, name


def test_rows_equal_the_analyser_called_directly(library, analyzer):
    df = load(library)
    grid = Grid.parse(ROLL, PITCH, PHASE)
    assert list(df["config_id"]) == list(range(18))
    assert list(df.columns) == ["config_id", *record_schema().names, "error"]
    for cid in range(grid.size):
        roll, pitch, phase = grid.configuration(cid)
        row = df.iloc[cid]
        assert (row["roll"], row["pitch"], row["phase"]) == (roll, pitch, phase)
        _same_row(row, analyzer.analyze(roll, pitch, phase).to_record())
        assert row["error"] == ""
    # The thesis's named states are reproduced by the engine; here just that the rows
    # carry real contact data: every configuration touched the nut.
    assert df["first_found"].all()


def test_metadata_round_trip(library, quarter_20, analyzer):
    meta = json.loads((library / METADATA_FILE).read_text())
    assert ThreadSpec.from_dict(meta["spec"]) == quarter_20
    assert Grid.from_dict(meta["grid"]) == Grid.parse(ROLL, PITCH, PHASE)
    assert meta["units"] == "in"
    assert meta["mesh"]["chord"] == CHORD
    assert meta["mesh"]["max_deviation"] == pytest.approx(analyzer.deviation, rel=1e-12)
    assert meta["contact"]["compliance_z"] == 0.0
    assert meta["contact"]["tolerances"] == pytest.approx(analyzer.tolerances)
    from threadmate import __version__

    assert meta["threadmate_version"] == __version__
    # Every part carries the same metadata in its Arrow schema, the grid's values
    # apart (they are in the metadata file only; the part names the grid's shape).
    parts = sorted(library.glob("part-*.parquet"))
    assert len(parts) == 5  # 18 configurations in chunks of 4
    for part in parts:
        carried = json.loads(pq.read_schema(part).metadata[b"threadmate"])
        assert {k: v for k, v in carried.items() if k != "grid"} == {
            k: v for k, v in meta.items() if k != "grid"
        }
        assert carried["grid"]["shape"] == [3, 2, 3] and carried["grid"]["size"] == 18
    assert load(library).attrs["threadmate"] == meta


def test_read_directly_with_pyarrow_pandas_and_duckdb(library):
    ours = load(library)
    table = ds.dataset(library, format="parquet").to_table()
    assert table.num_rows == 18
    assert sorted(table.column("config_id").to_pylist()) == list(range(18))
    direct = pd.read_parquet(library).sort_values("config_id").reset_index(drop=True)
    pd.testing.assert_frame_equal(direct, ours, check_like=False)
    duckdb = pytest.importorskip("duckdb")
    rows = duckdb.sql(
        f"SELECT config_id, classification FROM "
        f"read_parquet('{library}/*.parquet') ORDER BY config_id"
    ).fetchall()
    assert rows == list(zip(ours["config_id"], ours["classification"], strict=True))


def test_resumed_sweep_equals_uninterrupted(library, quarter_20, tmp_path):
    out = tmp_path / "resumed"
    sweep(
        quarter_20,
        ROLL,
        PITCH,
        PHASE,
        out=out,
        workers=2,
        chunk_size=4,
        chord=CHORD,
        max_chunks=2,
        model="thesis",
    )
    partial = info(out)
    assert partial["done"] == 8 and not partial["complete"]
    seen = []
    # Resume with another chunk size and in-process: only the missing 10 are computed.
    sweep(
        quarter_20,
        ROLL,
        PITCH,
        PHASE,
        out=out,
        workers=1,
        chunk_size=3,
        chord=CHORD,
        progress=lambda done, total: seen.append((done, total)),
        model="thesis",
    )
    assert seen[0] == (8, 18) and seen[-1] == (18, 18)
    assert len(seen) == 1 + math.ceil(10 / 3)
    resumed = load(out)
    assert resumed["config_id"].is_unique
    pd.testing.assert_frame_equal(resumed, load(library))
    # Running it again finds nothing to do and writes nothing.
    parts = sorted(out.glob("part-*.parquet"))
    sweep(quarter_20, ROLL, PITCH, PHASE, out=out, workers=1, chord=CHORD, model="thesis")
    assert sorted(out.glob("part-*.parquet")) == parts


def test_killed_worker_then_resume_equals_uninterrupted(library, quarter_20, tmp_path):
    out = tmp_path / "killed"
    factory = functools.partial(KillOnceAnalyzer, marker=str(tmp_path / "killed-once"))
    with pytest.raises(SweepInterrupted, match="run the same sweep again to resume"):
        sweep(
            quarter_20,
            ROLL,
            PITCH,
            PHASE,
            out=out,
            workers=2,
            chunk_size=1,
            chord=CHORD,
            analyzer=factory,
            model="thesis",
        )
    assert info(out)["done"] < 18
    sweep(
        quarter_20,
        ROLL,
        PITCH,
        PHASE,
        out=out,
        workers=2,
        chunk_size=1,
        chord=CHORD,
        analyzer=factory,
        model="thesis",
    )
    pd.testing.assert_frame_equal(load(out), load(library))


def test_mismatched_library_is_refused_not_mixed(library, quarter_20):
    before = sorted(p.name for p in library.iterdir())
    with pytest.raises(LibraryError, match="grid phase values"):
        sweep(
            quarter_20, ROLL, PITCH, "0:355:5", out=library, workers=1, chord=CHORD, model="thesis"
        )
    with pytest.raises(LibraryError, match="chord"):
        sweep(quarter_20, ROLL, PITCH, PHASE, out=library, workers=1, chord=5e-5, model="thesis")
    with pytest.raises(LibraryError, match="compliance"):
        sweep(
            quarter_20,
            ROLL,
            PITCH,
            PHASE,
            out=library,
            workers=1,
            chord=CHORD,
            model="thesis",
            compliance=Compliance(compliance_z=0.1),
        )
    with pytest.raises(LibraryError, match="model"):
        sweep(quarter_20, ROLL, PITCH, PHASE, out=library, workers=1, chord=CHORD)
    other = ThreadSpec.from_dict(
        {**quarter_20.to_dict(), "nut": {**quarter_20.to_dict()["nut"], "pitch_diameter": 0.2200}}
    )
    with pytest.raises(LibraryError, match=r"spec \(nut.pitch_diameter"):
        sweep(other, ROLL, PITCH, PHASE, out=library, workers=1, chord=CHORD, model="thesis")
    assert sorted(p.name for p in library.iterdir()) == before


def test_error_rows_are_recorded_and_the_sweep_goes_on(quarter_20, analyzer, tmp_path):
    out = sweep(
        quarter_20,
        "0,4",
        "0",
        PHASE,
        out=tmp_path / "flaky",
        workers=2,
        chunk_size=2,
        chord=CHORD,
        analyzer=FlakyAnalyzer,
        model="thesis",
    )
    df = load(out)
    assert len(df) == 6
    bad = df[df["phase"] == 185.0]
    assert list(bad["classification"]) == ["error", "error"]
    assert all("simulated failure at phase 185" in e for e in bad["error"])
    assert (bad["n_contacts"] == 0).all() and bad["interference"].isna().all()
    assert (bad["region_combination"] == "").all() and not bad["first_found"].any()
    good = df[df["phase"] != 185.0]
    assert (good["error"] == "").all()
    for _, row in good.iterrows():
        _same_row(row, analyzer.analyze(row["roll"], row["pitch"], row["phase"]).to_record())
    assert "FlakyAnalyzer" in df.attrs["threadmate"]["contact"]["analyzer"]
    assert summary(out)["counts"]["error"] == 2


@pytest.mark.parametrize("make", ["missing", "file", "no-metadata", "bad-json", "corrupt"])
def test_not_a_library_is_refused(make, library, tmp_path):
    path = tmp_path / "x"
    if make == "file":
        path.write_text("hello")
    elif make == "no-metadata":
        path.mkdir()
    elif make == "bad-json":
        path.mkdir()
        (path / METADATA_FILE).write_text("{not json")
    elif make == "corrupt":
        path.mkdir()
        (path / METADATA_FILE).write_text((library / METADATA_FILE).read_text())
        (path / "part-00000.parquet").write_bytes(b"PAR1 this is not parquet PAR1")
    for reader in (load, info, lambda p: query(p, 0, 0, 0)):
        with pytest.raises(LibraryError):
            reader(path)


def test_sweep_refuses_a_foreign_directory(quarter_20, tmp_path):
    (tmp_path / "notes.txt").write_text("mine")
    with pytest.raises(LibraryError, match="not a threadmate library"):
        sweep(quarter_20, "0", "0", "0", out=tmp_path, workers=1, chord=CHORD)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["notes.txt"]


def test_query_takes_the_nearest_grid_state_only_when_asked(library, analyzer):
    exact = query(library, 4, 2, 235)
    assert not exact["moved_to_grid"] and exact["computed"]
    assert exact["grid"] == {"roll": 4.0, "pitch": 2.0, "phase": 235.0}
    assert exact["config_id"] == Grid.parse(ROLL, PITCH, PHASE).config_id(2, 1, 2)
    direct = analyzer.analyze(4, 2, 235).to_record()
    assert exact["record"]["classification"] == direct["classification"]
    assert exact["record"]["third_c1_x"] == pytest.approx(direct["third_c1_x"], nan_ok=True)
    # 3.2 -> 4, 1.4 -> 2, -130 (= 230) -> 235: refused with the nearest named, or taken.
    with pytest.raises(InputError, match="nearest configuration is roll 4, pitch 2, phase 235"):
        query(library, 3.2, 1.4, -130)
    moved = query(library, 3.2, 1.4, -130, nearest=True)
    assert moved["moved_to_grid"] and moved["grid"] == exact["grid"]
    assert query(library, 4, 2, -125)["grid"] == exact["grid"]  # the same phase mod 360


def test_summary_counts_and_figures(library, tmp_path):
    df = pd.read_parquet(library)  # counted independently of the library API
    counts = df["classification"].value_counts().to_dict()
    doc = summary(library, phase=186)
    assert doc["done"] == 18 and doc["configurations"] == 18
    assert {k: v for k, v in doc["counts"].items() if v} == counts
    assert sum(doc["region_combinations"].values()) == 18
    # The same contacts listed in another order are one combination (as in the figure).
    as_sets = Counter(tuple(sorted(c.split(" + "))) for c in df["region_combination"])
    assert sorted(doc["region_combinations"].values()) == sorted(as_sets.values())
    three = {k: doc["counts"][k] for k in ("unstable", "quasi-stable", "stable")}
    assert three[doc["most_common"]] == max(three.values())
    at = doc["at_phase"]
    assert at["phase"] == 185.0
    assert sum(at["counts"].values()) == 6
    assert at["counts"]["unstable"] == int(
        ((df["phase"] == 185.0) & (df["classification"] == "unstable")).sum()
    )
    figures = write_figures(library, tmp_path / "figs", phase=185)
    import matplotlib.image as mpimg

    for path in figures.values():
        img = mpimg.imread(path)
        assert img.ndim == 3 and img.shape[0] > 100 and img.shape[1] > 100


def test_sweep_without_out_returns_the_rows(quarter_20, analyzer):
    df = sweep(quarter_20, "0", "0", "0,90", workers=1, chord=CHORD, model="thesis")
    assert isinstance(df, pd.DataFrame) and len(df) == 2
    _same_row(df.iloc[1], analyzer.analyze(0, 0, 90).to_record())


def test_bad_requests_raise_input_errors(quarter_20, tmp_path):
    out = tmp_path / "never"
    for kwargs, words in (
        # The API names its parameters (never the command line's options).
        ({"roll": "0:4:0"}, "^roll"),
        ({"workers": 0}, "^workers"),
        ({"chord": -1.0}, "^chord"),
        ({"chord": 0.01}, "too coarse"),
        ({"scheduler": 5}, "^scheduler"),
        ({"chunk_size": 0}, "chunk_size"),
        ({"model": "fixed"}, "^model"),
        ({"step": 0.0}, "step"),
        ({"step": 2.0, "phase_tolerance": 5.0}, "phase_tolerance"),
        ({"compliance": "stiff"}, "compliance"),
        ({"compliance": Compliance(compliance_z=1e3)}, "compliance_z"),
        ({"analyzer": FlakyAnalyzer}, "thesis"),
    ):
        with pytest.raises(InputError, match=words):
            sweep(
                quarter_20,
                **{"roll": "0", "pitch": "0", "phase": "0", "chord": CHORD, **kwargs},
                out=out,
            )
    assert not out.exists()


def test_scheduler_without_dask_says_how_to_install(quarter_20, tmp_path, monkeypatch):
    monkeypatch.setitem(sys.modules, "distributed", None)  # as if not installed
    with pytest.raises(InputError, match=r"pip install threadmate\[dask\]"):
        sweep(quarter_20, "0", "0", "0", out=tmp_path / "d", scheduler="local", chord=CHORD)
    assert not (tmp_path / "d").exists()


def test_dask_scheduler_setting_is_read(monkeypatch):
    dask = pytest.importorskip("dask")
    # An internal with no public form: how a sweep reads Dask's own setting.
    from threadmate.library._executors import scheduler_from_dask_config

    with dask.config.set({"scheduler-address": "tcp://10.1.2.3:8786"}):
        assert scheduler_from_dask_config() == "tcp://10.1.2.3:8786"
    with dask.config.set({"scheduler-address": None}):
        assert scheduler_from_dask_config() is None


@pytest.mark.slow
def test_dask_local_cluster_gives_the_same_rows(library, quarter_20, tmp_path):
    pytest.importorskip("distributed")
    out = sweep(
        quarter_20,
        ROLL,
        PITCH,
        PHASE,
        out=tmp_path / "dask",
        scheduler="local",
        workers=2,
        chunk_size=5,
        chord=CHORD,
        model="thesis",
    )
    rows = load(out)
    pd.testing.assert_frame_equal(rows, load(library))
    assert np.array_equal(rows["config_id"], np.arange(18))


# -- the mechanics (the default model) -----------------------------------------------------
M_ROLL, M_PITCH, M_PHASE = "-2,2", "-1", "0:315:45"  # 2 held tilts x 8 phases
M_STEP = 5.0  # continuation step (degrees); a divisor of the grid's 45
M_PHASE_STEP = 45.0  # the grid's phase step
M_SIZE = 16


def _circular(a: float, b: float) -> float:
    """Distance between two phases in degrees, modulo 360."""
    return abs((a - b + 180.0) % 360.0 - 180.0)


@pytest.fixture(scope="module")
def mech(quarter_20):
    """The mechanics built in the test process (default compliance and chord)."""
    return Mechanics(quarter_20, Compliance())


@pytest.fixture(scope="module")
def mech_library(quarter_20, tmp_path_factory):
    """One uninterrupted mechanics sweep with a two-process pool (one chunk per held tilt)."""
    out = tmp_path_factory.mktemp("mech") / "quarter-20"
    sweep(quarter_20, M_ROLL, M_PITCH, M_PHASE, out=out, workers=2, step=M_STEP)
    return out


@pytest.fixture(scope="module")
def mech_rows(mech_library):
    """The rows as written, read with pandas alone (not through the library API)."""
    return pd.read_parquet(mech_library)


def _path(rows: pd.DataFrame, start_id: str) -> list[str]:
    """State ids from a state along ``next_id`` to the state that has none."""
    by_id = rows.set_index("state_id")
    path = [start_id]
    while by_id.loc[path[-1], "next_id"]:
        path.append(by_id.loc[path[-1], "next_id"])
        assert len(path) <= len(rows), "a passive path runs in a cycle"
    return path


def test_mechanics_rows_follow_the_record_contract(mech_library, mech_rows, quarter_20):
    meta = json.loads((mech_library / METADATA_FILE).read_text())
    assert meta["model"] == "mechanics"
    assert meta["compliance"] == json.loads(json.dumps(Compliance().to_dict()))
    assert meta["continuation"]["step"] == M_STEP
    assert meta["continuation"]["phase_tolerance"] == 0.01
    assert list(mech_rows.columns) == [c.name for c in STATE_COLUMNS]
    assert mech_rows["state_id"].is_unique
    assert set(mech_rows["role"]) <= set(ROLES)
    assert set(mech_rows["transition"]) <= {"", *TRANSITIONS}
    assert set(mech_rows["transition_label"]) <= {"", *TRANSITION_LABELS}
    assert (mech_rows["error"] == "").all()
    # One start per configuration, numbered as the grid numbers them.
    grid = Grid.parse(M_ROLL, M_PITCH, M_PHASE)
    starts = mech_rows[mech_rows["role"] == "start"].sort_values("config_id")
    assert list(starts["config_id"]) == list(range(M_SIZE))
    for _, row in starts.iterrows():
        assert grid.configuration(row["config_id"]) == (
            row["held_roll"],
            row["held_pitch"],
            row["phase"],
        )
    # One Parquet part per held tilt, each holding that tilt only.
    parts = sorted(mech_library.glob("part-*.parquet"))
    assert len(parts) == 2
    for part in parts:
        tilts = pq.read_table(part, columns=["held_roll", "held_pitch"]).to_pandas()
        assert len(tilts.drop_duplicates()) == 1
    doc = info(mech_library)
    assert doc["done"] == M_SIZE and doc["complete"] and doc["model"] == "mechanics"
    assert doc["states"]["total"] == len(mech_rows)
    assert doc["states"]["by_role"] == mech_rows["role"].value_counts().to_dict()


def test_every_start_is_a_direct_settle(mech_rows, mech):
    rows = mech_rows.set_index("state_id")
    for _, row in mech_rows[mech_rows["role"] == "start"].iterrows():
        rest = mech.settle(row["held_roll"], row["held_pitch"], row["phase"])
        s = rest.state
        assert row["classification"] == s.classification
        assert (row["roll"], row["pitch"]) == pytest.approx((s.roll, s.pitch), abs=1e-9)
        assert [row[f"origin_{a}"] for a in "xyz"] == pytest.approx(list(s.origin), abs=1e-12)
        assert list(row["rotation"]) == pytest.approx(np.ravel(s.rotation).tolist(), abs=1e-12)
        assert row["centre_z"] == pytest.approx(s.centre[2], abs=1e-12)
        assert row["potential"] == pytest.approx(s.potential, rel=1e-9)
        assert list(row["contact_regions"]) == [c.regions for c in s.touching]
        assert list(row["contact_forces"]) == pytest.approx(
            [c.force for c in s.touching], rel=1e-9, abs=1e-12
        )
        assert row["n_contacts"] == len(s.touching)
        # The first contact and the states passed on the way settle into this start.
        before = mech_rows[
            (mech_rows["next_id"] == row["state_id"]) & (mech_rows["transition"] == "settling")
        ]
        chain = 0
        while len(before):
            assert len(before) == 1
            chain += 1
            prev = before.iloc[0]
            assert rows.loc[prev["state_id"], "classification"] == "unstable"
            before = mech_rows[
                (mech_rows["next_id"] == prev["state_id"]) & (mech_rows["transition"] == "settling")
            ]
        assert chain == len(rest.path)
        if rest.path:
            assert prev["role"] == "first-contact"


def test_passive_transitions_keep_the_held_tilt(mech_rows):
    by_id = mech_rows.set_index("state_id")
    moves = mech_rows[mech_rows["next_id"] != ""]
    assert len(moves) > 0
    assert moves["next_id"].isin(by_id.index).all()
    nxt = by_id.loc[moves["next_id"]]
    assert np.array_equal(nxt["held_roll"].to_numpy(), moves["held_roll"].to_numpy())
    assert np.array_equal(nxt["held_pitch"].to_numpy(), moves["held_pitch"].to_numpy())
    # Every transition has a kind and a label, and no work is negative friction.
    assert (moves["transition"] != "").all() and (moves["transition_label"] != "").all()
    assert (moves["work_friction"] >= 0).all()
    # States without a successor are where a search ends: the snap's in-phase state.
    ends = mech_rows[mech_rows["next_id"] == ""]
    assert set(ends["classification"]) == {"in-phase"}


def test_every_rest_state_rests_on_the_nut_without_entering_it(mech_rows, quarter_20):
    """Every rest state the library stores (the starts, the continued states, both sides
    of a jump, the snap's landing) touches the nut and does not enter it, by python-fcl BVHs
    of the whole meshes built here: free once lifted by the descent's length tolerance
    (1e-7 in), colliding 1e-6 in lower."""
    collides = collider(quarter_20).collides
    rest = mech_rows[mech_rows["classification"].isin(["stable", "quasi-stable", "in-phase"])]
    assert len(rest) >= M_SIZE
    up = np.array([0.0, 0.0, 1.0])
    for _, row in rest.iterrows():
        rotation = np.reshape(np.asarray(row["rotation"], dtype=float), (3, 3))
        origin = np.array([row[f"origin_{a}"] for a in "xyz"], dtype=float)
        assert not collides(rotation, origin + 1e-7 * up), row["state_id"]
        assert collides(rotation, origin - 1e-6 * up), row["state_id"]


def test_every_stored_jump_leaves_the_branch(mech_rows, quarter_20):
    """Every jump and snap the library stores joins two different states that are a jump by
    the continuation's own thresholds, recomputed from the stored poses: the landing in
    phase, or the compliance centre fallen more than pitch / 40, or the bolt axis turned
    more than 0.5 degree."""
    by_id = mech_rows.set_index("state_id")
    jumps = mech_rows[mech_rows["transition"].isin(["jump", "snap"])]
    assert len(jumps)
    for _, row in jumps.iterrows():
        after = by_id.loc[row["next_id"]]
        assert row["next_id"] != row["state_id"]
        fall = row["centre_z"] - after["centre_z"]
        turned = axis_angle(row["rotation"], after["rotation"])
        in_phase = after["classification"] == "in-phase"
        assert leaves_branch(fall, turned, in_phase, quarter_20.pitch), (row["state_id"], fall)


def test_every_stored_snap_screws_in(mech_rows, quarter_20):
    """Every snap the library stores lands on a state proved by screwing in: engaged,
    descending per turn within 10 % of the lead, its axis within a degree of the nut's at
    the end; an in-phase state that is not engaged says why."""
    by_id = mech_rows.set_index("state_id")
    snaps = mech_rows[mech_rows["transition"] == "snap"]
    assert len(snaps)
    for _, row in snaps.iterrows():
        end = by_id.loc[row["next_id"]]
        assert end["classification"] == "in-phase" and end["engaged"]
        assert end["screw_descent"] == pytest.approx(quarter_20.lead, rel=0.1)
        assert end["screw_tilt"] < 1.0
    unproved = mech_rows[(mech_rows["classification"] == "in-phase") & ~mech_rows["engaged"]]
    for _, row in unproved.iterrows():
        if not math.isnan(row["screw_descent"]):  # proved, and failed
            assert row["screw_note"], row["state_id"]


def test_passive_path_from_every_start_ends_in_the_snap(mech_rows):
    by_id = mech_rows.set_index("state_id")
    for _, start in mech_rows[mech_rows["role"] == "start"].iterrows():
        path = _path(mech_rows, start["state_id"])
        end = by_id.loc[path[-1]]
        assert end["classification"] == "in-phase"
        kinds = [by_id.loc[sid, "transition"] for sid in path[:-1]]
        if start["classification"] == "in-phase":
            assert kinds == []
            continue
        assert kinds[-1] == "snap" and "settling" not in kinds
        # Turns along the path add up to where it ends.
        turned = sum(by_id.loc[sid, "transition_turn"] for sid in path[:-1])
        assert _circular(start["phase"] + turned, end["phase"]) < 1e-6


@pytest.mark.parametrize(("roll", "phase"), [(2.0, 315.0), (-2.0, 315.0), (2.0, 135.0)])
def test_passive_path_agrees_with_search(mech_rows, mech, quarter_20, roll, phase):
    start = mech_rows[
        (mech_rows["role"] == "start")
        & (mech_rows["held_roll"] == roll)
        & (mech_rows["phase"] == phase)
    ].iloc[0]
    path = _path(mech_rows, start["state_id"])
    by_id = mech_rows.set_index("state_id")
    run = search(mech, roll, -1.0, phase, step=M_STEP, phase_tolerance=0.01)
    assert run.snap is not None
    end = by_id.loc[path[-1]]
    assert end["classification"] == "in-phase"
    assert _circular(end["phase"], run.snap.phase) <= M_PHASE_STEP
    snap_row = by_id.loc[path[-2]]
    assert snap_row["transition"] == "snap"
    # Both land in the thread at the same height, but for the screw's descent between
    # their snap phases (and a hundredth of a pitch).
    landed = run.states[-1]
    assert landed.classification == "in-phase"
    screw = quarter_20.lead * _circular(end["phase"], run.snap.phase) / 360.0
    assert abs(end["centre_z"] - landed.centre[2]) <= screw + quarter_20.pitch / 100
    work = sum(
        by_id.loc[sid, "work_friction"] + by_id.loc[sid, "work_potential"] for sid in path[:-1]
    )
    joins = sum(by_id.loc[sid, "role"] == "start" for sid in path[1:])
    jumps = sum(by_id.loc[sid, "transition"] == "jump" for sid in path[:-1])
    if joins == 0:  # the search's walk, step for step: the same snap and click
        assert _circular(end["phase"], run.snap.phase) <= 0.02
        assert snap_row["drop"] == pytest.approx(run.snap.drop, rel=1e-6)
        assert snap_row["click"] == pytest.approx(run.snap.click, rel=1e-6)
        if jumps == 0:
            # The same states, so the same work: the search's located contact changes
            # are no nodes of the work (mechanics.md, "The driver's work").
            assert work == pytest.approx(run.work, abs=1e-6)
    # A path that joins another start's states may reach the thread in two hops where the
    # search takes one (a jump a few hundredths of a degree before the snap, near the
    # window's edge): the click is then split, the landing the same (above). Where it
    # joins, or jumps between grid phases, the two walks settle different phases, and
    # the work differs by the trapezoidal rule's error over those steps.
    assert work == pytest.approx(run.work, rel=0.05)


def test_mechanics_summary_query_and_figures(mech_library, mech_rows, mech, tmp_path):
    starts = mech_rows[mech_rows["role"] == "start"]
    doc = summary(mech_library, phase=140)
    assert doc["model"] == "mechanics" and doc["units"] == "in"
    assert doc["done"] == M_SIZE == doc["configurations"]
    assert {k: v for k, v in doc["counts"].items() if v} == starts[
        "classification"
    ].value_counts().to_dict()
    assert "no-contact" not in doc["counts"]
    assert doc["states"]["total"] == len(mech_rows)
    assert doc["states"]["by_role"] == mech_rows["role"].value_counts().to_dict()
    assert doc["states"]["by_class"] == mech_rows["classification"].value_counts().to_dict()
    for role, counts in doc["states"]["by_role_and_class"].items():
        assert (
            counts
            == mech_rows.loc[mech_rows["role"] == role, "classification"].value_counts().to_dict()
        )
    moves = mech_rows[mech_rows["transition"] != ""]
    assert sum(sum(v.values()) for v in doc["states"]["transitions"].values()) == len(moves)
    assert doc["at_phase"]["phase"] == 135.0
    assert sum(doc["at_phase"]["counts"].values()) == 2
    configs = configurations(mech_library)
    assert list(configs["config_id"]) == list(range(M_SIZE))
    assert list(configs.columns) == [
        "config_id",
        "roll",
        "pitch",
        "phase",
        "classification",
        "n_contacts",
        "region_combination",
    ]

    q = query(mech_library, 2.3, -1, 136, nearest=True)
    assert q["moved_to_grid"] and q["model"] == "mechanics" and q["units"] == "in"
    assert q["grid"] == {"roll": 2.0, "pitch": -1.0, "phase": 135.0}
    assert q["record"]["role"] == "start"
    assert q["record"]["classification"] == mech.settle(2, -1, 135).classification

    figures = write_figures(mech_library, tmp_path / "figs", phase=135)
    import matplotlib.image as mpimg

    for path in figures.values():
        img = mpimg.imread(path)
        assert img.ndim == 3 and img.shape[0] > 100 and img.shape[1] > 100


def test_mechanics_resume_refuses_other_settings(mech_library, quarter_20):
    before = sorted(p.name for p in mech_library.iterdir())
    for kwargs, words in (
        ({"compliance": Compliance(force=20.0)}, "compliance"),
        ({"compliance": Compliance(stiffness=(1.0, 2.0))}, "compliance"),
        ({"compliance": Compliance(friction=0.1)}, "compliance"),
        ({"step": 2.0}, "continuation settings"),
        ({"model": "thesis"}, "model"),
    ):
        with pytest.raises(LibraryError, match=words):
            sweep(
                quarter_20,
                M_ROLL,
                M_PITCH,
                M_PHASE,
                out=mech_library,
                workers=1,
                **{"step": M_STEP, **kwargs},
            )
    assert sorted(p.name for p in mech_library.iterdir()) == before


def test_partial_mechanics_sweep_resumes_exactly(mech_library, quarter_20, tmp_path):
    out = tmp_path / "partial"
    sweep(quarter_20, M_ROLL, M_PITCH, M_PHASE, out=out, workers=2, step=M_STEP, max_chunks=1)
    partial = info(out)
    assert partial["done"] == 8 and not partial["complete"] and partial["parts"] == 1
    seen = []
    sweep(
        quarter_20,
        M_ROLL,
        M_PITCH,
        M_PHASE,
        out=out,
        workers=1,
        step=M_STEP,
        progress=lambda done, total: seen.append((done, total)),
    )
    assert seen == [(8, M_SIZE), (M_SIZE, M_SIZE)]
    resumed = load(out)
    pd.testing.assert_frame_equal(resumed, load(mech_library))
    assert (resumed["role"] == "start").sum() == M_SIZE


def test_write_library_round_trips_rows(mech_library, library, quarter_20, tmp_path):
    rows = load(mech_library)
    out = write_library(
        rows, tmp_path / "written", quarter_20, M_ROLL, M_PITCH, M_PHASE, step=M_STEP
    )
    again = load(out)
    pd.testing.assert_frame_equal(again, rows)
    assert again.attrs["threadmate"]["model"] == "mechanics"
    assert info(out)["complete"]
    # The written library is the same request as the sweep's: a resume finds nothing to do.
    sweep(quarter_20, M_ROLL, M_PITCH, M_PHASE, out=out, workers=1, step=M_STEP)
    pd.testing.assert_frame_equal(load(out), rows)
    # The thesis's rows, as plain dicts.
    thesis = load(library)
    out = write_library(
        thesis.to_dict("records"),
        tmp_path / "thesis",
        quarter_20,
        ROLL,
        PITCH,
        PHASE,
        model="thesis",
        chord=CHORD,
    )
    pd.testing.assert_frame_equal(load(out), thesis)


def test_write_library_refuses_rows_missing_a_column(mech_library, quarter_20, tmp_path):
    rows = load(mech_library).drop(columns=["next_id"])
    out = tmp_path / "never"
    with pytest.raises(InputError, match="next_id"):
        write_library(rows, out, quarter_20, M_ROLL, M_PITCH, M_PHASE, step=M_STEP)
    assert not out.exists()
    with pytest.raises(InputError, match="model"):
        write_library(load(mech_library), out, quarter_20, M_ROLL, M_PITCH, M_PHASE, model="fixed")
    assert not out.exists()


def test_the_architecture_page_lists_the_state_record_as_stored():
    """docs/architecture.md's state-record table names every column of a library's rows,
    in order, with its unit: a reader finds each column's meaning there."""
    page = Path(__file__).resolve().parents[1] / "docs" / "architecture.md"
    text = page.read_text(encoding="utf-8")
    section = text.split("## The state record", 1)[1].split("\n## ", 1)[0]
    rows = [line.split("|") for line in section.splitlines() if line.startswith("| `")]
    assert [r[1].strip().strip("`") for r in rows] == [c.name for c in STATE_COLUMNS]
    assert [r[3].strip() for r in rows] == [c.unit or "-" for c in STATE_COLUMNS]


def _inherited(quarter_20, conn) -> None:  # pragma: no cover - runs in a forked child
    """In a process forked after ``prepare_inherited``: build the worker's model with no
    contact scene built, and report which kernels were not compiled on arrival."""
    from threadmate.contact.scene import _kernels, _linkage, _obb, _scene
    from threadmate.library._workers import Job, _worker_for

    kernels = {
        "walk": _obb._crossing,
        "trees": _obb._build,
        "vertical touch": _kernels._vertical_touch,
        "signed distance": _kernels._signed_distance,
        "contact grouping": _linkage._linked,
    }
    cold = sorted(name for name, kernel in kernels.items() if not kernel.signatures)

    def refused(*args, **kwargs):
        raise AssertionError("a worker built a contact scene of its own")

    _scene.ContactScene.__init__ = refused
    try:
        job = Job(quarter_20, None, CHORD, "mechanics", Compliance())
        _worker_for(job)
        conn.send(("ok", cold))
    except BaseException as exc:  # noqa: BLE001 - reported to the test
        conn.send((repr(exc), cold))


def test_a_forked_worker_inherits_the_scene_and_the_compiled_kernels(quarter_20):
    """A pool's worker, forked after the sweep's process prepared the job
    (``prepare_inherited``), finds the contact scene, its collision trees included, and
    the compiled kernels there: it compiles, loads and builds none of them."""
    import multiprocessing

    from threadmate.library._workers import Job, prepare_inherited

    prepare_inherited(Job(quarter_20, None, CHORD, "mechanics", Compliance()))
    ours, theirs = multiprocessing.get_context("fork").Pipe()
    child = multiprocessing.get_context("fork").Process(
        target=_inherited, args=(quarter_20, theirs)
    )
    child.start()
    assert ours.poll(120)
    outcome, cold = ours.recv()
    child.join(30)
    assert outcome == "ok"
    assert cold == []
