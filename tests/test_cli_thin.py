"""A thin command line: the API validates with its own parameter names and never names an
option; the command line turns those names into its flags in one place and reports one
message (exit 2); ``run`` and ``recommend`` take the same roll spread; ``run`` has the
sweep's ``--max-starts``; a phase has one limit everywhere (the sweep grid's too); a CAD
mesh's triangle count has a limit the API owns and ``--max-mesh-faces`` raises."""

from __future__ import annotations

import ast
import re
from pathlib import Path

import pytest
import trimesh

from _cli import refused, run_cli
from _libraries import DESIGNATION, synthetic_library
from threadmate import InputError, MeshError

# The limits: internals with no public form (threadmate._validate owns them).
# The shared limits without a public form (threadmate._validate owns them): internals.
from threadmate._validate import MAX_FACES, MAX_PHASE, check_roll_spread
from threadmate.contact import MAX_SCREW_IN, MAX_STEP, MAX_TILT, ContactAnalyzer
from threadmate.geometry import load_mesh, spec_from_designation, write_stl
from threadmate.library import Grid, parse_range, sweep
from threadmate.network import MAX_K, from_library, recommend
from threadmate.pipeline import RUN_GRID, run_pipeline
from threadmate.planar import planar_state

SRC = Path(__file__).resolve().parents[1] / "src" / "threadmate"
#: A start of the bolt, for the commands that take one.
START = ("--roll", "0", "--pitch", "0", "--phase", "0")
#: An option's flag: two dashes and a letter.
FLAG = re.compile(r"--[a-z]")
#: API names of several words, which the command line's messages must not show.
API_NAMES = re.compile(
    r"\b(max_starts|max_faces|phase_tolerance|screw_in|torque_limit|roll_spread|compliance_z|"
    r"lateral_stiffness|chunk_size|mesh_units|countersink_diameter|nut_height)\b"
)


# -- the API names no option ------------------------------------------------------------------
def _messages(tree: ast.AST) -> list[tuple[int, str]]:
    """The text of every string in a ``raise`` or a warning outside the command line, and
    of every name a ``check_*`` function is given."""
    found = []
    for node in ast.walk(tree):
        parts: list[ast.AST] = []
        if isinstance(node, ast.Raise) and node.exc is not None:
            parts = [node.exc]
        elif isinstance(node, ast.Call):
            func = node.func
            name = func.attr if isinstance(func, ast.Attribute) else getattr(func, "id", "")
            if name == "warn" or (name.startswith("check_") and node.args):
                parts = node.args[:1]
        for part in parts:
            for sub in ast.walk(part):
                if isinstance(sub, ast.Constant) and isinstance(sub.value, str):
                    found.append((sub.lineno, sub.value))
    return found


def test_no_api_message_names_an_option():
    """Outside ``cli/`` no refusal, warning or checked name says ``--flag``: the API names
    its parameters; the command line alone knows its options."""
    offenders = []
    for path in sorted(SRC.rglob("*.py")):
        if "cli" in path.relative_to(SRC).parts:
            continue
        for line, text in _messages(ast.parse(path.read_text())):
            if FLAG.search(text):
                offenders.append(f"{path.relative_to(SRC)}:{line}: {text!r}")
    assert offenders == []


@pytest.mark.parametrize(
    ("call", "start"),
    [
        (lambda spec: sweep(spec, "0", "0", "0", model="fixed"), "model must be one of"),
        (lambda spec: sweep(spec, "0", "0", "0", workers=0), "workers 0 must be at least 1"),
        (lambda spec: sweep(spec, "0", "0", "0", step=20.0), "step must be within (0, "),
        (lambda spec: sweep(spec, "0", "0", "0", max_starts=0), "max_starts must be"),
        (lambda spec: sweep(spec, "0", "0", "0:180:180", max_starts=1), "the grid (roll"),
        (lambda spec: sweep(spec, "0", "0", "0", scheduler="x y"), "scheduler 'x y'"),
        (lambda spec: parse_range("1e7", "phase"), "phase 1e+07 is out of range"),
        (lambda spec: planar_state(spec, 2 * MAX_PHASE), "phase 2e+06 is out of range"),
        (lambda spec: check_roll_spread(MAX_TILT + 1), "roll_spread (degrees) is out of range"),
    ],
)
def test_the_api_refuses_in_its_own_names(quarter_20, call, start):
    with pytest.raises(InputError) as info:
        call(quarter_20)
    message = str(info.value)
    assert message.startswith(start) and not FLAG.search(message), message


