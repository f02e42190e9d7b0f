// The page of a run (threadmate.view): the settings ranked, the class map over the held
// tilts at any start phase, and every start linked to its search's page. Reads #tm-data.
(function () {
  "use strict";
  const D = JSON.parse(document.getElementById("tm-data").textContent);
  const config = { responsive: true, displaylogo: false };
  const note = document.getElementById("tm-start-note");
  const CLASSES = ["stable", "quasi-stable", "unstable", "in-phase", "error"];
  // The library figures' colours (threadmate.library).
  const COLOURS = ["#2ca02c", "#ff9f1c", "#d62728", "#1f77b4", "#000000"];
  const plots = [];

  function openStart(s) {
    if (s.page) {
      window.location.href = s.page;
    } else if (note) {
      note.textContent = "No page for the start at held roll " + s.roll + ", pitch " +
        s.pitch + ", phase " + s.phase + " deg yet. Write it with: " + s.command +
        " (run from the run folder's parent), then reload this page.";
      note.scrollIntoView({ block: "center" });
    }
  }
  for (const a of document.querySelectorAll("a.tm-start[data-start]")) {
    a.addEventListener("click", (ev) => {
      const s = D.starts[Number(a.dataset.start)];
      if (!s.page) { ev.preventDefault(); openStart(s); }
    });
  }

  // -- the settings ranked -------------------------------------------------------------
  const ranking = document.getElementById("tm-ranking");
  if (ranking && D.settings.length) {
    const groups = {};
    for (const s of D.settings) {
      const key = "F " + s.force + " N, k " + s.stiffness.join("/") + " N m/rad";
      (groups[key] = groups[key] || []).push(s);
    }
    const traces = [];
    for (const [key, rows] of Object.entries(groups)) {
      rows.sort((a, b) => a.held_pitch - b.held_pitch);
      const x = rows.map((s) => s.held_pitch);
      traces.push({ type: "scatter", mode: "lines+markers", name: key + ": snap share", x: x,
        y: rows.map((s) => 100 * s.share_snap), yaxis: "y",
        hovertemplate: "held pitch %{x} deg<br>%{y:.0f}% snap within one turn<extra></extra>" });
      traces.push({ type: "scatter", mode: "lines+markers", name: key + ": mean turn", x: x,
        y: rows.map((s) => s.turn_mean), yaxis: "y2",
        hovertemplate: "held pitch %{x} deg<br>mean turn %{y:.1f} deg<extra></extra>" });
    }
    const shapes = D.best ? [{ type: "line", xref: "x", yref: "paper", x0: D.best.held_pitch,
      x1: D.best.held_pitch, y0: 0, y1: 1, line: { color: "#d62728", dash: "dot" } }] : [];
    plots.push(Plotly.newPlot(ranking, traces, {
      margin: { l: 70, r: 20, t: 40, b: 50 },
      title: { text: "settings ranked: the pick dotted red", font: { size: 14 } },
      xaxis: { title: { text: "held pitch: pre-tilt about the nut's Y axis (deg)" },
        anchor: "y2", zeroline: false },
      yaxis: { title: { text: "snap share (%)" }, domain: [0.55, 1] },
      yaxis2: { title: { text: "mean turn (deg)" }, domain: [0, 0.45] },
      legend: { orientation: "h", y: -0.25 },
      shapes: shapes,
    }, config));
  }

  // -- the class map -------------------------------------------------------------------
  const map = document.getElementById("tm-classmap");
  const select = document.getElementById("tm-phase");
  if (map && D.starts.length) {
    const phases = [...new Set(D.starts.map((s) => s.phase))].sort((a, b) => a - b);
    const rolls = [...new Set(D.starts.map((s) => s.roll))].sort((a, b) => a - b);
    const pitches = [...new Set(D.starts.map((s) => s.pitch))].sort((a, b) => a - b);
    for (const ph of phases) {
      const o = document.createElement("option");
      o.value = String(ph); o.textContent = String(ph);
      select.appendChild(o);
    }
    const scale = [];
    CLASSES.forEach((c, i) => {
      scale.push([i / CLASSES.length, COLOURS[i]], [(i + 1) / CLASSES.length, COLOURS[i]]);
    });
    function grid(ph) {
      const z = [], text = [], idx = [];
      for (const p of pitches) {
        const zr = [], tr = [], ir = [];
        for (const r of rolls) {
          const k = D.starts.findIndex((s) => s.roll === r && s.pitch === p && s.phase === ph);
          const s = D.starts[k];
          const c = s ? CLASSES.indexOf(s.classification) : -1;
          zr.push(c < 0 ? (s ? 4.5 : null) : c + 0.5);
          tr.push(s ? s.classification + "<br>" + (s.snapped ? "snaps after " +
            (s.turn === null ? "-" : s.turn.toFixed(1)) + " deg" : "no snap within a turn") +
            (s.page ? "<br>click: open its search" : "<br>click: how to open its search") : "");
          ir.push(k);
        }
        z.push(zr); text.push(tr); idx.push(ir);
      }
      return { z: z, text: text, customdata: idx };
    }
    function draw(ph) {
      const g = grid(ph);
      return Plotly.react(map, [{
        type: "heatmap", x: rolls, y: pitches, z: g.z, text: g.text, customdata: g.customdata,
        zmin: 0, zmax: CLASSES.length, colorscale: scale, xgap: 2, ygap: 2,
        hovertemplate: "held roll %{x} deg, held pitch %{y} deg<br>%{text}<extra></extra>",
        colorbar: { tickvals: CLASSES.map((c, i) => i + 0.5), ticktext: CLASSES },
      }], {
        margin: { l: 70, r: 20, t: 40, b: 50 },
        title: { text: "class each start reaches, start phase " + ph + " deg",
          font: { size: 14 } },
        xaxis: { title: { text: "held roll: tilt about the nut's X axis (deg)" },
          tickvals: rolls },
        yaxis: { title: { text: "held pitch: tilt about the nut's Y axis (deg)" },
          tickvals: pitches },
      }, config);
    }
    plots.push(draw(phases[0]).then(() => {
      map.on("plotly_click", (ev) => {
        const k = ev.points && ev.points.length ? ev.points[0].customdata : -1;
        if (k >= 0) openStart(D.starts[k]);
      });
    }));
    select.addEventListener("change", () => draw(Number(select.value)));
  }
  Promise.all(plots).then(() => { document.body.dataset.ready = "true"; });
})();
