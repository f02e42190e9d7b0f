"""The bolt's point, the nut's countersink and the parts' lengths: the standards' tables
against their published values, specs through JSON and TOML, lengths in pitches, the
command-line options and their refusals.

The expected numbers are written out here from the standards (ASME B18.2.2, ASME B18.6.3,
ISO 4032), not read from threadmate's tables.
"""

from __future__ import annotations

import json
import math
from dataclasses import replace

import pytest

from _cli import THESIS_PARTS, run_cli
from _libraries import synthetic_library
from threadmate import InputError, SpecError
from threadmate.geometry import (
    BoltPoint,
    Countersink,
    ThreadSpec,
    countersink_limits,
    load_spec,
    save_spec,
    spec_from_designation,
    standard_nut_height,
    with_parts,
)

# -- the tables ------------------------------------------------------------------------------
#: ASME B18.2.2 hex nuts, basic thickness (in), with a UNC designation of each size.
B18_2_2_HEIGHTS = [
    ("1/4-20 UNC", 7 / 32),
    ("5/16-18 UNC", 17 / 64),
    ("3/8-16 UNC", 21 / 64),
    ("7/16-14 UNC", 3 / 8),
    ("1/2-13 UNC", 7 / 16),
    ("9/16-12 UNC", 31 / 64),
    ("5/8-11 UNC", 35 / 64),
    ("3/4-10 UNC", 41 / 64),
    ("7/8-9 UNC", 3 / 4),
    ("1-8 UNC", 55 / 64),
    ("1 1/8-7 UNC", 31 / 32),
    ("1 1/4-7 UNC", 1 + 1 / 16),
    ("1 3/8-6 UNC", 1 + 11 / 64),
    ("1 1/2-6 UNC", 1 + 9 / 32),
]
#: ASME B18.6.3 hex machine screw nuts, maximum thickness (in).
B18_6_3_HEIGHTS = [
    ("#0-80 UNF", 0.050),
    ("#1-64 UNC", 0.050),
    ("#2-56 UNC", 0.066),
    ("#3-48 UNC", 0.066),
    ("#4-40 UNC", 0.098),
    ("#5-40 UNC", 0.114),
    ("#6-32 UNC", 0.114),
    ("#8-32 UNC", 0.130),
    ("#10-24 UNC", 0.130),
    ("#12-24 UNC", 0.161),
]
#: ISO 4032 style-1 hex nuts: size d (mm), m max (mm), d_a max (mm).
ISO_4032 = [
    (1.6, 1.3, 1.84),
    (2, 1.6, 2.3),
    (2.5, 2.0, 2.9),
    (3, 2.4, 3.45),
    (4, 3.2, 4.6),
    (5, 4.7, 5.75),
    (6, 5.2, 6.75),
    (8, 6.8, 8.75),
    (10, 8.4, 10.8),
    (12, 10.8, 13),
    (14, 12.8, 15.1),
    (16, 14.8, 17.3),
    (18, 15.8, 19.5),
    (20, 18, 21.6),
    (22, 19.4, 23.7),
    (24, 21.5, 25.9),
    (27, 23.8, 29.1),
    (30, 25.6, 32.4),
    (33, 28.7, 35.6),
    (36, 31, 38.9),
    (39, 33.4, 42.1),
    (42, 34, 45.4),
    (45, 36, 48.6),
    (48, 38, 51.8),
    (52, 42, 56.2),
    (56, 45, 60.5),
    (60, 48, 64.8),
    (64, 51, 69.1),
]


@pytest.mark.parametrize(("designation", "height"), B18_2_2_HEIGHTS + B18_6_3_HEIGHTS)
def test_unified_nut_heights(designation, height):
    assert standard_nut_height(designation) == pytest.approx(height, abs=1e-12)
    spec = spec_from_designation(designation, nut_height="standard")
    assert spec.units == "in" and spec.nut.height == pytest.approx(height, abs=1e-12)


