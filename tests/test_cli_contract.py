"""The command line's contract with its user, in real processes: ``--help``, ``--version``,
``thread`` and a refused option import none of the heavy stages; a closed or full standard
output, a full disk and SIGTERM each end in one message (exit 2, or 130 for SIGTERM), no
traceback, no temporary file and no empty folder left behind."""

from __future__ import annotations

import ast
import importlib
import json
import os
import shutil
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import numpy as np
import pytest

from _cli import THESIS_PARTS, run_cli
from _libraries import DESIGNATION, REAL_GRID, mechanics_library, synthetic_library

#: The packages a command must not import before it needs them (seconds of start-up).
HEAVY = ("scipy", "pandas", "matplotlib", "trimesh", "numba")
#: The public packages whose names load on first use (PEP 562).
PACKAGES = (
    "geometry",
    "contact",
    "contact.scene",
    "contact.thesis",
    "contact.mechanics",
    "library",
    "network",
    "design",
    "planar",
    "pipeline",
    "view",
)
#: Every command and subcommand, for ``CMD --help``.
COMMANDS = (
    ["thread"],
    ["planar"],
    ["contact"],
    ["settle"],
    ["search"],
    ["screw"],
    ["sweep"],
    ["library"],
    ["library", "info"],
    ["library", "query"],
    ["library", "summary"],
    ["mesh"],
    ["network"],
    ["path"],
    ["recommend"],
    ["sensor"],
    ["program"],
    ["run"],
    ["view"],
)
ENTRY = "from threadmate.cli import main; main()"


def threadmate(*args: str, **kwargs) -> subprocess.CompletedProcess[str]:
    """``threadmate ARGS`` in a process of its own (the entry point's ``main``)."""
    env = {**os.environ, "MPLBACKEND": "Agg", **kwargs.pop("env", {})}
    return subprocess.run(
        [sys.executable, "-c", ENTRY, *map(str, args)],
        capture_output=kwargs.pop("capture_output", True),
        text=True,
        env=env,
        timeout=kwargs.pop("timeout", 300),
        **kwargs,
    )


def one_error(proc: subprocess.CompletedProcess[str], rc: int = 2) -> str:
    """The one line a refused command prints on stderr (checked: exit ``rc``, no
    traceback)."""
    assert proc.returncode == rc, proc.stderr
    assert "Traceback" not in proc.stderr
    assert proc.stderr.count("\n") == 1 and proc.stderr.startswith("threadmate: error:"), (
        proc.stderr
    )
    return proc.stderr


# -- start-up: nothing heavy before it is needed ------------------------------------------
def test_help_and_version_import_no_heavy_package():
    """The check of the issue, verbatim: import the command line, build its help."""
    code = textwrap.dedent(
        f"""
        import contextlib, io, sys
        from threadmate.cli import cli, main
        for argv in (["--help"], ["--version"]):
            with contextlib.redirect_stdout(io.StringIO()), contextlib.suppress(SystemExit):
                main(argv)
        print(sorted(m for m in {HEAVY!r} if m in sys.modules))
        """
    )
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.strip() == "[]"


