// tests/web_test.mjs PAGE INSTESS -- the browser test of `make web` (run by tests/web_test.sh, a stage of make test):
// Debian's Chromium, headless, opens PAGE (out/web/index.html) from file://, the test drives the page's controls
// through the DOM as a student would (select a patch, drag a slider, tick a box, press a tutorial button, drop an
// OBJ file), and after each change checks
//   - the command line the page shows: the options the test expects (its own list, not the page's);
//   - the canvas: its pixels, read back with getImageData, are byte for byte the PNG that `INSTESS ARGS -o FILE`
//     writes for the test's own ARGS (compared by `instess compare`, the golden tests' comparison; the split view
//     half by half, each against a render of half the width);
//   - that the control acted: the pixels differ from the frame before.
// Refusals (a state the program refuses, an OBJ with an error) must leave the canvas and the controls as they
// were and show the program's message.  Prints one line per check and "web: N passed, N failed".  Chromium is
// driven over its remote debugging protocol on a pipe (--remote-debugging-pipe: no port, no network), with a
// fresh profile folder that is removed at the end.  WEB_TEST_OUT (default build/web-test) keeps screenshots and,
// for a failure, the two images and their diff; WEB_SCREENSHOT=FILE also writes the README's screenshot there.
import { spawn, execFileSync } from "node:child_process";
import { mkdtempSync, rmSync, writeFileSync, mkdirSync, readFileSync, existsSync, copyFileSync } from "node:fs";
import { tmpdir } from "node:os";
import { join, resolve, basename } from "node:path";
import { deflateSync } from "node:zlib";

const [pagePath, instessPath] = process.argv.slice(2);
if (!pagePath || !instessPath) {
  console.error("usage: node tests/web_test.mjs out/web/index.html build/instess");
  process.exit(2);
}
const page = resolve(pagePath), instess = resolve(instessPath);
const outDir = resolve(process.env.WEB_TEST_OUT || "build/web-test");
mkdirSync(outDir, { recursive: true });
const meshDir = resolve("tests/data/meshes");

// ------------------------------------------------------------------ PNG (8-bit RGBA, no filter) for instess compare
const crcTable = Array.from({ length: 256 }, (_, n) => {
  let c = n;
  for (let k = 0; k < 8; k++) c = c & 1 ? 0xedb88320 ^ (c >>> 1) : c >>> 1;
  return c >>> 0;
});
function crc32(buf) {
  let c = 0xffffffff;
  for (const b of buf) c = crcTable[(c ^ b) & 255] ^ (c >>> 8);
  return (c ^ 0xffffffff) >>> 0;
}
function pngChunk(type, data) {
  const len = Buffer.alloc(4), crc = Buffer.alloc(4), td = Buffer.concat([Buffer.from(type, "latin1"), data]);
  len.writeUInt32BE(data.length), crc.writeUInt32BE(crc32(td));
  return Buffer.concat([len, td, crc]);
}
function encodePng(rgba, w, h) {
  const ihdr = Buffer.alloc(13);
  ihdr.writeUInt32BE(w, 0), ihdr.writeUInt32BE(h, 4), ihdr[8] = 8, ihdr[9] = 6;
  const raw = Buffer.alloc((4 * w + 1) * h);
  for (let y = 0; y < h; y++) rgba.copy(raw, y * (4 * w + 1) + 1, 4 * w * y, 4 * w * (y + 1));
  return Buffer.concat([Buffer.from([137, 80, 78, 71, 13, 10, 26, 10]), pngChunk("IHDR", ihdr),
                        pngChunk("IDAT", deflateSync(raw)), pngChunk("IEND", Buffer.alloc(0))]);
}

