"""The interactive pages in a real browser: headless Chromium driven by Selenium.

A small search (``threadmate search ... --json --html``) and a tiny run
(``threadmate run``, which writes report.html and the page of its signature's start) are
opened from disk with the network closed. Each page must load without an error on the
console, draw its 3-D scene and plots (elements present, a screenshot that is not blank),
and the search's slider must move the bolt to the pose of the state it names, as the
search's JSON document gives it. The run's click signature must be the search's own
states. Skipped, saying why, only where no Chromium and chromedriver can be found.
"""

from __future__ import annotations

import io
import json
import math
import re
import shutil
import tempfile
import time
from pathlib import Path

import numpy as np
import pytest

from _cli import THESIS_PARTS, run_captured

DESIGNATION = "1/4-20 UNC-2A/2B"
#: The search of the tests: a flat bolt upright at phase 340, 10-degree steps (a contact
#: change, then the snap after about 9 degrees).
SEARCH = (DESIGNATION, *THESIS_PARTS, "--roll", "0", "--pitch", "0", "--phase", "340")
STEP = 10.0
#: Flags Chromium needs as root in a closed network (a fresh profile is added).
CHROMIUM_FLAGS = (
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--enable-unsafe-swiftshader",
    "--window-size=1440,900",
)


def _binaries() -> tuple[str, str] | None:
    browser = next(
        (shutil.which(n) for n in ("chromium", "chromium-browser") if shutil.which(n)), None
    )
    driver = shutil.which("chromedriver")
    return None if browser is None or driver is None else (browser, driver)


@pytest.fixture(scope="module")
def browser():
    """One headless Chromium for the module, its console captured."""
    found = _binaries()
    if found is None:
        pytest.skip(
            "no browser: Debian's chromium and chromium-driver are not installed (the "
            "README's test command installs them with apt-get)"
        )
    webdriver = pytest.importorskip("selenium.webdriver")
    from selenium.webdriver.chrome.service import Service

    profile = tempfile.mkdtemp(prefix="threadmate-chromium-")
    opts = webdriver.ChromeOptions()
    for flag in (*CHROMIUM_FLAGS, f"--user-data-dir={profile}"):
        opts.add_argument(flag)
    opts.binary_location = found[0]
    opts.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    driver = webdriver.Chrome(service=Service(found[1]), options=opts)
    driver.set_page_load_timeout(120)
    yield driver
    driver.quit()
    shutil.rmtree(profile, ignore_errors=True)


def _open(driver, path: Path) -> list[dict]:
    """Open ``path`` and wait until its script says it is ready; the console's entries."""
    driver.get_log("browser")  # drop what an earlier page said
    driver.get(path.resolve().as_uri())
    deadline = time.monotonic() + 90
    while driver.execute_script("return document.body.dataset.ready") != "true":
        assert time.monotonic() < deadline, "the page never became ready"
        time.sleep(0.2)
    return driver.get_log("browser")


def _errors(log: list[dict]) -> list[str]:
    return [e["message"] for e in log if e.get("level") == "SEVERE"]


def _not_blank(element) -> None:
    """A screenshot of ``element`` holds a picture: many colours, not all background."""
    from PIL import Image

    img = np.asarray(Image.open(io.BytesIO(element.screenshot_as_png)).convert("RGB"))
    assert img.shape[0] > 200 and img.shape[1] > 200, img.shape
    inked = (np.abs(img.astype(int) - 255).sum(axis=2) > 60).mean()
    colours = len(np.unique(img.reshape(-1, 3), axis=0))
    assert inked > 0.01 and colours > 50, (inked, colours)


@pytest.fixture(scope="module")
def searched(tmp_path_factory):
    """``threadmate search --json --html --plot``: the document and the page (the
    figure beside them)."""
    folder = tmp_path_factory.mktemp("view-search")
    page = folder / "search.html"
    code, out, err = run_captured(
        "search", *SEARCH, "--step", STEP, "--json", "--html", page, "--plot", folder / "s.svg"
    )
    assert code == 0, err
    doc = json.loads(out)
    (folder / "search.json").write_text(out)
    return doc, page, folder


