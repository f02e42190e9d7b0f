"""The sweep on a real Dask distributed cluster: workers in separate processes, started here
on 127.0.0.1, give the process pool's library row for row; CAD mesh files travel to the
workers with the job, not by their path."""

from __future__ import annotations

import hashlib
import pickle
import shutil
from pathlib import Path

import pandas as pd
import pytest

from threadmate.contact import Compliance
from threadmate.geometry import bolt_mesh, nut_mesh
from threadmate.library import Grid, load, sweep

distributed = pytest.importorskip("distributed")

CHORD = 1e-4
ROLL, PITCH, PHASE = "-2,1", "1", "0"  # two held tilts (one chunk each), one phase
STEP = 10.0


def _rows(path: Path) -> pd.DataFrame:
    return load(path).sort_values(["config_id", "state_id"]).reset_index(drop=True)


@pytest.fixture(scope="module")
def worker_tmp(tmp_path_factory):
    """The workers' temporary directory (where shipped mesh files land)."""
    return tmp_path_factory.mktemp("workers")


@pytest.fixture(scope="module")
def cluster(worker_tmp):
    """A LocalCluster of two worker processes on the loopback interface."""
    with distributed.LocalCluster(
        n_workers=2,
        threads_per_worker=1,
        processes=True,
        host="127.0.0.1",
        dashboard_address=None,
        env={"TMPDIR": str(worker_tmp)},
    ) as c:
        yield c


@pytest.fixture(scope="module")
def mesh_paths(quarter_20, tmp_path_factory):
    """The pair's meshes written as STL files, as a CAD tool would hand them over."""
    folder = tmp_path_factory.mktemp("cad")
    paths = {}
    for kind, make in (("bolt", bolt_mesh), ("nut", nut_mesh)):
        paths[kind] = folder / f"{kind}.stl"
        make(quarter_20, CHORD).mesh.export(paths[kind])
    return paths


@pytest.mark.slow
def test_cluster_library_equals_the_pools(cluster, quarter_20, tmp_path):
    common = {"chord": CHORD, "step": STEP}
    pool = sweep(quarter_20, ROLL, PITCH, PHASE, out=tmp_path / "pool", workers=2, **common)
    dask = sweep(
        quarter_20,
        ROLL,
        PITCH,
        PHASE,
        out=tmp_path / "dask",
        scheduler=cluster.scheduler_address,
        **common,
    )
    a, b = _rows(pool), _rows(dask)
    assert len(a) >= 2 and set(a["config_id"]) == {0, 1}
    pd.testing.assert_frame_equal(a, b)


@pytest.mark.slow
def test_cluster_sweep_with_mesh_files_ships_their_bytes(
    cluster, worker_tmp, quarter_20, mesh_paths, tmp_path
):
    files = {"bolt_mesh": mesh_paths["bolt"], "nut_mesh": mesh_paths["nut"], "chord": CHORD}
    pool = sweep(
        quarter_20, "1", PITCH, PHASE, out=tmp_path / "pool", workers=1, step=STEP, **files
    )
    dask = sweep(
        quarter_20,
        "1",
        PITCH,
        PHASE,
        out=tmp_path / "dask",
        scheduler=cluster.scheduler_address,
        step=STEP,
        **files,
    )
    pd.testing.assert_frame_equal(_rows(pool), _rows(dask))
    # The workers read copies written from the bytes the job carried, of the same names.
    copies = sorted(p.name for p in worker_tmp.rglob("*.stl"))
    assert copies == ["bolt.stl", "nut.stl"]
    for copy in worker_tmp.rglob("*.stl"):
        assert copy.read_bytes() == mesh_paths[copy.stem].read_bytes()
        copy.unlink()

    # A job as a cluster's worker receives it loads its meshes without the sweep's path:
    # the files moved away, the job's chunk on the cluster gives the same rows. (The
    # job is an internal with no public form.)
    from threadmate.library._workers import Job, MeshFile, run_chunk, with_mesh_contents

    def mesh_file(path: Path) -> MeshFile:
        return MeshFile(str(path), "in", hashlib.sha256(path.read_bytes()).hexdigest())

    job = Job(
        quarter_20,
        Grid.parse("1", PITCH, PHASE),
        CHORD,
        "mechanics",
        Compliance(),
        step=STEP,
        bolt_mesh=mesh_file(mesh_paths["bolt"]),
        nut_mesh=mesh_file(mesh_paths["nut"]),
        mesh_units="in",  # as the files declare: another job than the sweep's, loaded anew
    )
    shipped = pickle.loads(pickle.dumps(with_mesh_contents(job)))
    assert shipped.key == job.key  # the bytes are no part of the job's identity
    moved = tmp_path / "moved"
    shutil.move(mesh_paths["bolt"].parent, moved)
    try:
        assert not mesh_paths["bolt"].exists()
        with distributed.Client(cluster) as client:
            table, settings = client.submit(run_chunk, shipped, [0], pure=False).result()
    finally:
        shutil.move(moved, mesh_paths["bolt"].parent)
    rows = table.to_pandas().sort_values(["config_id", "state_id"]).reset_index(drop=True)
    expected = _rows(pool)
    pd.testing.assert_frame_equal(rows, expected[rows.columns], check_dtype=False)
    assert settings["meshes"]["bolt"]["file"] == "bolt.stl"
    assert sorted(p.name for p in worker_tmp.rglob("*.stl")) == ["bolt.stl", "nut.stl"]