@pytest.mark.parametrize(("d", "m", "da"), ISO_4032)
def test_iso_nut_heights_and_countersinks(d, m, da):
    assert standard_nut_height(f"M{d:g}") == pytest.approx(m, abs=1e-12)
    assert countersink_limits(f"M{d:g}") == pytest.approx((d, da), abs=1e-12)
    spec = spec_from_designation(f"M{d:g}", nut_height="standard")
    assert spec.units == "mm" and spec.nut.height == pytest.approx(m, abs=1e-12)
    # The mean of d and d_a max, or d_a max where the mean does not clear the nut's major.
    want = (d + da) / 2 if (d + da) / 2 > spec.nut.major else da
    assert spec.nut.countersink.diameter == pytest.approx(want, abs=1e-12)
    assert spec.nut.countersink.angle == 120.0


def test_fine_pitch_nut_takes_its_size_height():
    # ISO 8673's fine-pitch nuts have ISO 4032's heights: the height goes by size.
    assert standard_nut_height("M10x1.25") == pytest.approx(8.4)
    assert standard_nut_height("1/4-28 UNF") == pytest.approx(7 / 32)


@pytest.mark.parametrize(
    ("designation", "limits"),
    [
        # ASME B18.2.2: d to d + 0.030 in for 3/8 in and smaller, to 1.08 d above.
        ("#10-24 UNC", (0.190, 0.220)),
        ("1/4-20 UNC", (0.250, 0.280)),
        ("3/8-16 UNC", (0.375, 0.405)),
        ("7/16-14 UNC", (0.4375, 0.4725)),
        ("1-8 UNC", (1.0, 1.08)),
        # ISO sizes outside ISO 4032's table: 1.08 d.
        ("M7", (7.0, 7.56)),
        ("M1", (1.0, 1.08)),
    ],
)
def test_countersink_limits(designation, limits):
    assert countersink_limits(designation) == pytest.approx(limits, abs=1e-12)


def test_countersink_default_is_the_mean_or_the_max():
    assert spec_from_designation("1/4-20 UNC").nut.countersink.diameter == pytest.approx(0.265)
    assert spec_from_designation("M6").nut.countersink.diameter == pytest.approx(6.375)
    # M1 (0.25 pitch, 5H): the nut's mean major diameter is 1.046 mm (1 to 0.838 + 0.056 +
    # 0.198), beyond the mean 1.04 mm: the maximum 1.08 mm.
    assert spec_from_designation("M1").nut.countersink.diameter == pytest.approx(1.08)
    # At minimum material even that is too small (the nut's major is 1.092 mm): the band
    # of 0.08 mm moved up to start there.
    spec = spec_from_designation("M1", "min")
    assert spec.nut.major == pytest.approx(1.092)
    assert spec.nut.countersink.diameter == pytest.approx(1.092 + 0.04)


@pytest.mark.parametrize(
    ("designation", "size", "covered"),
    [("M7", "M7", "M6, M8"), ("2-4.5 UNC", "size 2:", "1 1/2"), ("M1", "M1:", "M1.6")],
)
def test_standard_height_of_an_unknown_size_is_refused(designation, size, covered):
    with pytest.raises(SpecError) as exc:
        spec_from_designation(designation, nut_height="standard")
    assert size in str(exc.value) and covered in str(exc.value)


# -- defaults, lengths -----------------------------------------------------------------------
def test_designation_defaults_are_a_chamfer_and_a_countersink():
    spec = spec_from_designation("M6")
    # ISO 965-1 mean: bolt major (5.794 + 5.974)/2, minor (4.596 + 4.874)/2; nut minor
    # (4.917 + 5.153)/2.
    point = spec.bolt.point
    assert (point.form, point.angle, point.radius) == ("chamfer", 45.0, None)
    assert point.diameter == pytest.approx(4.735 - 0.1)
    chamfer = (5.884 - 4.635) / 2 / math.tan(math.radians(45))
    assert spec.point_height == pytest.approx(chamfer)
    assert spec.bolt.length == pytest.approx(chamfer + 1.0)
    depth = (6.375 - 5.035) / 2 / math.tan(math.radians(60))
    assert spec.countersink_depth == pytest.approx(depth)
    assert spec.nut.height == pytest.approx(depth + 1.0)