def test_search_plot_draws_every_state(searched):
    """``search --plot``: each panel has one marker per state of the search (every step
    and both sides of each event), not one per grid phase or per step alone."""
    doc, _, folder = searched
    svg = (folder / "s.svg").read_text()
    # The dots of the lines: the marker paths that are curves (the ticks are straight).
    dots = {m for m, d in re.findall(r'<path id="(m[0-9a-f]+)" d="([^"]*)"', svg) if "C" in d}
    used = re.findall(r'<use xlink:href="#(m[0-9a-f]+)"', svg)
    markers = sum(u in dots for u in used)
    finite = sum(s["driver_torque"] is not None for s in doc["states"])
    assert markers == 2 * len(doc["states"]) + finite
    phases = [s["phase"] for s in doc["states"]]
    for e in doc["events"]:  # both sides of each event, within the phase tolerance
        assert min(abs(p - e["phase"]) for p in phases if p < e["phase"]) <= 0.011
        assert min(abs(p - e["phase"]) for p in phases if p >= e["phase"]) <= 0.011


def _shown_bolt(driver) -> np.ndarray:
    xyz = driver.execute_script(
        "const t = document.getElementById('tm-scene').data[1];"
        "return [Array.from(t.x), Array.from(t.y), Array.from(t.z)];"
    )
    return np.asarray(xyz, dtype=float).T


def _bolt_local(driver) -> np.ndarray:
    xyz = driver.execute_script(
        "const b = JSON.parse(document.getElementById('tm-data').textContent).bolt;"
        "return [b.x, b.y, b.z];"
    )
    return np.asarray(xyz, dtype=float).T


def _pose(state: dict) -> tuple[np.ndarray, np.ndarray]:
    return np.asarray(state["rotation"], dtype=float), np.asarray(state["origin"], dtype=float)


def test_search_page_loads_and_draws(browser, searched):
    doc, page, _ = searched
    assert page.stat().st_size > 1_000_000  # plotly.js is inside
    assert "<script src=" not in page.read_text()  # nothing fetched
    log = _open(browser, page)
    assert _errors(log) == []
    scene = browser.find_element("id", "tm-scene")
    plots = browser.find_element("id", "tm-plots")
    assert scene.find_elements("css selector", "canvas"), "no WebGL canvas in the scene"
    assert len(plots.find_elements("css selector", ".scatterlayer .trace")) == 3
    _not_blank(scene)
    _not_blank(plots)
    # The plots are the search's own states: every phase the document holds.
    xs = browser.execute_script(
        "return document.getElementById('tm-plots').data.map((t) => Array.from(t.x));"
    )
    phases = [s["phase"] for s in doc["states"]]
    for x in xs:
        assert x == pytest.approx(phases, abs=1e-9)
    heights = browser.execute_script(
        "return Array.from(document.getElementById('tm-plots').data[0].y);"
    )
    assert heights == pytest.approx([s["centre"][2] for s in doc["states"]], abs=1e-12)
    # Every event is marked at its phase, the snap among them.
    shapes = browser.execute_script(
        "return document.getElementById('tm-plots').layout.shapes.slice(1).map((s) => s.x0);"
    )
    assert shapes == pytest.approx([e["phase"] for e in doc["events"]], abs=1e-9)
    assert any(e["kind"] == "snap" for e in doc["events"])


