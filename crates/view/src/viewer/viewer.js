// hullskin 3-D viewer: draws the hull described by the JSON block #hull-data with three.js
// (the global THREE, inlined above). Written by hull::viewer; everything is in this page.
(function () {
  "use strict";
  var log = window.hullskinLog;
  var status = document.getElementById("status");
  var data = JSON.parse(document.getElementById("hull-data").textContent);

  // ---- decoding ---------------------------------------------------------------------------
  function bytes(b64) {
    var bin = atob(b64), out = new Uint8Array(bin.length);
    for (var i = 0; i < bin.length; i++) out[i] = bin.charCodeAt(i);
    return out.buffer;
  }
  function f32(b64) { return new Float32Array(bytes(b64)); }
  function i16(b64) { return new Int16Array(bytes(b64)); }
  function rgb(hex) {
    var n = parseInt(hex.slice(1), 16);
    return new THREE.Vector3(((n >> 16) & 255) / 255, ((n >> 8) & 255) / 255, (n & 255) / 255);
  }
  function fmt(x) {
    if (typeof x !== "number" || !isFinite(x)) return "n/a";
    if (x === 0) return "0";
    var a = Math.abs(x);
    return a >= 1e-3 && a < 1e5 ? String(Number(x.toPrecision(3))) : x.toExponential(2);
  }

  // Options from the address: #field=mean&zebra=1&net=1&offsets=0&mirror=0&bare=1.
  var initial = Object.assign({}, data.initial);
  var bare = false;
  location.hash.replace(/^#/, "").split("&").forEach(function (kv) {
    var p = kv.split("="), k = p[0], v = p[1];
    if (k === "field" && (data.fields[v] || v === "none")) initial.field = v;
    else if (k === "bare") bare = v !== "0";
    else if (k in initial && typeof initial[k] === "boolean") initial[k] = v !== "0";
  });

  // ---- geometry of the starboard half -----------------------------------------------------
  var grid = data.grid, nu = grid.nu, nv = grid.nv;
  var positions = f32(grid.positions);
  var geometry = new THREE.BufferGeometry();
  geometry.setAttribute("position", new THREE.BufferAttribute(positions, 3));
  geometry.setAttribute("normal", new THREE.BufferAttribute(i16(grid.normals), 3, true));
  // Two triangles per cell, wound so that the front face is the outward side.
  var index = new Uint32Array(6 * (nu - 1) * (nv - 1)), t = 0;
  for (var i = 0; i + 1 < nu; i++) {
    for (var j = 0; j + 1 < nv; j++) {
      var a = i * nv + j, b = a + nv, c = a + 1, d = b + 1;
      if (grid.flip) index.set([a, c, b, b, c, d], t);
      else index.set([a, b, c, c, b, d], t);
      t += 6;
    }
  }
  geometry.setIndex(new THREE.BufferAttribute(index, 1));
  var fieldValues = {};
  Object.keys(data.fields).forEach(function (k) { fieldValues[k] = f32(data.fields[k].values); });
  geometry.setAttribute("value", new THREE.BufferAttribute(new Float32Array(nu * nv), 1));

  var GLSL_RAMP = [
    "uniform vec3 stops[5];",
    "vec3 ramp(float t) {",
    "  float x = clamp(t, 0.0, 1.0) * 4.0;",
    "  if (x < 1.0) return mix(stops[0], stops[1], x);",
    "  if (x < 2.0) return mix(stops[1], stops[2], x - 1.0);",
    "  if (x < 3.0) return mix(stops[2], stops[3], x - 2.0);",
    "  return mix(stops[3], stops[4], x - 3.0);",
    "}"
  ].join("\n");

  var surfaceMaterial = new THREE.ShaderMaterial({
    side: THREE.DoubleSide,
    polygonOffset: true, polygonOffsetFactor: 1, polygonOffsetUnits: 1,
    uniforms: {
      stops: { value: [0, 1, 2, 3, 4].map(function () { return new THREE.Vector3(); }) },
      lo: { value: 0 }, hi: { value: 1 },
      mode: { value: 0 },
      zebraAxis: { value: new THREE.Vector3(0, 0, 1) },
      zebraCount: { value: 16 }
    },
    vertexShader: [
      "attribute float value;",
      "varying vec3 vPos; varying vec3 vNormal; varying float vValue;",
      "void main() {",
      "  vec4 wp = modelMatrix * vec4(position, 1.0);",
      // modelMatrix is a rotation-free reflection/identity here: it maps normals too.
      "  vPos = wp.xyz; vNormal = mat3(modelMatrix) * normal; vValue = value;",
      "  gl_Position = projectionMatrix * viewMatrix * wp;",
      "}"
    ].join("\n"),
    fragmentShader: [
      GLSL_RAMP,
      "uniform float lo; uniform float hi; uniform int mode;",
      "uniform vec3 zebraAxis; uniform float zebraCount;",
      "varying vec3 vPos; varying vec3 vNormal; varying float vValue;",
      "void main() {",
      "  vec3 n = normalize(vNormal);",
      "  if (!gl_FrontFacing) n = -n;",
      "  vec3 v = normalize(cameraPosition - vPos);",
      // A key light above and left of the eye, a weak head light, and a sky light from +z.
      "  vec3 camUp = vec3(viewMatrix[0][1], viewMatrix[1][1], viewMatrix[2][1]);",
      "  vec3 camRight = vec3(viewMatrix[0][0], viewMatrix[1][0], viewMatrix[2][0]);",
      "  vec3 key = normalize(v + 0.9 * camUp - 0.4 * camRight);",
      "  float diff = 0.75 * max(dot(n, key), 0.0) + 0.25 * max(dot(n, v), 0.0);",
      "  float sky = 0.5 + 0.5 * n.z;",
      "  float spec = pow(max(dot(n, normalize(key + v)), 0.0), 48.0);",
      "  vec3 base;",
      "  if (mode == 2) {",
      // Zebra: stripes of a light environment, seen by reflection.
      "    vec3 r = reflect(-v, n);",
      "    float s = acos(clamp(dot(r, zebraAxis), -1.0, 1.0)) / 3.14159265 * zebraCount;",
      "    float w = max(fwidth(s), 1e-4);",
      "    float tri = abs(fract(s) - 0.5);",
      "    float band = smoothstep(0.25 - w, 0.25 + w, tri);",
      "    base = mix(vec3(0.06), vec3(0.97), band);",
      "    gl_FragColor = vec4(base * (0.75 + 0.25 * diff), 1.0);",
      "    return;",
      "  }",
      "  if (mode == 1) base = vec3(0.74, 0.77, 0.81);",
      "  else base = ramp((vValue - lo) / (hi - lo));",
      "  vec3 col = base * (0.42 + 0.1 * sky + 0.55 * diff) + 0.1 * spec;",
      "  gl_FragColor = vec4(col, 1.0);",
      "}"
    ].join("\n")
  });

  // ---- control net: the rows and columns of the poles -------------------------------------
  var net = data.net, poles = f32(net.points), seg = [];
  function pole(i, j) { var k = 3 * (i * net.nv + j); return [poles[k], poles[k + 1], poles[k + 2]]; }
  for (var pi = 0; pi < net.nu; pi++) {
    for (var pj = 0; pj < net.nv; pj++) {
      if (pi + 1 < net.nu) seg.push.apply(seg, pole(pi, pj).concat(pole(pi + 1, pj)));
      if (pj + 1 < net.nv) seg.push.apply(seg, pole(pi, pj).concat(pole(pi, pj + 1)));
    }
  }
  var netGeometry = new THREE.BufferGeometry();
  netGeometry.setAttribute("position", new THREE.Float32BufferAttribute(seg, 3));
  var netMaterial = new THREE.LineBasicMaterial({ color: 0x1b2a3a, transparent: true, opacity: 0.75 });
  var netPoints = new THREE.BufferGeometry();
  netPoints.setAttribute("position", new THREE.BufferAttribute(poles, 3));

  // ---- offsets: points coloured by their distance to the surface --------------------------
  var pointMaterial = function (colored) {
    return new THREE.ShaderMaterial({
      uniforms: {
        stops: { value: data.colormaps.sequential.map(rgb) },
        hi: { value: data.offsets && data.offsets.max > 0 ? data.offsets.max : 1 },
        size: { value: (colored ? 6 : 4) * (window.devicePixelRatio || 1) },
        colored: { value: colored ? 1 : 0 }
      },
      vertexShader: [
        "attribute float dist; uniform float size; varying float vDist;",
        "void main() { vDist = dist; gl_PointSize = size;",
        "  gl_Position = projectionMatrix * modelViewMatrix * vec4(position, 1.0); }"
      ].join("\n"),
      fragmentShader: [
        GLSL_RAMP,
        "uniform float hi; uniform int colored; varying float vDist;",
        "void main() {",
        "  float r = length(gl_PointCoord - 0.5) * 2.0;",
        "  if (r > 1.0) discard;",
        "  vec3 c = colored == 1 ? ramp(vDist / hi) : vec3(0.1, 0.16, 0.23);",
        "  gl_FragColor = vec4(r > 0.7 ? vec3(0.05) : c, 1.0);",
        "}"
      ].join("\n")
    });
  };
  var offsetGeometry = null;
  if (data.offsets) {
    offsetGeometry = new THREE.BufferGeometry();
    offsetGeometry.setAttribute("position", new THREE.BufferAttribute(f32(data.offsets.points), 3));
    offsetGeometry.setAttribute("dist", new THREE.BufferAttribute(f32(data.offsets.distance), 1));
  }
  netPoints.setAttribute("dist", new THREE.BufferAttribute(new Float32Array(net.nu * net.nv), 1));

  // ---- scene: the starboard half and its mirror image in y = 0 ----------------------------
  function half() {
    var g = new THREE.Group();
    g.add(new THREE.Mesh(geometry, surfaceMaterial));
    var n = new THREE.Group();
    n.add(new THREE.LineSegments(netGeometry, netMaterial));
    n.add(new THREE.Points(netPoints, pointMaterial(false)));
    g.add(n);
    var o = offsetGeometry ? new THREE.Points(offsetGeometry, pointMaterial(true)) : new THREE.Group();
    g.add(o);
    return { group: g, net: n, offsets: o };
  }
  var starboard = half(), port = half();
  port.group.scale.set(1, -1, 1);
  var scene = new THREE.Scene();
  scene.background = new THREE.Color(0xe9edf2);
  scene.add(starboard.group, port.group);

  var renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
  renderer.setPixelRatio(window.devicePixelRatio || 1);
  var view = document.getElementById("view");
  function viewSize() { return [Math.max(view.clientWidth, 1), Math.max(view.clientHeight, 1)]; }
  renderer.setSize(viewSize()[0], viewSize()[1]);
  view.appendChild(renderer.domElement);
  var camera = new THREE.PerspectiveCamera(30, viewSize()[0] / viewSize()[1], 0.1, 1000);
  camera.up.set(0, 0, 1);
  var controls = new THREE.OrbitControls(camera, renderer.domElement);

  // ---- state and UI -----------------------------------------------------------------------
  var el = function (id) { return document.getElementById(id); };
  var state = { field: initial.field, contrast: 0 };
  var fieldSelect = el("field");
  Object.keys(data.fields).concat(["none"]).forEach(function (k) {
    var opt = document.createElement("option");
    opt.value = k;
    opt.textContent = k === "none" ? "None (grey)" : data.fields[k].label;
    fieldSelect.appendChild(opt);
  });
  fieldSelect.value = state.field;
  el("zebra").checked = initial.zebra;
  el("net").checked = initial.net;
  el("offsets").checked = initial.offsets;
  el("offsets").disabled = !data.offsets;
  el("mirror").checked = initial.mirror;
  el("title").textContent = data.title;
  el("axes-units").textContent = data.units;
  if (bare) document.body.classList.add("bare");
  if (data.offsets) {
    el("offsets-bar").style.background = "linear-gradient(to right, " + data.colormaps.sequential.join(", ") + ")";
    el("offsets-legend").querySelector(".unit").textContent = data.units;
    ticks(el("offsets-ticks"), 0, data.offsets.max, false, false);
  }
  data.particulars.forEach(function (row) {
    var tr = document.createElement("tr");
    row.forEach(function (cell) {
      var td = document.createElement("td");
      td.textContent = cell;
      tr.appendChild(td);
    });
    el("particulars").appendChild(tr);
  });

  // Labels at the ends and the middle of a colour bar; a clipped end says so.
  function ticks(box, lo, hi, clipLo, clipHi) {
    box.textContent = "";
    [0, 0.5, 1].forEach(function (p) {
      var s = document.createElement("span");
      s.style.left = 100 * p + "%";
      s.className = p === 0 ? "first" : p === 1 ? "last" : "";
      var x = lo + p * (hi - lo);
      s.textContent = (p === 0 && clipLo ? "\u2264 " : p === 1 && clipHi ? "\u2265 " : "") + fmt(x);
      box.appendChild(s);
    });
  }

  function applyField() {
    var u = surfaceMaterial.uniforms, f = data.fields[state.field], zebra = el("zebra").checked;
    // The markers' own scale, unless the surface shows the same one.
    el("offsets-legend").hidden = !(data.offsets && el("offsets").checked) || (state.field === "error" && !zebra);
    var legend = el("legend");
    u.mode.value = zebra ? 2 : f ? 0 : 1;
    legend.classList.toggle("hidden-field", !f || zebra);
    if (!f) {
      el("legend-title").textContent = zebra ? "Zebra stripes" : "No field";
      el("legend-note").textContent = zebra ? "Reflection lines: on a fair surface they run smoothly." : "";
      return;
    }
    if (zebra) {
      el("legend-title").textContent = "Zebra stripes";
      el("legend-note").textContent =
        "Reflection lines: on a fair surface they run smoothly; a kink or wiggle marks a flaw.";
      return;
    }
    var stops = data.colormaps[f.map];
    var scale = Math.pow(2, -state.contrast);
    var lo = f.lo * scale, hi = f.hi * scale;
    u.stops.value = stops.map(rgb);
    u.lo.value = lo;
    u.hi.value = hi;
    var attr = geometry.getAttribute("value");
    attr.array.set(fieldValues[state.field]);
    attr.needsUpdate = true;
    el("legend-title").textContent = f.label + " " + f.symbol + " (" + f.unit + ")";
    el("legend-bar").style.background = "linear-gradient(to right, " + stops.join(", ") + ")";
    ticks(el("legend-ticks"), lo, hi, f.min < lo, f.max > hi);
    el("legend-note").textContent = f.note + " Range " + fmt(f.min) + " .. " + fmt(f.max) + " " + f.unit + ".";
  }

  function applyVisibility() {
    var mirror = el("mirror").checked;
    port.group.visible = mirror;
    [starboard, port].forEach(function (h) {
      h.net.visible = el("net").checked;
      h.offsets.visible = el("offsets").checked;
    });
  }

  // The box of the hull as shown (both halves when mirrored).
  function hullBox() {
    var box = new THREE.Box3().setFromObject(starboard.group.children[0]);
    if (port.group.visible) box.union(new THREE.Box3().setFromObject(port.group.children[0]));
    return box;
  }

  // The hull's vertices as drawn (both halves when mirrored), every `step`-th one.
  function hullPoints(step) {
    var pts = [], mirror = port.group.visible;
    for (var k = 0; k < positions.length; k += 3 * step) {
      pts.push(new THREE.Vector3(positions[k], positions[k + 1], positions[k + 2]));
      if (mirror) pts.push(new THREE.Vector3(positions[k], -positions[k + 1], positions[k + 2]));
    }
    return pts;
  }

  // A three-quarter view of the bow from forward, starboard and above the waterline (as a
  // naval architect looks at a model), centred on the hull's picture and at the distance where
  // the hull fills `FILL` of the picture's width or height.
  var VIEW_DIR = new THREE.Vector3(1.2, 1.0, 0.3).normalize(), FILL = 0.86;
  function frame() {
    var pts = hullPoints(2), centre = hullBox().getCenter(new THREE.Vector3());
    var dir = VIEW_DIR, fwd = dir.clone().negate();
    var right = new THREE.Vector3().crossVectors(fwd, camera.up).normalize();
    var up = new THREE.Vector3().crossVectors(right, fwd);
    var tanV = Math.tan((camera.fov * Math.PI) / 360), tanH = tanV * camera.aspect, dist = 0, c = new THREE.Vector3();
    // Distance, then a sideways shift that centres the picture; the shift changes the distance a
    // little, so repeat (three rounds leave well under a pixel).
    for (var round = 0; round < 4; round++) {
      dist = 0;
      pts.forEach(function (p) {
        c.subVectors(p, centre);
        var depth = c.dot(dir);
        var needH = Math.abs(c.dot(right)) / (FILL * tanH), needV = Math.abs(c.dot(up)) / (FILL * tanV);
        dist = Math.max(dist, depth + needH, depth + needV);
      });
      var x0 = Infinity, x1 = -Infinity, y0 = Infinity, y1 = -Infinity;
      pts.forEach(function (p) {
        c.subVectors(p, centre);
        var z = dist - c.dot(dir), x = c.dot(right) / (z * tanH), y = c.dot(up) / (z * tanV);
        x0 = Math.min(x0, x); x1 = Math.max(x1, x); y0 = Math.min(y0, y); y1 = Math.max(y1, y);
      });
      centre.addScaledVector(right, 0.5 * (x0 + x1) * dist * tanH).addScaledVector(up, 0.5 * (y0 + y1) * dist * tanV);
    }
    camera.position.copy(centre).addScaledVector(dir, dist);
    camera.near = dist / 100;
    camera.far = dist * 10;
    camera.updateProjectionMatrix();
    controls.target.copy(centre);
    controls.update();
  }

  function render() { renderer.render(scene, camera); }

  // Until the user moves the camera, a new window size frames the hull anew.
  var moved = false;
  function onResize() {
    var size = viewSize();
    camera.aspect = size[0] / size[1];
    camera.updateProjectionMatrix();
    renderer.setSize(size[0], size[1]);
    if (!moved) frame();
    render();
  }

  fieldSelect.addEventListener("change", function () { state.field = fieldSelect.value; applyField(); render(); });
  ["zebra"].forEach(function (id) { el(id).addEventListener("change", function () { applyField(); render(); }); });
  el("zebra-axis").addEventListener("change", function () {
    var v = el("zebra-axis").value;
    surfaceMaterial.uniforms.zebraAxis.value.set(v === "x" ? 1 : 0, v === "y" ? 1 : 0, v === "z" ? 1 : 0);
    render();
  });
  el("zebra-count").addEventListener("input", function () {
    surfaceMaterial.uniforms.zebraCount.value = Number(el("zebra-count").value);
    render();
  });
  el("contrast").addEventListener("input", function () {
    state.contrast = Number(el("contrast").value);
    applyField();
    render();
  });
  ["net", "offsets"].forEach(function (id) {
    el(id).addEventListener("change", function () { applyVisibility(); applyField(); render(); });
  });
  el("mirror").addEventListener("change", function () { applyVisibility(); frame(); render(); });
  el("reset").addEventListener("click", function () { moved = false; frame(); render(); });
  window.addEventListener("keydown", function (e) {
    if ((e.key === "h" || e.key === "H") && e.target.tagName !== "INPUT" && e.target.tagName !== "SELECT") {
      document.body.classList.toggle("bare");
      onResize();
    }
  });
  controls.addEventListener("change", render);
  controls.addEventListener("start", function () { moved = true; });
  window.addEventListener("resize", onResize);

  applyField();
  applyVisibility();
  frame();
  render();

  // What a test reads from the DOM once the first frame is drawn.
  var box = hullBox();
  status.setAttribute("data-triangles", String(renderer.info.render.triangles));
  status.setAttribute("data-vertices", String(nu * nv));
  var corners = [box.min.x, box.min.y, box.min.z, box.max.x, box.max.y, box.max.z];
  status.setAttribute("data-box", corners.map(function (x) { return x.toFixed(3); }).join(" "));
  status.setAttribute("data-field", state.field);
  var eye = [camera.position.x, camera.position.y, camera.position.z, controls.target.x, controls.target.y, controls.target.z];
  status.setAttribute("data-camera", eye.map(function (x) { return x.toFixed(3); }).join(" "));
  status.setAttribute("data-resources", String(performance.getEntriesByType("resource").length));
  if (!log.errors.length) status.setAttribute("data-state", "ok");
  status.textContent = log.errors.length ? "errors" : "ok " + renderer.info.render.triangles + " triangles";
  log.show();
})();