def test_flat_parts_are_the_thesis_spec():
    spec = spec_from_designation("1/4-20 UNC-2A/2B", point="flat", countersink=False)
    assert spec.bolt.point.form == "flat" and spec.nut.countersink is None
    assert spec.bolt.length == pytest.approx(0.05) and spec.nut.height == pytest.approx(0.05)
    doc = spec.to_dict()
    assert "point" not in doc["bolt"] and "countersink" not in doc["nut"]
    assert spec_from_designation("1/4-20 UNC-2A/2B", point="flat", countersink=None) == spec


def test_parts_given_to_a_designation():
    spec = spec_from_designation(
        "M8",
        point=BoltPoint("round", radius=15.0),
        countersink=Countersink(90.0),
        bolt_length="4p",
        nut_height="3 pitches",
    )
    assert spec.bolt.point.form == "round" and spec.bolt.point.radius == 15.0
    assert spec.nut.countersink.angle == 90.0
    assert spec.nut.countersink.diameter == pytest.approx((8 + 8.75) / 2)
    assert spec.bolt.length == pytest.approx(5.0) and spec.nut.height == pytest.approx(3.75)
    assert spec_from_designation("M8", bolt_length=7.5).bolt.length == 7.5


@pytest.mark.parametrize(
    ("kwargs", "words"),
    [
        ({"point": "square"}, "'bolt.point.form'"),
        ({"point": BoltPoint("chamfer", diameter=5.0)}, "'bolt.point.diameter'"),
        ({"countersink": Countersink(diameter=6.0)}, "'nut.countersink.diameter'"),
        ({"bolt_length": 0.5}, "'bolt.length'"),
        ({"bolt_length": "3x"}, "bolt_length"),
        ({"nut_height": "standard"}, "M7"),
    ],
)
def test_bad_parts_in_the_api(kwargs, words):
    with pytest.raises(SpecError, match=words):
        spec_from_designation("M7" if kwargs.get("nut_height") else "M6", **kwargs)


def test_lengths_in_pitches_in_a_spec_file(tmp_path):
    data = {
        "units": "mm",
        "pitch": 1.0,
        "bolt": {"major": 5.884, "pitch_diameter": 5.268, "minor": 4.735, "length": "3p"},
        "nut": {"major": 6.1465, "pitch_diameter": 5.425, "minor": 5.035, "height": "2.5 pitch"},
    }
    spec = ThreadSpec.from_dict(data)
    assert spec.bolt.length == 3.0 and spec.nut.height == 2.5
    data["bolt"]["length"] = "p3"
    with pytest.raises(SpecError, match="'bolt.length'"):
        ThreadSpec.from_dict(data)


# -- with_parts: the parts applied to a designation, a spec or a spec file -----------------------
def test_with_parts_on_a_designation_takes_the_standards_values():
    # M6 (pitch 1 mm), ISO 4032: nut height m = 5.2 mm, countersink d_a from 6 to 6.75 mm.
    spec = with_parts("M6", bolt_length="3p", nut_height="standard")
    assert spec.bolt.length == pytest.approx(3.0) and spec.nut.height == pytest.approx(5.2)
    assert spec.bolt.point.form == "chamfer" and spec.bolt.point.angle == 45.0
    assert spec.bolt.point.diameter == pytest.approx(4.735 - 0.1)  # ISO 965-1 mean minor
    assert spec.nut.countersink == Countersink(120.0, (6.0 + 6.75) / 2)
    # ASME B18.2.2: the 1/4 in hex nut is 7/32 in high.
    assert with_parts("1/4-20 UNC", nut_height="standard").nut.height == pytest.approx(7 / 32)
    # Text that is a number is a length in the spec's units.
    assert with_parts("M6", bolt_length="4.5").bolt.length == 4.5
    # No parts: the designation's spec as it expands; the thesis's parts: one pitch each.
    assert with_parts("M6") == spec_from_designation("M6")
    thesis = with_parts("1/4-20 UNC-2A/2B", point="flat", countersink=False)
    assert thesis.bolt.length == pytest.approx(0.05) and thesis.nut.height == pytest.approx(0.05)
    assert thesis.nut.countersink is None and thesis.bolt.point.form == "flat"
    mmc = with_parts("M6", condition="max", point="round")
    assert mmc.bolt.major == pytest.approx(5.974) and mmc.bolt.point.form == "round"


