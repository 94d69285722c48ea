// curray web: the page. Controls -> scene model -> (YAML text, and the core
// in every worker) -> traced pixels -> canvas. Classic script; needs core.js,
// yaml.js and the generated curray-core.js (CURRAY_WASM_BASE64) and
// textures.js (CURRAY_TEXTURES) loaded before it.
'use strict';

const CR_OUTCOMES = ['none', 'horizon', 'disc', 'sphere', 'sky', 'error', 'limit', 'outside'];
const CR_VIEWS = { colour: 0, redshift: 1, bolometric: 2 };

// ---- workers ---------------------------------------------------------------
// A worker holds one core instance: {type:'scene', gen, scene, sky, width,
// height} evaluates (answers {type:'frame', gen, message}); {type:'trace',
// gen, job, pix} traces (answers {type:'done', gen, job, pix, rgb, outcome,
// val}). Built from this function's text, so it needs no file of its own.
function crWorkerMain() {
  let core = null, scene = null, gen = -1;
  self.onmessage = (ev) => {
    const m = ev.data;
    try {
      if (m.type === 'init') {
        core = crCore(m.module);
        scene = core.scene();
        self.postMessage({ type: 'ready' });
      } else if (m.type === 'scene') {
        gen = m.gen;
        crSceneApply(scene, m.scene, m.sky);
        self.postMessage({ type: 'frame', gen, message: scene.frame(m.width, m.height) });
      } else if (m.type === 'trace') {
        if (m.gen !== gen) { self.postMessage({ type: 'done', gen: m.gen, job: m.job, stale: true }); return; }
        const t0 = performance.now();
        const r = scene.trace(m.pix);
        self.postMessage({ type: 'done', gen, job: m.job, pix: m.pix, rgb: r.rgb, outcome: r.outcome,
                           val: r.val, ms: performance.now() - t0 },
                         [m.pix.buffer, r.rgb.buffer, r.outcome.buffer, r.val.buffer]);
      }
    } catch (e) {
      self.postMessage({ type: 'error', gen, message: String(e && e.message || e) });
    }
  };
}

function crBase64Bytes(b64) {
  const s = atob(b64);
  const b = new Uint8Array(s.length);
  for (let i = 0; i < s.length; i++) b[i] = s.charCodeAt(i);
  return b;
}

// A pool of n workers tracing one image progressively: passes of step
// 16, 8, 4, 2, 1 (pixels whose i and j are multiples of the step, each
// painting its step x step block until a finer pass replaces it).
class CrRenderer {
  constructor(module, n, onPaint, onDone) {
    this.n = n;
    this.onPaint = onPaint;
    this.onDone = onDone;
    this.gen = 0;
    const src = [crWasiStubs, crCore, crSceneApply, crWorkerMain].map(String).join('\n') +
      '\ncrWorkerMain();\n';
    const url = URL.createObjectURL(new Blob([src], { type: 'text/javascript' }));
    this.workers = [];
    this.skySent = new Map();
    this.ready = Promise.all(Array.from({ length: n }, () => new Promise((res, rej) => {
      const w = new Worker(url);
      w.onerror = (e) => rej(new Error('worker: ' + e.message));
      w.onmessage = (ev) => { if (ev.data.type === 'ready') { w.onmessage = (e2) => this.message(w, e2.data); res(); } };
      w.postMessage({ type: 'init', module });
      this.workers.push(w);
    })));
  }

