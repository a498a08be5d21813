// The page: controls, and drawing what the worker (worker.js) renders. Every pixel comes from
// the kernel in WebAssembly; this file only moves bytes into canvases.
//
// URL parameters set the controls (and make runs reproducible, e.g. for scripts/web.sh test):
//   scene, method, beta, alpha, light, bsdf, selection, spheres, lobe, seed, spp (stop at),
//   pass (camera samples per pixel per pass; default: adaptive), test=1 (when done, write the
//   canvas pixels and the linear radiance into #test-result as JSON).
'use strict';

const $ = (id) => document.getElementById(id);
const params = new URLSearchParams(location.search);
const testMode = params.get('test') === '1';
const worker = new Worker('worker.js');
let info = null;
let jobs = 0; // starts sent; the worker numbers them the same way

function option(select, names) {
  select.replaceChildren(...names.map((n, i) => new Option(n, String(i))));
}

function indexOf(names, value, fallback) {
  const i = names.indexOf(value);
  return i >= 0 ? i : fallback;
}

// An f32 from the kernel as the shortest decimal that rounds back to it (0.1, not 0.100000001).
function shortF32(x) {
  for (let p = 1; p < 9; p++) {
    const s = x.toPrecision(p);
    if (Math.fround(Number(s)) === Math.fround(x)) return String(Number(s));
  }
  return String(x);
}

function setSceneDefaults(i) {
  const s = info.scenes[i];
  $('method').value = String(s.method);
  $('beta').value = shortF32(s.beta);
  $('alpha').value = shortF32(s.alpha);
  $('light').value = String(s.light_samples);
  $('bsdf').value = String(s.bsdf_samples);
}

function updateEnabled() {
  const m = info.methods[Number($('method').value)];
  $('beta').disabled = m !== 'power';
  $('alpha').disabled = m !== 'cutoff';
}

function num(id, fallback) {
  const v = Number($(id).value);
  return Number.isFinite(v) ? v : fallback;
}

function start() {
  updateEnabled();
  const scene = Number($('scene').value);
  const s = info.scenes[scene];
  $('description').textContent = s.description || s.error || '';
  for (const c of ['image', 'panel1', 'panel2', 'panel3', 'panel4']) {
    $(c).width = s.width || 1;
    $(c).height = s.height || 1;
  }
  const p = {
    scene,
    method: Number($('method').value),
    beta: num('beta', 2),
    alpha: num('alpha', 0.1),
    light: Math.max(0, Math.floor(num('light', 1))),
    bsdf: Math.max(0, Math.floor(num('bsdf', 1))),
    selection: Number($('selection').value),
    spheres: Number($('spheres').value),
    lobe: Number($('lobe').value),
    seed: Math.floor(num('seed', 0)) >>> 0,
    target: Math.max(0, Math.floor(num('target', 0))),
    pass: Math.max(0, Math.floor(Number(params.get('pass')) || 0)),
    radiance: testMode,
  };
  jobs += 1;
  $('status').textContent = 'rendering…';
  $('status').classList.remove('error');
  worker.postMessage({ type: 'start', params: p });
}

function drawBar(colorbar) {
  const bar = $('bar');
  const n = colorbar.length / 4 - 1; // the last pixel is the "no light" grey
  bar.width = n;
  bar.getContext('2d').putImageData(new ImageData(new Uint8ClampedArray(colorbar.buffer, 0, n * 4), n, 1), 0, 0);
  const g = colorbar.subarray(n * 4, n * 4 + 3);
  $('no-light-swatch').style.background = `rgb(${g[0]}, ${g[1]}, ${g[2]})`;
  $('ticks').replaceChildren(
    ...[0, 0.25, 0.5, 0.75, 1].map((v) => {
      const t = document.createElement('span');
      t.style.left = `${v * 100}%`;
      t.textContent = String(v);
      return t;
    }),
  );
}

