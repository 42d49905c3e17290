// web/page.js -- the page of `make web`: loads the module (web/web.c compiled to WebAssembly, embedded in the page
// in base64), builds the controls from the program's own tables (web_tables), renders a frame whenever a control
// changes and walks through the README's tutorial.
//
// A frame is a command line of the program: the page keeps its state as the program's options (the option names
// without "--", the values as the command line writes them), web_render parses the line with the program's option
// table, and the page shows the line: `build/instess LINE -o out.png` writes the same pixels (tests/web_test.mjs).
// The split view is two lines, the left half width/2 wide and the right half with the other patch, as `instess
// view`'s split screen.  What the program refuses (say, real normals on the CPU path) is refused here with its
// message, and the controls go back to the state shown.
//
// window.instess offers one function per control (setMesh, setPatch, ...), set(changes) for any of them,
// commands(), inspect(args, x, y, json) (the pipeline inspector: what `instess inspect` prints), and hooks:
// pixel(info) is called on a click with the pixel and the command line of its half (the click then shows the
// pixel's history under the canvas), frame(info) after every frame.
"use strict";
(function () {
  const $ = (id) => document.getElementById(id);
  const utf8 = new TextEncoder(), text = new TextDecoder("utf-8");
  let resolveReady, rejectReady;
  const api = {
    ready: new Promise((res, rej) => { resolveReady = res; rejectReady = rej; }),
    hooks: { pixel: null, frame: null },
  };
  window.instess = api;

  // ------------------------------------------------------------------ the module
  let ex = null, memory = null, ctx = 0;
  function cstr(p) {
    const b = new Uint8Array(memory.buffer);
    let q = p;
    while (b[q]) q++;
    return text.decode(b.subarray(p, q));
  }
  // f(pointer, length) with s (a string or bytes) copied into the module's memory, NUL-terminated
  function withBytes(s, f) {
    const b = typeof s === "string" ? utf8.encode(s) : s;
    const p = ex.web_alloc(b.length + 1);
    const m = new Uint8Array(memory.buffer, p, b.length + 1);
    m.set(b), m[b.length] = 0;
    try { return f(p, b.length); } finally { ex.web_free(p); }
  }

  // ------------------------------------------------------------------ state and command lines
  let tables = null, defaults = null, state = null;
  const objs = new Map();   // dropped OBJ name -> the reader's notes
  // The options the page sets, in the order its command lines list them.
  const ORDER = ["patch", "normals", "level", "instances", "grid", "path", "lod", "max-level", "lod-target", "lod-deviation",
                 "silhouette",                  "wire-levels", "fill", "light", "yaw", "pitch", "distance", "fov", "fit", "up", "cull",
                 "recompute-normals", "msaa", "size"];
  const FLAGS = new Set(["silhouette", "recompute-normals"]);
  const quote = (s) => /^[A-Za-z0-9._,#+=:@%\/-]+$/.test(s) ? s : "'" + s.replace(/'/g, "") + "'";

  // The command line of state s (overrides applied): the mesh, then each option whose value is not the program's
  // default; the level-of-detail options only with a --lod other than uniform (--lod-target only with screen,
  // --lod-deviation only with deviation), as the program requires.
  function lineOf(s, overrides) {
    s = Object.assign({}, s, overrides || {});
    const words = [quote(s.mesh)];
    for (const key of ORDER) {
      const v = s[key];
      const lodOnly = key === "max-level" || key === "silhouette" || key === "wire-levels" || key === "lod-target" ||
        key === "lod-deviation";
      if (lodOnly && s.lod === "uniform") continue;
      if (key === "lod-target" && s.lod !== "screen") continue;
      if (key === "lod-deviation" && s.lod !== "deviation") continue;
      if (FLAGS.has(key)) { if (v) words.push("--" + key); continue; }
      if (key === "wire-levels") { if (v) words.push("--wire-levels", "on"); continue; }
      if (key === "max-level") { words.push("--max-level", String(v)); continue; }
      if (String(v) === String(defaults[key])) continue;
      words.push("--" + key, quote(String(v)));
    }
    return words.join(" ");
  }
  // The parts of the canvas for state s: [{x, width, line}]
  function partsOf(s) {
    const [w, h] = s.size.split("x").map(Number);
    if (!s.split) return [{ x: 0, width: w, height: h, line: lineOf(s) }];
    const wl = Math.max(1, Math.floor(w / 2)), wr = Math.max(1, w - wl);
    return [{ x: 0, width: wl, height: h, line: lineOf(s, { size: wl + "x" + h }) },
            { x: wl, width: wr, height: h, line: lineOf(s, { size: wr + "x" + h, patch: s.other }) }];
  }
  api.commands = () => partsOf(state).map((p) => ({ x: p.x, width: p.width, height: p.height, args: p.line }));

  // ------------------------------------------------------------------ drawing
  const canvas = $("canvas"), g2d = canvas.getContext("2d");
  let lastFrame = null;
  // Render state s into the canvas; {ok, message, notes}.  Nothing is drawn unless every part rendered.
  function draw(s) {
    const parts = partsOf(s), t0 = performance.now(), stats = [];
    let notes = "";
    for (let k = 0; k < parts.length; k++) {
      const rc = withBytes(parts[k].line, (p) => ex.web_render(ctx, k, p));
      const n = cstr(ex.web_notes(ctx));
      if (n) notes += (notes ? "\n" : "") + n;
      if (rc !== 0) return { ok: false, message: cstr(ex.web_message(ctx)), notes };
      stats.push(JSON.parse(cstr(ex.web_stats(ctx, k))));
    }
    const w = parts.reduce((a, p) => a + p.width, 0), h = parts[0].height;
    if (canvas.width !== w || canvas.height !== h) canvas.width = w, canvas.height = h;
    for (let k = 0; k < parts.length; k++) {
      const p = parts[k], n = 4 * p.width * p.height;
      const px = new Uint8ClampedArray(memory.buffer, ex.web_frame(ctx, k), n);
      g2d.putImageData(new ImageData(new Uint8ClampedArray(px), p.width, p.height), p.x, 0);
    }
    const ms = performance.now() - t0;
    lastFrame = { ms, parts: parts.map((p, k) => Object.assign({ args: p.line, x: p.x, width: p.width }, stats[k])) };
    return { ok: true, notes };
  }

  function showFrame(s) {
    const f = lastFrame, sum = (key) => f.parts.reduce((a, p) => a + p[key], 0);
    $("status").innerHTML =
      `frame <b>${f.ms.toFixed(0)} ms</b> &middot; instess ${sum("render_ms").toFixed(0)} ms ` +
      `(shading + set-up ${sum("setup_ms").toFixed(0)}, raster ${sum("tile_ms").toFixed(0)}) &middot; ` +
      `resolve ${sum("resolve_ms").toFixed(0)} ms &middot; ${sum("triangles_drawn")} triangles drawn, ` +
      `${sum("vertices_shaded")} vertices shaded &middot; ` +
      `<span title="WebAssembly threads need SharedArrayBuffer, which a browser gives only to a page served with ` +
      `cross-origin isolation headers; a file opened from the disk has none. The image does not depend on the ` +
      `thread count.">${tables.threads} thread</span>`;
    $("command").textContent = f.parts.map((p) => "build/instess " + p.args + " -o " +
      (f.parts.length > 1 ? (p.x ? "right" : "left") : "out") + ".png").join("\n");
    $("view").style.width = Math.max(256, canvas.width) + "px";   /* the text under the image as wide as it */
    const split = f.parts.length > 1;
    $("divider").style.display = $("label-left").style.display = $("label-right").style.display = split ? "block" : "none";
    if (split) {
      const scale = canvas.clientWidth / canvas.width;
      $("divider").style.left = (f.parts[1].x * scale) + "px";
      $("label-left").textContent = s.patch, $("label-right").textContent = s.other;
      $("label-right").style.left = (f.parts[1].x * scale) + "px";
    }
    showStep(false);
    if (api.hooks.frame) api.hooks.frame(Object.assign({ state: Object.assign({}, s) }, f));
  }

  function showMessage(msg, error) {
    $("message").textContent = msg || "";
    $("message").className = error ? "error" : "";
  }

  // ------------------------------------------------------------------ changes
  let queued = null, waiters = [], scheduled = false;
  // Queue changes (option name -> value); the next animation frame renders them all at once.  The promise
  // resolves with {ok, message} when that frame is drawn (or refused).
  function set(changes) {
    queued = Object.assign(queued || {}, changes);
    if (!scheduled) scheduled = true, requestAnimationFrame(flush);
    return new Promise((res) => waiters.push(res));
  }
  function flush() {
    scheduled = false;
    const next = Object.assign({}, state, queued || {});
    queued = null;
    const done = waiters;
    waiters = [];
    let r;
    try {
      r = draw(next);
    } catch (e) {   // a trap in the module (out of memory, ...): say so, keep the state shown
      r = { ok: false, message: "the module stopped: " + e.message };
    }
    if (r.ok) state = next, showFrame(state);
    showMessage(r.ok ? r.notes || noteOf(state) : r.message + (r.notes ? "\n" + r.notes : ""), !r.ok);
    syncControls();
    for (const f of done) f({ ok: r.ok, message: r.ok ? "" : r.message });
  }
  api.set = set;
  api.state = () => Object.assign({}, state);
  api.frame = () => lastFrame;
  api.idle = () => (scheduled ? new Promise((res) => waiters.push(res)) : Promise.resolve({ ok: true }));
  const noteOf = (s) => objs.get(s.mesh) || "";

  // One function per control (hooks for what comes next; the tests drive these and the DOM controls alike).
  api.setMesh = (name) => set({ mesh: name });
  api.setPatch = (patch) => set({ patch });
  api.setLevel = (level) => set({ level: String(level) });
  api.setNormals = (normals) => set({ normals });
  api.setGrid = (grid) => set({ grid });
  api.setPath = (path) => set({ path });
  api.setFill = (fill) => set({ fill });
  api.setLight = (light) => set({ light });
  api.setLod = (lod, o = {}) => set(Object.assign({ lod },
    o.maxLevel !== undefined ? { "max-level": String(o.maxLevel) } : {},
    o.target !== undefined ? { "lod-target": String(o.target) } : {},
    o.deviation !== undefined ? { "lod-deviation": String(o.deviation) } : {},
    o.silhouette !== undefined ? { silhouette: !!o.silhouette } : {},
    o.wireLevels !== undefined ? { "wire-levels": !!o.wireLevels } : {}));
  api.setSplit = (on, other) => set(Object.assign({ split: !!on }, other ? { other } : {}));
  api.setCamera = (o) => set(Object.fromEntries(Object.entries(o).map(([k, v]) => [k, String(v)])));
  api.setSamples = (n) => set({ msaa: String(n) });
  api.setSize = (w, h) => set({ size: w + "x" + h });
  // Play the draw instance by instance (--instances 1, 2, ... up to the mesh's triangles, then the whole mesh):
  // `every` instances per frame, `ms` between frames; resolves when the playback ends (or is stopped).
  let playing = null;
  api.play = ({ every = 1, ms = 120 } = {}) => {
    if (playing) playing.stop = true;
    const run = { stop: false };
    playing = run;
    $("c-play").textContent = "stop";
    const n = lastFrame ? lastFrame.parts[0].mesh_triangles : 0;
    const wait = (t) => new Promise((res) => setTimeout(res, t));
    return (async () => {
      for (let k = 1; k < n && !run.stop; k += every) {
        const r = await set({ instances: String(k) });
        if (!r.ok) break;
        await wait(ms);
      }
      if (playing === run) playing = null, $("c-play").textContent = "play the draw";
      return set({ instances: "0" });
    })();
  };
  api.stop = () => { if (playing) playing.stop = true; };

  // A dropped OBJ: read (and checked) by the module at once; its name joins the mesh list.
  api.dropObj = (name, bytes) => {
    name = name.replace(/^.*[\\/]/, "");
    const rc = withBytes(name, (pn) => withBytes(bytes, (pd, len) => ex.web_drop_obj(ctx, pn, pd, len)));
    const notes = cstr(ex.web_notes(ctx));
    if (rc !== 0) {
      showMessage(cstr(ex.web_message(ctx)) + (notes ? "\n" + notes : ""), true);
      return Promise.resolve({ ok: false, message: cstr(ex.web_message(ctx)) });
    }
    objs.set(name, notes);
    if (![...$("c-mesh").options].some((o) => o.value === name)) $("c-mesh").add(new Option(name + " (dropped)", name));
    return set({ mesh: name, up: defaults.up }).then((r) => r);
  };

  // ------------------------------------------------------------------ controls
  const SELECTS = { mesh: "mesh", patch: "patch", normals: "normals", grid: "grid", path: "path", fill: "fill",
                    lod: "lod", cull: "cull", up: "up", fit: "fit", other: "patch" };
  const PAIRS = ["level", "max-level", "lod-target", "lod-deviation", "yaw", "pitch", "distance", "fov"];
  const CHECKS = { silhouette: "silhouette", "wire-levels": "wire-levels", "recompute-normals": "recompute",
                   split: "split" };
  function buildControls() {
    for (const [key, table] of Object.entries(SELECTS)) {
      const el = $("c-" + key);
      for (const name of tables[table]) el.add(new Option(name, name));
      el.addEventListener("change", () => set({ [key]: el.value }));
      if (tables.help[key]) el.title = tables.help[key];
    }
    for (const key of ["light", "msaa", "size"]) {
      $("c-" + key).addEventListener("change", () => set({ [key]: $("c-" + key).value }));
      if (tables.help[key]) $("c-" + key).title = tables.help[key];
    }
    for (const key of PAIRS) {
      const r = $("c-" + key), n = $("c-" + key + "-n");
      r.addEventListener("input", () => { n.value = r.value; set({ [key]: r.value }); });
      n.addEventListener("change", () => set({ [key]: n.value }));
      if (tables.help[key]) r.title = n.title = tables.help[key];
    }
    for (const [key, id] of Object.entries(CHECKS)) {
      $("c-" + id).addEventListener("change", () => set({ [key]: $("c-" + id).checked }));
      if (tables.help[key]) $("c-" + id).title = tables.help[key];
    }
    $("c-play").addEventListener("click", () => { if (playing) api.stop(); else api.play(); });
    // drag to orbit, the wheel to move the camera, a click to pick a pixel
    let drag = null;
    canvas.addEventListener("pointerdown", (e) => {
      drag = { x: e.clientX, y: e.clientY, yaw: +state.yaw, pitch: +state.pitch, moved: false };
      canvas.setPointerCapture(e.pointerId);
    });
    canvas.addEventListener("pointermove", (e) => {
      if (!drag) return;
      const dx = e.clientX - drag.x, dy = e.clientY - drag.y;
      if (Math.abs(dx) + Math.abs(dy) > 2) drag.moved = true;
      if (!drag.moved) return;
      let yaw = Math.round(drag.yaw - dx / 2);
      yaw = ((yaw + 540) % 360 + 360) % 360 - 180;
      const pitch = Math.max(-89, Math.min(89, Math.round(drag.pitch + dy / 2)));
      set({ yaw: String(yaw), pitch: String(pitch) });
    });
    canvas.addEventListener("pointerup", (e) => {
      const d = drag;
      drag = null;
      if (d && !d.moved) pick(e);
    });
    canvas.addEventListener("wheel", (e) => {
      e.preventDefault();
      const d = Math.max(1.1, Math.min(12, +state.distance * (e.deltaY > 0 ? 1.1 : 1 / 1.1)));
      set({ distance: d.toFixed(1) });
    }, { passive: false });
    // OBJ files: dropped anywhere, or chosen
    const readFile = (file) => file.arrayBuffer().then((b) => api.dropObj(file.name, new Uint8Array(b)));
    document.addEventListener("dragover", (e) => { e.preventDefault(); document.body.classList.add("dragging"); });
    document.addEventListener("dragleave", () => document.body.classList.remove("dragging"));
    document.addEventListener("drop", (e) => {
      e.preventDefault();
      document.body.classList.remove("dragging");
      const f = e.dataTransfer.files[0];
      if (f) api.dropping = readFile(f);
    });
    $("c-file").addEventListener("change", () => { if ($("c-file").files[0]) api.dropping = readFile($("c-file").files[0]); });
  }
  // The pixel under a click, in the canvas and in its half, with that half's command line: to the pixel hook.
  function pick(e) {
    const r = canvas.getBoundingClientRect();
    const x = Math.floor((e.clientX - r.left) * canvas.width / r.width), y = Math.floor((e.clientY - r.top) * canvas.height / r.height);
    const parts = lastFrame.parts, k = parts.length > 1 && x >= parts[1].x ? 1 : 0;
    const info = { x, y, part: k, partX: x - parts[k].x, args: parts[k].args,
                   rgba: Array.from(g2d.getImageData(x, y, 1, 1).data) };
    if (api.hooks.pixel) api.hooks.pixel(info);
    const h = api.inspect(info.args, info.partX, info.y);
    $("inspector").style.display = "block";
    $("inspector-title").textContent = h.ok ? `The pipeline inspector: pixel (${info.partX}, ${info.y}) -- ` +
      `build/instess inspect ${info.args} --pixel ${info.partX},${info.y}` : "The pipeline inspector";
    $("inspector-text").textContent = h.ok ? h.text : h.message;
  }
  // The history of pixel (x, y) of the render of args (one sample per pixel), as instess inspect prints it
  // (json: as its --json): {ok, text} or {ok: false, message}.
  api.inspect = (args, x, y, json) => {
    const p = withBytes(args, (a) => ex.web_inspect(ctx, a, x, y, json ? 1 : 0));
    return p ? { ok: true, text: cstr(p) } : { ok: false, message: cstr(ex.web_message(ctx)) };
  };
  // The controls show the state (after a change, or after a refusal put it back).
  function syncControls() {
    for (const key of Object.keys(SELECTS)) $("c-" + key).value = state[key];
    for (const key of ["light", "msaa", "size"]) $("c-" + key).value = state[key];
    for (const key of PAIRS) $("c-" + key).value = $("c-" + key + "-n").value = state[key];
    for (const [key, id] of Object.entries(CHECKS)) $("c-" + id).checked = !!state[key];
    const lod = state.lod !== "uniform";
    for (const id of ["max-level", "max-level-n", "silhouette", "wire-levels"]) $("c-" + id).disabled = !lod;
    $("c-lod-target").disabled = $("c-lod-target-n").disabled = state.lod !== "screen";
    $("c-lod-deviation").disabled = $("c-lod-deviation-n").disabled = state.lod !== "deviation";
    $("c-other").disabled = !state.split;
  }

  // ------------------------------------------------------------------ the tutorial (README, "The technique")
  const live = (s) => `<span class="live">${s}</span>`;
  const stat = (key) => lastFrame ? lastFrame.parts.reduce((a, p) => a + p[key], 0) : 0;
  const STEPS = [
    { title: "1. One triangle's grid, in stream 0",
      preset: { mesh: "tetrahedron", patch: "flat", level: "4", fill: "solid+wire" },
      html: () => `<p>The grid of level L has (L+1)(L+2)/2 points and L&sup2; triangles. Point (i, j) holds only
        its barycentric coordinates b = ((L&minus;i&minus;j)/L, i/L, j/L): the grid knows nothing about any mesh.
        Every coordinate is an integer over L, so the point mirrored along an edge holds the same floats swapped:
        the first ingredient of crack-free surfaces.</p>
        <p>Now: level ${live(state.level)}, ${live(stat("grid_points") / (lastFrame ? lastFrame.parts.length : 1))}
        points and ${live(stat("grid_triangles") / (lastFrame ? lastFrame.parts.length : 1))} triangles per mesh
        triangle. Move the level; try the grid <code>pg-fractional-odd</code> (the OpenGL&nbsp;4 / Direct3D&nbsp;11
        primitive generator's pattern) with a fractional level.</p>` },
    { title: "2. One instance per mesh triangle, in stream 1",
      preset: { mesh: "icosahedron", patch: "flat", level: "3", fill: "solid+wire", light: "normals" },
      html: () => `<p>Each mesh triangle becomes one record of Listing 1.1.2's layout in a second vertex buffer:</p>
        <table><tr><th>register</th><th>data</th></tr>
        <tr><td><code>POSITION0</code> (stream 0)</td><td>the grid point's barycentrics b</td></tr>
        <tr><td><code>TEXCOORD0..2</code></td><td>the triangle's vertices v0, v1, v2</td></tr>
        <tr><td><code>TEXCOORD3..5</code></td><td>its vertex normals n0, n1, n2</td></tr>
        <tr><td><code>TEXCOORD6..8</code></td><td>the vertex opposite each edge, across it</td></tr>
        <tr><td><code>TEXCOORD9..11</code></td><td>texture coordinates t0, t1, t2</td></tr>
        <tr><td><code>TEXCOORD12</code></td><td>the triangle's index</td></tr></table>
        <p>The opposite vertices come from adjacency (welding by exact position, then an edge map). A boundary
        edge gets the triangle's own third vertex: the smoothed patch then falls back to the N-Patch there.
        This mesh has ${live(stat("mesh_triangles") / (lastFrame ? lastFrame.parts.length : 1))} triangles: as
        many instances of the one grid.</p>` },
    { title: "3. Stream frequencies: the draw call",
      preset: { mesh: "cube", patch: "smooth", level: "8", fill: "solid+wire" },
      html: () => `<pre>dev_set_stream_source(dev, 0, grid_vb, 0, sizeof(float3));
dev_set_stream_source(dev, 1, instance_vb, 0, sizeof(is_patch_instance));
dev_set_stream_source_freq(dev, 0, IS_STREAMSOURCE_INDEXEDDATA | n_triangles);
dev_set_stream_source_freq(dev, 1, IS_STREAMSOURCE_INSTANCEDATA | 1);
dev_draw_indexed_primitive(dev, IS_PT_TRIANGLELIST, 0, 0, grid_points, 0, grid_triangles);</pre>
        <p>The device fetches, for instance i and index k, stream 0 at <code>ib[k] + BaseVertexIndex</code> and
        stream 1 at <code>i / divider</code>, as D3D9 did. Now: ${live(stat("mesh_triangles") / (lastFrame ? lastFrame.parts.length : 1))}
        instances &times; ${live(stat("grid_points") / (lastFrame ? lastFrame.parts.length : 1))} grid points =
        ${live(stat("vertices_shaded"))} vertices shaded (with the wireframe, twice: one draw per pass).</p>` },
    { title: "4. The vertex shader, beside the HLSL",
      preset: { mesh: "cube", patch: "smooth", level: "16" },
      html: () => `<p>A shader is a C function that asks for registers by semantic (<code>in-&gt;texcoord[3]</code>
        is n0), reads its constants and writes <code>oPos</code>, <code>COLOR0</code> and texture coordinates.
        Listing 1.1.2's heart (<code>vs/smooth.c</code>):</p>
        <pre>float3 g = vs_gregory(b);               // gregory coords
float3 fn = vs_smooth_fn(T);            // |dot(face normal, neighbour's)|
float3 posN = vs_evaluate_npatch(v0, v1, v2, n0, n1, n2, b);
float bl = 3 * 3 * 3 * b.x * b.y * b.z; // Eq. 1.1.9
pos0 = vs_lerp3(edge_patch(...), posN, fminf(1.0f, fn0 + bl));
...
return vs_lerp3(g.x pos2 + g.y pos0 + g.z pos1, posN, bl);</pre>
        <p>Each of the ${live(stat("vertices_shaded"))} vertices of this frame ran it once.</p>` },
    { title: "5. The patches",
      preset: { mesh: "cube", patch: "smooth", other: "npatch", split: true, level: "16", size: "768x512" },
      html: () => `<p><b>N-Patch</b> (<code>npatch</code>): a cubic B&eacute;zier triangle from the corners and
        their normals; watertight where neighbours agree on normals, but only C0 across edges: the cube shows
        creases. <b>Intermediate smoothed patch</b> (<code>smooth-initial</code>, Listing 1.1.1): smooth across
        edges, but coplanar triangles sweep a valley. <b>Final smoothed patch</b> (<code>smooth</code>, Listing
        1.1.2): each curve blended towards the N-Patch by fn + bl: smooth on both. For comparison:
        <code>phong</code> and <code>pn-aen</code>.</p>
        <p>Left ${live(state.patch)}, right ${live(state.other)}: change either. Normals: <code>real</code> (the
        patch's own) shows the difference; under <code>linear</code> (what D3D9 rendered) every curved patch
        shades alike.</p>` },
    { title: "6. The errata of the listings",
      preset: { mesh: "cube", patch: "smooth-initial", other: "smooth", split: true, level: "16", light: "grazing",
                size: "768x512" },
      html: () => `<p>The article's listings were OCR'd and carry typos and real mistakes: the control points
        lack their /3, <code>fn0..fn2</code> use an undefined <code>n</code> and pair opposite vertices with the
        wrong edges, Gregory coordinates are 0/0 at the corners, curve parameters divide by zero on edges, and a
        naive evaluation is not watertight. <code>docs/errata.md</code> lists each with its resolution and
        test.</p><p>Under a grazing light the intermediate patch's valley along the cube's diagonals (left, fig
        1.1.8b) is gone in the final patch (right).</p>` },
    { title: "7. Crack-free, to the bit",
      preset: { mesh: "cylinder", patch: "npatch", other: "pn-aen", split: true, level: "8", normals: "linear",
                yaw: "20", pitch: "-35", distance: "2.8", size: "768x512" },
      html: () => `<p>Two triangles sharing an edge see it with their vertices in opposite order. instess
        evaluates every edge point in a canonical vertex order, so both sides compute identical bits; with the
        top-left fill rule no pixel is left out or drawn twice (<code>tests/test_cracks.c</code> counts every
        pixel's coverage to prove it).</p><p>The surface stays closed as long as the two sides agree on the
        normals. The cylinder's rim vertices are split: radial normals for the side, axial ones for the caps.
        Left: the N-Patch's two rim curves differ, and the background shows through along the rim. Right:
        PN-AEN averages the edge control points of both sides and closes it (fig-001-5).</p>` },
    { title: "8. Three ways to the same N-Patch",
      preset: { mesh: "sphere", patch: "npatch", normals: "linear", level: "6", path: "npatch-mode" },
      html: () => `<p>D3D9 offered three: the device's own N-patch mode (<code>SetNPatchMode</code>),
        tessellation through instancing, and tessellation on the CPU into a vertex buffer
        (<code>D3DXTessellateNPatches</code>). They share one evaluator, so the three give the same bytes: switch
        the path (now ${live(state.path)}) and the picture does not change.</p>` },
    { title: "9. Adaptive level of detail, still through instancing",
      preset: { mesh: "sphere", patch: "smooth", lod: "screen", "max-level": "32", "lod-target": "8",
                fill: "solid+wire", "wire-levels": true, distance: "2.6" },
      html: () => `<p>Every mesh edge gets a level of its own, computed once from its two welded end points, so
        both triangles of an edge agree: <code>distance</code> scales the finest level by depth,
        <code>screen</code> divides the projected length of the edge's control polygon by the target in pixels.
        A triangle with edge levels (l0, l1, l2) is drawn with the refinement pattern of that triple; the
        triangles are sorted into buckets by pattern, and each bucket is one instanced draw.</p>
        <p>Now: ${live(stat("buckets") || 0)} draws of ${live(stat("patterns") || 0)} patterns; the wire's colour
        is each pattern's finest level (blue 1, green 8, red 64).</p>` },
  ];
  let current = 0;
  function showStep(navigate) {
    const nav = $("steps");
    if (!nav.children.length)
      STEPS.forEach((st, k) => {
        const b = document.createElement("button");
        b.textContent = String(k + 1), b.title = st.title;
        b.addEventListener("click", () => api.step(k));
        nav.appendChild(b);
      });
    [...nav.children].forEach((b, k) => b.classList.toggle("on", k === current));
    const st = STEPS[current];
    $("step").innerHTML = `<h3>${st.title}</h3>${st.html()}<p><button class="show" id="show">Show it</button>
      <span class="note">sets the controls; then change them</span></p>`;
    $("show").addEventListener("click", () => api.step(current));
  }
  // Step k: its text, and the controls set to its picture (from the program's defaults).
  api.step = (k) => {
    current = Math.max(0, Math.min(STEPS.length - 1, k));
    const base = Object.assign({}, initialState(), { mesh: state.mesh.endsWith(".obj") ? "cube" : state.mesh });
    return set(Object.assign(base, STEPS[current].preset));
  };
  api.steps = () => STEPS.map((s) => s.title);

  // ------------------------------------------------------------------ start
  function initialState() {
    return Object.assign({}, defaults, { "max-level": "16", silhouette: false, "wire-levels": false,
                                         "recompute-normals": false, split: false, other: "npatch" });
  }
  async function start() {
    const b64 = $("instess-wasm").textContent.trim();
    const bin = atob(b64), bytes = new Uint8Array(bin.length);
    for (let k = 0; k < bin.length; k++) bytes[k] = bin.charCodeAt(k);
    const log = (fd, t) => (fd === 2 ? console.warn : console.log)("instess: " + t);
    const { instance } = await WebAssembly.instantiate(bytes, instessWasi(() => memory, log));
    ex = instance.exports, memory = ex.memory;
    if (ex._initialize) ex._initialize();
    ctx = ex.web_create();
    tables = JSON.parse(cstr(ex.web_tables(ctx)));
    defaults = tables.defaults;
    const build = document.querySelector('meta[name="instess-build"]');
    $("build").textContent = `instess ${tables.version} · ${build ? build.content : "WebAssembly"} · ` +
      `${tables.threads} thread · rasterizer: reference path`;
    buildControls();
    state = initialState();
    syncControls();
    showStep(false);
    const r = await set({});
    if (!r.ok) throw new Error(r.message);
    resolveReady(api);
  }
  start().catch((e) => {
    $("status").textContent = "the page could not start: " + e.message;
    rejectReady(e);
  });
})();
