"""``threadmate thread``: JSON and table output, spec files, and refusals (exit 2)."""

from __future__ import annotations

import json
import math
import subprocess
import sys

import pytest

from _cli import THESIS_PARTS, run_cli
from threadmate.geometry import BoltSpec, NutSpec, ThreadSpec, save_spec


def test_json_quarter_20(capsys):
    # The thesis's flat parts: one pitch of bolt and of nut.
    rc, out, err = run_cli(capsys, "thread", "1/4-20 UNC-2A/2B", *THESIS_PARTS, "--json")
    assert rc == 0
    doc = json.loads(out)  # exactly one JSON document
    assert doc["units"] == "in" and doc["pitch"] == pytest.approx(0.05)
    assert doc["designation"] == "1/4-20 UNC-2A/2B"
    assert doc["bolt"]["major"] == pytest.approx([0.2408, 0.2489])
    assert doc["bolt"]["pitch_diameter"] == pytest.approx([0.2127, 0.2164])
    assert doc["nut"]["minor"] == pytest.approx([0.196, 0.207])
    assert doc["nut"]["pitch_diameter"] == pytest.approx([0.2175, 0.2224])
    spec = doc["spec"]  # mean material by default
    assert spec["units"] == "in" and spec["hand"] == "right"
    assert spec["bolt"]["pitch_diameter"] == pytest.approx((0.2127 + 0.2164) / 2)
    assert spec["nut"]["pitch_diameter"] == pytest.approx((0.2175 + 0.2224) / 2)
    assert spec["bolt"]["length"] == pytest.approx(0.05)  # one pitch, as in the thesis
    assert spec["nut"]["outer_radius"] == pytest.approx(1.6 * spec["nut"]["major"] / 2)


@pytest.mark.parametrize(("condition", "pick"), [("max", 1), ("min", 0), ("maximum", 1)])
def test_json_m6_conditions(capsys, condition, pick):
    rc, out, _ = run_cli(capsys, "thread", "M6x1-6g/6H", "--condition", condition, "--json")
    assert rc == 0
    doc = json.loads(out)
    assert doc["units"] == "mm" and doc["pitch"] == 1.0
    assert doc["bolt"]["major"] == pytest.approx([5.794, 5.974])
    assert doc["bolt"]["pitch_diameter"] == pytest.approx([5.212, 5.324])
    assert doc["nut"]["minor"] == pytest.approx([4.917, 5.153])
    assert doc["nut"]["pitch_diameter"] == pytest.approx([5.350, 5.500])
    # Maximum material: largest bolt, smallest nut; minimum material the reverse.
    bolt_pd = [5.212, 5.324][pick]
    nut_pd = [5.500, 5.350][pick]
    assert doc["spec"]["bolt"]["pitch_diameter"] == pytest.approx(bolt_pd)
    assert doc["spec"]["nut"]["pitch_diameter"] == pytest.approx(nut_pd)


def test_table_output(capsys):
    rc, out, err = run_cli(capsys, "thread", "#10-24 UNC")
    assert rc == 0 and err == ""
    assert "#10-24 UNC-2A/2B" in out
    for value in ("0.1818", "0.1890", "0.1586", "0.1619", "0.1450", "0.1560", "0.1629", "0.1672"):
        assert value in out
    assert "pitch diameter" in out and "bolt 2A" in out and "nut 2B" in out


def _spec() -> ThreadSpec:
    return ThreadSpec(
        units="in",
        pitch=0.05,
        bolt=BoltSpec(major=0.2449, pitch_diameter=0.2146, minor=0.1887, root_fillet=0.006),
        nut=NutSpec(major=0.25, pitch_diameter=0.22, minor=0.2015),
        hand="left",
    )


@pytest.mark.parametrize("suffix", [".json", ".toml"])
def test_spec_file_round_trip(capsys, tmp_path, suffix):
    path = save_spec(_spec(), tmp_path / f"pair{suffix}")
    rc, out, _ = run_cli(capsys, "thread", str(path), "--json")
    assert rc == 0
    doc = json.loads(out)
    assert doc["units"] == "in" and doc["pitch"] == pytest.approx(0.05)
    # A spec has single values: the limits are [v, v].
    assert doc["bolt"]["major"] == [0.2449, 0.2449]
    assert doc["bolt"]["pitch_diameter"] == [0.2146, 0.2146]
    assert doc["nut"]["minor"] == [0.2015, 0.2015]
    assert doc["spec"] == _spec().to_dict()
    assert ThreadSpec.from_dict(doc["spec"]) == _spec()


def test_json_and_toml_agree(capsys, tmp_path):
    docs = []
    for suffix in (".json", ".toml"):
        path = save_spec(_spec(), tmp_path / f"pair{suffix}")
        docs.append(json.loads(run_cli(capsys, "thread", str(path), "--json")[1]))
    assert docs[0] == docs[1]


def test_designation_spec_survives_a_file(capsys, tmp_path):
    # Expand, save, and read back through the command: the same spec.
    _, out, _ = run_cli(capsys, "thread", "M8", "--condition", "min", "--json")
    spec = ThreadSpec.from_dict(json.loads(out)["spec"])
    path = save_spec(spec, tmp_path / "m8.toml")
    _, out2, _ = run_cli(capsys, "thread", str(path), "--json")
    assert ThreadSpec.from_dict(json.loads(out2)["spec"]) == spec