// ------------------------------------------------------------------ Chromium over its debugging pipe
const profile = mkdtempSync(join(tmpdir(), "instess-web-test-"));
const chromium = process.env.CHROMIUM || "chromium";
const browser = spawn(chromium, [
  "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
  "--disable-background-networking", "--disable-component-update", "--disable-sync",
  "--user-data-dir=" + profile, "--remote-debugging-pipe", "--window-size=1400,1000", "about:blank",
], { stdio: ["ignore", "ignore", "pipe", "pipe", "pipe"], detached: true });   // (its own process group: see finish)
let browserLog = "";
browser.stderr.on("data", (d) => { browserLog = (browserLog + d).slice(-4000); });
let nextId = 1, inbox = "";
const pending = new Map(), listeners = [];
browser.stdio[4].on("data", (d) => {
  inbox += d.toString("utf8");
  let z;
  while ((z = inbox.indexOf("\0")) >= 0) {
    const msg = JSON.parse(inbox.slice(0, z));
    inbox = inbox.slice(z + 1);
    if (msg.id && pending.has(msg.id)) {
      const { res, rej } = pending.get(msg.id);
      pending.delete(msg.id);
      msg.error ? rej(new Error(msg.error.message)) : res(msg.result);
    } else {
      for (const l of listeners) l(msg);
    }
  }
});
const exited = new Promise((res) => browser.on("exit", (code, sig) => res(code ?? sig)));
function send(method, params = {}, sessionId) {
  const id = nextId++;
  browser.stdio[3].write(JSON.stringify({ id, method, params, sessionId }) + "\0");
  return new Promise((res, rej) => pending.set(id, { res, rej }));
}
let session = null;
const cdp = (method, params) => send(method, params, session);
// Evaluate expr in the page (awaiting a promise); its value, or throw with the page's exception.
async function evaluate(expr) {
  const r = await cdp("Runtime.evaluate", { expression: expr, awaitPromise: true, returnByValue: true });
  if (r.exceptionDetails) throw new Error("in the page: " + (r.exceptionDetails.exception?.description || r.exceptionDetails.text));
  return r.result.value;
}

// ------------------------------------------------------------------ checks
let passed = 0, failed = 0;
function report(ok, name, why) {
  if (ok) passed++, console.log("ok   " + name);
  else failed++, console.log("FAIL " + name + ": " + why);
}
const slug = (s) => s.replace(/[^A-Za-z0-9]+/g, "-").replace(/^-|-$/g, "").slice(0, 60);

// The canvas: {w, h, rgba (Buffer)}.
async function canvasPixels() {
  const r = await evaluate(`(() => { const c = document.getElementById("canvas");
    const d = c.getContext("2d").getImageData(0, 0, c.width, c.height).data;
    let s = ""; for (let k = 0; k < d.length; k += 0x8000) s += String.fromCharCode.apply(null, d.subarray(k, k + 0x8000));
    return { w: c.width, h: c.height, b64: btoa(s) }; })()`);
  return { w: r.w, h: r.h, rgba: Buffer.from(r.b64, "base64") };
}
// Columns [x0, x0 + w) of image img.
function crop(img, x0, w) {
  const out = Buffer.alloc(4 * w * img.h);
  for (let y = 0; y < img.h; y++) img.rgba.copy(out, 4 * w * y, 4 * (img.w * y + x0), 4 * (img.w * y + x0 + w));
  return { w, h: img.h, rgba: out };
}
// Split a command line as the page quotes it ('...' around a word with odd characters).
function words(line) {
  const out = [];
  line.replace(/'([^']*)'|(\S+)/g, (_, q, w) => { out.push(q !== undefined ? q : w); return ""; });
  return out;
}
// A command line as {mesh, options: Map}: the comparison does not depend on the order of the options.
function parseLine(line) {
  const w = words(line), opts = new Map();
  let mesh = null;
  for (let k = 0; k < w.length; k++) {
    if (!w[k].startsWith("--")) { mesh = w[k]; continue; }
    const flag = w[k] === "--silhouette" || w[k] === "--recompute-normals";
    opts.set(w[k], flag ? "" : w[++k]);
  }
  return { mesh, opts };
}
function sameLine(a, b) {
  const p = parseLine(a), q = parseLine(b);
  if (p.mesh !== q.mesh || p.opts.size !== q.opts.size) return false;
  for (const [k, v] of p.opts) if (q.opts.get(k) !== v) return false;
  return true;
}
// The program's PNG for args (run in folder cwd: a dropped OBJ is found there by its name); the file's path.
let renders = 0;
function nativeRender(args, cwd) {
  const file = join(outDir, `native-${++renders}.png`);
  execFileSync(instess, [...words(args), "-q", "-o", file], { cwd: cwd || process.cwd(), stdio: ["ignore", "ignore", "pipe"] });
  return file;
}
// Pixels img equal the program's render of args: `instess compare` says "identical".
function sameAsNative(name, img, args, cwd) {
  const nat = nativeRender(args, cwd), web = join(outDir, `web-${renders}.png`);
  writeFileSync(web, encodePng(img.rgba, img.w, img.h));
  try {
    execFileSync(instess, ["compare", nat, web], { stdio: ["ignore", "pipe", "pipe"] });
    return null;
  } catch (e) {
    const dir = join(outDir, "failures");
    mkdirSync(dir, { recursive: true });
    const base = join(dir, slug(name));
    copyFileSync(nat, base + ".native.png"), copyFileSync(web, base + ".web.png");
    try { execFileSync(instess, ["compare", nat, web, "--diff", base + ".diff.png"], { stdio: "ignore" }); } catch {}
    return `the canvas differs from \`instess ${args}\` (${(e.stdout || "").toString().trim().split("\n").slice(1, 3).join("; ")}); ` +
           `images in ${dir}`;
  }
}