def test_with_parts_on_a_spec_keeps_its_own(tmp_path):
    flat = spec_from_designation("M6", point="flat", countersink=False)
    assert with_parts(flat) is flat
    # A chamfer and the standard countersink (the spec names its designation): the default
    # lengths follow the new ends, so this is the designation's own spec.
    assert with_parts(flat, point="chamfer", countersink=True) == spec_from_designation("M6")
    own = spec_from_designation("M6", point="flat", countersink=False, bolt_length=4.0)
    assert with_parts(own, point="chamfer").bolt.length == 4.0  # its own length stays
    # A spec file, as a path or as text: a countersink's diameter asks for one (120 deg).
    path = save_spec(flat, tmp_path / "m6.toml")
    for given in (path, str(path)):
        got = with_parts(given, countersink_diameter=6.5, nut_height=2.0)
        assert got.nut.countersink == Countersink(120.0, 6.5) and got.nut.height == 2.0
        assert got.bolt == flat.bolt


@pytest.mark.parametrize(
    ("spec", "kwargs", "error", "start"),
    [
        ("M6", {"point": "flat", "chamfer_angle": 30.0}, InputError, "chamfer_angle applies"),
        ("M6", {"countersink": False, "countersink_angle": 90}, InputError, "countersink_angle"),
        (
            "M6",
            {"point_diameter": 5.0},
            SpecError,
            "point_diameter: spec key 'bolt.point.diameter'",
        ),
        ("M6", {"bolt_length": 0.5}, SpecError, "bolt_length: spec key 'bolt.length'"),
        ("M6", {"bolt_length": "3x"}, SpecError, "bolt_length must be a length in mm"),
        ("M7", {"nut_height": "standard"}, SpecError, "nut_height='standard': no standard"),
        ("custom", {"nut_height": "standard"}, InputError, "nut_height='standard' needs a"),
        ("custom", {"countersink": True}, InputError, "countersink: the spec has no countersink"),
    ],
)
def test_with_parts_refuses_in_its_parameters_names(spec, kwargs, error, start):
    if spec == "custom":  # a spec that names no designation
        spec = replace(
            spec_from_designation("M6", point="flat", countersink=False), designation=None
        )
    with pytest.raises(error) as exc:
        with_parts(spec, **kwargs)
    assert str(exc.value).startswith(start) and "--" not in str(exc.value), exc.value


# -- files -----------------------------------------------------------------------------------
@pytest.mark.parametrize("suffix", [".json", ".toml"])
@pytest.mark.parametrize(
    "kwargs",
    [
        {},
        {"point": "round", "countersink": Countersink(90.0, 0.27)},
        {"point": BoltPoint("chamfer", 30.0, 0.18), "countersink": False},
        {"point": "flat", "bolt_length": "2p", "nut_height": "standard"},
    ],
)
def test_spec_round_trip(tmp_path, suffix, kwargs):
    spec = spec_from_designation("1/4-20 UNC-2A/2B", **kwargs)
    path = save_spec(spec, tmp_path / f"pair{suffix}")
    back = load_spec(path)
    assert back == spec
    assert back.bolt.point == spec.bolt.point and back.nut.countersink == spec.nut.countersink
    assert back.designation == spec.designation


def test_point_shorthand_in_a_spec_file():
    data = spec_from_designation("M6", point="flat", countersink=False).to_dict()
    data["bolt"].pop("length")
    data["bolt"]["point"] = "chamfer"
    spec = ThreadSpec.from_dict(data)
    assert spec.bolt.point == spec_from_designation("M6").bolt.point


def test_library_metadata_keeps_the_parts(tmp_path):
    spec = spec_from_designation("1/4-20 UNC-2A/2B", point="round")
    from threadmate.library import info

    lib = synthetic_library(tmp_path / "lib", spec)
    stored = info(lib)["metadata"]["spec"]
    assert stored["bolt"]["point"]["form"] == "round"
    assert stored["nut"]["countersink"] == {"angle": 120.0, "diameter": pytest.approx(0.265)}
    assert ThreadSpec.from_dict(stored) == spec