def test_a_suggested_value_is_the_parameter_s():
    """The API suggests a value as ``name=value``; the command line as ``--flag value``."""
    spec = spec_from_designation(DESIGNATION)
    with pytest.raises(InputError, match=r"pass max_starts=2 to run it$"):
        sweep(spec, "0", "0", "0:180:180", max_starts=1)


# -- the command line: one message naming the flag -------------------------------------------
@pytest.fixture(scope="module")
def synth_lib(tmp_path_factory, quarter_20):
    return synthetic_library(tmp_path_factory.mktemp("thin") / "lib", quarter_20)


@pytest.mark.parametrize(
    ("args", "words"),
    [
        (["search", "M6", *START, "--step", "20"], f"--step must be within (0, {MAX_STEP:g}]"),
        (["search", "M6", *START, "--turns", "0"], "--turns must be within (0, "),
        (["search", "M6", *START, "--step", "0.001", "--turns", "2"], "give --step 0.02 or"),
        (
            ["search", "M6", *START, "--screw-in", "800"],
            f"--screw-in must be within [0, {MAX_SCREW_IN:g}] degrees",
        ),
        (["screw", "M6", *START, "--torque-limit", "0"], "--torque-limit must be a positive"),
        (["settle", "M6", *START, "--stiffness", "1,-2"], "--stiffness (pitch) -2 N m/rad is"),
        (["settle", "M6", *START, "--compliance-z", "1e9"], "--compliance-z 1e+09 is out of"),
        (["contact", "M6", *START[:4], "--phase", "2e6"], "--phase 2e+06 is out of range"),
        (["settle", "M6", *START, "--max-mesh-faces", "10"], "--max-mesh-faces needs --bolt"),
        (["thread", "M6", "--point", "flat", "--round-radius", "1"], "--round-radius applies"),
        (["thread", "M6", "--nut-height", "3x"], "--nut-height must be a length in mm"),
        (["thread", "M7", "--nut-height", "standard"], "--nut-height standard: no standard"),
        (["sweep", "M6", "-o", "{tmp}/l", "--phase", "0,2e6"], "--phase 2e+06 is out of range"),
        (["sweep", "M6", "-o", "{tmp}/l", "--phase-tolerance", "6"], "--phase-tolerance must"),
        (["sweep", "M6", "-o", "{tmp}/l", "--scheduler", "x y"], "--scheduler 'x y' is not"),
        (
            ["sweep", "M6", "-o", "{tmp}/l", "--roll", "0", "--pitch", "0", "--phase", "0,180"]
            + ["--max-starts", "1"],
            "use a coarser grid, or pass --max-starts 2 to run it",
        ),
        (["sweep", "M6", "-o", "{tmp}/l", "--max-starts", "0"], "--max-starts must be a whole"),
        (
            ["library", "query", "{lib}", *START[:4], "--phase", "2e6"],
            "--phase 2e+06 is out of range",
        ),
        (
            ["path", "{lib}", *START, "--k", str(MAX_K + 1)],
            f"--k must be a whole number from 1 to {MAX_K}",
        ),
        (["path", "{lib}", *START[:4], "--phase", "2e6"], "--phase 2e+06 is out of range"),
    ],
)
def test_an_api_refusal_names_the_flag(capsys, tmp_path, synth_lib, args, words):
    argv = [a.format(tmp=tmp_path, lib=synth_lib) for a in args]
    line = refused(capsys, *argv)
    assert words in line, line
    assert not API_NAMES.search(line), line
    assert not (tmp_path / "l").exists()


def test_run_takes_the_sweeps_max_starts(capsys, tmp_path):
    """``run`` has the sweep's limit on starts, with the same words, and writes nothing."""
    count = Grid.parse(RUN_GRID["roll"], RUN_GRID["pitch"], RUN_GRID["phase"]).size
    line = refused(capsys, "run", "-o", tmp_path / "r", "--max-starts", str(count - 1))
    assert f"has {count:,} configurations" in line
    assert f"past the limit of {count - 1:,} starts" in line
    assert f"pass --max-starts {count} to run it" in line
    assert not (tmp_path / "r").exists()
    grid = [a for k in ("roll", "pitch", "phase") for a in (f"--{k}", RUN_GRID[k])]
    sweep_line = refused(
        capsys, "sweep", DESIGNATION, "-o", tmp_path / "l", *grid, "--max-starts", str(count - 1)
    )
    assert sweep_line.split(" starts; ")[1] == line.split(" starts; ")[1]  # one limit, one text
    with pytest.raises(InputError, match=f"pass max_starts={count} to run it"):
        run_pipeline(spec_from_designation(DESIGNATION), tmp_path / "api", max_starts=count - 1)
    assert not (tmp_path / "api" / "library").exists()