let before = null;   // the canvas before the step
// One step: run the page action `act` (JS in the page: DOM events), wait for the frame, then check the command
// lines against `expect` (the test's own; one per part) and the pixels against the program; `acts`: the pixels
// must differ from the frame before.  cwd: where the program finds a dropped OBJ.
async function step(name, act, expect, { acts = true, cwd } = {}) {
  try {
    const r = await evaluate(`(async () => { ${act}; return await instess.idle(); })()`);
    if (r && r.ok === false) return report(false, name, "the page refused: " + r.message);
    const lines = (await evaluate("instess.commands()")).map((c) => c.args);
    const exp = Array.isArray(expect) ? expect : [expect];
    if (lines.length !== exp.length || !lines.every((l, k) => sameLine(l, exp[k])))
      return report(false, name, `the page shows \`${lines.join(" | ")}\`, expected \`${exp.join(" | ")}\``);
    const img = await canvasPixels();
    const parts = await evaluate("instess.commands()");
    for (let k = 0; k < parts.length; k++) {
      const half = parts.length > 1 ? crop(img, parts[k].x, parts[k].width) : img;
      const why = sameAsNative(name + (parts.length > 1 ? ` part ${k}` : ""), half, exp[k], cwd);
      if (why) return report(false, name, why);
    }
    if (acts && before && before.w === img.w && before.h === img.h && before.rgba.equals(img.rgba))
      return report(false, name, "the control did not act: the canvas is the frame before");
    before = img;
    report(true, name + ` (${parts.length > 1 ? "both halves" : "canvas"} = instess ${exp.join(" | ")})`);
  } catch (e) {
    report(false, name, e.message);
  }
}
// A refusal: the action is refused with a message containing `says`; canvas, command and controls unchanged.
async function refused(name, act, says) {
  try {
    const cmd0 = await evaluate("JSON.stringify(instess.commands())"), patch0 = await evaluate(`document.getElementById("c-patch").value`);
    const r = await evaluate(`(async () => { ${act}; return await instess.idle(); })()`);
    const msg = await evaluate(`document.getElementById("message").textContent`);
    const img = await canvasPixels();
    if (r && r.ok !== false && !msg.includes(says)) return report(false, name, "the page did not refuse");
    if (!msg.includes(says)) return report(false, name, `the message is "${msg}", not one saying "${says}"`);
    if (await evaluate("JSON.stringify(instess.commands())") !== cmd0) return report(false, name, "the command line changed");
    if (await evaluate(`document.getElementById("c-patch").value`) !== patch0) return report(false, name, "the controls changed");
    if (!before.rgba.equals(img.rgba)) return report(false, name, "the canvas changed");
    report(true, name + ` (refused: ${msg.split("\n")[0]})`);
  } catch (e) {
    report(false, name, e.message);
  }
}
// DOM actions, as a user's: choose in a select, move a slider, tick a box, press a button.
const choose = (id, v) => `{ const e = document.getElementById("${id}"); e.value = ${JSON.stringify(v)}; e.dispatchEvent(new Event("change")); }`;
const slide = (id, v) => `{ const e = document.getElementById("${id}"); e.value = ${JSON.stringify(String(v))}; e.dispatchEvent(new Event("input")); }`;
const tick = (id, on) => `{ const e = document.getElementById("${id}"); e.checked = ${on}; e.dispatchEvent(new Event("change")); }`;
const press = (sel) => `document.querySelector(${JSON.stringify(sel)}).click()`;
// Drop a file on the page (a DataTransfer with the file, as the browser builds it for a real drop).
const drop = (name, text) => `{ const dt = new DataTransfer(); dt.items.add(new File([${JSON.stringify(text)}], ${JSON.stringify(name)}));
  document.dispatchEvent(new DragEvent("drop", { dataTransfer: dt, bubbles: true, cancelable: true }));
  await instess.dropping; }`;
