// curray web: the page's scene model as curray's scene file (YAML) and back.
// Classic script. crSceneYaml(scene) writes the file the command line
// renders; crSceneFromYaml(text) reads the scene files curray ships and
// writes (block mappings, flow lists, comments). Values are checked by the
// core when the scene is evaluated, with the command line's messages; this
// reader only refuses what the page cannot hold (animations, unknown keys).
'use strict';

function crNum(v) {
  if (v === Infinity) return 'inf';
  return String(v);
}
function crDeg(v) { return crNum(v) + ' deg'; }
function crRgb(c) { return '[' + c.join(', ') + ']'; }
function crSame(a, b) { return a.length === b.length && a.every((v, i) => v === b[i]); }

// The scene file of scene s; cmd: the command line shown as a comment.
function crSceneYaml(s, cmd) {
  const L = [];
  const o = s.observer, d = s.accretion;
  L.push('# curray scene written by the browser explorer (web/)');
  if (cmd) L.push('#   ' + cmd);
  L.push('---');
  L.push('metric:', '  m: ' + crNum(s.metric.m), '  a: ' + crNum(s.metric.a), '  q: ' + crNum(s.metric.q));
  L.push('observer:');
  const inf = o.r === Infinity;
  L.push('  r: ' + crNum(o.r), '  theta: ' + crDeg(o.theta), '  phi: ' + crDeg(o.phi));
  if (o.roll) L.push('  roll: ' + crDeg(o.roll));
  if (!inf && o.pitch) L.push('  pitch: ' + crDeg(o.pitch));
  if (!inf && o.yaw) L.push('  yaw: ' + crDeg(o.yaw));
  if (inf) {
    L.push('  hextent: ' + crNum(o.hextent));
    if (o.vextent !== null) L.push('  vextent: ' + crNum(o.vextent));
  } else {
    if (o.projection !== 'equirectangular') {
      L.push('  hfov: ' + crDeg(o.hfov));
      if (o.vfov !== null) L.push('  vfov: ' + crDeg(o.vfov));
    }
    if (o.motion === 'velocity') L.push('  motion: [' + o.v.map(crNum).join(', ') + ']');
    else if (o.motion !== 'static') L.push('  motion: ' + o.motion);
    if (o.motion === 'orbit' && o.retrograde) L.push('  retrograde: true');
    if (o.projection !== 'rectilinear') L.push('  projection: ' + o.projection);
  }
  if (d.enabled) {
    L.push('accretion:');
    if (d.model === 'keplerian') {
      L.push('  model: keplerian');
      L.push('  radius: [' + (d.r_in === null ? '' : crNum(d.r_in) + ', ') + crNum(d.r_out) + ']');
      if (d.retrograde) L.push('  retrograde: true');
      L.push('  temperature: ' + crNum(d.temperature));
      if (d.inside_isco !== 'nothing') L.push('  inside_isco: ' + d.inside_isco);
    } else {
      L.push('  color1: ' + crRgb(d.color1));
      if (d.color2 !== null) L.push('  color2: ' + crRgb(d.color2));
      L.push('  resolution: ' + crRgb(d.resolution));
      if (d.yaw) L.push('  yaw: ' + crDeg(d.yaw));
      L.push('  radius: [' + crNum(d.r_in) + ', ' + crNum(d.r_out) + ']');
    }
  }
  if (s.skymap.image) {
    L.push('skymap:', '  image: ' + s.skymap.image);
    if (s.skymap.boundary !== Infinity) L.push('  boundary: ' + crNum(s.skymap.boundary));
  }
  for (const p of s.spheres) {
    L.push('sphere:', '  color: ' + crRgb(p.color), '  resolution: ' + crRgb(p.resolution),
           '  r: ' + crNum(p.r), '  theta: ' + crDeg(p.theta), '  phi: ' + crDeg(p.phi));
    for (const k of ['roll', 'pitch', 'yaw']) if (p[k]) L.push('  ' + k + ': ' + crDeg(p[k]));
    L.push('  radius: ' + crNum(p.radius));
  }
  // the command line's defaults: the horizon is black next to a keplerian disc
  const kep = s.accretion.enabled && s.accretion.model === 'keplerian';
  const defaults = { sky_color: [0, 0, 0], horizon_color: kep ? [0, 0, 0] : [255, 0, 0],
                     error_color: [0, 0, 255], limit_color: [255, 255, 0] };
  for (const k in defaults) if (!crSame(s[k], defaults[k])) L.push(k + ': ' + crRgb(s[k]));
  if (s.redshift_sky) L.push('redshift_sky: true');
  return L.join('\n') + '\n';
}

// ---- reading ------------------------------------------------------------------

class CrYamlError extends Error {}