# -- run and recommend: one roll spread -------------------------------------------------------
@pytest.mark.parametrize("spread", [-1.0, MAX_TILT + 1.0, float("nan")])
def test_run_and_recommend_refuse_the_same_roll_spreads(capsys, tmp_path, synth_lib, spread):
    run_line = refused(capsys, "run", "-o", tmp_path / "r", "--roll-spread", str(spread))
    rec_line = refused(capsys, "recommend", synth_lib, "--roll-spread", str(spread))
    assert run_line == rec_line and "--roll-spread (degrees)" in run_line
    with pytest.raises(InputError, match=r"^roll_spread \(degrees\)"):
        recommend(from_library(synth_lib), roll_spread=spread)
    with pytest.raises(InputError, match=r"^roll_spread \(degrees\)"):
        run_pipeline(spec_from_designation(DESIGNATION), tmp_path / "api", roll_spread=spread)
    assert not (tmp_path / "r").exists() and not (tmp_path / "api").exists()


def test_run_and_recommend_take_the_same_largest_roll_spread(capsys, synth_lib):
    """The largest held roll a grid holds is the largest spread, for both."""
    assert check_roll_spread(MAX_TILT) == MAX_TILT == 45.0
    assert recommend(from_library(synth_lib), roll_spread=MAX_TILT).roll_spread == MAX_TILT
    rc, out, err = run_cli(capsys, "recommend", synth_lib, "--roll-spread", str(MAX_TILT))
    assert rc == 0, err


# -- one phase limit --------------------------------------------------------------------------
@pytest.mark.parametrize("phase", [MAX_PHASE * 1.5, -MAX_PHASE * 1.5])
def test_the_grid_takes_the_phase_limit_of_every_phase(quarter_20, phase):
    with pytest.raises(InputError, match="^phase .* is out of range: give degrees within"):
        Grid.parse("0", "0", [0.0, phase])
    assert Grid.parse("0", "0", [MAX_PHASE]).phase == (MAX_PHASE % 360.0,)


# -- the triangles of a CAD mesh --------------------------------------------------------------
@pytest.fixture(scope="module")
def box_stl(tmp_path_factory):
    """A closed box of 12 triangles as a binary STL, bolt-framed (tip face at z = 0)."""
    box = trimesh.creation.box(extents=(0.2, 0.2, 0.1))
    box.apply_translation((0.0, 0.0, 0.05))
    path = tmp_path_factory.mktemp("box") / "box.stl"
    write_stl(box, path)
    return path


def test_the_mesh_face_limit_is_the_apis(quarter_20, box_stl, tmp_path, capsys):
    """The limit is the API's (its default, its parameter ``max_faces``); the command line
    raises it with ``--max-mesh-faces`` and says so when it refuses."""
    assert load_mesh.__defaults__[-1] == MAX_FACES
    with pytest.raises(MeshError, match=r"has 12 triangles, .* raise the limit: max_faces=12$"):
        load_mesh(box_stl, "bolt", max_faces=4)
    with pytest.raises(MeshError, match=r"raise the limit: max_faces=12$"):
        ContactAnalyzer(quarter_20, bolt_mesh=box_stl, max_faces=4)
    with pytest.raises(MeshError, match=r"raise the limit: max_faces=12$"):
        sweep(quarter_20, "0", "0", "0", out=tmp_path / "lib", bolt_mesh=box_stl, max_faces=4)
    assert not (tmp_path / "lib").exists()
    for command in (["settle", DESIGNATION, *START], ["sweep", DESIGNATION, "-o", tmp_path / "l"]):
        line = refused(capsys, *command, "--bolt-mesh", box_stl, "--max-mesh-faces", "4")
        assert "has 12 triangles, more than the 4" in line
        assert line.endswith("raise the limit: --max-mesh-faces 12")
    assert not (tmp_path / "l").exists()
    line = refused(
        capsys, "settle", DESIGNATION, *START, "--bolt-mesh", box_stl, "--max-mesh-faces", "3"
    )
    assert "--max-mesh-faces must be a whole number >= 4" in line


def test_every_mapped_flag_is_an_option_of_a_command():
    """The one map from the API's names to the flags names real options only (an internal
    of the command line, checked against its commands)."""
    from threadmate.cli import cli

    # The commands' registration and the flag map: CLI internals with no public form.
    from threadmate.cli._main import _register
    from threadmate.cli._options import FLAGS

    _register()
    library = cli.commands["library"]
    commands = [*cli.commands.values(), *library.commands.values()]
    flags = {flag for c in commands for p in c.params for flag in (*p.opts, *p.secondary_opts)}
    assert set(FLAGS.values()) <= flags, set(FLAGS.values()) - flags