# -- the command line ------------------------------------------------------------------------
def test_thread_reports_the_standard_nut_height(capsys):
    rc, out, err = run_cli(capsys, "thread", "M6x1-6g/6H", "--nut-height", "standard", "--json")
    assert rc == 0, err
    doc = json.loads(out)
    assert doc["units"] == "mm"
    assert doc["spec"]["nut"]["height"] == pytest.approx(5.2)
    parts = doc["parts"]
    assert parts["nut_height"] == pytest.approx(5.2)
    assert parts["point"]["form"] == "chamfer" and parts["point"]["angle"] == 45.0
    assert parts["point"]["height"] == pytest.approx(parts["bolt_length"] - 1.0)
    assert parts["countersink"]["angle"] == 120.0
    assert parts["countersink"]["diameter"] == pytest.approx(6.375)


def test_thread_text_shows_the_parts_with_units(capsys):
    rc, out, err = run_cli(capsys, "thread", "M6", "--point", "round", "--nut-height", "standard")
    assert rc == 0, err
    assert "bolt point: round, radius 8.2376 mm, to a 4.635 mm tip" in out
    assert "nut countersink: 120 deg included, 6.375 mm at the face" in out
    assert "nut height 5.2 mm" in out and "bolt length" in out
    rc, out, err = run_cli(capsys, "thread", "1/4-20 UNC", *THESIS_PARTS)
    assert rc == 0, err
    assert "bolt point: flat" in out and "bolt length 0.05 in" in out
    assert "nut countersink: none" in out and "nut height 0.05 in" in out


def test_thread_options_in_pitches_and_angles(capsys):
    rc, out, err = run_cli(
        capsys,
        "thread",
        "M6",
        "--chamfer-angle",
        "30",
        "--point-diameter",
        "4.5",
        "--countersink-angle",
        "90",
        "--countersink-diameter",
        "6.5",
        "--bolt-length",
        "3p",
        "--nut-height",
        "2.5",
        "--json",
    )
    assert rc == 0, err
    spec = json.loads(out)["spec"]
    assert spec["bolt"]["point"] == {"form": "chamfer", "angle": 30.0, "diameter": 4.5}
    assert spec["nut"]["countersink"] == {"angle": 90.0, "diameter": 6.5}
    assert spec["bolt"]["length"] == 3.0 and spec["nut"]["height"] == 2.5


def test_options_on_a_spec_file(capsys, tmp_path):
    flat = spec_from_designation("M6", point="flat", countersink=False)
    path = save_spec(flat, tmp_path / "m6.json")
    # Without options: the file's own parts.
    rc, out, _ = run_cli(capsys, "thread", path, "--json")
    assert json.loads(out)["spec"] == flat.to_dict()
    # A chamfer and the standard countersink: the default lengths follow the new ends.
    rc, out, err = run_cli(capsys, "thread", path, "--point", "chamfer", "--countersink", "--json")
    assert rc == 0, err
    got = ThreadSpec.from_dict(json.loads(out)["spec"])
    assert got == spec_from_designation("M6")
    # Its own lengths stay.
    own = save_spec(
        spec_from_designation("M6", point="flat", countersink=False, bolt_length=4.0),
        tmp_path / "own.toml",
    )
    rc, out, err = run_cli(capsys, "thread", own, "--point", "chamfer", "--json")
    assert rc == 0, err
    assert json.loads(out)["spec"]["bolt"]["length"] == 4.0


@pytest.mark.parametrize(
    ("args", "words"),
    [
        (["--point", "square"], "--point"),
        (["--point-diameter", "5"], "'bolt.point.diameter'"),
        (["--countersink-diameter", "6"], "'nut.countersink.diameter'"),
        (["--bolt-length", "0.5"], "'bolt.length'"),
        (["--bolt-length", "3x"], "--bolt-length"),
        (["--chamfer-angle", "85"], "'bolt.point.angle'"),
        (["--countersink-angle", "nan"], "'nut.countersink.angle'"),
        (["--round-radius", "9"], "--round-radius"),
        (["--no-countersink", "--countersink-diameter", "7"], "--countersink-diameter"),
        (["--point", "flat", "--chamfer-angle", "30"], "--chamfer-angle"),
    ],
)
def test_bad_parts_exit_2_with_one_line(capsys, args, words):
    rc, out, err = run_cli(capsys, "thread", "M6x1-6g/6H", *args)
    assert rc == 2 and out == "", err
    assert err.startswith("threadmate: error:") and err.count("\n") == 1, err
    assert "Traceback" not in err and words in err


