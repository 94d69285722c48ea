// curray web: the WebAssembly core (src/wasm/web.h) from JavaScript.
//
// Classic script (no ES module), so that the page works from file:// as
// well as from any static web server: it defines crCore and crSceneApply,
// shared by the page and its workers (worker code is built from this file's
// functions, see app.js). Nothing here computes physics: every number comes
// from the core; this file only moves values in and out of its memory.
'use strict';

// The WASI functions the module imports (stdio it never uses): refused.
function crWasiStubs() {
  const nosys = () => 52; // WASI ENOSYS
  return { wasi_snapshot_preview1: { fd_close: nosys, fd_seek: nosys, fd_write: nosys } };
}

// One instance of the core: crCore(module) -> {scene(), reproject(...)};
// each scene() is one cr_web (a scene and its evaluated frame) of it.
function crCore(module) {
  const inst = new WebAssembly.Instance(module, crWasiStubs());
  const x = inst.exports;
  if (x._initialize) x._initialize();
  const enc = new TextEncoder(), dec = new TextDecoder();
  const strBuf = x.malloc(512);
  function str(s, slot) { // two scratch strings: key and word
    const b = enc.encode(s + '\0');
    if (b.length > 255) throw new Error('string too long: ' + s);
    new Uint8Array(x.memory.buffer, strBuf + 256 * slot, b.length).set(b);
    return strBuf + 256 * slot;
  }
  function cstr(p) {
    const m = new Uint8Array(x.memory.buffer);
    let e = p;
    while (m[e]) e++;
    return dec.decode(m.subarray(p, e));
  }
  // scratch buffers, grown on demand: get(name, bytes) -> pointer
  const bufs = {};
  function get(name, n) {
    const b = bufs[name];
    if (b && b.n >= n) return b.p;
    if (b) x.free(b.p);
    const p = x.malloc(n);
    if (!p) throw new Error('out of memory');
    bufs[name] = { p, n };
    return p;
  }
  function scene() {
    const w = x.cr_web_new();
    const fail = () => { throw new Error(cstr(x.cr_web_message(w))); };
    return {
      handle: w,
      set(key, v) { if (x.cr_web_set(w, str(key, 0), v)) fail(); },
      word(key, v) { if (x.cr_web_set_word(w, str(key, 0), str(v, 1))) fail(); },
      clearSpheres() { x.cr_web_clear_spheres(w); },
      addSphere() { if (x.cr_web_add_sphere(w)) fail(); },
      // rgb: Uint8Array of width*height*3 (row 0 at theta = 0), or null
      sky(width, height, rgb) {
        if (!rgb) { x.cr_web_sky(w, 0, 0); return; }
        const p = x.cr_web_sky(w, width, height);
        if (!p) throw new Error('sky image ' + width + 'x' + height + ' refused (too large)');
        new Uint8Array(x.memory.buffer, p, rgb.length).set(rgb);
      },
      // evaluate at width x height: '' or the command line's message
      frame(width, height) { return x.cr_web_frame(w, width, height) ? cstr(x.cr_web_message(w)) : ''; },
      // trace pixel indices j * width + i: {rgb (9 a pixel), outcome, val (4 a pixel)}
      trace(pix) {
        const n = pix.length;
        const pPix = get('pix', 4 * n), pRgb = get('rgb', 9 * n), pOut = get('out', n), pVal = get('val', 32 * n);
        new Int32Array(x.memory.buffer, pPix, n).set(pix);
        if (x.cr_web_trace(w, pPix, n, pRgb, pOut, pVal) !== n) throw new Error('trace refused');
        const buf = x.memory.buffer;
        return {
          rgb: new Uint8Array(buf, pRgb, 9 * n).slice(),
          outcome: new Uint8Array(buf, pOut, n).slice(),
          val: new Float64Array(buf, pVal, 4 * n).slice(),
        };
      },
      probe(px, py) {
        const p = get('probe', 8 * 16);
        if (x.cr_web_probe(w, px, py, p)) return null;
        const v = new Float64Array(x.memory.buffer, p, 11);
        return {
          outcome: v[0], redshift: v[1], hit_r: v[2], hit_phi: v[3], bolo: v[4], steps: v[5],
          object: v[6], E: v[7], L: v[8], carter: v[9], r_plus: v[10],
        };
      },
      width() { return x.cr_web_width(w); },
      height() { return x.cr_web_height(w); },
    };
  }
  // view's pixels looked up in sky's (an equirectangular frame of the same
  // observer), skyRgba its RGBA image (copied into the core only when
  // skyChanged); cell: the interpolation cell (web.h: CR_WEB_LOOK_CELL = 8,
  // 1 exact everywhere). Returns an ImageData of view's size over the core's
  // memory (valid until the next call into this core), or null.
  let skyLen = 0;
  function reproject(view, sky, skyRgba, skyChanged, cell) {
    const W = view.width(), H = view.height(), n = 4 * W * H;
    if (!W || !H) return null;
    const pSky = get('lsky', skyRgba.length);
    if (skyChanged || skyLen !== skyRgba.length) {
      new Uint8Array(x.memory.buffer, pSky, skyRgba.length).set(skyRgba);
      skyLen = skyRgba.length;
    }
    const pOut = get('lout', n);
    if (x.cr_web_reproject(view.handle, sky.handle, pSky, pOut, cell || 8)) return null;
    return new ImageData(new Uint8ClampedArray(x.memory.buffer, pOut, n), W, H);
  }
  return { scene, reproject };
}