  // Start tracing scene at width x height; steps: the passes (coarse first).
  start(scene, sky, width, height, steps) {
    const gen = ++this.gen;
    this.width = width;
    this.height = height;
    this.rgb = new Uint8Array(9 * width * height);
    this.outcome = new Uint8Array(width * height);
    this.val = new Float64Array(4 * width * height);
    this.level = new Uint8Array(width * height).fill(255); // step that painted the pixel
    this.steps = steps;
    this.pass = -1;
    this.queue = [];
    this.busy = new Map();
    this.message_ = '';
    this.framesLeft = this.workers.length;
    this.t0 = performance.now();
    this.passTimes = [];
    for (const w of this.workers) {
      // the sky image travels only when it changed (undefined: keep it)
      const same = this.skySent.get(w) === sky;
      this.skySent.set(w, sky);
      w.postMessage({ type: 'scene', gen, scene, sky: same ? undefined : sky, width, height });
    }
    return gen;
  }

  nextPass() {
    this.pass++;
    if (this.pass >= this.steps.length) {
      this.passTimes.push(performance.now() - this.t0);
      this.onDone(this);
      return;
    }
    if (this.pass > 0) this.passTimes.push(performance.now() - this.t0);
    const s = this.steps[this.pass], prev = this.pass > 0 ? this.steps[this.pass - 1] : 0;
    const W = this.width, H = this.height;
    const list = [];
    for (let j = 0; j < H; j += s)
      for (let i = 0; i < W; i += s)
        if (!(prev && i % prev === 0 && j % prev === 0)) list.push(j * W + i);
    // chunks small enough that a change of scene is answered quickly
    const chunk = Math.max(64, Math.min(2048, Math.ceil(list.length / (4 * this.n))));
    for (let k = 0; k < list.length; k += chunk) this.queue.push(Int32Array.from(list.slice(k, k + chunk)));
    this.jobsLeft = this.queue.length;
    if (!this.jobsLeft) { this.nextPass(); return; }
    for (const w of this.workers) this.feed(w);
  }

  feed(w) {
    if (this.busy.get(w) || !this.queue.length) return;
    const pix = this.queue.shift();
    this.busy.set(w, true);
    w.postMessage({ type: 'trace', gen: this.gen, job: this.pass, pix }, [pix.buffer]);
  }

  message(w, m) {
    if (m.gen !== this.gen) {
      if (m.type === 'done') { this.busy.set(w, false); this.feed(w); }
      return;
    }
    if (m.type === 'error') { this.message_ = m.message; this.onDone(this, m.message); return; }
    if (m.type === 'frame') {
      if (m.message) { this.message_ = m.message; this.framesLeft = -1; this.onDone(this, m.message); return; }
      if (--this.framesLeft === 0) this.nextPass();
      return;
    }
    if (m.type !== 'done') return;
    this.busy.set(w, false);
    if (!m.stale) {
      const s = this.steps[this.pass];
      const W = this.width;
      for (let k = 0; k < m.pix.length; k++) {
        const p = m.pix[k];
        this.rgb.set(m.rgb.subarray(9 * k, 9 * k + 9), 9 * p);
        this.outcome[p] = m.outcome[k];
        this.val.set(m.val.subarray(4 * k, 4 * k + 4), 4 * p);
        this.level[p] = s;
      }
      this.onPaint(this, m.pix, s, W);
      if (--this.jobsLeft === 0) { this.nextPass(); return; }
    }
    this.feed(w);
  }
}

// ---- the scene model ---------------------------------------------------------
// Values in the scene file's units (angles in degrees); null: key left out.
function crDefaultScene() {
  return {
    name: 'scene.yml',
    metric: { m: 1, a: 0, q: 0 },
    observer: {
      r: 30, theta: 85, phi: 0, roll: 0, pitch: 0, yaw: 0, hfov: 70, vfov: null,
      hextent: 30, vextent: null, motion: 'static', v: [0, 0, 0], retrograde: false,
      projection: 'rectilinear',
    },
    accretion: {
      enabled: true, model: 'chessboard', color1: [0, 255, 0], color2: null, resolution: [2, 12],
      yaw: 0, r_in: 6, r_out: 15, retrograde: false, temperature: 1e4, inside_isco: 'nothing',
    },
    skymap: { image: null, boundary: Infinity },
    spheres: [],
    sky_color: [255, 255, 255], horizon_color: [0, 0, 0], error_color: [0, 0, 255],
    limit_color: [255, 255, 0], redshift_sky: false,
  };
}

