"""Faults around a library: a killed sweep, files that do not belong, bad settings.

Each check runs the real command line or API on a tiny grid and looks at what is left on
disk and in the process table.
"""

from __future__ import annotations

import json
import os
import re
import shutil
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path

import pyarrow.parquet as pq
import pytest

from _cli import refused, run_cli
from threadmate import InputError, LibraryError, library

DESIGNATION = "1/4-20 UNC-2A/2B"


def _children(pid: int) -> list[int]:
    """Pids of the processes whose parent is ``pid`` (Linux /proc)."""
    out = []
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            fields = (entry / "stat").read_text().rsplit(")", 1)[1].split()
        except OSError:
            continue
        if int(fields[1]) == pid:
            out.append(int(entry.name))
    return out


def _alive(pid: int) -> bool:
    try:
        state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
    except OSError:
        return False
    return state != "Z"


@pytest.mark.skipif(not Path("/proc").is_dir(), reason="needs /proc (Linux)")
def test_killed_sweep_leaves_no_worker_behind(tmp_path):
    lib = tmp_path / "lib"
    # Four held tilts of the mechanics: each worker is busy for many seconds per chunk.
    cmd = [
        sys.executable,
        "-c",
        "from threadmate.cli import main; main()",
        "sweep",
        DESIGNATION,
        "--roll",
        "0:3:1",
        "--pitch",
        "0",
        "--phase",
        "0:270:90",
        "--workers",
        "2",
        "-o",
        str(lib),
    ]
    proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    workers: list[int] = []
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline and proc.poll() is None and len(workers) < 2:
        workers = _children(proc.pid)
        time.sleep(0.2)
    time.sleep(2.0)  # let them start on their chunks
    if proc.poll() is not None:
        pytest.skip("the sweep finished before it could be killed")
    workers = _children(proc.pid)
    os.kill(proc.pid, signal.SIGKILL)
    proc.wait()
    assert len(workers) >= 2, f"the pool's workers were not seen: {workers}"
    deadline = time.monotonic() + 15
    while time.monotonic() < deadline and any(_alive(w) for w in workers):
        time.sleep(0.2)
    assert not any(_alive(w) for w in workers), "a worker outlived its killed sweep"


@pytest.fixture(scope="module")
def small_library(tmp_path_factory, quarter_20):
    out = tmp_path_factory.mktemp("faults") / "lib"
    return library.sweep(quarter_20, "0", "0", "0:180:180", out=out, workers=1, model="thesis")


def test_stray_parquet_file_is_named(small_library, tmp_path, capsys):
    lib = tmp_path / "lib"
    shutil.copytree(small_library, lib)
    shutil.copy(next(lib.glob("part-*.parquet")), lib / "extra.parquet")
    with pytest.raises(LibraryError, match="extra.parquet does not belong to the library"):
        library.info(lib)
    code, out, err = run_cli(capsys, "library", "info", lib)
    assert code == 2
    assert "extra.parquet does not belong" in err
    assert "Traceback" not in err


def test_part_of_another_library_is_named(small_library, tmp_path, quarter_20):
    lib = tmp_path / "lib"
    shutil.copytree(small_library, lib)
    other = library.sweep(
        quarter_20, "0", "0", "0:180:180", out=tmp_path / "other", workers=1, model="thesis"
    )
    part = next(other.glob("part-*.parquet"))
    shutil.copy(part, lib / "part-00099.parquet")
    with pytest.raises(LibraryError, match="part-00099.parquet does not belong"):
        library.load(lib)


def test_stale_temporaries_are_removed_on_resume(small_library, tmp_path, quarter_20):
    lib = tmp_path / "lib"
    shutil.copytree(small_library, lib)
    stale = lib / ".part-00007.parquet.abc123.tmp"
    stale.write_bytes(b"half a part")
    library.sweep(quarter_20, "0", "0", "0:180:180", out=lib, workers=1, model="thesis")
    assert not stale.exists()