def test_no_heavy_package_for_help_thread_or_refusals(tmp_path):
    """Every ``CMD --help``, ``thread`` (text and JSON) and refusals of each kind (a tilt,
    a phase, a designation, a spec file, a compliance, a workers count, a grid) leave the
    heavy packages unloaded: each answers without seconds of imports."""
    bad_spec = tmp_path / "bad.json"
    bad_spec.write_text('{"units": "in", "pitch": 0.05, "pitch": 0.0625}')
    ok = [["--help"], ["--version"], *[[*c, "--help"] for c in COMMANDS]]
    ok += [["thread", "M6"], ["thread", "1/4-20 UNC-2A/2B", "--json"]]
    refused = [
        ["thread", "M6x7.3-9z"],
        ["thread", str(bad_spec)],
        ["settle", "M6", "--roll", "99", "--pitch", "0", "--phase", "0"],
        ["search", "M6", "--roll", "0", "--pitch", "0", "--phase", "1e20"],
        ["screw", "M6", "--roll", "0", "--pitch", "0", "--phase", "0", "--force", "-1"],
        ["contact", "M6", "--roll", "0", "--pitch", "46", "--phase", "0"],
        ["planar", "M6", "--phase", "nan"],
        ["sweep", "M6", "-o", str(tmp_path / "l"), "--workers", "0"],
        ["sweep", "M6", "-o", str(tmp_path / "l"), "--roll", "0:50:5"],
        ["run", "-o", str(tmp_path / "r"), "--phase", "0:x:5"],
        ["run", "-o", str(tmp_path / "r"), "--roll-spread", "-1"],
        ["recommend", str(tmp_path / "l"), "--roll-spread", "46"],
        ["search", "M6", "--roll", "0", "--pitch", "0", "--phase", "0", "--step", "20"],
        ["search", "M6", "--roll", "0", "--pitch", "0", "--phase", "0", "--screw-in", "800"],
        ["path", str(tmp_path / "l"), "--roll", "0", "--pitch", "0", "--phase", "1e7"],
        ["mesh", "M6", "-o", str(tmp_path / "m"), "--point", "hex"],
        ["view", str(tmp_path / "missing.json")],
        ["view", str(tmp_path), "--start", "0,0"],
        ["search", "M6", "--roll", "0", "--pitch", "0", "--phase", "0", "--html", "x.png"],
    ]
    runs = ok + refused
    code = textwrap.dedent(
        f"""
        import contextlib, io, json, sys
        from threadmate.cli import main
        loaded = {{}}
        for argv in {runs!r}:
            out, err = io.StringIO(), io.StringIO()
            with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
                try:
                    main(argv)
                except SystemExit as exc:
                    code = exc.code
            loaded[" ".join(argv)] = [code, sorted(m for m in {HEAVY!r} if m in sys.modules)]
        print(json.dumps(loaded))
        """
    )
    env = {**os.environ, "MPLBACKEND": "Agg"}
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env)
    assert proc.returncode == 0, proc.stderr
    loaded = json.loads(proc.stdout.splitlines()[-1])
    # The refusals are refusals, the rest answers (so the loop ran each command for real).
    assert {a: c for a, (c, _) in loaded.items()} == {
        **{" ".join(a): 0 for a in ok},
        **{" ".join(a): 2 for a in refused},
    }
    # Modules stay loaded, so the first run that loads one is its culprit.
    assert {argv: mods for argv, (_, mods) in loaded.items() if mods} == {}


def test_help_and_thread_answer_quickly():
    """A generous bound on the wall time of a start (the imports above are the cause of a
    slow one; this only guards against a regression of seconds)."""
    for args in (["--help"], ["--version"], ["thread", "M6"], ["settle", "--help"]):
        start = time.perf_counter()
        proc = threadmate(*args)
        assert proc.returncode == 0, proc.stderr
        assert time.perf_counter() - start < 5.0, args


@pytest.mark.parametrize("package", PACKAGES)
def test_lazy_package_exports_every_name_it_lists(package):
    """Each public package names in ``__all__`` exactly the names its ``_SOURCES`` table
    lists, each is the object of the submodule that holds it, the type checkers' block
    re-exports the same names from the same submodules (explicitly, ``name as name``, so
    that a strict type checker sees them exported), and importing the package alone loads
    none of its submodules."""
    mod = importlib.import_module(f"threadmate.{package}")
    where = {name: source for source, names in mod._SOURCES.items() for name in names}
    assert sum(len(names) for names in mod._SOURCES.values()) == len(where)  # none twice
    assert mod.__all__ == list(where)
    for name, source in where.items():
        owner = importlib.import_module(source, mod.__name__)
        assert getattr(mod, name) is getattr(owner, name), name
    assert set(mod.__all__) <= set(dir(mod))
    with pytest.raises(AttributeError, match="no attribute 'nothing_here'"):
        _ = mod.nothing_here
    # The TYPE_CHECKING block imports the same names from the same submodules, each as an
    # explicit re-export.
    tree = ast.parse(Path(mod.__file__).read_text())
    block = next(n for n in tree.body if isinstance(n, ast.If) and "TYPE_CHECKING" in ast.dump(n))
    assert all(isinstance(n, ast.ImportFrom) for n in block.body)
    aliases = [a for n in block.body for a in n.names]
    assert [a.name for a in aliases if a.asname != a.name] == []
    typed = {
        a.name: "." * n.level + (n.module or "")
        for n in block.body
        if isinstance(n, ast.ImportFrom)
        for a in n.names
    }
    assert len(typed) == len(aliases)
    assert typed == where
    code = (
        f"import sys, threadmate.{package}; "
        f"print([m for m in sys.modules if m.startswith('threadmate.{package}.')])"
    )
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.strip() == "[]"