// ---- images --------------------------------------------------------------------
// An image (Blob) as RGB bytes, decoded without colour management so that
// the page sees the pixel values the command line's PNG reader sees.
async function crDecodeImage(blob) {
  const bmp = await createImageBitmap(blob, { colorSpaceConversion: 'none', premultiplyAlpha: 'none' });
  const c = new OffscreenCanvas(bmp.width, bmp.height);
  const g = c.getContext('2d');
  g.drawImage(bmp, 0, 0);
  const d = g.getImageData(0, 0, bmp.width, bmp.height).data;
  const rgb = new Uint8Array(3 * bmp.width * bmp.height);
  for (let p = 0, q = 0; p < d.length; p += 4, q += 3) { rgb[q] = d[p]; rgb[q + 1] = d[p + 1]; rgb[q + 2] = d[p + 2]; }
  return { width: bmp.width, height: bmp.height, rgb };
}
function crDataUrlBlob(url) {
  const i = url.indexOf(',');
  return new Blob([crBase64Bytes(url.slice(i + 1))], { type: url.slice(5, url.indexOf(';')) });
}

// ---- the page ------------------------------------------------------------------
const CR_SIZES = { '320x180': [320, 180], '640x360': [640, 360], '1280x720': [1280, 720],
                   '320x240': [320, 240], '640x480': [640, 480] };
const CR_STEPS = [16, 8, 4, 2, 1];
const CR_SKY_SIZE = [1024, 512];

class CrApp {
  constructor(module) {
    this.module = module;
    this.scene = crDefaultScene();
    this.sky = null;          // {width, height, rgb} of the scene's sky image
    this.images = {};         // name -> decoded image (shipped textures, the user's)
    this.view = 'colour';
    this.size = [640, 360];
    const n = Math.max(1, navigator.hardwareConcurrency || 2);
    this.nWorkers = n;
    this.canvas = document.getElementById('view');
    this.ctx = this.canvas.getContext('2d');
    this.core = crCore(module);
    this.probeScene = this.core.scene();
    this.lookView = this.core.scene();
    this.lookSky = this.core.scene();
    this.renderer = new CrRenderer(module, n, (r, pix, s) => this.paint(r, pix, s), (r, msg) => this.done(r, msg));
    this.skyRenderer = null;
    this.skyKey = '';
    this.probeSky = this.lookViewSky = undefined; // the sky image each core holds
    this.renderDone = Promise.resolve('');
    this.skyDone = Promise.resolve('');
    this.resolveRender = null;
    this.lastTimes = null;
    this.bind();
  }

  el(id) { return document.getElementById(id); }