async function screenshot(file) {
  const r = await cdp("Page.captureScreenshot", { format: "png" });
  writeFileSync(file, Buffer.from(r.data, "base64"));
}

// ------------------------------------------------------------------ the run
async function main() {
  await send("Target.setDiscoverTargets", { discover: true });
  const { targetInfos } = await send("Target.getTargets");
  const target = targetInfos.find((t) => t.type === "page");
  if (!target) throw new Error("Chromium opened no page");
  session = (await send("Target.attachToTarget", { targetId: target.targetId, flatten: true })).sessionId;
  await cdp("Runtime.enable");
  await cdp("Page.enable");
  await cdp("Emulation.setDeviceMetricsOverride", { width: 1400, height: 1000, deviceScaleFactor: 1, mobile: false });
  const errors = [];
  listeners.push((m) => {
    if (m.method === "Runtime.exceptionThrown") errors.push(m.params.exceptionDetails.exception?.description || "exception");
  });
  await cdp("Page.navigate", { url: "file://" + page });
  try {
    await evaluate(`new Promise((res, rej) => { const t = Date.now(); (function wait() {
      if (window.instess && instess.ready) instess.ready.then(res, rej);
      else if (Date.now() - t > 30000) rej(new Error("no window.instess after 30 s")); else setTimeout(wait, 50); })(); })`);
    report(true, "the page opens from file:// and its module starts");
  } catch (e) {
    report(false, "the page opens from file:// and its module starts", e.message);
    return;
  }
  const threads = await evaluate(`document.getElementById("status").textContent + " / " + document.getElementById("threads-note").textContent`);
  report(/1 thread/.test(threads) && /cross-origin isolation/.test(threads), "the page says it draws on 1 thread, and why",
         `it says: ${threads}`);

  // the state the page opens with: the program's defaults
  await step("the first frame", "", "cube", { acts: false });
  await screenshot(join(outDir, "page-default.png"));
  // each control, as a student changes it
  await step("patch: npatch", choose("c-patch", "npatch"), "cube --patch npatch");
  await step("level slider: 3", slide("c-level", 3), "cube --patch npatch --level 3");
  await step("normals: quadratic", choose("c-normals", "quadratic"), "cube --patch npatch --level 3 --normals quadratic");
  await step("mesh: icosahedron", choose("c-mesh", "icosahedron"), "icosahedron --patch npatch --level 3 --normals quadratic");
  await step("fill: solid+wire", choose("c-fill", "solid+wire"), "icosahedron --patch npatch --level 3 --normals quadratic --fill solid+wire");
  await step("grid: pg-fractional-odd, level 5 (number box)",
             choose("c-grid", "pg-fractional-odd") + ";" + `{ const e = document.getElementById("c-level-n"); e.value = "5"; e.dispatchEvent(new Event("change")); }`,
             "icosahedron --patch npatch --level 5 --normals quadratic --fill solid+wire --grid pg-fractional-odd");
  await step("light: grazing, samples 1", choose("c-light", "grazing") + ";" + choose("c-msaa", "1"),
             "icosahedron --patch npatch --level 5 --normals quadratic --fill solid+wire --grid pg-fractional-odd --light grazing --msaa 1");
  // the camera at angles where the C libraries' sinf / cosf / tanf disagree in the last bit (web/trig_table.c)
  await step("camera: yaw -75, pitch 41, field of view 60, distance 2.7",
             slide("c-yaw", -75) + ";" + slide("c-pitch", 41) + ";" + slide("c-fov", 60) + ";" + slide("c-distance", "2.7"),
             "icosahedron --patch npatch --level 5 --normals quadratic --fill solid+wire --grid pg-fractional-odd --light grazing --msaa 1 --yaw -75 --pitch 41 --fov 60 --distance 2.7");
  await step("size: 640x480, up x, cull none", choose("c-size", "640x480") + ";" + choose("c-up", "x") + ";" + choose("c-cull", "none"),
             "icosahedron --patch npatch --level 5 --normals quadratic --fill solid+wire --grid pg-fractional-odd --light grazing --msaa 1 --yaw -75 --pitch 41 --fov 60 --distance 2.7 --size 640x480 --up x --cull none");
  // the level of detail (tess/): per-edge levels, buckets of patterns
  await step("LOD: screen on the sphere, max level 24, wire by level",
             press("#steps button:nth-child(1)") + "; await instess.idle();" + choose("c-mesh", "sphere") + ";" + choose("c-lod", "screen") + ";" +
             slide("c-max-level", 24) + ";" + tick("c-wire-levels", true) + ";" + choose("c-patch", "smooth"),
             "sphere --level 4 --fill solid+wire --lod screen --max-level 24 --wire-levels on");
  await step("LOD: target 14 px", slide("c-lod-target", 14), "sphere --level 4 --fill solid+wire --lod screen --max-level 24 --wire-levels on --lod-target 14");
  await step("LOD: deviation, 1.5 px", choose("c-lod", "deviation") + ";" + slide("c-lod-deviation", 1.5),
             "sphere --level 4 --fill solid+wire --lod deviation --max-level 24 --wire-levels on --lod-deviation 1.5");
  await step("LOD: distance, silhouette, turned", choose("c-lod", "distance") + ";" + tick("c-silhouette", true) + ";" + slide("c-yaw", 100),
             "sphere --level 4 --fill solid+wire --lod distance --max-level 24 --wire-levels on --silhouette --yaw 100");
  await step("framing: box", choose("c-fit", "box"), "sphere --level 4 --fill solid+wire --lod distance --max-level 24 --wire-levels on --silhouette --yaw 100 --fit box");
  // split view: two renders of half the width, the right one with the other patch
  await step("tutorial step 5: the split view", press("#steps button:nth-child(5)") + "; await instess.idle();" + press("#show"),
             ["cube --level 16 --size 384x512", "cube --level 16 --patch npatch --size 384x512"]);
  if (process.env.WEB_SCREENSHOT) await screenshot(process.env.WEB_SCREENSHOT);
  await screenshot(join(outDir, "page-split.png"));
  await step("split: the right half's patch", choose("c-other", "phong"),
             ["cube --level 16 --size 384x512", "cube --level 16 --patch phong --size 384x512"]);
  await step("split: off", tick("c-split", false), "cube --level 16 --size 768x512");
  await step("tutorial step 8: the device's N-patch mode", press("#steps button:nth-child(8)") + "; await instess.idle();" + press("#show"),
             "sphere --patch npatch --normals linear --level 6 --path npatch-mode");
  await step("path: cpu (the same N-Patch)", choose("c-path", "cpu"), "sphere --patch npatch --normals linear --level 6 --path cpu", { acts: false });
  {   // the three paths give the same bytes: the page agrees with itself too
    const cpu = before;
    await step("path: instanced", choose("c-path", "instanced"), "sphere --patch npatch --normals linear --level 6", { acts: false });
    report(cpu.rgba.equals(before.rgba), "paths cpu and instanced: the same canvas", "they differ");
  }
  // refusals: the program's message, nothing changed
  await refused("the CPU path refuses the smoothed patch", choose("c-path", "cpu") + ";" + choose("c-patch", "smooth"), "--path npatch-mode and cpu draw the N-Patch");
  // an OBJ dropped on the page (web/obj.c): the same mesh as the program's import, so the same pixels
  const torus = readFileSync(join(meshDir, "web_torus.obj"), "utf8");
  await step("drop web_torus.obj", drop("web_torus.obj", torus), "web_torus.obj --patch npatch --normals linear --level 6", { cwd: meshDir });
  await step("OBJ: smooth, real normals, pitch 60", choose("c-patch", "smooth") + ";" + choose("c-normals", "real") + ";" + slide("c-pitch", 60),
             "web_torus.obj --level 6 --pitch 60", { cwd: meshDir });
  await step("OBJ: recompute the normals", tick("c-recompute", true), "web_torus.obj --level 6 --pitch 60 --recompute-normals", { cwd: meshDir });
  await step("drop web_concave.obj (a concave quad, normals without texture coordinates)",
             drop("web_concave.obj", readFileSync(join(meshDir, "web_concave.obj"), "utf8")) + ";" + tick("c-recompute", false) + ";" + choose("c-cull", "none"),
             "web_concave.obj --level 6 --pitch 60 --cull none", { cwd: meshDir });
  await screenshot(join(outDir, "page-obj.png"));
  await refused("an OBJ naming a vertex it does not define", drop("bad.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n"),
                "bad.obj line 4: the face names vertex 4, but the file defines 3");
  await refused("a file that is not OBJ", drop("notes.obj", "hello\nworld\n"), "notes.obj: no faces");
  // a pixel click reaches the inspector's hook with its half's command line
  try {
    const hit = await evaluate(`new Promise((res) => { instess.hooks.pixel = res;
      const c = document.getElementById("canvas"), r = c.getBoundingClientRect();
      const at = { clientX: r.left + 10.5 * r.width / c.width, clientY: r.top + 20.5 * r.height / c.height, pointerId: 1, bubbles: true };
      c.dispatchEvent(new PointerEvent("pointerdown", at)); c.dispatchEvent(new PointerEvent("pointerup", at)); })`);
    const cmd = (await evaluate("instess.commands()"))[0].args;
    report(hit.x === 10 && hit.y === 20 && hit.args === cmd, "a click hands its pixel to instess.hooks.pixel",
           `got ${JSON.stringify(hit)}`);
  } catch (e) {
    report(false, "a click hands its pixel to instess.hooks.pixel", e.message);
  }
  // the click shows the pixel's history: the same text as `instess inspect` for that half's command line
  try {
    const at = await evaluate(`(() => { const c = document.getElementById("canvas"), r = c.getBoundingClientRect();
      const x = c.width >> 1, y = c.height >> 1;
      const e = { clientX: r.left + (x + 0.5) * r.width / c.width, clientY: r.top + (y + 0.5) * r.height / c.height, pointerId: 1, bubbles: true };
      c.dispatchEvent(new PointerEvent("pointerdown", e)); c.dispatchEvent(new PointerEvent("pointerup", e));
      return { x, y }; })()`);
    const shown = await evaluate(`document.getElementById("inspector-text").textContent`);
    const cmd = (await evaluate("instess.commands()"))[0].args;
    const native = execFileSync(instess, ["inspect", ...words(cmd), "--pixel", `${at.x},${at.y}`, "-q"], { cwd: meshDir }).toString();
    report(shown === native && /fragment 1: draw 0/.test(native), "a click shows the pixel's history, as instess inspect prints it",
           `the page shows ${JSON.stringify(shown.slice(0, 200))}, instess inspect ${JSON.stringify(native.slice(0, 200))}`);
  } catch (e) {
    report(false, "a click shows the pixel's history, as instess inspect prints it", e.message);
  }
  // the draw one instance at a time: --instances 3 is the program's file; the play button steps 1, 2, ... and ends
  // on the whole mesh
  try {
    const base = (await evaluate("instess.commands()"))[0].args;
    await step("instances: 3 (the draw's instance count)", `instess.set({ instances: "3" })`, base + " --instances 3",
               { cwd: meshDir });
    const seen = await evaluate(`(async () => { const seen = [];
      instess.hooks.frame = (f) => seen.push(f.state.instances);
      await instess.play({ every: 1, ms: 0 });
      instess.hooks.frame = null; return seen; })()`);
    const n = (await evaluate("instess.frame()")).parts[0].mesh_triangles;
    const want = [...Array(n - 1).keys()].map((k) => String(k + 1)).concat(["0"]);
    report(JSON.stringify(seen) === JSON.stringify(want), "the play button draws instances 1.." + (n - 1) + ", then the mesh",
           `frames ${JSON.stringify(seen)}`);
    await step("after the playback: the whole mesh again", "", base, { cwd: meshDir, acts: true });
  } catch (e) {
    report(false, "the draw one instance at a time", e.message);
  }
  report(errors.length === 0, "no uncaught exception in the page", errors.join("; "));
}