def test_lazy_exports_refuses_a_name_under_two_submodules():
    # threadmate._lazy is the public faces' internal loader; it has no public form.
    from threadmate._lazy import lazy_exports

    with pytest.raises(ValueError, match="'name' is listed under .a and .b"):
        lazy_exports("pkg", {}, {".a": ("name",), ".b": ("other", "name")})


def test_the_options_defaults_are_the_apis_own():
    """The options take their defaults and choices from the API's names (light modules,
    so that the help imports no stage), restating none."""
    from threadmate import contact, geometry, library, network, pipeline

    # The options module and the commands' registration: CLI internals with no public form.
    from threadmate.cli import _options, cli
    from threadmate.cli._main import _register
    from threadmate.contact import MAX_TILT

    _register()

    def param(command: str, name: str):
        return next(p for p in cli.commands[command].params if p.name == name)

    for command in ("search", "screw", "sweep", "run"):
        assert param(command, "step").default is contact.CONTINUATION_STEP
    assert param("search", "screw_in").default is contact.SCREW_IN
    assert param("sweep", "phase_tolerance").default is contact.PHASE_TOLERANCE
    assert tuple(param("sweep", "model").type.choices) == library.MODELS
    assert param("run", "spec_text").default is pipeline.DEFAULT_DESIGNATION
    # The sweep's default grid as the help quotes it: the thesis's (chapter 4).
    for axis, text in (("roll", "-4:4:1"), ("pitch", "-4:4:1"), ("phase", "0:355:5")):
        assert library.DEFAULT_RANGES[axis] == text
        assert param("sweep", axis).help.endswith(f"(default {text}).")
    owners = {
        "CONTINUATION_STEP": contact,
        "SCREW_IN": contact,
        "DEFAULT_CHORD": geometry,
        "MODELS": library,
        "MAX_K": network,
        "DEFAULT_DESIGNATION": pipeline,
        "RUN_GRID": pipeline,
    }
    for name, owner in owners.items():  # imported where used, never a copy
        assert getattr(_options, name, getattr(owner, name)) is getattr(owner, name), name
    assert MAX_TILT == contact.MAX_TILT == library.MAX_TILT == 45.0


# -- standard output closed or full -------------------------------------------------------
@pytest.mark.parametrize("as_json", [False, True])
def test_stdout_closed(as_json):
    extra = ["--json"] if as_json else []
    proc = subprocess.run(
        ["bash", "-c", '"$@" >&-', "_", sys.executable, "-c", ENTRY, "thread", "M6", *extra],
        capture_output=False,
        stderr=subprocess.PIPE,
        text=True,
    )
    assert "standard output is closed" in one_error(proc)


@pytest.mark.skipif(not Path("/dev/full").exists(), reason="needs /dev/full")
@pytest.mark.parametrize("as_json", [False, True])
@pytest.mark.parametrize("unbuffered", ["", "1"])
def test_stdout_full(as_json, unbuffered):
    extra = ["--json"] if as_json else []
    with open("/dev/full", "w") as full:
        proc = threadmate(
            "thread",
            "M6",
            *extra,
            stdout=full,
            stderr=subprocess.PIPE,
            capture_output=False,
            env={"PYTHONUNBUFFERED": unbuffered},
        )
    assert "cannot write to standard output: No space left on device" in one_error(proc)


# -- a full disk ----------------------------------------------------------------------------
class Disk:
    """A small tmpfs of its own, to fill."""

    def __init__(self, root: Path) -> None:
        self.root = root

    def fill(self, leave: int) -> None:
        """Fill the disk but for ``leave`` bytes."""
        free = shutil.disk_usage(self.root).free
        with open(self.root / "filler", "ab") as f:
            f.write(b"\0" * max(0, free - leave))

    def contents(self) -> list[str]:
        return sorted(str(p.relative_to(self.root)) for p in self.root.rglob("*"))