  // ---- controls <-> model ----
  get(path) { return path.split('.').reduce((o, k) => o[k], this.scene); }
  put(path, v) {
    const ks = path.split('.'), last = ks.pop();
    ks.reduce((o, k) => o[k], this.scene)[last] = v;
  }
  controls() { return Array.from(document.querySelectorAll('[data-key]')); }
  // model -> controls
  show() {
    const rgbHex = (c) => '#' + c.map((v) => v.toString(16).padStart(2, '0')).join('');
    for (const c of this.controls()) {
      const v = this.get(c.dataset.key), t = c.dataset.type;
      if (t === 'bool') c.checked = !!v;
      else if (t === 'color') c.value = rgbHex(v === null ? [0, 0, 0] : v);
      else if (t === 'inf') c.checked = v === Infinity;
      else if (t === 'null') c.checked = v === null;
      else if (t === 'num' || t === 'deg') { if (v !== Infinity && v !== null) c.value = String(v); }
      else c.value = v;
    }
    this.el('sky-image').value = this.scene.skymap.image === null ? '' :
      (this.scene.skymap.image in CURRAY_TEXTURES ? this.scene.skymap.image : 'own');
    this.el('view-mode').value = this.view;
    this.el('size').value = this.size.join('x');
    this.relevance();
  }
  // control -> model
  read(c) {
    const k = c.dataset.key, t = c.dataset.type;
    if (t === 'bool') this.put(k, c.checked);
    else if (t === 'color') {
      const h = c.value;
      this.put(k, [1, 3, 5].map((i) => parseInt(h.slice(i, i + 2), 16)));
    } else if (t === 'inf') {
      const num = this.el(c.dataset.for);
      this.put(k, c.checked ? Infinity : Number(num.value));
    } else if (t === 'null') {
      const num = this.el(c.dataset.for);
      this.put(k, c.checked ? null : Number(num.value));
    } else if (t === 'num' || t === 'deg') {
      const x = Number(c.value);
      const lock = c.dataset.lock && this.el(c.dataset.lock);
      if (lock && lock.checked) return; // the number waits behind "inf" / "ISCO"
      this.put(k, c.value.trim() === '' || !isFinite(x) ? NaN : x);
    } else this.put(k, c.value);
  }
  // which controls apply (as the scene file's keys do)
  relevance() {
    const s = this.scene, o = s.observer, inf = o.r === Infinity, kep = s.accretion.model === 'keplerian';
    const on = (cls, yes) => document.querySelectorAll('.' + cls).forEach((e) => e.classList.toggle('off', !yes));
    on('only-finite', !inf);
    on('only-inf', inf);
    on('only-velocity', !inf && o.motion === 'velocity');
    on('only-orbit', !inf && o.motion === 'orbit');
    on('only-fov', !inf && o.projection !== 'equirectangular');
    on('only-chess', !kep);
    on('only-kep', kep);
    on('only-sky', s.skymap.image !== null);
  }

  bind() {
    for (const c of this.controls())
      c.addEventListener(c.tagName === 'SELECT' || c.type === 'checkbox' || c.type === 'color' ? 'change' : 'input',
                         () => { this.read(c); this.changed(); });
    this.el('view-mode').addEventListener('change', (e) => { this.view = e.target.value; this.repaintAll(); });
    this.el('size').addEventListener('change', (e) => { this.size = CR_SIZES[e.target.value]; this.changed(); });
    this.el('sky-image').addEventListener('change', (e) => this.chooseSky(e.target.value));
    this.el('sky-file').addEventListener('change', (e) => this.ownSky(e.target.files[0]));
    this.el('yaml-import').addEventListener('click', () => this.importYaml(this.el('yaml').value));
    this.el('yaml-file').addEventListener('change', async (e) => {
      const f = e.target.files[0];
      if (f) { this.el('yaml').value = await f.text(); this.importYaml(this.el('yaml').value, f.name); }
    });
    this.el('yaml-save').addEventListener('click', () => {
      const a = document.createElement('a');
      a.href = URL.createObjectURL(new Blob([this.yaml()], { type: 'text/yaml' }));
      a.download = this.scene.name;
      a.click();
    });
    this.el('look').addEventListener('change', () => this.changed());
    this.canvas.addEventListener('mousemove', (e) => this.hover(e));
    this.canvas.addEventListener('pointerdown', (e) => this.dragStart(e));
    window.addEventListener('pointermove', (e) => this.dragMove(e));
    window.addEventListener('pointerup', () => this.dragEnd());
  }

  async chooseSky(v) {
    if (v === '') { this.scene.skymap.image = null; this.sky = null; }
    else if (v === 'own') { this.el('sky-file').click(); return; }
    else {
      if (!this.images[v]) this.images[v] = await crDecodeImage(crDataUrlBlob(CURRAY_TEXTURES[v]));
      this.scene.skymap.image = v;
      this.sky = this.images[v];
    }
    this.changed();
  }
  async ownSky(file) {
    if (!file) return;
    try {
      this.images[file.name] = await crDecodeImage(file);
    } catch (e) { this.error(file.name + ': cannot read the image (' + e.message + ')'); return; }
    this.scene.skymap.image = file.name;
    this.sky = this.images[file.name];
    this.show();
    this.changed();
  }