@pytest.mark.parametrize(
    ("designation", "message"),
    [
        ("1/4-21 UNC", "21 threads per inch is not in the UNC series"),
        ("M6x0.9", "pitch 0.9 is not an ISO 261 pitch"),
        ("1/4-20 UNC-5A", "unknown thread class '5A'"),
        ("Q6", "cannot read thread designation"),
        ("M6-6k", "unknown tolerance position 'k'"),
    ],
)
def test_bad_designation_exit_2(capsys, designation, message):
    rc, out, err = run_cli(capsys, "thread", designation, "--json")
    assert rc == 2
    assert out == ""
    assert err.startswith("threadmate: error: ") and message in err
    assert "Traceback" not in err


def _bad_spec(edit) -> dict:
    data = {
        "units": "in",
        "pitch": 0.05,
        "bolt": {"major": 0.2449, "pitch_diameter": 0.2146, "minor": 0.1887},
        "nut": {"major": 0.25, "pitch_diameter": 0.22, "minor": 0.2015},
    }
    edit(data)
    return data


@pytest.mark.parametrize(
    ("edit", "key"),
    [
        (lambda d: d["bolt"].update(minor=0.2200), "bolt.minor"),  # diameter order
        (lambda d: d["nut"].update(pitch_diameter=0.2600), "nut.pitch_diameter"),
        (lambda d: d["bolt"].update(length=-0.1), "bolt.length"),  # negative length
        (lambda d: d["nut"].update(minor=0.1500), "nut.minor"),  # a nut of another pitch
        (lambda d: d["bolt"].update(pitch_diameter=0.2210), "bolt.pitch_diameter"),  # no entry
    ],
)
@pytest.mark.parametrize("suffix", [".json", ".toml"])
def test_invalid_spec_file_exit_2(capsys, tmp_path, edit, key, suffix):
    import tomli_w

    data = _bad_spec(edit)
    path = tmp_path / f"bad{suffix}"
    path.write_text(json.dumps(data) if suffix == ".json" else tomli_w.dumps(data))
    rc, out, err = run_cli(capsys, "thread", str(path), "--json")
    assert rc == 2 and out == ""
    assert f"'{key}'" in err and "Traceback" not in err


def test_missing_spec_file_exit_2(capsys, tmp_path):
    rc, out, err = run_cli(capsys, "thread", str(tmp_path / "nope.json"))
    assert rc == 2 and out == "" and "not found" in err


def test_bad_condition_is_a_usage_error(capsys):
    rc, out, err = run_cli(capsys, "thread", "M6", "--condition", "nominal")
    assert rc == 2 and out == "" and "nominal" in err


def test_real_process_no_traceback():
    # The installed entry point in a fresh interpreter: exit 2, one line, no traceback.
    code = "from threadmate.cli import main; main()"
    proc = subprocess.run(
        [sys.executable, "-c", code, "thread", "1/4-20 UNK-2A"],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert proc.returncode == 2 and proc.stdout == ""
    assert "unknown thread series 'UNK'" in proc.stderr and "Traceback" not in proc.stderr
    proc = subprocess.run(
        [sys.executable, "-c", code, "thread", "1/2-13 UNC-2A/2B LH", "--json"],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert proc.returncode == 0
    doc = json.loads(proc.stdout)
    assert doc["spec"]["hand"] == "left"
    # Independent closed form: the mean axial clearance (nut PD - bolt PD)/sqrt(3) from
    # the published 1/2-13 limits 0.4435-0.4485 (2A) and 0.4500-0.4565 (2B).
    spec = doc["spec"]
    clearance = (spec["nut"]["pitch_diameter"] - spec["bolt"]["pitch_diameter"]) / math.sqrt(3)
    assert clearance == pytest.approx(((0.4500 + 0.4565) - (0.4435 + 0.4485)) / 2 / math.sqrt(3))


# -- issue 11 ------------------------------------------------------------------------------
@pytest.mark.parametrize(
    ("edit", "key"),
    [
        (lambda d: d.update(pitch=1e308), "pitch"),
        (lambda d: d["nut"].update(outer_radius=1e300), "nut.outer_radius"),
        (lambda d: d["bolt"].update(major=1e300), "bolt.major"),
    ],
)
def test_absurd_spec_numbers_exit_2_with_range(capsys, tmp_path, edit, key):
    path = tmp_path / "absurd.json"
    path.write_text(json.dumps(_bad_spec(edit)))
    rc, out, err = run_cli(capsys, "thread", str(path), "--json")
    assert rc == 2 and out == "" and "Traceback" not in err
    assert err.count("\n") == 1 and f"'{key}'" in err and "from 0.0001 to 1000 in" in err


@pytest.mark.parametrize("text", ["", "   "])
def test_empty_designation_says_so(capsys, text):
    rc, out, err = run_cli(capsys, "thread", text)
    assert rc == 2 and out == "" and "Traceback" not in err
    assert "empty thread designation" in err and "not found" not in err


def test_directory_as_spec_says_so(capsys, tmp_path):
    rc, out, err = run_cli(capsys, "thread", str(tmp_path))
    assert rc == 2 and out == "" and "Traceback" not in err
    assert f"{tmp_path} is a directory, not a spec file" in err
