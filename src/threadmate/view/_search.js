// The page of a search (threadmate.view): the 3-D scene, the plots against phase and the
// slider that links them. Reads its data from the element #tm-data.
(function () {
  "use strict";
  const D = JSON.parse(document.getElementById("tm-data").textContent);
  const U = D.units;
  const N = D.states.length;
  const sceneDiv = document.getElementById("tm-scene");
  const plotDiv = document.getElementById("tm-plots");
  const slider = document.getElementById("tm-slider");
  const readout = document.getElementById("tm-readout");
  const table = document.getElementById("tm-contacts");
  const config = { responsive: true, displaylogo: false };

  function fmt(v, digits) {
    return v === null || v === undefined ? "-" : Number(v).toPrecision(digits);
  }

  // The bolt's display mesh in F at state i: x_F = R x_B + origin (conventions.md).
  function boltAt(i) {
    const s = D.states[i];
    const R = s.rotation;
    const o = s.origin;
    const bx = D.bolt.x, by = D.bolt.y, bz = D.bolt.z;
    const n = bx.length;
    const x = new Array(n), y = new Array(n), z = new Array(n);
    for (let m = 0; m < n; m++) {
      const a = bx[m], b = by[m], c = bz[m];
      x[m] = R[0] * a + R[1] * b + R[2] * c + o[0];
      y[m] = R[3] * a + R[4] * b + R[5] * c + o[1];
      z[m] = R[6] * a + R[7] * b + R[8] * c + o[2];
    }
    return { x: x, y: y, z: z };
  }

  function contactsAt(i) {
    const cs = D.states[i].contacts;
    const p = { x: [], y: [], z: [], text: [] };
    const a = { x: [], y: [], z: [] };
    const h = { x: [], y: [], z: [] };
    for (const c of cs) {
      p.x.push(c.point[0]); p.y.push(c.point[1]); p.z.push(c.point[2]);
      p.text.push(c.regions + "<br>force " + fmt(c.force, 4) + " N");
      const len = (c.force === null ? 0 : c.force) * D.arrow;
      const tip = [0, 1, 2].map((k) => c.point[k] + c.normal[k] * len);
      a.x.push(c.point[0], tip[0], null);
      a.y.push(c.point[1], tip[1], null);
      a.z.push(c.point[2], tip[2], null);
      h.x.push(tip[0]); h.y.push(tip[1]); h.z.push(tip[2]);
    }
    return { points: p, arrows: a, heads: h };
  }

  // -- the scene -----------------------------------------------------------------------
  const bolt0 = boltAt(0);
  const c0 = contactsAt(0);
  const axis = (t) => ({ title: { text: t }, showspikes: false });
  const sceneData = [
    { type: "mesh3d", name: "nut", x: D.nut.x, y: D.nut.y, z: D.nut.z, i: D.nut.i,
      j: D.nut.j, k: D.nut.k, color: "#b8bec6", opacity: 0.45, flatshading: true,
      hoverinfo: "name", showlegend: true,
      lighting: { ambient: 0.55, diffuse: 0.8, specular: 0.1 } },
    { type: "mesh3d", name: "bolt", x: bolt0.x, y: bolt0.y, z: bolt0.z, i: D.bolt.i,
      j: D.bolt.j, k: D.bolt.k, color: "#4f7fb8", opacity: 0.75, flatshading: true,
      hoverinfo: "name", showlegend: true,
      lighting: { ambient: 0.5, diffuse: 0.85, specular: 0.15 } },
    { type: "scatter3d", mode: "markers", name: "contacts", x: c0.points.x,
      y: c0.points.y, z: c0.points.z, text: c0.points.text, hoverinfo: "text",
      marker: { size: 5, color: "#d62728" } },
    { type: "scatter3d", mode: "lines", name: "force on the bolt (N)", x: c0.arrows.x,
      y: c0.arrows.y, z: c0.arrows.z, hoverinfo: "skip",
      line: { color: "#e6550d", width: 7 } },
    { type: "scatter3d", mode: "markers", name: "arrow heads", showlegend: false,
      x: c0.heads.x, y: c0.heads.y, z: c0.heads.z, hoverinfo: "skip",
      marker: { size: 4, symbol: "diamond", color: "#e6550d" } },
  ];
  const sceneLayout = {
    margin: { l: 0, r: 0, t: 30, b: 0 },
    title: { text: "bolt on nut, frame F (" + U + ")", font: { size: 14 } },
    legend: { x: 0, y: 1, bgcolor: "rgba(255,255,255,0.7)" },
    scene: {
      aspectmode: "data",
      xaxis: axis("x (" + U + ")"),
      yaxis: axis("y (" + U + ")"),
      zaxis: axis("z (" + U + ")"),
      camera: { eye: { x: 1.3, y: -1.5, z: 0.8 } },
    },
    uirevision: "keep",
  };

  // -- the plots against phase -----------------------------------------------------------
  const phase = D.states.map((s) => s.phase);
  const custom = D.states.map((s, i) => i);
  const series = [
    ["height", "centre height (" + U + ")", "y"],
    ["tilt", "axis tilt (deg)", "y2"],
    ["torque", "torque (N m)", "y3"],
  ];
  const plotData = series.map(([key, label, yaxis]) => ({
    type: "scatter", mode: "lines+markers", name: label, x: phase,
    y: D.states.map((s) => s[key]), yaxis: yaxis, customdata: custom,
    line: { color: "#3182bd", width: 1.6 }, marker: { size: 5 },
    hovertemplate: "phase %{x:.3f} deg<br>" + label + " %{y:.5g}<br>state %{customdata}" +
      "<extra></extra>",
  }));
  const shapes = [{
    type: "line", xref: "x", yref: "paper", x0: phase[0], x1: phase[0], y0: 0, y1: 1,
    line: { color: "#2ca02c", width: 2 },
  }];
  const notes = [];
  let lifted = 0; // the other events' labels step up, so that close ones do not overlap
  for (const e of D.events) {
    const snap = e.kind === "snap";
    shapes.push({
      type: "line", xref: "x", yref: "paper", x0: e.phase, x1: e.phase, y0: 0, y1: 1,
      line: { color: snap ? "#d62728" : "#8a949e", width: snap ? 2 : 1,
        dash: snap ? "solid" : "dash" },
    });
    notes.push({
      x: e.phase, xref: "x", y: 1.0, yref: "paper", yanchor: "bottom", showarrow: false,
      captureevents: true, hovertext: "show the state after it",
      yshift: snap ? 0 : 14 * (lifted++ % 3),
      xanchor: snap ? "right" : "left",
      text: snap ? "snap: click " + fmt(e.click, 3) + " " + U : e.kind,
      font: { size: snap ? 12 : 10, color: snap ? "#d62728" : "#5a6570" },
      textangle: snap ? 0 : -30,
    });
  }
  const plotLayout = {
    margin: { l: 70, r: 15, t: 80, b: 50 },
    showlegend: false,
    hovermode: "closest",
    xaxis: { title: { text: "phase (deg, turned " + D.sense + ")" }, anchor: "y3" },
    yaxis: { title: { text: series[0][1] }, domain: [0.7, 1.0] },
    yaxis2: { title: { text: series[1][1] }, domain: [0.37, 0.65] },
    yaxis3: { title: { text: series[2][1] }, domain: [0.0, 0.32] },
    shapes: shapes,
    annotations: notes,
  };

  // -- linking ---------------------------------------------------------------------------
  let current = 0;
  function show(i) {
    i = Math.max(0, Math.min(N - 1, i | 0));
    current = i;
    slider.value = String(i);
    const s = D.states[i];
    const b = boltAt(i);
    const c = contactsAt(i);
    Plotly.restyle(sceneDiv, { x: [b.x], y: [b.y], z: [b.z] }, [1]);
    Plotly.restyle(sceneDiv, {
      x: [c.points.x, c.arrows.x, c.heads.x],
      y: [c.points.y, c.arrows.y, c.heads.y],
      z: [c.points.z, c.arrows.z, c.heads.z],
      text: [c.points.text, null, null],
    }, [2, 3, 4]);
    Plotly.relayout(plotDiv, { "shapes[0].x0": s.phase, "shapes[0].x1": s.phase });
    readout.textContent =
      "state " + i + " of " + (N - 1) + ": phase " + s.phase.toFixed(3) + " deg, " +
      s.classification + (s.regions ? " on " + s.regions : "") + "; centre height " +
      fmt(s.height, 6) + " " + U + ", tilt " + fmt(s.tilt, 4) + " deg, torque " +
      fmt(s.torque, 4) + " N m" + (i > 0 ? "; fall since the state before " +
      fmt(D.states[i - 1].height - s.height, 3) + " " + U : "") +
      (i === D.snap ? " (after the snap)" : "");
    readout.dataset.state = String(i);
    let rows = "<table><tr><th class=\"tm-text\">bolt/nut regions</th><th>x (" + U +
      ")</th><th>y (" + U + ")</th><th>z (" + U + ")</th><th>force (N)</th></tr>";
    for (const ct of s.contacts) {
      rows += "<tr><td class=\"tm-text\">" + ct.regions + "</td><td>" +
        ct.point.map((v) => v.toFixed(5)).join("</td><td>") + "</td><td>" +
        fmt(ct.force, 4) + "</td></tr>";
    }
    table.innerHTML = rows + "</table>" + (s.contacts.length ? "" :
      "<p class=\"tm-note\">no touching contact</p>");
  }

  // The contact zone: a cube of one and a half pitches around the most loaded contact of
  // the snap's landing (else of the last state), fixed while the slider moves, so that a
  // drop of a few thousandths shows; the button toggles it with the whole scene.
  const landing = D.states[D.snap === null ? N - 1 : D.snap].contacts;
  const focus = landing.length ? landing.reduce((a, c) =>
    ((c.force || 0) > (a.force || 0) ? c : a)).point : null;
  const zoomBtn = document.getElementById("tm-zoom");
  let zoomed = false;
  function zoom(on) {
    zoomed = on && focus !== null;
    if (zoomed) {
      const mid = focus;
      const h = 0.75 * D.pitch;
      Plotly.relayout(sceneDiv, {
        "scene.aspectmode": "cube",
        "scene.xaxis.range": [mid[0] - h, mid[0] + h],
        "scene.yaxis.range": [mid[1] - h, mid[1] + h],
        "scene.zaxis.range": [mid[2] - h, mid[2] + h],
      });
    } else {
      Plotly.relayout(sceneDiv, {
        "scene.aspectmode": "data",
        "scene.xaxis.autorange": true,
        "scene.yaxis.autorange": true,
        "scene.zaxis.autorange": true,
      });
    }
    zoomBtn.textContent = zoomed ? "whole scene" : "zoom to the contacts";
  }

  Promise.all([
    Plotly.newPlot(sceneDiv, sceneData, sceneLayout, config),
    Plotly.newPlot(plotDiv, plotData, plotLayout, config),
  ]).then(function () {
    slider.addEventListener("input", () => show(Number(slider.value)));
    document.getElementById("tm-prev").addEventListener("click", () => show(current - 1));
    document.getElementById("tm-next").addEventListener("click", () => show(current + 1));
    for (const btn of document.querySelectorAll("button.tm-event")) {
      btn.addEventListener("click", () => show(Number(btn.dataset.state)));
    }
    zoomBtn.addEventListener("click", () => zoom(!zoomed));
    plotDiv.on("plotly_clickannotation", (ev) => show(D.events[ev.index].state));
    plotDiv.on("plotly_click", (ev) => {
      if (ev.points && ev.points.length) show(ev.points[0].customdata);
    });
    show(0);
    document.body.dataset.ready = "true";
  });
})();