const watchdog = setTimeout(() => { console.log("FAIL the browser test did not finish in 10 minutes"); failed++; finish(); }, 600000);
async function finish() {
  clearTimeout(watchdog);
  try { await Promise.race([send("Browser.close"), new Promise((r) => setTimeout(r, 3000))]); } catch {}
  browser.kill();
  await Promise.race([exited, new Promise((r) => setTimeout(r, 3000))]);
  // Chromium's helper processes can outlive the browser and still write into the profile (rmSync then failed with
  // ENOTEMPTY after every test had passed): end its whole process group first
  try { process.kill(-browser.pid, "SIGKILL"); } catch {}
  await new Promise((r) => setTimeout(r, 200));
  try {
    rmSync(profile, { recursive: true, force: true, maxRetries: 10, retryDelay: 200 });
  } catch (e) {
    console.error(`web: note: the browser profile ${profile} was not removed (${e.code || e.message})`);
  }
  console.log(`web: ${passed} passed, ${failed} failed`);
  process.exit(failed ? 1 : 0);
}
browser.on("error", (e) => { console.log("FAIL cannot start " + chromium + ": " + e.message); failed++; finish(); });
main().catch((e) => { failed++; console.log("FAIL the browser test stopped: " + e.message + "\n" + browserLog.slice(-1000)); }).finally(finish);