def test_standard_height_of_an_unknown_size_exits_2(capsys):
    rc, out, err = run_cli(capsys, "thread", "M7", "--nut-height", "standard")
    assert rc == 2 and out == ""
    assert err.startswith("threadmate: error: --nut-height standard: ") and err.count("\n") == 1
    assert "M7" in err and "M6, M8" in err


@pytest.mark.parametrize(
    ("edit", "key"),
    [
        (lambda d: d["bolt"].update(point={"form": "square"}), "bolt.point.form"),
        (
            lambda d: d["bolt"].update(point={"form": "chamfer", "diameter": 5.0}),
            "bolt.point.diameter",
        ),
        (
            lambda d: d["nut"].update(countersink={"angle": 120, "diameter": 6.0}),
            "nut.countersink.diameter",
        ),
        (lambda d: d["nut"].update(countersink={"angle": 120}), "nut.countersink.diameter"),
        (lambda d: d["bolt"].update(point="chamfer", length=0.5), "bolt.length"),
    ],
)
def test_bad_parts_in_a_spec_file_exit_2(capsys, tmp_path, edit, key):
    data = spec_from_designation("M6", point="flat", countersink=False).to_dict()
    edit(data)
    path = tmp_path / "bad.json"
    path.write_text(json.dumps(data))
    rc, out, err = run_cli(capsys, "thread", path)
    assert rc == 2 and out == "" and err.count("\n") == 1 and "Traceback" not in err
    assert f"'{key}'" in err


def test_spec_file_without_a_designation_needs_values(capsys, tmp_path):
    data = spec_from_designation("M6", point="flat", countersink=False).to_dict()
    data.pop("designation")
    path = tmp_path / "custom.json"
    path.write_text(json.dumps(data))
    for args, words in (
        (["--countersink"], "--countersink-diameter"),
        (["--nut-height", "standard"], "--nut-height standard needs a designation"),
    ):
        rc, out, err = run_cli(capsys, "thread", path, *args)
        assert rc == 2 and out == "" and err.count("\n") == 1 and words in err
    rc, out, err = run_cli(capsys, "thread", path, "--countersink-diameter", "6.5", "--json")
    assert rc == 0, err
    assert json.loads(out)["spec"]["nut"]["countersink"] == {"angle": 120.0, "diameter": 6.5}


def test_every_command_that_expands_a_designation_takes_the_parts():
    from threadmate.cli import cli

    # The commands' registration: a CLI internal with no public form.
    from threadmate.cli._main import _register

    _register()
    names = {
        "point",
        "chamfer_angle",
        "point_diameter",
        "round_radius",
        "countersink",
        "countersink_angle",
        "countersink_diameter",
        "bolt_length",
        "nut_height",
    }
    commands = {"thread", "planar", "mesh", "contact", "settle", "search", "sweep", "run"}
    for name in commands:
        params = {p.name for p in cli.commands[name].params}
        assert "condition" in params and names <= params, name


def test_spec_file_with_an_informative_designation(capsys, tmp_path):
    # A designation that names no standard thread is read only when a standard value is
    # asked for.
    data = spec_from_designation("M6", point="flat", countersink=False).to_dict()
    data["designation"] = "my thread"
    path = tmp_path / "mine.json"
    path.write_text(json.dumps(data))
    rc, out, err = run_cli(capsys, "thread", path, "--point", "chamfer", "--json")
    assert rc == 0, err
    assert json.loads(out)["spec"]["bolt"]["point"]["form"] == "chamfer"
    rc, out, err = run_cli(capsys, "thread", path, "--countersink")
    assert rc == 2 and err.count("\n") == 1 and "--countersink: cannot read" in err
