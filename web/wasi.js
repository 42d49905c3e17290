// web/wasi.js -- the few WASI calls the page's WebAssembly makes (wasi-libc's clock, stdout and stderr), for the
// browser: no files, no environment.  instessWasi(memory, log) returns the import object; memory() gives the
// module's current memory (it grows), log(fd, text) receives each line written to fd 1 or 2.  A call the module
// makes that is not here answers ENOSYS and is logged once, so a build that needs more says so on the console.
"use strict";
function instessWasi(memory, log) {
  const ENOSYS = 52, EBADF = 8, ESPIPE = 70;
  const pending = { 1: "", 2: "" }, missing = new Set();
  const utf8 = new TextDecoder("utf-8");
  const now = typeof performance !== "undefined" ? () => performance.now() : () => Date.now();
  const calls = {
    // CLOCK_REALTIME (0) and the monotonic clocks, in nanoseconds: the page's own clock (performance.now)
    clock_time_get(id, precision, out) {
      const ms = id === 0 ? Date.now() : now();
      new DataView(memory().buffer).setBigUint64(out, BigInt(Math.round(ms * 1e6)), true);
      return 0;
    },
    clock_res_get(id, out) {
      new DataView(memory().buffer).setBigUint64(out, 1000n, true);
      return 0;
    },
    // stdout and stderr, line by line, to log; other descriptors do not exist
    fd_write(fd, iovs, n, written) {
      if (fd !== 1 && fd !== 2) return EBADF;
      const view = new DataView(memory().buffer);
      let total = 0;
      for (let k = 0; k < n; k++) {
        const p = view.getUint32(iovs + 8 * k, true), len = view.getUint32(iovs + 8 * k + 4, true);
        pending[fd] += utf8.decode(new Uint8Array(memory().buffer, p, len));
        total += len;
      }
      let nl;
      while ((nl = pending[fd].indexOf("\n")) >= 0) {
        log(fd, pending[fd].slice(0, nl));
        pending[fd] = pending[fd].slice(nl + 1);
      }
      view.setUint32(written, total, true);
      return 0;
    },
    fd_close(fd) { return EBADF; },
    fd_seek(fd, offset, whence, out) { return ESPIPE; },
    fd_fdstat_get(fd, out) { return fd <= 2 ? 0 : EBADF; },
    environ_sizes_get(count, size) {
      const view = new DataView(memory().buffer);
      view.setUint32(count, 0, true), view.setUint32(size, 0, true);
      return 0;
    },
    environ_get() { return 0; },
    args_sizes_get(count, size) { return calls.environ_sizes_get(count, size); },
    args_get() { return 0; },
    proc_exit(code) { throw new Error("the module exited (" + code + ")"); },
  };
  const ns = new Proxy(calls, {
    get(target, name) {
      if (name in target) return target[name];
      return (...args) => {
        if (!missing.has(name)) missing.add(name), log(2, "instess: WASI call " + String(name) + " is not provided");
        return ENOSYS;
      };
    },
  });
  // emscripten's standalone output also tells the page when its memory grew (nothing to do: views are made anew)
  const env = new Proxy({ emscripten_notify_memory_growth() {} }, {
    get(target, name) {
      if (name in target) return target[name];
      return () => { throw new Error("instess: the module imports env." + String(name) + ", which the page lacks"); };
    },
  });
  return { wasi_snapshot_preview1: ns, env };
}
if (typeof module !== "undefined") module.exports = { instessWasi };