@pytest.mark.parametrize("scheduler", ["nonsense", "tcp://", "http:/host", "12 34"])
def test_unknown_scheduler_is_refused_before_anything_is_written(
    tmp_path, quarter_20, scheduler, capsys
):
    # The API names its parameter, the command line its option.
    with pytest.raises(InputError, match="^scheduler"):
        library.sweep(quarter_20, "0", "0", "0", out=tmp_path / "lib", scheduler=scheduler)
    assert not (tmp_path / "lib").exists()
    code, _, err = run_cli(
        capsys,
        "sweep",
        DESIGNATION,
        "--roll",
        "0",
        "--pitch",
        "0",
        "--phase",
        "0",
        "--scheduler",
        scheduler,
        "-o",
        tmp_path / "lib2",
    )
    assert code == 2
    assert "--scheduler" in err and "Traceback" not in err
    assert not (tmp_path / "lib2").exists()


@pytest.mark.parametrize("chord", [0.004, 1e-9])
def test_chord_out_of_the_meshes_range_is_refused_before_anything_is_written(
    tmp_path, quarter_20, chord
):
    # 0.004 in lies between the mesh's limit (pitch x 0.02 = 0.001 in) and a tenth of the
    # pitch (0.005 in), where the sweep used to start and then fail in its worker.
    with pytest.raises(InputError, match="chord"):
        library.sweep(quarter_20, "0", "0", "0", out=tmp_path / "lib", chord=chord)
    assert not (tmp_path / "lib").exists()


def _all_commands(group, prefix=()):
    import click

    for name, cmd in group.commands.items():
        if isinstance(cmd, click.Group):
            yield from _all_commands(cmd, (*prefix, name))
        else:
            yield (*prefix, name), cmd


def test_every_command_takes_the_same_condition_spellings(capsys):
    # The command tree, registered in full (an internal of the command line).
    from threadmate.cli import cli

    # The commands' registration: a CLI internal with no public form.
    from threadmate.cli._main import _register

    _register()

    with_condition = {
        " ".join(path): cmd
        for path, cmd in _all_commands(cli)
        if any(p.name == "condition" for p in cmd.params)
    }
    assert {"thread", "planar", "mesh", "contact", "settle", "search", "sweep", "run"} <= set(
        with_condition
    )
    for cmd in with_condition.values():
        option = next(p for p in cmd.params if p.name == "condition")
        for spelling, canonical in (
            ("MMC", "max"),
            ("maximum", "max"),
            ("lmc", "min"),
            ("Minimum", "min"),
            ("mid", "mean"),
            ("mean", "mean"),
        ):
            assert option.type.convert(spelling, option, None) == canonical
    # And the command line agrees: the same limits for two spellings of one condition.
    _, a, _ = run_cli(capsys, "thread", DESIGNATION, "--condition", "mmc", "--json")
    _, b, _ = run_cli(capsys, "thread", DESIGNATION, "--condition", "max", "--json")
    assert a == b


@pytest.mark.skipif(not Path("/proc").is_dir(), reason="needs /proc (Linux)")
def test_unwritable_library_and_figure_folders_arerefused(small_library, capsys, quarter_20):
    with pytest.raises(LibraryError, match="cannot create the library"):
        library.sweep(quarter_20, "0", "0", "0", out="/proc/threadmate-x/lib", model="thesis")
    for args in (
        [
            "sweep",
            DESIGNATION,
            "--roll",
            "0",
            "--pitch",
            "0",
            "--phase",
            "0",
            "-o",
            "/proc/threadmate-x/lib",
        ],
        ["library", "summary", str(small_library), "-o", "/proc/threadmate-x/figs"],
    ):
        code, out, err = run_cli(capsys, *args)
        assert code == 2, args
        assert err.startswith("threadmate: error: -o /proc/threadmate-x") and "Traceback" not in err


# -- a library whose rows do not fit its grid ---------------------------------------------
def _edit_grid(lib: Path, **grid) -> None:
    meta_file = lib / library.METADATA_FILE
    meta = json.loads(meta_file.read_text())
    meta["grid"].update(grid)
    meta_file.write_text(json.dumps(meta))


