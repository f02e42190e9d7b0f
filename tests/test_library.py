"""The sweep stage on the real contact engine (python-fcl): rows, resume, refusal, storage.

Grids are tiny and the chord coarse (1e-4 in) so that the whole file stays fast; the rows
are checked against the contact analyser called directly in the test process.
"""

from __future__ import annotations

import functools
import json
import math
import os
import sys

import numpy as np
import pandas as pd
import pyarrow.dataset as ds
import pyarrow.parquet as pq
import pytest

from threadmate._errors import InputError, LibraryError
from threadmate.contact import ContactAnalyzer, record_schema
from threadmate.geometry import ThreadSpec
from threadmate.library import (
    METADATA_FILE,
    Grid,
    SweepInterrupted,
    info,
    load,
    query,
    summary,
    sweep,
    write_figures,
)

CHORD = 1e-4
ROLL, PITCH, PHASE = "-3,0,4", "0,2", "0,185,235"   # 18 configurations


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
    """One uninterrupted sweep with a two-process pool."""
    out = tmp_path_factory.mktemp("lib") / "quarter-20"
    sweep(quarter_20, ROLL, PITCH, PHASE, out=out, workers=2, chunk_size=4, chord=CHORD)
    return out


def _same_row(row: pd.Series, rec: dict) -> None:
    for name, value in rec.items():
        got = row[name]
        if isinstance(value, float):
            assert (math.isnan(got) and math.isnan(value)) or got == pytest.approx(
                value, rel=1e-12, abs=1e-15), name
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
    # Every part carries the same metadata in its Arrow schema.
    parts = sorted(library.glob("part-*.parquet"))
    assert len(parts) == 5     # 18 configurations in chunks of 4
    for part in parts:
        assert json.loads(pq.read_schema(part).metadata[b"threadmate"]) == meta
    assert load(library).attrs["threadmate"] == meta


def test_read_directly_with_pyarrow_pandas_and_duckdb(library):
    ours = load(library)
    table = ds.dataset(library, format="parquet").to_table()
    assert table.num_rows == 18
    assert sorted(table.column("config_id").to_pylist()) == list(range(18))
    direct = pd.read_parquet(library).sort_values("config_id").reset_index(drop=True)
    pd.testing.assert_frame_equal(direct, ours, check_like=False)
    duckdb = pytest.importorskip("duckdb")
    rows = duckdb.sql(f"SELECT config_id, classification FROM "
                      f"read_parquet('{library}/*.parquet') ORDER BY config_id").fetchall()
    assert rows == list(zip(ours["config_id"], ours["classification"], strict=True))


def test_resumed_sweep_equals_uninterrupted(library, quarter_20, tmp_path):
    out = tmp_path / "resumed"
    sweep(quarter_20, ROLL, PITCH, PHASE, out=out, workers=2, chunk_size=4, chord=CHORD,
          max_chunks=2)
    partial = info(out)
    assert partial["done"] == 8 and not partial["complete"]
    seen = []
    # Resume with another chunk size and in-process: only the missing 10 are computed.
    sweep(quarter_20, ROLL, PITCH, PHASE, out=out, workers=1, chunk_size=3, chord=CHORD,
          progress=lambda done, total: seen.append((done, total)))
    assert seen[0] == (8, 18) and seen[-1] == (18, 18)
    assert len(seen) == 1 + math.ceil(10 / 3)
    resumed = load(out)
    assert resumed["config_id"].is_unique
    pd.testing.assert_frame_equal(resumed, load(library))
    # Running it again finds nothing to do and writes nothing.
    parts = sorted(out.glob("part-*.parquet"))
    sweep(quarter_20, ROLL, PITCH, PHASE, out=out, workers=1, chord=CHORD)
    assert sorted(out.glob("part-*.parquet")) == parts


def test_killed_worker_then_resume_equals_uninterrupted(library, quarter_20, tmp_path):
    out = tmp_path / "killed"
    factory = functools.partial(KillOnceAnalyzer, marker=str(tmp_path / "killed-once"))
    with pytest.raises(SweepInterrupted, match="run the same sweep again to resume"):
        sweep(quarter_20, ROLL, PITCH, PHASE, out=out, workers=2, chunk_size=1, chord=CHORD,
              analyzer=factory)
    assert info(out)["done"] < 18
    sweep(quarter_20, ROLL, PITCH, PHASE, out=out, workers=2, chunk_size=1, chord=CHORD,
          analyzer=factory)
    pd.testing.assert_frame_equal(load(out), load(library))


def test_mismatched_library_is_refused_not_mixed(library, quarter_20):
    before = sorted(p.name for p in library.iterdir())
    with pytest.raises(LibraryError, match="grid phase values"):
        sweep(quarter_20, ROLL, PITCH, "0:355:5", out=library, workers=1, chord=CHORD)
    with pytest.raises(LibraryError, match="chord"):
        sweep(quarter_20, ROLL, PITCH, PHASE, out=library, workers=1, chord=5e-5)
    with pytest.raises(LibraryError, match="compliance"):
        sweep(quarter_20, ROLL, PITCH, PHASE, out=library, workers=1, chord=CHORD,
              compliance_z=0.1)
    other = ThreadSpec.from_dict({**quarter_20.to_dict(),
                                  "nut": {**quarter_20.to_dict()["nut"],
                                          "pitch_diameter": 0.2200}})
    with pytest.raises(LibraryError, match=r"spec \(nut.pitch_diameter"):
        sweep(other, ROLL, PITCH, PHASE, out=library, workers=1, chord=CHORD)
    assert sorted(p.name for p in library.iterdir()) == before


