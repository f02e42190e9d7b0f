"""Bad input and faults met by a new user: exit 2, one ``threadmate: error:`` line naming
the problem, no traceback, and nothing written."""

from __future__ import annotations

import json
import shutil

import pytest

from _cli import run_cli
from threadmate.geometry import spec_from_designation
from threadmate.library import sweep

DESIGNATION = "1/4-20 UNC-2A/2B"
SPEC = {
    "units": "in",
    "pitch": 0.05,
    "bolt": {"major": 0.24485, "pitch_diameter": 0.21455, "minor": 0.1887},
    "nut": {"major": 0.25, "pitch_diameter": 0.21995, "minor": 0.2015},
}


def _refused(capsys, tmp_path, *args, message):
    before = sorted(tmp_path.rglob("*"))
    rc, out, err = run_cli(capsys, *args)
    assert rc == 2, err
    assert out == ""
    assert "Traceback" not in err
    assert err.count("\n") == 1 and err.startswith("threadmate: error:"), err
    assert message in err
    assert sorted(tmp_path.rglob("*")) == before


@pytest.mark.parametrize(
    ("raw", "message"),
    [
        ('"pitch": ' + "9" * 400, "spec key 'pitch' must be a finite number"),
        ('"pitch": ' + "9" * 5000, "is not valid JSON"),
        ('"pitch": 0.05, "designation": 5', "spec key 'designation' must be text"),
        ('"pitch": 0.05, "starts": ' + "9" * 400, "spec key 'starts' must be a finite number"),
    ],
)
def test_spec_file_numbers_and_types(tmp_path, capsys, raw, message):
    text = json.dumps(SPEC).replace('"pitch": 0.05', raw)
    path = tmp_path / "pair.json"
    path.write_text(text)
    _refused(capsys, tmp_path, "thread", path, message=message)


def test_spec_file_nested_too_deeply(tmp_path, capsys):
    path = tmp_path / "deep.json"
    path.write_text("[" * 100000 + "]" * 100000)
    _refused(capsys, tmp_path, "thread", path, message="nested too deeply")


def test_search_plot_unwritable_before_work(tmp_path, capsys):
    (tmp_path / "f").write_text("")
    args = ("search", DESIGNATION, "--roll", "0", "--pitch", "0", "--phase", "0")
    _refused(capsys, tmp_path, *args, "--plot", tmp_path / "f" / "a.png", message="--plot")


def test_mesh_folder_in_place_of_a_file(tmp_path, capsys):
    (tmp_path / "m" / "bolt.stl").mkdir(parents=True)
    _refused(
        capsys, tmp_path, "mesh", "M6", "-o", tmp_path / "m", message="bolt.stl is a directory"
    )


@pytest.mark.parametrize("command", ["sweep", "run"])
def test_workers_beyond_any_machine(tmp_path, capsys, command):
    args = [command, DESIGNATION, "--workers", "9" * 20, "-o", tmp_path / "out"]
    if command == "sweep":
        args += ["--model", "thesis", "--roll", "0", "--pitch", "0", "--phase", "0"]
    _refused(capsys, tmp_path, *args, message="--workers must be a whole number from 1 to 1024")


@pytest.mark.parametrize("text", ["1,,2", ",", "1,", ""])
def test_run_compare_list_with_an_empty_item(tmp_path, capsys, text):
    _refused(
        capsys,
        tmp_path,
        "run",
        "--compare-stiffness",
        text,
        "-o",
        tmp_path / "r",
        message="--compare-stiffness",
    )


@pytest.fixture(scope="module")
def thesis_library(tmp_path_factory):
    out = tmp_path_factory.mktemp("thesis") / "library"
    spec = spec_from_designation(DESIGNATION, point="flat", countersink=False)
    sweep(spec, "0", "0", "0", out=out, model="thesis", workers=1)
    return out