def test_slider_moves_the_bolt_to_the_states_pose(browser, searched):
    from selenium.webdriver.common.keys import Keys

    doc, page, _ = searched
    assert _errors(_open(browser, page)) == []
    local = _bolt_local(browser)
    first = _shown_bolt(browser)
    rot, origin = _pose(doc["states"][0])
    assert first == pytest.approx(local @ rot.T + origin, abs=1e-9)

    slider = browser.find_element("id", "tm-slider")
    slider.send_keys(Keys.END)  # as a user drags it to the last state: the landing
    last = len(doc["states"]) - 1
    deadline = time.monotonic() + 10
    while browser.find_element("id", "tm-readout").get_attribute("data-state") != str(last):
        assert time.monotonic() < deadline, "the slider did not move the page"
        time.sleep(0.1)
    shown = _shown_bolt(browser)
    rot, origin = _pose(doc["states"][last])
    assert shown == pytest.approx(local @ rot.T + origin, abs=1e-9)
    # It moved: the landing is lower than the start by the drop of the compliance centre.
    assert np.abs(shown - first).max() > 1e-3
    assert shown[:, 2].min() < first[:, 2].min() - 1e-3
    # The contacts shown are the state's touching contacts.
    points = browser.execute_script(
        "const t = document.getElementById('tm-scene').data[2];"
        "return [Array.from(t.x), Array.from(t.y), Array.from(t.z)];"
    )
    touching = [
        c["point"]
        for c in doc["states"][last]["contacts"]
        if c["gap"] == 0.0 or (c["force"] or 0.0) > 0.0
    ]
    assert touching
    np.testing.assert_allclose(np.asarray(points).T, np.asarray(touching), atol=1e-12)
    readout = browser.find_element("id", "tm-readout").text
    assert f"phase {doc['states'][last]['phase']:.3f} deg" in readout
    _not_blank(browser.find_element("id", "tm-scene"))


def test_snap_button_shows_the_landing(browser, searched):
    doc, page, _ = searched
    _open(browser, page)
    snap = doc["snap"]["phase"]
    button = next(
        b
        for b in browser.find_elements("css selector", "button.tm-event")
        if b.text.startswith("snap")
    )
    button.click()
    index = int(browser.find_element("id", "tm-readout").get_attribute("data-state"))
    # The first state at or past the snap's phase: the in-phase landing.
    expected = next(i for i, s in enumerate(doc["states"]) if s["phase"] >= snap)
    assert index == expected
    assert doc["states"][index]["classification"] == "in-phase"
    cursor = browser.execute_script(
        "return document.getElementById('tm-plots').layout.shapes[0].x0;"
    )
    assert cursor == pytest.approx(doc["states"][index]["phase"])
    # The snap's label above the plots leads there too.
    from selenium.webdriver.common.keys import Keys

    browser.find_element("id", "tm-slider").send_keys(Keys.HOME)
    assert browser.find_element("id", "tm-readout").get_attribute("data-state") == "0"
    labels = browser.find_elements("css selector", "#tm-plots g.annotation")
    assert len(labels) == len(doc["events"])
    labels[[e["kind"] for e in doc["events"]].index("snap")].click()
    assert browser.find_element("id", "tm-readout").get_attribute("data-state") == str(index)
    # Zoomed to the contacts, the scene spans one and a half pitches around the landing's
    # most loaded contact.
    browser.find_element("id", "tm-zoom").click()
    ranges = browser.execute_script(
        "const s = document.getElementById('tm-scene').layout.scene;"
        "return [s.xaxis.range, s.yaxis.range, s.zaxis.range];"
    )
    landing = [c for c in doc["states"][index]["contacts"] if (c["force"] or 0.0) > 0.0]
    focus = max(landing, key=lambda c: c["force"])["point"]
    pitch = doc["spec"]["pitch"]
    for (lo, hi), x in zip(ranges, focus, strict=True):
        assert lo == pytest.approx(x - 0.75 * pitch) and hi == pytest.approx(x + 0.75 * pitch)


