// The report's mechanism view (linkstress/report/mechanism_view.py writes its data): draws the
// links, joints and joint forces of one position into the SVG and redraws when the slider moves.
// SVG user units are metres with y negated, so that +y points up on the page.
(function () {
  "use strict";
  const SVG = "http://www.w3.org/2000/svg";
  const data = JSON.parse(document.getElementById("view-data").textContent);
  const svg = document.getElementById("view-svg");
  const slider = document.getElementById("view-slider");
  const angleText = document.getElementById("view-angle");
  const readout = document.getElementById("view-readout");
  const play = document.getElementById("view-play");
  const size = data.size_m;
  const digits = data.decimals;
  const [xmin, ymin, xmax, ymax] = data.extent_m;

  svg.setAttribute("viewBox", [xmin, -ymax, xmax - xmin, ymax - ymin].join(" "));
  svg.setAttribute("style", "width:100%;max-height:560px;border:1px solid #ddd;background:#fff");

  function element(tag, attributes, parent) {
    const node = document.createElementNS(SVG, tag);
    for (const [key, value] of Object.entries(attributes)) node.setAttribute(key, value);
    (parent || svg).appendChild(node);
    return node;
  }

  function place(pose, point) {
    const c = Math.cos(pose[2]), s = Math.sin(pose[2]);
    return [pose[0] + c * point[0] - s * point[1], pose[1] + s * point[0] + c * point[1]];
  }

  function svgPoint(p) {
    return p[0].toFixed(digits) + "," + (-p[1]).toFixed(digits);
  }

  // Colour of a von Mises value [MPa] on the sweep's one scale: linear between the colour stops.
  function stressColour(value) {
    const stops = data.stress_scale.colours;
    const t = Math.min(Math.max(value / (data.stress_scale.max_mpa || 1), 0), 1) * (stops.length - 1);
    const i = Math.min(Math.floor(t), stops.length - 2), f = t - i;
    const rgb = [1, 3, 5].map(function (at) {
      const a = parseInt(stops[i].substr(at, 2), 16), b = parseInt(stops[i + 1].substr(at, 2), 16);
      return Math.round(a + f * (b - a));
    });
    return "rgb(" + rgb.join(", ") + ")";
  }

  const stroke = {"vector-effect": "non-scaling-stroke"};
  const drawn = {};
  // Uncoloured links (the ground, unstressed links) underneath, so that they hide no stress colour.
  const order = Object.entries(data.links).sort(function (a, b) {
    return Boolean(a[1].von_mises_mpa) - Boolean(b[1].von_mises_mpa);
  });
  for (const [name, link] of order) {
    drawn[name] = {
      path: element("path", Object.assign({"data-link": name, "fill-rule": "evenodd", stroke: link.colour,
        "stroke-width": 1.5, fill: "transparent"}, stroke)),
      label: element("text", {"data-label": name, "font-size": 0.03 * size, fill: "#222",
        "text-anchor": "middle"}),
    };
    drawn[name].label.textContent = name;
    if (link.max_at_m) {
      drawn[name].max = element("circle", {"data-max": name, r: 0.008 * size, fill: "#000"});
    }
  }
  const joints = {};
  for (const name of Object.keys(data.joints || {})) {
    joints[name] = element("circle", Object.assign({"data-joint": name, r: 0.006 * size, fill: "#fff",
      stroke: "#000", "stroke-width": 1}, stroke));
  }
  const arrows = (data.forces || []).map(function (force) {
    return element("path", Object.assign({"data-force": force.label, stroke: "crimson", "stroke-width": 2,
      fill: "transparent"}, stroke));
  });

  // An arrow from p - scale F to the joint p, with a head at the joint.
  function arrowPath(p, force) {
    const k = data.force_scale_m_per_n;
    const tail = [p[0] - k * force[0], p[1] - k * force[1]];
    const length = Math.hypot(p[0] - tail[0], p[1] - tail[1]);
    if (length === 0) return "";
    const head = Math.min(0.03 * size, 0.4 * length);
    const ux = (p[0] - tail[0]) / length, uy = (p[1] - tail[1]) / length;
    const left = [p[0] - head * (ux - 0.5 * uy), p[1] - head * (uy + 0.5 * ux)];
    const right = [p[0] - head * (ux + 0.5 * uy), p[1] - head * (uy - 0.5 * ux)];
    return "M" + svgPoint(tail) + " L" + svgPoint(p) + " M" + svgPoint(left) + " L" + svgPoint(p) + " L" + svgPoint(right);
  }

  function show(node, visible) {
    node.setAttribute("visibility", visible ? "visible" : "hidden");
  }

  function row(cells, tag) {
    return "<tr>" + cells.map(function (c) { return "<" + tag + ">" + c + "</" + tag + ">"; }).join("") + "</tr>";
  }

  function draw(k) {
    const ok = data.feasible[k];
    const where = "position " + (k + 1) + " of " + data.frames.length;
    angleText.textContent = "input angle " + data.input_angle_deg[k].toFixed(1) + " deg, " + where +
      (ok ? "" : " \u2014 infeasible: " + data.reason[k]);
    svg.setAttribute("data-feasible", ok ? "yes" : "no");
    const rows = [];
    for (const [name, link] of Object.entries(data.links)) {
      const parts = drawn[name];
      show(parts.path, ok);
      show(parts.label, ok);
      if (parts.max) show(parts.max, ok);
      if (!ok) continue;
      const pose = link.pose[k];
      const d = link.rings.map(function (ring) {
        return "M" + ring.map(function (p) { return svgPoint(place(pose, p)); }).join(" L") + (link.closed ? " Z" : "");
      }).join(" ");
      parts.path.setAttribute("d", d);
      const middle = link.rings[0].reduce(function (a, p) { return [a[0] + p[0], a[1] + p[1]]; }, [0, 0])
        .map(function (v) { return v / link.rings[0].length; });
      const at = place(pose, middle);
      parts.label.setAttribute("x", at[0].toFixed(digits));
      parts.label.setAttribute("y", (-at[1]).toFixed(digits));
      if (link.von_mises_mpa) {
        const value = link.von_mises_mpa[k];
        parts.path.setAttribute("fill", stressColour(value));
        parts.path.setAttribute("fill-opacity", "0.75");
        parts.path.setAttribute("data-von-mises-mpa", String(value));
        parts.max.setAttribute("cx", link.max_at_m[k][0].toFixed(digits));
        parts.max.setAttribute("cy", (-link.max_at_m[k][1]).toFixed(digits));
        rows.push(row([name, link.stress_label, value.toFixed(data.stress_scale.decimals) + " MPa"], "td"));
      } else if (link.closed) {
        parts.path.setAttribute("fill", "#d8d8d8");
        parts.path.setAttribute("fill-opacity", "0.5");
      }
    }
    for (const [name, circle] of Object.entries(joints)) {
      show(circle, ok);
      if (!ok) continue;
      circle.setAttribute("cx", data.joints[name][k][0].toFixed(digits));
      circle.setAttribute("cy", (-data.joints[name][k][1]).toFixed(digits));
    }
    (data.forces || []).forEach(function (force, i) {
      show(arrows[i], ok);
      if (!ok) return;
      const f = force.force_n[k];
      arrows[i].setAttribute("d", arrowPath(data.joints[force.joint][k], f));
      rows.push(row([force.label, "at " + force.joint, Math.hypot(f[0], f[1]).toFixed(data.force_decimals) + " N"], "td"));
    });
    readout.innerHTML = rows.length ? "<table>" + row(["", "at this position", "value"], "th") + rows.join("") + "</table>" : "";
  }

  function colourBar() {
    const bar = document.getElementById("view-colour-bar");
    if (!data.stress_scale) {
      bar.textContent = "no section stresses computed: links not coloured";
      return;
    }
    const stops = data.stress_scale.colours.join(", ");
    const top = data.stress_scale.max_mpa;
    const ticks = [0, 0.25, 0.5, 0.75, 1].map(function (t) {
      return '<span style="position:absolute;left:' + (100 * t) + '%;transform:translateX(-50%)">' +
        (t * top).toPrecision(3) + "</span>";
    }).join("");
    bar.innerHTML = '<div style="margin:0.3em 1.5em 0 1.5em"><div style="height:14px;background:linear-gradient(to right, ' +
      stops + ')"></div><div style="position:relative;height:1.2em;font-size:0.8em">' + ticks +
      '</div><div style="text-align:center;font-size:0.85em">' + data.stress_scale.label +
      " at the position [MPa], one scale for the whole sweep</div></div>";
  }

  let timer = null;
  play.addEventListener("click", function () {
    if (timer !== null) {
      clearInterval(timer);
      timer = null;
      play.textContent = "play";
      return;
    }
    play.textContent = "pause";
    timer = setInterval(function () {
      slider.value = String((Number(slider.value) + 1) % data.frames.length);
      draw(Number(slider.value));
    }, 60);
  });
  play.disabled = data.frames.length < 2;
  slider.addEventListener("input", function () { draw(Number(slider.value)); });
  colourBar();
  draw(Number(slider.value));
})();