@pytest.mark.parametrize(
    ("edit", "message"),
    [
        (lambda d: d.update(format_version=999), "format version 999"),
        (lambda d: d.update(spec={"units": "in"}), "spec key 'pitch' is missing"),
        (lambda d: d.update(mesh="x"), "key 'mesh' must be a table"),
        (lambda d: d.update(units="mm"), "key 'units'"),
        # The stored grid's roll (no option of the command): named as the metadata's.
        (lambda d: d["grid"].update(roll=[99.0]), "_threadmate.json: roll: 99 deg is out of range"),
    ],
)
def test_library_with_hand_edited_metadata(tmp_path, capsys, thesis_library, edit, message):
    lib = tmp_path / "lib"
    shutil.copytree(thesis_library, lib)
    meta = lib / "_threadmate.json"
    doc = json.loads(meta.read_text())
    edit(doc)
    meta.write_text(json.dumps(doc))
    _refused(capsys, tmp_path, "library", "info", lib, message=message)


# -- spec files: what a JSON reader would let through ---------------------------------------
@pytest.mark.parametrize(
    ("old", "new", "key"),
    [
        ('"pitch": 0.05', '"pitch": 0.05, "pitch": 0.0625', "'pitch'"),
        ('"major": 0.25', '"major": 0.25, "major": 0.26', "'nut.major'"),
    ],
)
def test_spec_file_key_given_twice(tmp_path, capsys, old, new, key):
    path = tmp_path / "pair.json"
    path.write_text(json.dumps(SPEC).replace(old, new))
    _refused(capsys, tmp_path, "thread", path, message=f"key {key} is given twice")


def test_spec_file_not_utf8_names_the_byte(tmp_path, capsys):
    text = json.dumps({"designation": "Gewinde f\u00fcr Mutter", **SPEC}, ensure_ascii=False)
    data = text.encode("latin-1")
    path = tmp_path / "pair.json"
    path.write_bytes(data)
    offset = data.index(b"\xfc")  # the first byte that is no UTF-8
    message = f"{path} is not UTF-8 text: byte 0xfc at offset {offset}"
    _refused(capsys, tmp_path, "thread", path, message=message)


@pytest.mark.parametrize("suffix", [".json", ".toml"])
def test_spec_file_with_a_byte_order_mark_is_read(tmp_path, capsys, suffix):
    plain = tmp_path / f"plain{suffix}"
    if suffix == ".json":
        plain.write_text(json.dumps(SPEC))
    else:
        lines = [f'units = "{SPEC["units"]}"', f"pitch = {SPEC['pitch']}"]
        for body in ("bolt", "nut"):
            lines += [f"[{body}]", *(f"{k} = {v}" for k, v in SPEC[body].items())]
        plain.write_text("\n".join(lines) + "\n")
    marked = tmp_path / f"marked{suffix}"
    marked.write_bytes(b"\xef\xbb\xbf" + plain.read_bytes())
    rc, out, err = run_cli(capsys, "thread", marked, "--json")
    assert rc == 0, err
    rc, ref, err = run_cli(capsys, "thread", plain, "--json")
    assert rc == 0, err
    assert json.loads(out)["spec"] == json.loads(ref)["spec"]
    assert json.loads(out)["spec"]["nut"]["minor"] == SPEC["nut"]["minor"]


@pytest.mark.parametrize("command", ["thread", "planar"])
def test_spec_without_thread_overlap(tmp_path, capsys, command):
    # A nut whose minor diameter (0.246 in) is above the bolt's major (0.24485 in): the
    # crests never meet, though every other rule holds (PD and minor of the bolt below the
    # nut's, thread depths within the 60-degree profile).
    nut = {"major": 0.26, "pitch_diameter": 0.2475, "minor": 0.246}
    path = tmp_path / "pair.json"
    path.write_text(json.dumps({**SPEC, "nut": nut}))
    message = "spec key 'nut.minor' (0.246 in) is not below 'bolt.major' (0.24485 in)"
    _refused(capsys, tmp_path, command, path, message=message)