// Flow value "[a, [b, c]]" or a scalar, as nested arrays of strings.
function crFlow(text, line) {
  let i = 0;
  function value() {
    while (text[i] === ' ') i++;
    if (text[i] === '[') {
      i++;
      const out = [];
      for (;;) {
        while (text[i] === ' ') i++;
        if (text[i] === ']') { i++; return out; }
        out.push(value());
        while (text[i] === ' ') i++;
        if (text[i] === ',') { i++; continue; }
        if (text[i] === ']') { i++; return out; }
        throw new CrYamlError('line ' + line + ': expected , or ] in a list');
      }
    }
    let j = i;
    while (j < text.length && text[j] !== ',' && text[j] !== ']') j++;
    const v = text.slice(i, j).trim().replace(/^(["'])(.*)\1$/, '$2');
    i = j;
    return v;
  }
  const v = value();
  while (text[i] === ' ') i++;
  if (i < text.length) throw new CrYamlError('line ' + line + ': unexpected text after the value');
  return v;
}

// Block structure: a mapping is {map: [{key, value, line}]} (keys may
// repeat: sphere); a block list is {list: [...]}; a flow list an array.
function crYamlTree(text) {
  const lines = [];
  text.split(/\r?\n/).forEach((raw, n) => {
    let t = raw.replace(/\s+#.*$/, '').replace(/^#.*$/, '');
    if (!t.trim() || t.trim() === '---' || t.trim() === '...') return;
    if (/\t/.test(t.match(/^\s*/)[0])) throw new CrYamlError('line ' + (n + 1) + ': tabs are not allowed for indentation');
    lines.push({ indent: t.match(/^ */)[0].length, text: t.trim(), line: n + 1 });
  });
  let k = 0;
  function block(indent) {
    if (k < lines.length && lines[k].indent === indent && lines[k].text.startsWith('- ')) {
      const list = [];
      while (k < lines.length && lines[k].indent === indent && lines[k].text.startsWith('- ')) {
        // "- key: value" starts a mapping indented by 2 more
        lines[k] = { indent: indent + 2, text: lines[k].text.slice(2).trim(), line: lines[k].line };
        list.push(block(indent + 2));
      }
      return { list };
    }
    const map = [];
    while (k < lines.length && lines[k].indent === indent && !lines[k].text.startsWith('- ')) {
      const { text: t, line } = lines[k];
      const m = t.match(/^([A-Za-z_][A-Za-z0-9_]*)\s*:(?:\s+(.*))?$/);
      if (!m) throw new CrYamlError('line ' + line + ': expected "key: value"');
      k++;
      if (m[2] !== undefined && m[2] !== '') map.push({ key: m[1], value: crFlow(m[2], line), line });
      else if (k < lines.length && lines[k].indent > indent) map.push({ key: m[1], value: block(lines[k].indent), line });
      else map.push({ key: m[1], value: null, line });
    }
    if (k < lines.length && lines[k].indent > indent) throw new CrYamlError('line ' + lines[k].line + ': unexpected indentation');
    return { map };
  }
  const root = block(0);
  if (k < lines.length) throw new CrYamlError('line ' + lines[k].line + ': unexpected indentation');
  return root;
}

// The scene model of a scene file's text; throws CrYamlError naming the line.
function crSceneFromYaml(text) {
  const root = crYamlTree(text);
  const s = crDefaultScene();
  // a file's defaults are the command line's, not the page's demo
  s.sky_color = [0, 0, 0]; s.horizon_color = [255, 0, 0];
  s.accretion.enabled = false;
  s.accretion.color2 = null;
  const at = (e) => 'line ' + e.line + ': ' + e.path + ': ';
  function scalar(e) {
    if (typeof e.value !== 'string') throw new CrYamlError(at(e) + 'expected a single value');
    return e.value;
  }
  function number(e, v) {
    v = v === undefined ? scalar(e) : v;
    if (Array.isArray(v) && v[0] === 'linear') throw new CrYamlError(at(e) + 'animations ([linear, start, end]) are not shown by the page; render them with the command line');
    if (typeof v !== 'string') throw new CrYamlError(at(e) + 'expected a number');
    if (/^\+?(inf|\.inf|infinity)$/i.test(v)) return Infinity;
    const x = Number(v);
    if (v === '' || !isFinite(x)) throw new CrYamlError(at(e) + 'expected a number, got "' + v + '"');
    return x;
  }
  function angle(e, v) {
    v = v === undefined ? scalar(e) : v;
    if (Array.isArray(v)) return number(e, v);
    const m = String(v).match(/^(\S+)\s*(deg|rad|pi)?$/);
    if (!m) throw new CrYamlError(at(e) + 'expected an angle ("90", "90 deg", "1.5 rad", "0.5 pi"), got "' + v + '"');
    const x = number(e, m[1]);
    return m[2] === 'rad' ? x * 180 / Math.PI : m[2] === 'pi' ? x * 180 : x;
  }
  function list(e, n) {
    if (!Array.isArray(e.value) || (n && e.value.length !== n)) throw new CrYamlError(at(e) + 'expected a list of ' + n + ' items');
    return e.value;
  }
  function rgb(e) { return list(e, 3).map((v) => number(e, v)); }
  function bool(e) {
    const v = scalar(e).toLowerCase();
    if (['true', 'yes', 'on'].includes(v)) return true;
    if (['false', 'no', 'off'].includes(v)) return false;
    throw new CrYamlError(at(e) + 'expected true or false, got "' + v + '"');
  }
  function section(e, keys, fn) {
    if (!e.value || !e.value.map) throw new CrYamlError(at(e) + 'expected a mapping');
    for (const c of e.value.map) {
      c.path = e.path + '.' + c.key;
      if (!keys.includes(c.key)) throw new CrYamlError(at(c) + 'unknown key (expected one of: ' + keys.join(', ') + ')');
      fn(c);
    }
  }
  function sphere(e) {
    const p = { color: [255, 255, 255], resolution: [1, 1], r: 0, theta: 90, phi: 0, roll: 0, pitch: 0, yaw: 0, radius: 1 };
    section(e, ['color', 'resolution', 'r', 'theta', 'phi', 'roll', 'pitch', 'yaw', 'radius'], (c) => {
      if (c.key === 'color') p.color = rgb(c);
      else if (c.key === 'resolution') p.resolution = list(c, 2).map((v) => number(c, v));
      else if (['theta', 'phi', 'roll', 'pitch', 'yaw'].includes(c.key)) p[c.key] = angle(c);
      else p[c.key] = number(c);
    });
    s.spheres.push(p);
  }
  const top = ['metric', 'observer', 'accretion', 'skymap', 'sphere', 'spheres', 'sky_color',
               'horizon_color', 'error_color', 'limit_color', 'redshift_sky'];
  if (!root.map) throw new CrYamlError('a scene must be a mapping of keys (metric, observer, ...)');
  for (const e of root.map) {
    e.path = e.key;
    if (!top.includes(e.key)) throw new CrYamlError(at(e) + 'unknown key (expected one of: ' + top.join(', ') + ')');
    if (e.key === 'metric') section(e, ['m', 'a', 'q'], (c) => { s.metric[c.key] = number(c); });
    else if (e.key === 'observer') {
      const o = s.observer;
      o.hfov = null;
      section(e, ['r', 'theta', 'phi', 'roll', 'pitch', 'yaw', 'hfov', 'vfov', 'hextent', 'vextent',
                  'motion', 'projection', 'retrograde'], (c) => {
        if (c.key === 'motion') {
          if (Array.isArray(c.value)) { o.motion = 'velocity'; o.v = list(c, 3).map((v) => number(c, v)); }
          else o.motion = scalar(c);
        } else if (c.key === 'projection') o.projection = scalar(c);
        else if (c.key === 'retrograde') o.retrograde = bool(c);
        else if (['r', 'hextent', 'vextent'].includes(c.key)) o[c.key] = number(c);
        else o[c.key] = angle(c);
      });
      if (o.hfov === null) o.hfov = 70;
    } else if (e.key === 'accretion') {
      const d = s.accretion;
      d.enabled = true;
      section(e, ['model', 'color1', 'color2', 'resolution', 'yaw', 'radius', 'retrograde',
                  'temperature', 'inside_isco', 'mass_msun', 'mdot_edd'], (c) => {
        if (c.key === 'model') d.model = scalar(c);
        else if (c.key === 'color1' || c.key === 'color2') d[c.key] = rgb(c);
        else if (c.key === 'resolution') d.resolution = list(c, 2).map((v) => number(c, v));
        else if (c.key === 'yaw') d.yaw = angle(c);
        else if (c.key === 'radius') {
          if (Array.isArray(c.value) && c.value.length === 2) { d.r_in = number(c, c.value[0]); d.r_out = number(c, c.value[1]); }
          else if (Array.isArray(c.value) && c.value.length === 1) { d.r_in = null; d.r_out = number(c, c.value[0]); }
          else { d.r_in = null; d.r_out = number(c); }
        } else if (c.key === 'retrograde') d.retrograde = bool(c);
        else if (c.key === 'temperature') d.temperature = number(c);
        else if (c.key === 'inside_isco') d.inside_isco = scalar(c);
        else throw new CrYamlError(at(c) + 'the page sets the disc by its temperature; mass_msun and mdot_edd are for the command line');
      });
    } else if (e.key === 'skymap') {
      section(e, ['image', 'boundary'], (c) => {
        if (c.key === 'image') s.skymap.image = scalar(c);
        else s.skymap.boundary = number(c);
      });
    } else if (e.key === 'sphere') sphere(e);
    else if (e.key === 'spheres') {
      if (!e.value || !e.value.list) throw new CrYamlError(at(e) + 'expected a list of spheres');
      e.value.list.forEach((m, i) => sphere({ value: m, line: e.line, path: 'spheres[' + i + ']' }));
    } else if (e.key === 'redshift_sky') s.redshift_sky = bool(e);
    else s[e.key] = rgb(e);
  }
  // as the command line: a keplerian disc's horizon is black unless given
  if (s.accretion.enabled && s.accretion.model === 'keplerian' &&
      !root.map.some((e) => e.key === 'horizon_color')) s.horizon_color = [0, 0, 0];
  return s;
}