@pytest.fixture
def disk(tmp_path):
    """A 2 MiB tmpfs (skipped where this process may not mount one)."""
    root = tmp_path / "disk"
    root.mkdir()
    if shutil.which("mount") is None:
        pytest.skip("needs mount")
    proc = subprocess.run(
        ["mount", "-t", "tmpfs", "-o", "size=2m", "tmpfs", str(root)], capture_output=True
    )
    if proc.returncode != 0:
        pytest.skip(f"cannot mount a tmpfs here: {proc.stderr.decode().strip()}")
    try:
        yield Disk(root)
    finally:
        subprocess.run(["umount", "-l", str(root)], check=False)


@pytest.fixture(scope="module")
def synth_lib(tmp_path_factory, quarter_20):
    return synthetic_library(tmp_path_factory.mktemp("contract-synthetic") / "lib", quarter_20)


@pytest.mark.parametrize(
    ("args", "named"),
    [
        (["network", "{lib}", "-o", "{disk}/new/sub/net.graphml"], "new/sub/net.graphml"),
        (
            ["network", "{lib}", "-o", "{disk}/n.graphml", "--json-graph", "{disk}/new/n.json"],
            "n.graphml",
        ),
        (["recommend", "{lib}", "-o", "{disk}/new/sub/rec.json"], "new/sub/rec.json"),
        (["recommend", "{lib}", "--plot", "{disk}/new/rec.png"], "new/rec.png"),
    ],
)
def test_full_disk_graph_outputs(disk, synth_lib, args, named):
    disk.fill(0)  # a folder still fits (tmpfs keeps them in memory), no byte of a file
    argv = [a.format(lib=synth_lib, disk=disk.root) for a in args]
    err = one_error(threadmate(*argv))
    assert "No space left on device" in err
    assert str(disk.root / named) in err  # the file is named
    # Nothing half-written, and the folders this run made are gone again.
    assert disk.contents() == ["filler"]


def test_full_disk_sweep_keeps_what_is_saved(disk):
    out = disk.root / "new" / "lib"
    disk.fill(0)
    argv = ["sweep", "M6", "--model", "thesis", "--roll", "0", "--pitch", "0"]
    err = one_error(threadmate(*argv, "--phase", "0", "-o", out, "--workers", "1"))
    assert "No space left on device" in err and str(out) in err
    assert disk.contents() == ["filler"]  # no empty folder left behind


def test_full_disk_run_says_where_and_leaves_no_empty_folder(disk):
    disk.fill(0)
    out = disk.root / "job" / "x"
    err = one_error(threadmate("run", "-o", out, "--roll", "0", "--pitch", "0", "--phase", "0"))
    assert "No space left on device" in err and str(out) in err
    assert disk.contents() == ["filler"]


