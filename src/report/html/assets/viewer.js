// surfkit's report viewer: WebGL 2, no dependency. Reads the page model embedded in
// #surfkit-data (see src/report/html/page.rs), draws each view's mesh with its overlays,
// fills the side panel, and exposes `window.surfkit` (camera, select, frame timing) so that
// tests and users' scripts can drive it.
"use strict";
(function () {
  const data = JSON.parse(document.getElementById("surfkit-data").textContent);
  const page = data.page;
  const surfkit = { ready: false, page, camera: null, views: [], select: null, measureFrameTime: null };
  window.surfkit = surfkit;

  // ---- decoding -------------------------------------------------------------------------
  function bytes(b64) {
    const s = atob(b64 || "");
    const out = new Uint8Array(s.length);
    for (let i = 0; i < s.length; i++) out[i] = s.charCodeAt(i);
    return out;
  }
  const f32 = (b64) => new Float32Array(bytes(b64).buffer);
  const u32 = (b64) => new Uint32Array(bytes(b64).buffer);
  const rgb = (c) => `rgb(${c[0]},${c[1]},${c[2]})`;
  const el = (tag, props, ...children) => {
    const e = document.createElement(tag);
    Object.assign(e, props || {});
    for (const c of children) e.append(c);
    return e;
  };

  // Polygons fanned into triangles, and the first triangle of every polygon (so that a
  // face id names its triangles for highlights).
  function triangulate(mesh) {
    const indices = u32(mesh.indices);
    const faces = mesh.faces;
    const offsets = mesh.arity === null ? u32(mesh.offsets) : null;
    const start = offsets ? (f) => offsets[f] : (f) => f * mesh.arity;
    if (mesh.arity === 3) {
      return { triangles: indices, firstTriangle: (f) => f };
    }
    let count = 0;
    for (let f = 0; f < faces; f++) count += Math.max(start(f + 1) - start(f) - 2, 0);
    const triangles = new Uint32Array(3 * count);
    const first = new Uint32Array(faces + 1);
    let t = 0;
    for (let f = 0; f < faces; f++) {
      first[f] = t / 3;
      const s = start(f), n = start(f + 1) - s;
      for (let k = 1; k + 1 < n; k++) {
        triangles[t++] = indices[s];
        triangles[t++] = indices[s + k];
        triangles[t++] = indices[s + k + 1];
      }
    }
    first[faces] = t / 3;
    return { triangles, firstTriangle: (f) => first[f] };
  }

  function facesToTriangles(faceIds, tri, faceCount) {
    const out = [];
    for (const f of faceIds) {
      if (f >= faceCount) continue;
      for (let t = tri.firstTriangle(f); t < tri.firstTriangle(f + 1); t++) {
        out.push(tri.triangles[3 * t], tri.triangles[3 * t + 1], tri.triangles[3 * t + 2]);
      }
    }
    return new Uint32Array(out);
  }

  // Area-weighted vertex normals (smooth shading, isophotes).
  function vertexNormals(positions, triangles) {
    const n = new Float32Array(positions.length);
    for (let t = 0; t < triangles.length; t += 3) {
      const a = 3 * triangles[t], b = 3 * triangles[t + 1], c = 3 * triangles[t + 2];
      const ux = positions[b] - positions[a], uy = positions[b + 1] - positions[a + 1], uz = positions[b + 2] - positions[a + 2];
      const vx = positions[c] - positions[a], vy = positions[c + 1] - positions[a + 1], vz = positions[c + 2] - positions[a + 2];
      const nx = uy * vz - uz * vy, ny = uz * vx - ux * vz, nz = ux * vy - uy * vx;
      for (const i of [a, b, c]) { n[i] += nx; n[i + 1] += ny; n[i + 2] += nz; }
    }
    return n;
  }

  // ---- matrices (column-major) ----------------------------------------------------------
  function perspective(fovy, aspect, near, far) {
    const f = 1 / Math.tan(fovy / 2), nf = 1 / (near - far);
    return new Float32Array([f / aspect, 0, 0, 0, 0, f, 0, 0, 0, 0, (far + near) * nf, -1, 0, 0, 2 * far * near * nf, 0]);
  }
  const sub = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
  const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
  const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
  const normalize = (a) => { const l = Math.hypot(a[0], a[1], a[2]) || 1; return [a[0] / l, a[1] / l, a[2] / l]; };
  function lookAt(eye, target, up) {
    const z = normalize(sub(eye, target)), x = normalize(cross(up, z)), y = cross(z, x);
    return new Float32Array([x[0], y[0], z[0], 0, x[1], y[1], z[1], 0, x[2], y[2], z[2], 0,
      -dot(x, eye), -dot(y, eye), -dot(z, eye), 1]);
  }

  // ---- camera: an orbit around a target, z up (as the PNG pictures) -----------------------
  const FOV = (35 * Math.PI) / 180;
  const radius = Math.max(...page.views.map((v) => v.radius), 1e-30);
  // The distance at which a sphere of radius r fills the narrowest view (vertically or
  // horizontally, whichever field of view is smaller).
  function fitDistance(r) {
    let half = FOV / 2;
    for (const v of surfkit.views) {
      const aspect = v.canvas.clientWidth / Math.max(v.canvas.clientHeight, 1);
      if (aspect > 0) half = Math.min(half, Math.atan(Math.tan(FOV / 2) * aspect));
    }
    return r / Math.sin(half);
  }
  function homeCamera() {
    const [azimuth, elevation] = page.initial_view;
    return { target: [0, 0, 0], distance: 1.1 * fitDistance(radius), yaw: (azimuth * Math.PI) / 180, pitch: (elevation * Math.PI) / 180 };
  }
  const camera = { target: [0, 0, 0], distance: 1, yaw: 0, pitch: 0 };
  surfkit.camera = camera;
  function eye() {
    const c = Math.cos(camera.pitch);
    return [camera.target[0] + camera.distance * c * Math.cos(camera.yaw),
      camera.target[1] + camera.distance * c * Math.sin(camera.yaw),
      camera.target[2] + camera.distance * Math.sin(camera.pitch)];
  }

  // ---- GL -------------------------------------------------------------------------------
  const VERTEX = `#version 300 es
  in vec3 position; in vec3 normal; in float t;
  uniform mat4 projection, modelView; uniform float pointSize, depthBias;
  out vec3 viewPosition; out vec3 viewNormal; out float colourT;
  void main() {
    vec4 p = modelView * vec4(position, 1.0);
    viewPosition = p.xyz; viewNormal = mat3(modelView) * normal; colourT = t;
    gl_Position = projection * p;
    gl_Position.z -= depthBias * gl_Position.w;
    gl_PointSize = pointSize;
  }`;
  const FRAGMENT = `#version 300 es
  precision highp float;
  in vec3 viewPosition; in vec3 viewNormal; in float colourT;
  uniform int lit, smoothNormals, byQuality, stripes; uniform vec3 colour; uniform float alpha;
  uniform sampler2D lut;
  out vec4 fragColour;
  void main() {
    if (lit == 0) { fragColour = vec4(colour, alpha); return; }
    vec3 n = smoothNormals == 1 ? normalize(viewNormal) : normalize(cross(dFdx(viewPosition), dFdy(viewPosition)));
    vec3 v = normalize(-viewPosition);
    if (dot(n, v) < 0.0) n = -n;
    vec3 base = colour;
    if (byQuality == 1) base = colourT < -0.5 ? vec3(0.55) : texture(lut, vec2(clamp(colourT, 0.0, 1.0) * (255.0 / 256.0) + 0.5 / 256.0, 0.5)).rgb;
    vec3 light = normalize(vec3(0.35, 0.55, 1.0));
    vec3 c = base * (0.3 + 0.7 * max(dot(n, light), 0.0));
    if (stripes == 1) c *= mix(0.2, 1.0, step(0.5, fract(12.0 * dot(n, light))));
    if (stripes == 2) { vec3 r = reflect(-v, n); c *= mix(0.2, 1.0, step(0.5, fract(6.0 * r.y))); }
    fragColour = vec4(c, alpha);
  }`;

  function compile(gl, type, source) {
    const s = gl.createShader(type);
    gl.shaderSource(s, source);
    gl.compileShader(s);
    if (!gl.getShaderParameter(s, gl.COMPILE_STATUS)) throw new Error("shader: " + gl.getShaderInfoLog(s));
    return s;
  }
  function program(gl) {
    const p = gl.createProgram();
    gl.attachShader(p, compile(gl, gl.VERTEX_SHADER, VERTEX));
    gl.attachShader(p, compile(gl, gl.FRAGMENT_SHADER, FRAGMENT));
    gl.bindAttribLocation(p, 0, "position");
    gl.bindAttribLocation(p, 1, "normal");
    gl.bindAttribLocation(p, 2, "t");
    gl.linkProgram(p);
    if (!gl.getProgramParameter(p, gl.LINK_STATUS)) throw new Error("program: " + gl.getProgramInfoLog(p));
    const u = {};
    for (const name of ["projection", "modelView", "pointSize", "depthBias", "lit", "smoothNormals", "byQuality", "stripes", "colour", "alpha", "lut"]) {
      u[name] = gl.getUniformLocation(p, name);
    }
    return { p, u };
  }
  function newBuffer(gl, target, array) {
    const b = gl.createBuffer();
    gl.bindBuffer(target, b);
    gl.bufferData(target, array, gl.STATIC_DRAW);
    return b;
  }
  // A vertex array of positions (and normals, colour coordinates when given), with an
  // optional element buffer; buffers it creates are listed in `owned` when given (so that
  // a temporary overlay can free them).
  function vertexArray(gl, positions, normals, ts, elements, owned) {
    const vao = gl.createVertexArray();
    const buffer = (target, array) => {
      if (array instanceof WebGLBuffer) return array; // shared with the mesh
      const b = newBuffer(gl, target, array);
      if (owned) owned.push(b);
      return b;
    };
    gl.bindVertexArray(vao);
    gl.bindBuffer(gl.ARRAY_BUFFER, buffer(gl.ARRAY_BUFFER, positions));
    gl.enableVertexAttribArray(0);
    gl.vertexAttribPointer(0, 3, gl.FLOAT, false, 0, 0);
    if (normals) {
      gl.bindBuffer(gl.ARRAY_BUFFER, buffer(gl.ARRAY_BUFFER, normals));
      gl.enableVertexAttribArray(1);
      gl.vertexAttribPointer(1, 3, gl.FLOAT, false, 0, 0);
    } else gl.vertexAttrib3f(1, 0, 0, 1);
    if (ts) {
      gl.bindBuffer(gl.ARRAY_BUFFER, buffer(gl.ARRAY_BUFFER, ts));
      gl.enableVertexAttribArray(2);
      gl.vertexAttribPointer(2, 1, gl.FLOAT, false, 0, 0);
    } else gl.vertexAttrib1f(2, -1);
    if (elements) buffer(gl.ELEMENT_ARRAY_BUFFER, elements);
    gl.bindVertexArray(null);
    return vao;
  }

  // Frame time (ms) above which a view draws a subset of its triangles while moving.
  const MOVING_BUDGET = 40;
  const bar = page.colour_bar;
  const range = bar ? bar.range : null;
  let stripes = 0;
  let moving = false, restTimer = 0;

  function makeView(spec, container) {
    const box = el("div", { className: "view" });
    const canvas = el("canvas", {});
    box.append(canvas, el("div", { className: "name", textContent: spec.name }));
    container.append(box);
    const gl = canvas.getContext("webgl2", { antialias: true, preserveDrawingBuffer: true });
    if (!gl) throw new Error("this browser has no WebGL 2: the report's views cannot be drawn");
    const prog = program(gl);
    const positions = f32(spec.mesh.positions);
    const tri = triangulate(spec.mesh);
    const smooth = page.shading === "smooth";
    const normals = smooth ? vertexNormals(positions, tri.triangles) : null;
    let ts = null;
    if (spec.mesh.quality && range) {
      const q = f32(spec.mesh.quality);
      ts = new Float32Array(q.length);
      const span = range[1] - range[0] || 1;
      for (let i = 0; i < q.length; i++) ts[i] = Number.isFinite(q[i]) ? (q[i] - range[0]) / span : -1;
    }
    // the mesh's vertex buffers, shared by its highlights and the selection
    const shared = {
      positions: newBuffer(gl, gl.ARRAY_BUFFER, positions),
      normals: normals ? newBuffer(gl, gl.ARRAY_BUFFER, normals) : null,
      ts: ts ? newBuffer(gl, gl.ARRAY_BUFFER, ts) : null,
    };
    const mesh = vertexArray(gl, shared.positions, shared.normals, shared.ts, tri.triangles);
    const triangleCount = tri.triangles.length / 3;
    // While the camera moves, a view whose full frame took more than MOVING_BUDGET ms
    // draws every k-th triangle (k chosen from that time), and the whole mesh once it rests.
    let coarse = null, fullFrameMs = 0;
    function buildCoarse(step) {
      const picked = new Uint32Array(3 * Math.ceil(triangleCount / step));
      let k = 0;
      for (let t = 0; t < triangleCount; t += step) { picked[k++] = tri.triangles[3 * t]; picked[k++] = tri.triangles[3 * t + 1]; picked[k++] = tri.triangles[3 * t + 2]; }
      coarse = { vao: vertexArray(gl, shared.positions, shared.normals, shared.ts, picked.subarray(0, k)), count: k, step };
    }
    const lut = gl.createTexture();
    gl.bindTexture(gl.TEXTURE_2D, lut);
    const lutBytes = new Uint8Array(256 * 3);
    data.colour_map.forEach((c, i) => lutBytes.set(c, 3 * i));
    gl.pixelStorei(gl.UNPACK_ALIGNMENT, 1);
    gl.texImage2D(gl.TEXTURE_2D, 0, gl.RGB8, 256, 1, 0, gl.RGB, gl.UNSIGNED_BYTE, lutBytes);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MIN_FILTER, gl.LINEAR);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MAG_FILTER, gl.LINEAR);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_WRAP_S, gl.CLAMP_TO_EDGE);

    const overlays = [];
    const overlay = (name, kind, colour, vao, count) => overlays.push({ name, kind, colour: colour.map((c) => c / 255), vao, count, visible: true });
    for (const h of spec.highlights) {
      const idx = facesToTriangles(u32(h.faces), tri, spec.mesh.faces);
      overlay(h.name, "faces", h.colour, vertexArray(gl, shared.positions, shared.normals, null, idx), idx.length);
    }
    for (const l of spec.lines) {
      const p = f32(l.segments);
      overlay(l.name, "lines", l.colour, vertexArray(gl, p, null, null, null), p.length / 3);
    }
    for (const pt of spec.points) {
      const p = f32(pt.positions);
      overlay(pt.name, "points", pt.colour, vertexArray(gl, p, null, null, null), p.length / 3);
      overlays[overlays.length - 1].size = pt.size;
    }
    let selection = [];
    let selectionBuffers = [];

    function resize() {
      const dpr = window.devicePixelRatio || 1;
      const w = Math.max(1, Math.round(canvas.clientWidth * dpr)), h = Math.max(1, Math.round(canvas.clientHeight * dpr));
      if (canvas.width !== w || canvas.height !== h) { canvas.width = w; canvas.height = h; }
    }
    function draw(full) {
      resize();
      gl.viewport(0, 0, canvas.width, canvas.height);
      gl.clearColor(48 / 255, 48 / 255, 54 / 255, 1);
      gl.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT);
      gl.enable(gl.DEPTH_TEST);
      gl.depthFunc(gl.LEQUAL);
      gl.useProgram(prog.p);
      const u = prog.u;
      const near = Math.max(camera.distance - 2.5 * radius, camera.distance * 1e-3);
      gl.uniformMatrix4fv(u.projection, false, perspective(FOV, canvas.width / canvas.height, near, camera.distance + 2.5 * radius));
      gl.uniformMatrix4fv(u.modelView, false, lookAt(eye(), camera.target, [0, 0, 1]));
      gl.uniform1i(u.smoothNormals, smooth ? 1 : 0);
      gl.uniform1i(u.stripes, stripes);
      gl.uniform1f(u.pointSize, 7 * (window.devicePixelRatio || 1));
      gl.uniform1f(u.depthBias, 0);
      gl.uniform1f(u.alpha, 1);
      gl.uniform1i(u.lut, 0);
      gl.activeTexture(gl.TEXTURE0);
      gl.bindTexture(gl.TEXTURE_2D, lut);
      // the mesh
      gl.uniform1i(u.lit, 1);
      gl.uniform1i(u.byQuality, ts ? 1 : 0);
      gl.uniform3f(u.colour, 0.72, 0.72, 0.76);
      gl.enable(gl.POLYGON_OFFSET_FILL);
      gl.polygonOffset(1, 1);
      if (coarse && !full) { gl.bindVertexArray(coarse.vao); gl.drawElements(gl.TRIANGLES, coarse.count, gl.UNSIGNED_INT, 0); }
      else { gl.bindVertexArray(mesh); gl.drawElements(gl.TRIANGLES, tri.triangles.length, gl.UNSIGNED_INT, 0); }
      gl.disable(gl.POLYGON_OFFSET_FILL);
      gl.uniform1i(u.byQuality, 0);
      // highlighted faces in front of the mesh (polygon offset), then lines and points:
      // first dimmed through the surface (flaws hidden inside), then depth-tested.
      const all = overlays.concat(selection);
      for (const o of all) {
        if (!o.visible || o.kind !== "faces" || !o.count) continue;
        gl.uniform3fv(u.colour, o.colour);
        gl.bindVertexArray(o.vao);
        gl.drawElements(gl.TRIANGLES, o.count, gl.UNSIGNED_INT, 0);
      }
      gl.uniform1i(u.lit, 0);
      gl.uniform1f(u.depthBias, 2e-4);
      gl.enable(gl.BLEND);
      gl.blendFunc(gl.SRC_ALPHA, gl.ONE_MINUS_SRC_ALPHA);
      for (const pass of [0, 1]) {
        if (pass === 0) { gl.disable(gl.DEPTH_TEST); gl.uniform1f(u.alpha, 0.3); } else { gl.enable(gl.DEPTH_TEST); gl.uniform1f(u.alpha, 1); }
        for (const o of all) {
          if (!o.visible || o.kind === "faces" || !o.count) continue;
          gl.uniform3fv(u.colour, o.colour);
          gl.uniform1f(u.pointSize, (o.size || 7) * (window.devicePixelRatio || 1));
          gl.bindVertexArray(o.vao);
          gl.drawArrays(o.kind === "lines" ? gl.LINES : gl.POINTS, 0, o.count);
        }
      }
      gl.disable(gl.BLEND);
      gl.bindVertexArray(null);
    }
    function select(flaw) {
      for (const o of selection) gl.deleteVertexArray(o.vao);
      for (const b of selectionBuffers) gl.deleteBuffer(b);
      selection = [];
      selectionBuffers = [];
      if (!flaw) return;
      const owned = selectionBuffers;
      const yellow = [255, 216, 74].map((c) => c / 255);
      if (flaw.faces.length) {
        const idx = facesToTriangles(flaw.faces, tri, spec.mesh.faces);
        selection.push({ kind: "faces", colour: yellow, vao: vertexArray(gl, shared.positions, shared.normals, null, idx, owned), count: idx.length, visible: true });
      }
      const vs = flaw.vertices.filter((v) => v < spec.mesh.vertices);
      const pts = new Float32Array(3 * vs.length);
      vs.forEach((v, i) => pts.set(positions.subarray(3 * v, 3 * v + 3), 3 * i));
      selection.push({ kind: "points", colour: yellow, vao: vertexArray(gl, pts, null, null, null, owned), count: vs.length, visible: true });
      if (flaw.closed_loop && vs.length > 2) {
        const seg = new Float32Array(6 * vs.length);
        vs.forEach((v, i) => { seg.set(positions.subarray(3 * v, 3 * v + 3), 6 * i); const w = vs[(i + 1) % vs.length]; seg.set(positions.subarray(3 * w, 3 * w + 3), 6 * i + 3); });
        selection.push({ kind: "lines", colour: yellow, vao: vertexArray(gl, seg, null, null, null, owned), count: 2 * vs.length, visible: true });
      }
    }
    function setVisible(name, visible) { for (const o of overlays) if (o.name === name) o.visible = visible; }
    function finish() { const px = new Uint8Array(4); gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, px); }
    // The first full frame, waited for: what the GPU (or software renderer) takes.
    function calibrate() {
      const t0 = performance.now();
      draw(true);
      finish();
      fullFrameMs = performance.now() - t0;
      if (fullFrameMs > MOVING_BUDGET && triangleCount > 20000) buildCoarse(Math.ceil((2 * fullFrameMs) / MOVING_BUDGET));
    }
    attachControls(canvas);
    new ResizeObserver(() => requestDraw()).observe(canvas);
    return { spec, canvas, draw, select, setVisible, finish, calibrate, triangleCount,
      get fullFrameMs() { return fullFrameMs; }, get movingStep() { return coarse ? coarse.step : 1; } };
  }

  // ---- interaction ----------------------------------------------------------------------
  let pending = false;
  function requestDraw() {
    if (pending) return;
    pending = true;
    requestAnimationFrame(() => {
      pending = false;
      if (!surfkit.ready) {
        for (const v of surfkit.views) v.calibrate();
        surfkit.ready = true;
        document.body.dataset.ready = "true";
      } else for (const v of surfkit.views) v.draw(!moving);
    });
  }
  function moved() {
    moving = true;
    clearTimeout(restTimer);
    restTimer = setTimeout(() => { moving = false; requestDraw(); }, 200);
    requestDraw();
  }
  function attachControls(canvas) {
    let last = null, pan = false;
    canvas.addEventListener("contextmenu", (e) => e.preventDefault());
    canvas.addEventListener("pointerdown", (e) => {
      canvas.setPointerCapture(e.pointerId);
      last = [e.clientX, e.clientY];
      pan = e.button === 2 || e.shiftKey;
    });
    canvas.addEventListener("pointerup", () => { last = null; });
    canvas.addEventListener("pointermove", (e) => {
      if (!last) return;
      const dx = e.clientX - last[0], dy = e.clientY - last[1];
      last = [e.clientX, e.clientY];
      if (pan) {
        const s = (2 * camera.distance * Math.tan(FOV / 2)) / canvas.clientHeight;
        const back = normalize(sub(eye(), camera.target)), right = normalize(cross([0, 0, 1], back)), up = cross(back, right);
        for (let i = 0; i < 3; i++) camera.target[i] += s * (-dx * right[i] + dy * up[i]);
      } else {
        camera.yaw -= dx * 0.008;
        camera.pitch = Math.max(-1.55, Math.min(1.55, camera.pitch + dy * 0.008));
      }
      moved();
    });
    canvas.addEventListener("wheel", (e) => {
      e.preventDefault();
      camera.distance *= Math.exp(e.deltaY * 0.0012);
      moved();
    }, { passive: false });
    canvas.addEventListener("dblclick", () => resetView());
  }
  function resetView() {
    Object.assign(camera, homeCamera());
    requestDraw();
  }

  // ---- side panel -----------------------------------------------------------------------
  function fillSummary() {
    const table = document.getElementById("summary");
    for (const [k, v] of page.summary) table.append(el("tr", {}, el("td", { textContent: k }), el("td", { textContent: v })));
    if (page.text) {
      const t = document.getElementById("text-report");
      t.hidden = false;
      t.querySelector("pre").textContent = page.text;
    }
    document.getElementById("generator").textContent = `written by ${data.generator}`;
  }
  function fillLegend() {
    const legend = document.getElementById("legend");
    for (const entry of page.legend) {
      const box = el("input", { type: "checkbox", checked: true });
      box.addEventListener("change", () => { for (const v of surfkit.views) v.setVisible(entry.name, box.checked); requestDraw(); });
      legend.append(el("label", { className: "entry" }, box, el("span", { className: "swatch", style: `background:${rgb(entry.colour)}` }),
        `${entry.name.replaceAll("_", " ")} (${entry.count})`));
    }
  }
  function showDetails(flaw) {
    const box = document.getElementById("flaw-details");
    box.hidden = false;
    box.replaceChildren(
      el("div", { className: "kind", textContent: `#${flaw.index} ${flaw.kind.replaceAll("_", " ")}` }),
      el("div", { className: "description", textContent: flaw.description }),
      el("div", { className: "fix", textContent: "fix: " + flaw.fix + (flaw.fix_verified === true ? " (checked by applying it)" : flaw.fix_verified === false ? " (applying it did NOT remove the flaw)" : "") }),
      el("div", { className: "elements", textContent: `at (${flaw.position.map((x, i) => (x + page.views[0].origin[i]).toPrecision(7)).join(", ")}); ` +
        `faces ${flaw.faces.slice(0, 12).join(" ")}${flaw.faces.length > 12 ? " …" : ""}; vertices ${flaw.vertices.slice(0, 12).join(" ")}${flaw.vertices.length > 12 ? " …" : ""}` }));
  }
  function fillFlaws() {
    if (!page.flaws.length) return;
    document.getElementById("flaws").hidden = false;
    document.getElementById("flaw-count").textContent = `(${page.flaws.length})`;
    const list = document.getElementById("flaw-list");
    const colours = Object.fromEntries(page.legend.map((l) => [l.name, l.colour]));
    const items = page.flaws.map((f) => {
      const li = el("li", {}, el("span", { className: "index", textContent: f.index }),
        el("span", { className: "swatch", style: `background:${rgb(colours[f.kind] || [200, 200, 200])}` }),
        el("span", { textContent: `${f.kind.replaceAll("_", " ")}: ${f.description}` }));
      li.dataset.flawIndex = f.index;
      li.addEventListener("click", () => select(f.index));
      return li;
    });
    list.append(...items);
  }
  function select(index) {
    const flaw = page.flaws.find((f) => f.index === index);
    if (!flaw) return;
    for (const li of document.querySelectorAll("#flaw-list li.selected")) li.classList.remove("selected");
    const li = document.querySelector(`#flaw-list li[data-flaw-index="${index}"]`);
    if (li) li.classList.add("selected");
    camera.target = flaw.position.slice();
    camera.distance = 1.6 * fitDistance(flaw.radius);
    for (const v of surfkit.views) v.select(flaw);
    showDetails(flaw);
    requestDraw();
  }
  surfkit.select = select;

  function fillColourBar() {
    if (!bar) return;
    const box = document.getElementById("colour-bar");
    box.hidden = false;
    box.querySelector(".quantity").textContent = bar.quantity;
    box.querySelector(".max").textContent = bar.max_label;
    box.querySelector(".min").textContent = bar.min_label;
    const canvas = box.querySelector("canvas");
    const ctx = canvas.getContext("2d");
    const rows = canvas.height;
    for (let row = 0; row < rows; row++) {
      const value = bar.max - ((bar.max - bar.min) * row) / (rows - 1);
      const t = Math.min(1, Math.max(0, (value - bar.range[0]) / (bar.range[1] - bar.range[0] || 1)));
      ctx.fillStyle = rgb(data.colour_map[Math.round(t * 255)]);
      ctx.fillRect(0, row, canvas.width, 1);
    }
  }

  // The optimization log: each series on one logarithmic axis.
  function fillPlot() {
    const plot = page.plot;
    if (!plot) return;
    const box = document.getElementById("plot");
    box.hidden = false;
    const NS = "http://www.w3.org/2000/svg";
    const svg = document.createElementNS(NS, "svg");
    const W = 800, H = 200, L = 60, R = 150, T = 22, B = 30;
    svg.setAttribute("viewBox", `0 0 ${W} ${H}`);
    svg.setAttribute("preserveAspectRatio", "none");
    const fy = plot.log_y ? (y) => Math.log10(y) : (y) => y;
    const pts = plot.series.flatMap((s) => s.x.map((x, i) => [x, s.y[i]])).filter(([, y]) => Number.isFinite(y) && (!plot.log_y || y > 0));
    if (!pts.length) return;
    const xs = pts.map((p) => p[0]), ys = pts.map((p) => fy(p[1]));
    const x0 = Math.min(...xs), x1 = Math.max(...xs, x0 + 1);
    let y0 = Math.min(...ys), y1 = Math.max(...ys);
    if (plot.log_y) { y0 = Math.floor(y0); y1 = Math.ceil(y1); }
    if (y1 <= y0) y1 = y0 + 1;
    const sx = (x) => L + ((x - x0) / (x1 - x0)) * (W - L - R), sy = (y) => H - B - ((y - y0) / (y1 - y0)) * (H - T - B);
    const add = (tag, attrs, text) => { const e = document.createElementNS(NS, tag); for (const k in attrs) e.setAttribute(k, attrs[k]); if (text !== undefined) e.textContent = text; svg.append(e); return e; };
    add("text", { x: L, y: 14 }, plot.title);
    add("line", { x1: L, y1: H - B, x2: W - R, y2: H - B, stroke: "#888" });
    add("line", { x1: L, y1: T, x2: L, y2: H - B, stroke: "#888" });
    const ticks = plot.log_y ? Math.min(y1 - y0, 12) : 4;
    for (let i = 0; i <= ticks; i++) {
      const y = y0 + ((y1 - y0) * i) / ticks;
      add("line", { x1: L - 4, y1: sy(y), x2: W - R, y2: sy(y), stroke: "#444" });
      add("text", { x: 4, y: sy(y) + 4 }, plot.log_y ? `1e${Math.round(y)}` : y.toPrecision(3));
    }
    add("text", { x: (L + W - R) / 2, y: H - 6 }, plot.x_label);
    add("text", { x: L - 4, y: H - B + 14 }, String(x0));
    add("text", { x: W - R - 10, y: H - B + 14 }, String(x1));
    plot.series.forEach((s, k) => {
      const d = s.x.map((x, i) => [x, s.y[i]]).filter(([, y]) => Number.isFinite(y) && (!plot.log_y || y > 0))
        .map(([x, y], i) => `${i ? "L" : "M"}${sx(x).toFixed(1)},${sy(fy(y)).toFixed(1)}`).join("");
      add("path", { d, fill: "none", stroke: rgb(s.colour), "stroke-width": 2 });
      add("rect", { x: W - R + 10, y: T + 16 * k, width: 10, height: 10, fill: rgb(s.colour) });
      add("text", { x: W - R + 26, y: T + 9 + 16 * k }, s.name);
    });
    box.append(svg);
  }

  // Median time of `frames` redraws of every view (as while the camera moves when
  // `moving`), each waited for (readPixels).
  surfkit.measureFrameTime = function (frames, moving) {
    const times = [];
    for (let i = 0; i < frames; i++) {
      camera.yaw += 0.01;
      const t0 = performance.now();
      for (const v of surfkit.views) { v.draw(!moving); v.finish(); }
      times.push(performance.now() - t0);
    }
    times.sort((a, b) => a - b);
    return times[Math.floor(times.length / 2)];
  };

  // ---- start ----------------------------------------------------------------------------
  fillSummary();
  fillLegend();
  fillFlaws();
  fillColourBar();
  fillPlot();
  document.getElementById("shading-mode").addEventListener("change", (e) => { stripes = Number(e.target.value); requestDraw(); });
  document.getElementById("reset-view").addEventListener("click", resetView);
  const container = document.getElementById("views");
  try {
    for (const spec of page.views) surfkit.views.push(makeView(spec, container));
    Object.assign(camera, homeCamera());
  } catch (err) {
    container.append(el("div", { className: "message", textContent: String(err.message || err) }));
    throw err;
  }
  requestDraw();
})();
