"""Shared fixtures: thread pairs built directly from published limits (not from our tables)."""

from __future__ import annotations

import json

import matplotlib
import pytest

matplotlib.use("Agg")

from threadmate.geometry import BoltSpec, NutSpec, ThreadSpec, save_spec  # noqa: E402


@pytest.fixture(scope="session")
def quarter_20() -> ThreadSpec:
    """1/4-20 UNC-2A/2B at mean material, from the ASME B1.1 table values.

    Bolt: major 0.2408-0.2489, PD 0.2127-0.2164, minor near the UNR reference (root
    radius 0.125 p). Nut: minor 0.196-0.207, PD 0.2175-0.2224, major min 0.2500.
    """
    return ThreadSpec(
        units="in",
        pitch=0.05,
        bolt=BoltSpec(major=0.24485, pitch_diameter=0.21455, minor=0.1887, root_fillet=0.00625),
        nut=NutSpec(major=0.2500, pitch_diameter=0.21995, minor=0.2015),
    )


@pytest.fixture(scope="session")
def sharp_quarter_20() -> ThreadSpec:
    """The same pair with every corner sharp."""
    return ThreadSpec(
        units="in",
        pitch=0.05,
        bolt=BoltSpec(major=0.24485, pitch_diameter=0.21455, minor=0.1887),
        nut=NutSpec(major=0.2500, pitch_diameter=0.21995, minor=0.2015),
    )


@pytest.fixture(scope="session")
def quarter_20_file(quarter_20, tmp_path_factory):
    """:func:`quarter_20` saved as a JSON spec file (by :func:`threadmate.geometry.save_spec`)."""
    return save_spec(quarter_20, tmp_path_factory.mktemp("spec") / "quarter-20.json")


@pytest.fixture()
def spec_file(tmp_path, request):
    """The requesting test module's ``SPEC`` dict written by hand as a JSON spec file."""
    path = tmp_path / "pair.json"
    path.write_text(json.dumps(request.module.SPEC))
    return path