# -- SIGTERM ---------------------------------------------------------------------------------
def test_sigterm_while_run_writes_figures(tmp_path_factory):
    """SIGTERM once ``run`` is writing its figures: exit 130 with "aborted", no traceback,
    no ``.*.tmp`` left (as for SIGINT)."""
    lib = mechanics_library(tmp_path_factory)
    out = tmp_path_factory.mktemp("sigterm") / "job"
    shutil.copytree(lib, out / "library")  # the sweep stage reuses it: straight to the rest
    argv = ["run", DESIGNATION, *THESIS_PARTS, "-o", str(out)]
    for key in ("roll", "pitch", "phase"):
        argv += [f"--{key}", REAL_GRID[key]]
    env = {**os.environ, "MPLBACKEND": "Agg"}
    proc = subprocess.Popen(
        [sys.executable, "-c", ENTRY, *argv, "--workers", "1"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env=env,
    )
    figures = out / "figures"
    deadline = time.monotonic() + 240
    while proc.poll() is None and time.monotonic() < deadline:
        if figures.is_dir() and any(figures.iterdir()):
            break
        time.sleep(0.01)
    assert proc.poll() is None, "the run ended before its figures: nothing to interrupt"
    proc.send_signal(signal.SIGTERM)
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == 130, err
    assert "Traceback" not in err
    assert err.rstrip().endswith("threadmate: aborted (SIGTERM)")
    assert [str(p) for p in out.rglob(".*.tmp")] == []


# -- options ---------------------------------------------------------------------------------
@pytest.mark.parametrize(
    "args",
    [
        ["settle", "M6", "--roll", "0", "--pitch", "0"],
        ["search", "M6", "--roll", "0", "--pitch", "0"],
        ["screw", "M6", "--roll", "0", "--pitch", "0"],
        ["contact", "M6", "--roll", "0", "--pitch", "0"],
        ["planar", "M6"],
        ["path", "{lib}", "--roll", "0", "--pitch", "0"],
        ["library", "query", "{lib}", "--roll", "0", "--pitch", "0"],
        ["library", "summary", "{lib}"],
    ],
)
@pytest.mark.parametrize("phase", ["1e20", "-1000001", "inf"])
def test_one_phase_limit_for_every_command(capsys, synth_lib, args, phase):
    argv = [a.format(lib=synth_lib) for a in args] + ["--phase", phase]
    rc, out, err = run_cli(capsys, *argv)
    assert rc == 2 and out == "" and err.count("\n") == 1, err
    assert "--phase" in err
    assert "within +/-1e+06" in err or "must be a finite number" in err


def test_phase_at_the_limit_is_taken(capsys):
    # 1e6 deg is 2777 turns and 280 deg: the planar state of phase 280 (modulo 360).
    rc, out, err = run_cli(capsys, "planar", "M6", "--phase", "1e6", "--json")
    assert rc == 0, err
    rc, ref, err = run_cli(capsys, "planar", "M6", "--phase", "280", "--json")
    assert rc == 0, err
    a, b = json.loads(out), json.loads(ref)
    assert len(a["contacts"]) == len(b["contacts"])
    for ca, cb in zip(a["contacts"], b["contacts"], strict=True):
        assert ca.keys() == cb.keys()
        for key, value in ca.items():
            if isinstance(value, str):
                assert value == cb[key], key
            else:  # numbers and vectors
                assert np.allclose(value, cb[key], rtol=1e-9, atol=1e-9), key
    assert a["contact_angle"] == pytest.approx(b["contact_angle"], abs=1e-6)


def test_summary_phase_off_the_grid_is_refused(capsys, synth_lib):
    rc, out, err = run_cli(capsys, "library", "summary", synth_lib, "--phase", "45")
    assert rc == 2 and out == "" and err.count("\n") == 1, err
    assert "--phase 45 is not a phase of the library's grid (0, 90, 180, 270 deg" in err
    # On the grid, modulo 360: the counts are at that phase.
    rc, out, err = run_cli(capsys, "library", "summary", synth_lib, "--phase", "450", "--json")
    assert rc == 0, err
    assert json.loads(out)["at_phase"]["phase"] == 90.0


def test_mesh_does_not_overwrite_a_users_files(capsys, tmp_path):
    (tmp_path / "nut.stl").write_text("my nut")
    args = ("mesh", "M6", "-o", tmp_path, "--chord", "0.0025")
    rc, out, err = run_cli(capsys, *args)
    assert rc == 2 and out == "" and err.count("\n") == 1, err
    assert f"{tmp_path / 'nut.stl'} already exists; pass --force to overwrite" in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["nut.stl"]
    assert (tmp_path / "nut.stl").read_text() == "my nut"
    rc, _, err = run_cli(capsys, *args, "--force")
    assert rc == 0, err
    assert (tmp_path / "nut.stl").read_bytes()[:80].startswith(b"threadmate units=mm nut")


def test_sigterm_in_a_finaliser_still_stops_the_command():
    """A signal that arrives while Python runs a finaliser (matplotlib's weakref callbacks
    when a figure is written) raises there, where Python can only drop the exception: it
    is raised again a moment later and stops the command. Here the finaliser sends SIGTERM
    to its own process and runs on, so the handler raises inside it."""
    script = """
import os, signal
from threadmate.cli._main import _sigterm_as_interrupt, _Terminated

class Finalised:
    def __del__(self):
        os.kill(os.getpid(), signal.SIGTERM)
        for _ in range(100000):
            pass

try:
    with _sigterm_as_interrupt():
        Finalised()
        for _ in range(10**7):
            pass
    print("ran to the end")
except _Terminated:
    print("stopped")
"""
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True)
    assert done.stdout.strip() == "stopped", done.stdout + done.stderr
    assert "Traceback" not in done.stderr