function base64(bytes) {
  let s = '';
  for (let i = 0; i < bytes.length; i += 0x8000) {
    s += String.fromCharCode.apply(null, bytes.subarray(i, i + 0x8000));
  }
  return btoa(s);
}

function report(m) {
  // The canvas pixels as drawn, read back, without alpha.
  const { width: w, height: h } = m;
  const data = $('image').getContext('2d').getImageData(0, 0, w, h).data;
  const rgb = new Uint8Array(w * h * 3);
  for (let i = 0; i < w * h; i++) {
    rgb[3 * i] = data[4 * i];
    rgb[3 * i + 1] = data[4 * i + 1];
    rgb[3 * i + 2] = data[4 * i + 2];
  }
  const out = $('test-result');
  out.textContent = JSON.stringify({
    width: w,
    height: h,
    spp: m.spp,
    samples_per_second: m.samplesPerSecond,
    rgb: base64(rgb),
    radiance: base64(m.radiance),
  });
  document.body.dataset.test = 'done';
}

function draw(m) {
  const n = m.width * m.height * 4;
  ['image', 'panel1', 'panel2', 'panel3', 'panel4'].forEach((id, k) => {
    const img = new ImageData(new Uint8ClampedArray(m.rgba.buffer, k * n, n), m.width, m.height);
    $(id).getContext('2d', { willReadFrequently: id === 'image' }).putImageData(img, 0, 0);
  });
  const rate = m.samplesPerSecond >= 1e6 ? `${(m.samplesPerSecond / 1e6).toFixed(2)} M` : `${(m.samplesPerSecond / 1e3).toFixed(1)} k`;
  $('status').textContent =
    `${m.spp} spp${m.done ? ' (done)' : ''} · last pass ${m.passSpp} spp in ${m.passMs.toFixed(0)} ms · ` +
    `${rate} camera samples/s (one worker)`;
  if (m.done && testMode) report(m);
}

worker.onmessage = (e) => {
  const m = e.data;
  if (m.type === 'info') {
    info = m.info;
    option($('scene'), info.scenes.map((s) => s.name));
    option($('method'), info.methods);
    option($('selection'), info.light_selection);
    option($('spheres'), info.sphere_sampling);
    option($('lobe'), info.lobe_mixing);
    drawBar(m.colorbar);
    const scene = indexOf(info.scenes.map((s) => s.name), params.get('scene'), info.default_scene);
    $('scene').value = String(scene);
    setSceneDefaults(scene);
    if (params.has('method')) $('method').value = String(indexOf(info.methods, params.get('method'), Number($('method').value)));
    for (const id of ['beta', 'alpha', 'light', 'bsdf', 'seed']) if (params.has(id)) $(id).value = params.get(id);
    if (params.has('spp')) $('target').value = params.get('spp');
    $('selection').value = String(indexOf(info.light_selection, params.get('selection'), info.default_light_selection));
    $('spheres').value = String(indexOf(info.sphere_sampling, params.get('spheres'), info.default_sphere_sampling));
    $('lobe').value = String(indexOf(info.lobe_mixing, params.get('lobe'), info.default_lobe_mixing));
    start();
  } else if (m.type === 'frame') {
    if (m.id === jobs) draw(m);
  } else if (m.type === 'error') {
    if (m.id !== 0 && m.id !== jobs) return;
    $('status').textContent = `error: ${m.message}`;
    $('status').classList.add('error');
    if (testMode) {
      $('test-result').textContent = JSON.stringify({ error: m.message });
      document.body.dataset.test = 'error';
    }
  }
};

$('controls').addEventListener('change', (e) => {
  if (e.target.id === 'target') {
    // Only where to stop changed: the same render goes on.
    worker.postMessage({ type: 'target', target: Math.max(0, Math.floor(num('target', 0))) });
    return;
  }
  if (e.target.id === 'scene') setSceneDefaults(Number($('scene').value));
  start();
});
$('restart').addEventListener('click', start);