  cmd() {
    return 'curray -s ' + this.scene.name + ' -o out -x ' + this.size[0] + ' -y ' + this.size[1];
  }
  yaml() { return crSceneYaml(this.scene, this.cmd()); }

  async importYaml(text, name) {
    let s;
    try { s = crSceneFromYaml(text); } catch (e) { this.error((name || 'scene.yml') + ': ' + e.message); return false; }
    s.name = name || this.scene.name;
    const img = s.skymap.image;
    if (img && !this.images[img] && CURRAY_TEXTURES[img])
      this.images[img] = await crDecodeImage(crDataUrlBlob(CURRAY_TEXTURES[img]));
    if (img && !this.images[img]) {
      this.error(s.name + ': skymap.image: ' + img + ' is not loaded; choose it under "sky" (own image) first');
      return false;
    }
    this.scene = s;
    this.sky = img ? this.images[img] : null;
    this.show();
    return this.changed();
  }

  error(msg) {
    const m = this.el('message');
    m.textContent = msg;
    m.className = msg ? 'error' : '';
  }

  // Evaluate the scene on this thread (the message, the probe) and start
  // the workers; false when the core refuses the scene.
  changed() {
    this.changeT0 = performance.now();
    this.relevance();
    this.el('yaml').value = this.yaml();
    this.el('cmd').textContent = this.cmd() + (this.scene.skymap.image ? '   (with ' + this.scene.skymap.image + ' next to ' + this.scene.name + ')' : '');
    const [W, H] = this.size;
    let msg;
    if (this.resolveRender) this.resolveRender('superseded');
    this.renderDone = new Promise((res) => { this.resolveRender = res; });
    try {
      // the sky image is copied into the core only when it changed
      crSceneApply(this.probeScene, this.scene, this.sky === this.probeSky ? undefined : this.sky);
      this.probeSky = this.sky;
      msg = this.probeScene.frame(W, H);
    } catch (e) { msg = String(e.message || e); }
    this.error(msg);
    if (msg) { this.renderer.gen++; this.resolveDone(msg); return false; }
    if (this.canvas.width !== W || this.canvas.height !== H) { this.canvas.width = W; this.canvas.height = H; }
    this.image = this.ctx.createImageData(W, H);
    this.t0 = performance.now();
    this.renderer.start(this.scene, this.sky, W, H, CR_STEPS);
    if (this.el('look').checked) this.startSky();
    else this.el('look-status').textContent = '';
    return true;
  }

  // the full sky of the observer for looking around: traced again only when
  // something other than the camera's direction or field of view changed
  startSky() {
    const o = this.scene.observer;
    if (o.r === Infinity) { this.el('look-status').textContent = 'the observer at infinity cannot look around'; return; }
    const s = JSON.parse(JSON.stringify(this.scene, (k, v) => v === Infinity ? 'Infinity' : v),
                        (k, v) => v === 'Infinity' ? Infinity : v);
    Object.assign(s.observer, { roll: 0, pitch: 0, yaw: 0, projection: 'equirectangular', vfov: null });
    const key = JSON.stringify(s, (k, v) => v === Infinity ? 'inf' : v) + (this.scene.skymap.image || '');
    if (key === this.skyKey) return;
    this.skyKey = key;
    this.skyModel = s;
    if (!this.skyRenderer)
      this.skyRenderer = new CrRenderer(this.module, this.nWorkers, (r, pix, st) => this.paintSky(r, pix, st),
                                        (r, msg) => {
                                          this.el('look-status').textContent = msg || 'sky traced in ' + Math.round(r.passTimes[r.passTimes.length - 1]) + ' ms';
                                          if (this.resolveSky) this.resolveSky(msg || '');
                                        });
    // resolves when this sky is traced (test and bench hook)
    this.skyDone = new Promise((res) => { this.resolveSky = res; });
    const [SW, SH] = CR_SKY_SIZE;
    crSceneApply(this.lookSky, s, this.sky);
    const msg = this.lookSky.frame(SW, SH);
    if (msg) { this.el('look-status').textContent = msg; return; }
    this.skyRgba = new Uint8Array(4 * SW * SH);
    this.skyDirty = true;
    this.el('look-status').textContent = 'tracing the sky for looking around...';
    this.skyRenderer.start(s, this.sky, SW, SH, CR_STEPS);
  }