@pytest.mark.parametrize(
    ("grid", "words"),
    [
        # The phase list cut short, its size kept: the size contradicts the values.
        ({"phase": [0.0]}, "states a size of 2"),
        # Cut short with the size to match: configuration 1 lies beyond a grid of 1.
        ({"phase": [0.0], "size": 1}, "beyond the grid (first: 1)"),
        # Same count, another value: configuration 1 (phase 180 in the rows) is phase 90.
        ({"phase": [0.0, 90.0]}, "phase 180, where the grid"),
    ],
)
def test_rows_that_do_not_fit_the_grid_arerefused(small_library, tmp_path, capsys, grid, words):
    # small_library: roll 0, pitch 0, phases 0 and 180 (configurations 0 and 1, both done).
    lib = tmp_path / "lib"
    shutil.copytree(small_library, lib)
    _edit_grid(lib, **grid)
    for read in (library.info, library.load, library.progress, library.summary):
        with pytest.raises(LibraryError, match=re.escape(words)):
            read(lib)
    with pytest.raises(LibraryError, match=re.escape(words)):
        library.query(lib, 0, 0, 0)
    for args in (
        ["library", "info", lib],
        ["library", "info", lib, "--json"],
        ["library", "query", lib, "--roll", "0", "--pitch", "0", "--phase", "0"],
        ["library", "summary", lib],
    ):
        assert words in refused(capsys, *args)


def test_a_state_away_from_its_starts_held_tilt_isrefused(tmp_path, quarter_20):
    from _libraries import SYNTH_COMPLIANCE, SYNTH_GRID, synthetic_rows

    rows = synthetic_rows()
    # A continued state moved to another held tilt than its start's (config_id 0 is held
    # roll 0, pitch -1 on this grid): the part was mixed by hand.
    i = rows.index[(rows["config_id"] == 0) & (rows["role"] != "start")][0]
    rows.loc[i, "held_pitch"] = 1.0
    lib = library.write_library(
        rows, tmp_path / "lib", quarter_20, **SYNTH_GRID, compliance=SYNTH_COMPLIANCE
    )
    with pytest.raises(LibraryError, match="a state of configuration 0 in its parts is at held"):
        library.load(lib)


def test_parts_carry_the_grid_shape_not_its_values(tmp_path, quarter_20, small_library):
    # 36,000 phases (0.01 deg): before, every part carried all of them (and the roll
    # values) in its schema; now its metadata is as small as for a grid of one phase.
    lib = library.sweep(
        quarter_20,
        "0",
        "0",
        "0:359.99:0.01",
        out=tmp_path / "lib",
        workers=1,
        model="thesis",
        chunk_size=2,
        max_chunks=1,
    )
    meta = json.loads((lib / library.METADATA_FILE).read_text())
    assert len(meta["grid"]["phase"]) == 36_000  # the values, once, in the metadata file
    (part,) = lib.glob("part-*.parquet")
    carried = json.loads(pq.read_schema(part).metadata[b"threadmate"])
    assert carried["grid"] == {
        "shape": [1, 1, 36_000],
        "size": 36_000,
        "order": meta["grid"]["order"],
        "values": "in _threadmate.json",
    }
    assert len(pq.read_schema(part).metadata[b"threadmate"]) < 4_000
    doc = library.info(lib)
    assert (doc["done"], doc["configurations"], doc["complete"]) == (2, 36_000, False)


def test_a_library_whose_parts_carry_the_whole_grid_still_reads(small_library, tmp_path):
    # The parts of libraries written before carried every grid value: the same format.
    lib = tmp_path / "lib"
    shutil.copytree(small_library, lib)
    meta_text = (lib / library.METADATA_FILE).read_text()
    full = json.dumps(json.loads(meta_text), sort_keys=True).encode()
    for part in lib.glob("part-*.parquet"):
        table = pq.read_table(part)
        pq.write_table(table.replace_schema_metadata({b"threadmate": full}), part)
    assert library.info(lib)["done"] == 2
    assert len(library.load(lib)) == 2


