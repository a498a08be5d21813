// picomis in a Web Worker: loads the kernel (picomis.wasm) and renders progressive passes,
// sending each pass's images to the page. No rendering code here: the kernel does it all
// (see web/wasm/src/lib.rs for the exports).
'use strict';

let wasm = null; // the module's exports
let job = null; // the current render: {id, target, passSpp, ...}
let jobId = 0;

function bytes(ptr, len) {
  return new Uint8Array(wasm.memory.buffer, ptr, len);
}

function text(ptr, len) {
  return new TextDecoder().decode(bytes(ptr, len));
}

async function load() {
  const url = new URL('picomis.wasm', self.location.href);
  let instance;
  try {
    ({ instance } = await WebAssembly.instantiateStreaming(fetch(url), {}));
  } catch (e) {
    // A server without the application/wasm type: fall back to the bytes.
    const response = await fetch(url);
    if (!response.ok) throw new Error(`${url}: ${response.status} ${response.statusText}`);
    ({ instance } = await WebAssembly.instantiate(await response.arrayBuffer(), {}));
  }
  wasm = instance.exports;
  const ptr = wasm.info_ptr();
  const info = JSON.parse(text(ptr, wasm.info_len()));
  // The colour bar of the weight panels (the desktop figure's colour map), 256 steps + grey.
  const barPtr = wasm.colorbar_ptr(256);
  const colorbar = bytes(barPtr, 257 * 4).slice();
  postMessage({ type: 'info', info, colorbar }, [colorbar.buffer]);
}

function start(p) {
  const id = ++jobId;
  const ok = wasm.setup(p.scene, p.method, p.beta, p.alpha, p.light, p.bsdf, p.spheres, p.lobe, p.selection, p.seed);
  if (ok !== 0) {
    job = null;
    postMessage({ type: 'error', id, message: text(wasm.message_ptr(), wasm.message_len()) });
    return;
  }
  job = {
    id,
    target: p.target, // stop at this spp (0: never)
    passSpp: p.pass > 0 ? p.pass : 1, // samples per pixel per pass
    auto: !(p.pass > 0), // adapt the pass size to about 150 ms
    radiance: !!p.radiance, // send the linear radiance when done (tests)
    width: wasm.width(),
    height: wasm.height(),
    sampleMs: 0, // time spent sampling
    samples: 0, // camera samples taken
  };
  setTimeout(() => step(id), 0);
}

function step(id) {
  if (!job || job.id !== id) return; // replaced by a newer render
  const before = wasm.spp();
  let k = job.passSpp;
  if (job.target > 0) k = Math.min(k, job.target - before);
  if (k <= 0) return;
  const t0 = performance.now();
  const added = wasm.add_samples(k);
  const t1 = performance.now();
  const ptr = wasm.update();
  const t2 = performance.now();
  const rgba = bytes(ptr, wasm.rgba_len()).slice();
  const spp = wasm.spp();
  job.sampleMs += t1 - t0;
  job.samples += added * job.width * job.height;
  const done = added === 0 || (job.target > 0 && spp >= job.target);
  const msg = {
    type: 'frame',
    id,
    width: job.width,
    height: job.height,
    spp,
    passSpp: added,
    passMs: t2 - t0,
    samplesPerSecond: job.samples / (job.sampleMs / 1000),
    done,
    rgba,
  };
  const transfer = [rgba.buffer];
  if (done && job.radiance) {
    msg.radiance = bytes(wasm.radiance_ptr(), wasm.radiance_len()).slice();
    transfer.push(msg.radiance.buffer);
  }
  postMessage(msg, transfer);
  if (done) return;
  if (job.auto) {
    const ms = t2 - t0;
    if (ms < 80) job.passSpp = Math.min(job.passSpp * 2, 1024);
    else if (ms > 300 && job.passSpp > 1) job.passSpp = Math.max(1, job.passSpp >> 1);
  }
  setTimeout(() => step(id), 0);
}

onmessage = (e) => {
  const m = e.data;
  if (m.type === 'start') {
    try {
      start(m.params);
    } catch (err) {
      postMessage({ type: 'error', id: jobId, message: String(err) });
    }
  } else if (m.type === 'target' && job) {
    // A new stopping point for the same render: go on from where it is.
    const stopped = job.target > 0 && wasm.spp() >= job.target;
    job.target = m.target;
    const id = job.id;
    if (stopped && (job.target === 0 || wasm.spp() < job.target)) setTimeout(() => step(id), 0);
  } else if (m.type === 'stop') {
    job = null;
  }
};

load().catch((err) => postMessage({ type: 'error', id: 0, message: `loading the kernel: ${err}` }));