  paintBlocks(r, pix, s, img, view) {
    const W = r.width, H = r.height, d = img, off = CR_VIEWS[view] * 3;
    for (let k = 0; k < pix.length; k++) {
      const p = pix[k], i0 = p % W, j0 = (p - i0) / W;
      const c0 = r.rgb[9 * p + off], c1 = r.rgb[9 * p + off + 1], c2 = r.rgb[9 * p + off + 2];
      for (let j = j0; j < Math.min(H, j0 + s); j++)
        for (let i = i0; i < Math.min(W, i0 + s); i++) {
          const q = 4 * (j * W + i);
          d[q] = c0; d[q + 1] = c1; d[q + 2] = c2; d[q + 3] = 255;
        }
    }
  }
  paint(r, pix, s) {
    this.paintBlocks(r, pix, s, this.image.data, this.view);
    if (!this.frameQueued) {
      this.frameQueued = true;
      requestAnimationFrame(() => { this.frameQueued = false; if (!this.dragging) this.ctx.putImageData(this.image, 0, 0); });
    }
  }
  paintSky(r, pix, s) { this.paintBlocks(r, pix, s, this.skyRgba, this.view); this.skyDirty = true; }
  repaintAll() {
    const r = this.renderer;
    if (!r.rgb || !this.image) return;
    const all = [];
    for (let p = 0; p < r.level.length; p++) if (r.level[p] !== 255) all.push(p);
    // coarse pixels first, so that finer ones paint over their blocks
    all.sort((a, b) => r.level[b] - r.level[a]);
    for (const p of all) this.paintBlocks(r, [p], r.level[p], this.image.data, this.view);
    this.ctx.putImageData(this.image, 0, 0);
    if (this.skyRenderer && this.skyRenderer.rgb) {
      const q = this.skyRenderer, sk = [];
      for (let p = 0; p < q.level.length; p++) if (q.level[p] !== 255) sk.push(p);
      sk.sort((a, b) => q.level[b] - q.level[a]);
      for (const p of sk) this.paintBlocks(q, [p], q.level[p], this.skyRgba, this.view);
      this.skyDirty = true;
    }
  }

  done(r, msg) {
    if (msg) { this.error(msg); this.resolveDone(msg); return; }
    this.ctx.putImageData(this.image, 0, 0);
    const t = r.passTimes.map((x) => Math.round(x));
    this.lastTimes = r.passTimes.slice();
    this.el('status').textContent = r.width + 'x' + r.height + ', ' + this.nWorkers + ' workers: passes done at ' +
      t.join(', ') + ' ms';
    this.resolveDone('');
  }
  resolveDone(msg) {
    const f = this.resolveRender;
    this.resolveRender = null;
    if (f) f(msg);
  }
  // resolves with '' when the latest render is complete, or with its message
  // ('superseded' when a newer change replaced it)
  whenDone() { return this.renderDone; }