// The scene model of the page (app.js: crDefaultScene) into a core: every
// key through cr_web_set / cr_web_set_word in the scene file's units.
function crSceneApply(core, s, sky) {
  const rgbNum = (c) => (c[0] << 16) | (c[1] << 8) | c[2];
  const o = s.observer, d = s.accretion;
  core.word('name', s.name || 'scene.yml');
  core.set('metric.m', s.metric.m);
  core.set('metric.a', s.metric.a);
  core.set('metric.q', s.metric.q);
  core.set('observer.r', o.r);
  for (const k of ['theta', 'phi', 'roll', 'pitch', 'yaw', 'hfov', 'hextent']) core.set('observer.' + k, o[k]);
  core.set('observer.vfov', o.vfov === null ? NaN : o.vfov);
  core.set('observer.vextent', o.vextent === null ? NaN : o.vextent);
  core.word('observer.motion', o.motion);
  core.set('observer.v_r', o.v[0]);
  core.set('observer.v_theta', o.v[1]);
  core.set('observer.v_phi', o.v[2]);
  core.set('observer.retrograde', o.retrograde ? 1 : 0);
  core.word('observer.projection', o.projection);
  core.set('accretion.enabled', d.enabled ? 1 : 0);
  core.word('accretion.model', d.model);
  core.set('accretion.color1', rgbNum(d.color1));
  core.set('accretion.color2', d.color2 === null ? NaN : rgbNum(d.color2));
  core.set('accretion.n_radial', d.resolution[0]);
  core.set('accretion.n_sectors', d.resolution[1]);
  core.set('accretion.yaw', d.yaw);
  core.set('accretion.r_in', d.r_in === null ? NaN : d.r_in);
  core.set('accretion.r_out', d.r_out);
  core.set('accretion.retrograde', d.retrograde ? 1 : 0);
  core.set('accretion.temperature', d.temperature);
  core.word('accretion.inside_isco', d.inside_isco);
  core.clearSpheres();
  for (const p of s.spheres) {
    core.addSphere();
    core.set('sphere.color', rgbNum(p.color));
    core.set('sphere.n_lat', p.resolution[0]);
    core.set('sphere.n_lon', p.resolution[1]);
    for (const k of ['r', 'theta', 'phi', 'roll', 'pitch', 'yaw', 'radius']) core.set('sphere.' + k, p[k]);
  }
  // sky: {width, height, rgb}; null: no sky image; undefined: keep the one
  // set before (a worker is sent its image only when it changes)
  if (sky) core.sky(sky.width, sky.height, sky.rgb);
  else if (sky === null) core.sky(0, 0, null);
  if (sky !== null) core.set('skymap.boundary', s.skymap.boundary);
  core.set('sky_color', rgbNum(s.sky_color));
  core.set('horizon_color', rgbNum(s.horizon_color));
  core.set('error_color', rgbNum(s.error_color));
  core.set('limit_color', rgbNum(s.limit_color));
  core.set('redshift_sky', s.redshift_sky ? 1 : 0);
}
