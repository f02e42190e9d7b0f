"""``threadmate settle`` on a descent that did not converge: said plainly (a warning on
stderr, the pose titled "Not a rest state" with the residuals and the steps), and
``converged`` a JSON boolean; a converged descent keeps "Rest pose"."""

from __future__ import annotations

import dataclasses
import json

import pytest

import threadmate.contact
from _cli import THESIS_PARTS, run_cli
from threadmate.contact import Compliance, Mechanics, contact_scene, settle
from threadmate.geometry import spec_from_designation

ARGS = ("1/4-20 UNC-2A/2B", *THESIS_PARTS, "--roll", "1", "--pitch", "0", "--phase", "0")


@pytest.fixture(scope="module")
def rest():
    """The real rest state the command computes for ARGS."""
    spec = spec_from_designation("1/4-20 UNC-2A/2B", point="flat", countersink=False)
    mech = Mechanics(spec, Compliance(), scene=contact_scene(spec))
    return settle(mech, 1.0, 0.0, 0.0)


def test_a_converged_descent_is_a_rest_pose(rest, capsys):
    assert rest.balance["converged"]  # the case: a descent that balances
    rc, out, err = run_cli(capsys, "settle", *ARGS)
    assert rc == 0 and "warning" not in err
    assert "Rest pose: roll" in out and "Not a rest state" not in out
    rc, out, err = run_cli(capsys, "settle", *ARGS, "--json")
    doc = json.loads(out)
    assert doc["converged"] is True and doc["balance"]["converged"] is True


def test_a_descent_that_did_not_converge_is_said_plainly(rest, monkeypatch, capsys):
    """The same state as a descent that stopped 60 steps short of the balance (force
    residual 0.28 of the 10 N load: 2.8 N)."""
    stopped = dataclasses.replace(
        rest, balance={"force": 0.28, "moment": 0.27, "converged": 0.0}, iterations=60
    )
    monkeypatch.setattr(threadmate.contact, "settle", lambda *a, **k: stopped)
    rc, out, err = run_cli(capsys, "settle", *ARGS)
    assert rc == 0
    (warning,) = [line for line in err.splitlines() if line.strip()]
    assert warning.startswith("threadmate: warning: not a rest state: the descent did not ")
    assert "force residual 2.8 N (0.28 of the load)" in warning and "after 60 steps" in warning
    assert "Rest pose" not in out
    pose = next(line for line in out.splitlines() if line.startswith("Not a rest state ("))
    assert "the descent did not converge" in pose and "after 60 steps" in pose
    assert "NO rest state" in out.splitlines()[0]

    rc, out, err = run_cli(capsys, "settle", *ARGS, "--json")
    doc = json.loads(out)
    assert doc["converged"] is False and doc["balance"]["converged"] is False
    assert "not a rest state" in err


def test_the_real_unconverged_start_agrees_with_its_document(capsys):
    """#10-32 (1, -1, 90), the issue's start: whatever the descent reaches, the text, the
    warning and the JSON say the same."""
    args = ("settle", "#10-32 UNF-2A/2B", "--roll", "1", "--pitch", "-1", "--phase", "90")
    rc, out, err = run_cli(capsys, *args, "--json")
    assert rc == 0
    converged = json.loads(out)["converged"]
    assert isinstance(converged, bool)
    assert ("not a rest state" in err) is (not converged)
    rc, out, err = run_cli(capsys, *args)
    assert ("Rest pose:" in out) is converged
    assert ("Not a rest state (" in out) is (not converged)