  // ---- cursor readout ----
  hover(e) {
    const b = this.canvas.getBoundingClientRect();
    const x = (e.clientX - b.left) * this.canvas.width / b.width - 0.5;
    const y = (e.clientY - b.top) * this.canvas.height / b.height - 0.5;
    const p = this.probeScene.probe(x, y);
    if (!p) return;
    const f = (v, n) => (v === -1 || Number.isNaN(v) ? '-' : v.toPrecision(n || 6));
    this.el('readout').textContent =
      'pixel (' + Math.round(x) + ', ' + Math.round(y) + '): ' + CR_OUTCOMES[p.outcome] +
      (p.outcome === 2 || p.outcome === 3 ? ' at r = ' + f(p.hit_r) + ' M, phi = ' + f(p.hit_phi * 180 / Math.PI, 4) + ' deg' : '') +
      ', g = ' + f(p.redshift) + (p.bolo >= 0 ? ', bolometric ' + f(p.bolo, 4) : '') +
      ' | E = ' + f(p.E) + ', L = ' + f(p.L) + ', Carter Q = ' + f(p.carter) + ' | ' + p.steps + ' steps | r+ = ' + f(p.r_plus) + ' M';
  }

  // ---- looking around: drag turns the camera (observer.yaw, pitch) ----
  dragStart(e) {
    if (!this.el('look').checked || this.scene.observer.r === Infinity) return;
    this.dragging = { x: e.clientX, y: e.clientY, yaw: this.scene.observer.yaw, pitch: this.scene.observer.pitch };
    try { this.canvas.setPointerCapture(e.pointerId); } catch (err) { /* a synthetic pointer */ }
  }
  dragMove(e) {
    if (!this.dragging) return;
    this.lookMs = null;
    const o = this.scene.observer, fov = o.projection === 'equirectangular' ? 360 : o.hfov;
    const k = fov / this.canvas.getBoundingClientRect().width;
    o.yaw = Math.round(100 * (this.dragging.yaw + (e.clientX - this.dragging.x) * k)) / 100;
    o.pitch = Math.round(100 * Math.max(-90, Math.min(90, this.dragging.pitch + (e.clientY - this.dragging.y) * k))) / 100;
    this.show();
    this.lookMs = this.look();
  }
  // the view reprojected from the sky image: no ray traced
  look() {
    const [W, H] = this.size;
    if (!this.skyRgba) return -1;
    const t0 = performance.now();
    crSceneApply(this.lookView, this.scene, this.sky === this.lookViewSky ? undefined : this.sky);
    this.lookViewSky = this.sky;
    if (this.lookView.frame(W, H)) return -1;
    const [SW, SH] = CR_SKY_SIZE;
    if (this.lookSky.width() !== SW) return -1;
    const out = this.core.reproject(this.lookView, this.lookSky, this.skyRgba, this.skyDirty);
    this.skyDirty = false;
    if (!out) return -1;
    this.lookImage = out;
    if (this.canvas.width !== W) { this.canvas.width = W; this.canvas.height = H; }
    this.ctx.putImageData(out, 0, 0);
    const ms = performance.now() - t0;
    this.el('look-status').textContent = 'looking around: ' + ms.toFixed(1) + ' ms a frame (reprojected; traced when you let go)';
    return ms;
  }
  dragEnd() {
    if (!this.dragging) return;
    this.dragging = null;
    this.changed();
  }
}

async function crMain() {
  const bytes = crBase64Bytes(CURRAY_WASM_BASE64);
  const module = await WebAssembly.compile(bytes);
  const app = new CrApp(module);
  window.crApp = app;
  const sel = app.el('sky-image');
  for (const name of Object.keys(CURRAY_TEXTURES)) {
    const o = document.createElement('option');
    o.value = o.textContent = name;
    sel.insertBefore(o, sel.lastElementChild);
  }
  await app.renderer.ready;
  app.show();
  app.changed();
  app.started = true;
}

window.addEventListener('load', () => {
  crMain().catch((e) => {
    const m = document.getElementById('message');
    m.textContent = 'curray could not start: ' + e.message;
    m.className = 'error';
    console.error(e);
  });
});
