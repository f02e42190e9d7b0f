"""Faults around a library: a killed sweep, files that do not belong, bad settings.

Each check runs the real command line or API on a tiny grid and looks at what is left on
disk and in the process table.
"""

from __future__ import annotations

import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from _cli import run_cli
from threadmate import library
from threadmate._errors import InputError, LibraryError

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
    with pytest.raises(InputError, match="--scheduler"):
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
    from threadmate.cli._main import _register, cli

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
def test_unwritable_library_and_figure_folders_are_refused(small_library, capsys, quarter_20):
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