def test_error_rows_are_recorded_and_the_sweep_goes_on(quarter_20, analyzer, tmp_path):
    out = sweep(quarter_20, "0,4", "0", PHASE, out=tmp_path / "flaky", workers=2,
                chunk_size=2, chord=CHORD, analyzer=FlakyAnalyzer)
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


def test_query_snaps_to_the_nearest_grid_state(library, analyzer):
    exact = query(library, 4, 2, 235)
    assert not exact["snapped"] and exact["computed"]
    assert exact["grid"] == {"roll": 4.0, "pitch": 2.0, "phase": 235.0}
    assert exact["config_id"] == Grid.parse(ROLL, PITCH, PHASE).config_id(2, 1, 2)
    direct = analyzer.analyze(4, 2, 235).to_record()
    assert exact["record"]["classification"] == direct["classification"]
    assert exact["record"]["third_c1_x"] == pytest.approx(direct["third_c1_x"], nan_ok=True)
    # 3.2 -> 4, 1.4 -> 2, -130 (= 230) -> 235.
    snapped = query(library, 3.2, 1.4, -130)
    assert snapped["snapped"] and snapped["grid"] == exact["grid"]


def test_summary_counts_and_figures(library, tmp_path):
    df = pd.read_parquet(library)          # counted independently of the library API
    counts = df["classification"].value_counts().to_dict()
    doc = summary(library, phase=186)
    assert doc["done"] == 18 and doc["configurations"] == 18
    assert {k: v for k, v in doc["counts"].items() if v} == counts
    assert sum(doc["region_combinations"].values()) == 18
    three = {k: doc["counts"][k] for k in ("unstable", "quasi-stable", "stable")}
    assert three[doc["most_common"]] == max(three.values())
    at = doc["at_phase"]
    assert at["phase"] == 185.0
    assert sum(at["counts"].values()) == 6
    assert at["counts"]["unstable"] == int(((df["phase"] == 185.0)
                                            & (df["classification"] == "unstable")).sum())
    figures = write_figures(library, tmp_path / "figs", phase=185)
    import matplotlib.image as mpimg
    for path in figures.values():
        img = mpimg.imread(path)
        assert img.ndim == 3 and img.shape[0] > 100 and img.shape[1] > 100


def test_sweep_without_out_returns_the_rows(quarter_20, analyzer):
    df = sweep(quarter_20, "0", "0", "0,90", workers=1, chord=CHORD)
    assert isinstance(df, pd.DataFrame) and len(df) == 2
    _same_row(df.iloc[1], analyzer.analyze(0, 0, 90).to_record())


def test_bad_requests_raise_input_errors(quarter_20, tmp_path):
    out = tmp_path / "never"
    for kwargs, words in (({"roll": "0:4:0"}, "--roll"), ({"workers": 0}, "--workers"),
                          ({"chord": -1.0}, "--chord"), ({"chord": 0.01}, "too coarse"),
                          ({"scheduler": 5}, "--scheduler"), ({"chunk_size": 0}, "chunk_size")):
        with pytest.raises(InputError, match=words):
            sweep(quarter_20, **{"roll": "0", "pitch": "0", "phase": "0", "chord": CHORD,
                                 **kwargs}, out=out)
    assert not out.exists()


def test_scheduler_without_dask_says_how_to_install(quarter_20, tmp_path, monkeypatch):
    monkeypatch.setitem(sys.modules, "distributed", None)   # as if not installed
    with pytest.raises(InputError, match=r"pip install threadmate\[dask\]"):
        sweep(quarter_20, "0", "0", "0", out=tmp_path / "d", scheduler="local", chord=CHORD)
    assert not (tmp_path / "d").exists()


def test_dask_scheduler_setting_is_read(monkeypatch):
    dask = pytest.importorskip("dask")
    from threadmate.library._sweep import _scheduler_from_dask_config

    with dask.config.set({"scheduler-address": "tcp://10.1.2.3:8786"}):
        assert _scheduler_from_dask_config() == "tcp://10.1.2.3:8786"
    with dask.config.set({"scheduler-address": None}):
        assert _scheduler_from_dask_config() is None


@pytest.mark.slow
def test_dask_local_cluster_gives_the_same_rows(library, quarter_20, tmp_path):
    pytest.importorskip("distributed")
    out = sweep(quarter_20, ROLL, PITCH, PHASE, out=tmp_path / "dask", scheduler="local",
                workers=2, chunk_size=5, chord=CHORD)
    rows = load(out)
    pd.testing.assert_frame_equal(rows, load(library))
    assert np.array_equal(rows["config_id"], np.arange(18))