# -- an incomplete library ----------------------------------------------------------------
@pytest.fixture(scope="module")
def unfinished(tmp_path_factory, quarter_20):
    """The synthetic mechanics library without its held tilt (1, 1): its sweep stopped
    there. Returns (path, starts done, configurations)."""
    from _libraries import SYNTH_COMPLIANCE, SYNTH_GRID, synthetic_rows

    rows = synthetic_rows()
    rows = rows[~((rows["held_roll"] == 1.0) & (rows["held_pitch"] == 1.0))]
    path = library.write_library(
        rows,
        tmp_path_factory.mktemp("unfinished") / "lib",
        quarter_20,
        **SYNTH_GRID,
        compliance=SYNTH_COMPLIANCE,
    )
    # Counted here from the rows and the grid's lists (2 x 3 x 4 configurations).
    total = len(SYNTH_GRID["roll"]) * len(SYNTH_GRID["pitch"]) * len(SYNTH_GRID["phase"])
    return path, rows.loc[rows["role"] == "start", "config_id"].nunique(), total


def test_an_incomplete_library_says_how_far_it_got(unfinished, capsys, tmp_path):
    lib, done, total = unfinished
    assert (done, total) == (20, 24)
    words = f"{done} of {total} starts done"
    code, out, _ = run_cli(capsys, "library", "info", lib)
    assert code == 0 and words in out and "INCOMPLETE" in out and "interrupted" in out
    code, out, _ = run_cli(capsys, "library", "info", lib, "--json")
    doc = json.loads(out)
    assert (doc["done"], doc["configurations"], doc["complete"]) == (done, total, False)
    assert doc["sweeping"] is None
    code, out, _ = run_cli(capsys, "library", "summary", lib)
    assert code == 0 and words in out
    doc = json.loads(run_cli(capsys, "library", "summary", lib, "--json")[1])
    assert (doc["done"], doc["configurations"], doc["complete"]) == (done, total, False)
    out_file = tmp_path / "net.graphml"
    code, out, _ = run_cli(capsys, "network", lib, "-o", out_file)
    assert code == 0 and words in out
    doc = json.loads(run_cli(capsys, "network", lib, "-o", out_file, "--json")[1])
    assert (doc["done"], doc["configurations"], doc["complete"]) == (done, total, False)


def test_recommend_refuses_an_incomplete_library_unless_partial(unfinished, capsys):
    lib, done, total = unfinished
    line = refused(capsys, "recommend", lib)
    assert f"library {lib}: {done} of {total} starts done" in line and "--partial" in line
    with pytest.raises(InputError, match="incomplete"):
        from threadmate.network import from_library, recommend

        recommend(from_library(lib))
    code, out, _ = run_cli(capsys, "recommend", lib, "--partial")
    assert code == 0 and f"note: from an incomplete library: {done} of {total} starts" in out
    doc = json.loads(run_cli(capsys, "recommend", lib, "--partial", "--json")[1])
    assert doc["complete"] is False
    assert doc["progress"] == [{"done": done, "configurations": total, "complete": False}]
    # The held tilt missing is not ranked: held pitch +1 has starts at roll 0 only.
    plus = next(s for s in doc["settings"] if s["held_pitch"] == 1.0)
    assert plus["starts"] + plus["failed"] == 4


# -- one sweep at a time ------------------------------------------------------------------
_SWEEP = (
    "import sys; from threadmate import library; "
    "from threadmate.geometry import spec_from_designation as s; "
    "library.sweep(s('1/4-20 UNC-2A/2B'), '-4:4:1', '-4:4:1', '0:355:5', out=sys.argv[1], "
    "workers=2, model='thesis', chunk_size=4)"
)


def _parts(lib: Path) -> int:
    return len(list(lib.glob("part-*.parquet")))


def _wait_for(what, timeout: float = 120.0) -> None:
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if what():
            return
        time.sleep(0.1)
    raise AssertionError("timed out")