def test_view_draws_a_saved_search(browser, searched, capsys):
    from _cli import run_cli

    doc, _, folder = searched
    code, out, err = run_cli(capsys, "view", folder / "search.json", "-o", folder / "again.html")
    assert code == 0, err
    assert _errors(_open(browser, folder / "again.html")) == []
    data = browser.execute_script(
        "return JSON.parse(document.getElementById('tm-data').textContent).states.length;"
    )
    assert data == len(doc["states"])


def test_view_refuses_what_it_cannot_draw(tmp_path, capsys):
    from _cli import refused

    old = tmp_path / "old.json"
    old.write_text(json.dumps({"units": {}, "states": []}))
    assert "not a search's document" in refused(capsys, "view", old)
    assert "no such file" in refused(capsys, "view", tmp_path / "missing.json")
    assert "--start" in refused(capsys, "view", old, "--start", "0,0,0")
    assert "not a threadmate run folder" in refused(capsys, "view", tmp_path)
    # A document whose pose is not a rotation matrix: refused, nothing written.
    from threadmate.geometry import with_parts

    bent = tmp_path / "bent.json"
    bent.write_text(
        json.dumps(
            {
                "units": {},
                "parameters": {},
                "start": {},
                "snap": None,
                "events": [],
                "spec": with_parts(DESIGNATION).to_dict(),
                "states": [
                    {"phase": 0, "origin": [0, 0, 0], "rotation": [1, 2], "centre": [0, 0, 0],
                     "contacts": []}
                ],
            }
        )
    )  # fmt: skip
    assert "state 0 has no pose" in refused(capsys, "view", bent)
    assert "--html" in refused(capsys, "search", *SEARCH, "--html", tmp_path / "x.png")
    assert not list(tmp_path.glob("*.html"))


# -- a run -----------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def ran(tmp_path_factory):
    """A tiny ``threadmate run``: one held tilt, two start phases 30 degrees apart, a
    10-degree continuation step."""
    out = tmp_path_factory.mktemp("view-run") / "job"
    code, stdout, err = run_captured(
        "run", DESIGNATION, *THESIS_PARTS, "-o", out, "--roll", "0", "--pitch", "0",
        "--phase", "300,330", "--step", STEP, "--workers", "1", "--json",
    )  # fmt: skip
    assert code == 0, err
    return out, json.loads(stdout)


def test_report_signature_is_the_searchs_own_states(ran):
    out, doc = ran
    pages = sorted((out / "views").glob("*.json"))
    assert len(pages) == 1
    search = json.loads(pages[0].read_text())
    phases = np.array([s["phase"] for s in search["states"]])
    # Every step of the continuation (no gap wider than a step) ...
    assert np.diff(phases).max() <= STEP + 1e-9
    # ... and both sides of each event, within the phase tolerance of it.
    for e in search["events"]:
        before = phases[phases < e["phase"] + 1e-9].max()
        after = phases[phases >= e["phase"] - 1e-9].min()
        assert e["phase"] - before <= 0.011 and after - e["phase"] <= 0.011, e
    # Finer than the grid (30 deg apart here), and the report says so with the count.
    assert len(phases) > 3
    report = (out / "report.md").read_text()
    assert f"its {len(phases)} states, every {STEP:g} deg step" in report
    assert f"views/{pages[0].stem}.html" in report
    assert str(out / "report.html") in doc["pages"]


