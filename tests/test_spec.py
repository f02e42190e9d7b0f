"""Thread specs: validation names the key, defaults follow conventions.md, files round-trip."""

from __future__ import annotations

import json

import pytest

from threadmate import SpecError
from threadmate.geometry import BoltSpec, NutSpec, ThreadSpec, load_spec, save_spec


def _spec_dict() -> dict:
    return {
        "units": "in",
        "pitch": 0.05,
        "bolt": {"major": 0.2449, "pitch_diameter": 0.2146, "minor": 0.1887},
        "nut": {"major": 0.25, "pitch_diameter": 0.22, "minor": 0.2015},
    }


def test_defaults_follow_conventions():
    spec = ThreadSpec.from_dict(_spec_dict())
    assert spec.hand == "right" and spec.starts == 1
    assert spec.bolt.length == pytest.approx(0.05)  # one pitch, as in the thesis
    assert spec.nut.height == pytest.approx(0.05)
    assert spec.nut.outer_radius == pytest.approx(1.6 * 0.25 / 2)
    assert spec.lead == pytest.approx(0.05)
    assert spec.axial_clearance == pytest.approx((0.22 - 0.2146) / 3**0.5)


@pytest.mark.parametrize(
    ("edit", "key"),
    [
        (lambda d: d["bolt"].update(minor=0.22), "bolt.minor"),  # minor above PD
        (lambda d: d["nut"].update(pitch_diameter=0.26), "nut.pitch_diameter"),  # PD above major
        (lambda d: d["bolt"].update(length=-1.0), "bolt.length"),  # negative length
        (lambda d: d["nut"].update(height=-0.05), "nut.height"),
        (lambda d: d.update(units="cm"), "units"),
        (lambda d: d.update(pitch=0.0), "pitch"),
        (lambda d: d.update(hand="middle"), "hand"),
        (lambda d: d.update(starts=0), "starts"),
        (lambda d: d["bolt"].update(pitch_diameter=0.2210), "bolt.pitch_diameter"),  # cannot enter
        (lambda d: d["bolt"].update(major=0.26), "bolt.major"),  # cannot enter
        (lambda d: d["bolt"].pop("major"), "bolt.major"),  # missing
        (lambda d: d["nut"].update(thread="x"), "nut.thread"),  # unknown key
        (lambda d: d["bolt"].update(crest_fillet=0.02), "bolt.crest_fillet"),  # does not fit
        (lambda d: d["nut"].update(outer_radius=0.1), "nut.outer_radius"),
        # A nut of another pitch: its diameters span more than a 0.05 pitch profile allows.
        (lambda d: d["nut"].update(minor=0.15), "nut.minor"),
    ],
)
def test_invalid_specs_name_the_key(edit, key):
    data = _spec_dict()
    edit(data)
    with pytest.raises(SpecError, match=f"'{key}'"):
        ThreadSpec.from_dict(data)


@pytest.mark.parametrize("suffix", [".json", ".toml"])
def test_file_round_trip(tmp_path, suffix):
    spec = ThreadSpec(
        units="mm",
        pitch=1.0,
        bolt=BoltSpec(5.884, 5.268, 4.77, root_fillet=0.125),
        nut=NutSpec(6.0, 5.425, 5.035),
        hand="left",
        starts=2,
    )
    path = save_spec(spec, tmp_path / f"pair{suffix}")
    assert load_spec(path) == spec


def test_load_refuses_missing_and_malformed(tmp_path):
    with pytest.raises(SpecError, match="not found"):
        load_spec(tmp_path / "nope.json")
    bad = tmp_path / "bad.json"
    bad.write_text("{not json")
    with pytest.raises(SpecError, match="not valid JSON"):
        load_spec(bad)
    partial = tmp_path / "partial.json"
    partial.write_text(json.dumps({"units": "in", "pitch": 0.05}))
    with pytest.raises(SpecError, match="'bolt'"):
        load_spec(partial)


# -- issue 11: absurd but finite numbers are refused with the allowed range ---------------
@pytest.mark.parametrize(
    ("edit", "key", "text"),
    [
        (lambda d: d.update(pitch=1e308), "pitch", "from 0.0001 to 1000 in"),
        (lambda d: d.update(pitch=1e-9), "pitch", "from 0.0001 to 1000 in"),
        (
            lambda d: d["nut"].update(outer_radius=1e300),
            "nut.outer_radius",
            "from 0.0001 to 1000 in",
        ),
        (lambda d: d["bolt"].update(major=1e300), "bolt.major", "from 0.0001 to 1000 in"),
        (lambda d: d["nut"].update(root_fillet=1e300), "nut.root_fillet", "to 1000 in"),
        (lambda d: d["bolt"].update(length=1e300), "bolt.length", "from 0.0001 to 1000 in"),
        (lambda d: d["bolt"].update(length=20.0), "bolt.length", "at most 200 pitches"),
        (lambda d: d["nut"].update(height=10.5), "nut.height", "at most 200 pitches"),
        (lambda d: d.update(starts=10**9), "starts", "from 1 to 16"),
        (lambda d: d.update(starts=1e308), "starts", "from 1 to 16"),
        (lambda d: d.update(starts=float("inf")), "starts", "finite"),
        (lambda d: d.update(pitch=1.0), "pitch", "exceeds 'nut.major'"),
    ],
)
def test_absurd_magnitudes_refused_with_range(edit, key, text):
    data = _spec_dict()
    edit(data)
    with pytest.raises(SpecError) as exc:
        ThreadSpec.from_dict(data)
    message = str(exc.value)
    assert f"'{key}'" in message and text in message


def test_absurd_magnitude_refused_by_the_constructor_too():
    with pytest.raises(SpecError, match="'pitch' is out of range.*0.0001 to 1000 mm"):
        ThreadSpec(
            units="mm",
            pitch=1e308,
            bolt=BoltSpec(5.884, 5.268, 4.77),
            nut=NutSpec(6.0, 5.425, 5.035),
        )


def test_real_threads_at_the_edges_are_accepted():
    # A watch screw, M0.3 x 0.08 (mm) and in inches, and a big M300 x 6 all pass.
    for units, scale in (("mm", 1.0), ("in", 1 / 25.4)):
        p = 0.08 * scale
        ThreadSpec(
            units=units,
            pitch=p,
            bolt=BoltSpec(0.3 * scale, 0.3 * scale - 0.65 * p, 0.3 * scale - 1.2 * p),
            nut=NutSpec(0.3 * scale + 0.01 * p, 0.3 * scale - 0.6 * p, 0.3 * scale - 1.08 * p),
        )
    ThreadSpec(
        units="mm",
        pitch=6.0,
        bolt=BoltSpec(300.0, 296.1, 292.6),
        nut=NutSpec(300.1, 296.2, 293.6),
        starts=4,
    )


def test_load_refuses_a_directory_and_says_so(tmp_path):
    with pytest.raises(SpecError, match="is a directory, not a spec file"):
        load_spec(tmp_path)
    folder = tmp_path / "looks.json"
    folder.mkdir()
    with pytest.raises(SpecError, match="looks.json is a directory, not a spec file"):
        load_spec(folder)