@pytest.mark.skipif(not Path("/proc").is_dir(), reason="needs /proc (Linux)")
def test_a_second_sweep_is_refused_and_a_killed_ones_lock_does_not_block(tmp_path, capsys):
    from threadmate.geometry import spec_from_designation

    lib = tmp_path / "lib"
    first = subprocess.Popen(
        [sys.executable, "-c", _SWEEP, str(lib)],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
    )
    try:
        _wait_for(lambda: _parts(lib) >= 2 or first.poll() is not None)
        assert first.poll() is None, first.stderr.read().decode() if first.stderr else ""
        lock = json.loads((lib / ".threadmate-sweep.lock").read_text())
        assert lock["pid"] == first.pid and lock["host"] == socket.gethostname()
        assert library.info(lib)["sweeping"]["pid"] == first.pid
        code, out, _ = run_cli(capsys, "library", "info", lib)
        assert f"INCOMPLETE, a sweep (process {first.pid} on" in out
        # A second sweep of the same library, as a real process: refused at once, by name.
        t0 = time.monotonic()
        second = subprocess.run(
            [
                sys.executable,
                "-c",
                "from threadmate.cli import main; main()",
                "sweep",
                DESIGNATION,
                "--model",
                "thesis",
                "--roll",
                "-4:4:1",
                "--pitch",
                "-4:4:1",
                "--workers",
                "1",
                "--chunk-size",
                "4",
                "-o",
                str(lib),
            ],
            capture_output=True,
            text=True,
            timeout=300,
        )
        assert second.returncode == 2, second.stderr
        lines = [x for x in second.stderr.splitlines() if x.strip()]
        assert len(lines) == 1 and "Traceback" not in second.stderr, second.stderr
        assert f"is being swept by process {first.pid} on {socket.gethostname()}" in lines[0]
        assert second.stdout == ""
        # The first goes on writing, unharmed (its temporary parts were left alone).
        n = _parts(lib)
        _wait_for(lambda: _parts(lib) > n + 1 or first.poll() is not None)
        assert first.poll() is None, first.stderr.read().decode() if first.stderr else ""
        assert time.monotonic() - t0 < 240
        os.kill(first.pid, signal.SIGKILL)
        first.wait()
    finally:
        if first.poll() is None:
            first.kill()
            first.wait()
        if first.stderr is not None:
            first.stderr.close()
    # The killed sweep's lock file stays, naming a process that no longer runs: it does not
    # block the resume, at once (while the killed sweep's pool workers are still exiting).
    stale = json.loads((lib / ".threadmate-sweep.lock").read_text())
    assert stale["pid"] == first.pid
    before = _parts(lib)
    library.sweep(
        spec_from_designation(DESIGNATION),
        "-4:4:1",
        "-4:4:1",
        "0:355:5",
        out=lib,
        workers=1,
        model="thesis",
        chunk_size=4,
        max_chunks=1,
    )
    assert _parts(lib) == before + 1
    doc = library.info(lib)
    assert doc["sweeping"] is None and doc["done"] == 4 * (before + 1)  # chunks of 4
    assert not (lib / ".threadmate-sweep.lock").exists()
    assert not list(lib.glob(".*.tmp"))


_FORK_AND_DIE = """
import os, sys, time
from threadmate.library import _store
with _store.sweep_lock(sys.argv[1]):
    child = os.fork()
    if child == 0:  # as a pool worker forked by the sweep does
        _store.release_inherited_locks()
        os.close(1), os.close(2)  # the test reads the parent's output to its end
        time.sleep(60)
        os._exit(0)
    print(child, flush=True)
    os._exit(0)  # dies holding the lock: its file stays
"""


@pytest.mark.skipif(not hasattr(os, "fork"), reason="needs fork")
def test_a_forked_worker_does_not_keep_a_dead_sweeps_lock(tmp_path):
    from threadmate.library._store import sweep_lock  # an internal with no public form

    lib = tmp_path / "lib"
    lib.mkdir()
    done = subprocess.run(
        [sys.executable, "-c", _FORK_AND_DIE, str(lib)], capture_output=True, text=True
    )
    child = int(done.stdout.split()[0])
    try:
        assert _alive(child)  # the forked worker outlives the sweep ...
        assert (lib / ".threadmate-sweep.lock").exists()
        with sweep_lock(lib):  # ... but not its lock
            assert json.loads((lib / ".threadmate-sweep.lock").read_text())["pid"] == os.getpid()
    finally:
        os.kill(child, signal.SIGKILL)