def test_run_page_loads_and_links_each_start(browser, ran, capsys):
    from _cli import refused, run_cli

    out, _ = ran
    log = _open(browser, out / "report.html")
    assert _errors(log) == []
    for div in ("tm-ranking", "tm-classmap"):
        element = browser.find_element("id", div)
        assert element.find_elements("css selector", ".main-svg"), div
        _not_blank(element)
    starts = browser.execute_script(
        "return JSON.parse(document.getElementById('tm-data').textContent).starts;"
    )
    assert sorted((s["roll"], s["pitch"], s["phase"]) for s in starts) == [
        (0, 0, 300),
        (0, 0, 330),
    ]
    linked = [s for s in starts if s["page"]]
    assert len(linked) == 1 and (out / linked[0]["page"]).is_file()
    # A start without a page says how to write it.
    missing = next(s for s in starts if not s["page"])
    index = starts.index(missing)
    browser.find_element("css selector", f'a.tm-start[data-start="{index}"]').click()
    note = browser.find_element("id", "tm-start-note").text
    other = f"0,0,{missing['phase']:g}"
    assert f"--start {other}" in note
    # The linked start opens its search's page.
    browser.find_element(
        "css selector", f'a.tm-start[data-start="{starts.index(linked[0])}"]'
    ).click()
    deadline = time.monotonic() + 90
    while browser.execute_script("return document.body.dataset.ready") != "true" or not (
        browser.current_url.endswith(".html") and "views/" in browser.current_url
    ):
        assert time.monotonic() < deadline, browser.current_url
        time.sleep(0.2)
    assert _errors(browser.get_log("browser")) == []
    _not_blank(browser.find_element("id", "tm-scene"))

    # threadmate view RUN --start writes the other start's page; the run page links it.
    assert "not on the run's grid" in refused(capsys, "view", out, "--start", "0,0,310")
    code, _, err = run_cli(capsys, "view", out, "--start", other)
    assert code == 0, err
    assert _errors(_open(browser, out / "report.html")) == []
    starts = browser.execute_script(
        "return JSON.parse(document.getElementById('tm-data').textContent).starts;"
    )
    assert all(s["page"] and (out / s["page"]).is_file() for s in starts)
    name = f"search-r+0-p+0-ph{missing['phase']:g}.json"
    written = json.loads((out / "views" / name).read_text())
    assert written["start"] == {"roll": 0.0, "pitch": 0.0, "phase": missing["phase"]}
    # The library's snap of that start (grid phases and both sides of its jump) agrees.
    assert math.isclose(written["snap"]["phase"], library_snap(out, missing["phase"]), abs_tol=1.0)


def library_snap(out: Path, phase: float) -> float:
    """The snap phase starts.csv gives the start at ``phase``."""
    import csv

    with (out / "starts.csv").open() as fh:
        row = next(r for r in csv.DictReader(fh) if float(r["phase_deg"]) == phase)
    return float(row["snap_phase_deg"])


# -- the meshes drawn ------------------------------------------------------------------------
def test_display_meshes_are_thinned_and_whole_near_the_contacts():
    from scipy.spatial import cKDTree

    from threadmate.geometry import thread_meshes, with_parts
    from threadmate.view import display_meshes

    spec = with_parts(DESIGNATION, point="flat", countersink=False)
    # A contact on the nut's top face at the bore's edge, and one at the bolt's tip rim.
    on_nut = np.array([[spec.nut.minor / 2, 0.0, 0.0]])
    on_bolt = np.array([[0.0, spec.bolt.major / 2 - 0.01, 0.0]])
    bolt, nut = display_meshes(spec, on_nut, on_bolt)
    zone = 0.6 * spec.pitch
    for shown, source, point in zip(
        (bolt, nut), thread_meshes(spec), (on_bolt, on_nut), strict=True
    ):
        v = np.asarray(source.mesh.vertices)
        assert shown.source_faces == len(source.mesh.faces)
        assert len(shown.faces) < 0.6 * shown.source_faces  # thinned
        assert shown.faces.min() >= 0 and shown.faces.max() < len(shown.vertices)
        # Every vertex within the zone is drawn where it is.
        near = v[np.linalg.norm(v - point, axis=1) < 0.9 * zone]
        assert len(near) > 20
        distance, _ = cKDTree(shown.vertices).query(near)
        assert distance.max() < 1e-12
        # And nothing drawn strays from the body: every drawn vertex lies within a cell of
        # the source mesh's vertices.
        distance, _ = cKDTree(v).query(shown.vertices)
        assert distance.max() < spec.pitch / 14 * math.sqrt(3)
