// web/measure.mjs WASM... -- the frame time of the page's module, for the README's comparison of the toolchains:
// each module is run in node (V8, Chromium's engine) through web/wasi.js, as the page runs it, and renders the
// scenes below ROUNDS times, the modules taking turns frame by frame.  Reported per module and scene: the median
// CPU time of a frame (process.cpuUsage: user + system of this process, which other processes on the machine do
// not add to) and the median wall-clock time beside it.  The first frame of each scene (loading the mesh,
// compiling) is not counted.  Usage: node web/measure.mjs build/web-wasi/instess.wasm build/web-emscripten/instess.wasm
import { readFileSync } from "node:fs";
import { createRequire } from "node:module";
const require = createRequire(import.meta.url);
const { instessWasi } = require("./wasi.js");

const SCENES = ["cube", "cube --msaa 1", "sphere --patch npatch --level 16",
                "sphere --lod screen --max-level 32 --fill solid+wire --wire-levels on --distance 2.2"];
const ROUNDS = Number(process.env.ROUNDS || 15);

function load(path) {
  let memory = null;
  const { exports: ex } = new WebAssembly.Instance(new WebAssembly.Module(readFileSync(path)),
    instessWasi(() => memory, (fd, t) => console.error(path + ": " + t)));
  memory = ex.memory;
  if (ex._initialize) ex._initialize();
  const ctx = ex.web_create();
  const render = (line) => {
    const b = new TextEncoder().encode(line + "\0"), p = ex.web_alloc(b.length);
    new Uint8Array(memory.buffer, p, b.length).set(b);
    const rc = ex.web_render(ctx, 0, p);
    ex.web_free(p);
    if (rc !== 0) throw new Error(path + ": " + line + ": the module refused the frame");
  };
  return { path, render };
}

const median = (a) => { const s = [...a].sort((x, y) => x - y); return s[s.length >> 1]; };
const modules = process.argv.slice(2).map(load);
if (!modules.length) { console.error("usage: node web/measure.mjs WASM..."); process.exit(2); }
for (const scene of SCENES) {
  const cpu = modules.map(() => []), wall = modules.map(() => []);
  for (const m of modules) m.render(scene);   // the first frame: not counted
  for (let r = 0; r < ROUNDS; r++)
    modules.forEach((m, k) => {
      const c0 = process.cpuUsage(), t0 = performance.now();
      m.render(scene);
      const t1 = performance.now(), c = process.cpuUsage(c0);
      cpu[k].push((c.user + c.system) / 1000), wall[k].push(t1 - t0);
    });
  for (let k = 0; k < modules.length; k++)
    console.log(`${modules[k].path}\t${scene}\tcpu ${median(cpu[k]).toFixed(1)} ms\twall ${median(wall[k]).toFixed(1)} ms`);
}
