// sepal web viewer: page logic around the wasm module (sepal_web.cpp). Loads an asset by
// URL (?asset=, the URL box) or from a dropped / picked file, and draws on change. With
// ?test=1 it draws fixed views instead and writes their pixels into #result (the headless
// Chromium test reads them with --dump-dom); ?bench=N times N frames. ?scene=kiosk/scene.txt
// plays a scene bundle (docs/scenes.md) with its lights and camera on the clock (?time=T
// fixes it; with ?test=1 one frame per backend into #result).
'use strict';
var params = new URLSearchParams(location.search);
var Module = {
  canvas: document.getElementById('sepal'),
  print: function (t) { console.log(t); },
  printErr: function (t) { console.error(t); },
  onRuntimeInitialized: function () { start(); }
};
var api = null, statusBox = document.getElementById('status'), result = document.getElementById('result');
var lastMs = 0, pending = false;

function bind() {
  var c = Module.cwrap;
  api = {
    init: c('sepal_web_init', 'number', ['string', 'number', 'number']),
    scene: c('sepal_web_scene', 'number', ['string']),
    backend: c('sepal_web_set_backend', 'number', ['number']),
    terms: c('sepal_web_set_terms', 'number', ['number']),
    orbit: c('sepal_web_orbit', null, ['number', 'number']),
    light: c('sepal_web_move_light', null, ['number', 'number']),
    zoom: c('sepal_web_zoom', null, ['number']),
    reset: c('sepal_web_reset_view', null, []),
    draw: c('sepal_web_draw', 'number', []),
    error: c('sepal_web_error', 'string', []),
    status: c('sepal_web_status', 'string', []),
    flags: c('sepal_web_flags', 'string', [])
  };
  api.load = function (bytes) {
    var p = Module._malloc(bytes.length);
    Module.HEAPU8.set(bytes, p);
    var ok = Module._sepal_web_load(p, bytes.length);
    Module._free(p);
    return ok;
  };
  api.sceneOpen = c('sepal_web_scene_open', 'number', ['string']);
  api.sceneDraw = c('sepal_web_scene_draw', 'number', ['number']);
  api.sceneOrbit = c('sepal_web_scene_orbit', null, ['number', 'number']);
  api.sceneFile = function (name, bytes) {
    var p = Module._malloc(bytes.length), n = Module._malloc(name.length * 4 + 1);
    Module.HEAPU8.set(bytes, p);
    Module.stringToUTF8(name, n, name.length * 4 + 1);
    var ok = Module._sepal_web_scene_file(n, p, bytes.length);
    Module._free(p);
    Module._free(n);
    return ok;
  };
  api.read = function (w, h) {
    var n = w * h * 4, p = Module._malloc(n);
    Module._sepal_web_read(p);
    var out = Module.HEAPU8.slice(p, p + n);
    Module._free(p);
    return out;
  };
}

// XHR rather than fetch: it also reads file:// pages (Chromium with --allow-file-access-from-files).
function fetchBytes(url, done) {
  var x = new XMLHttpRequest();
  x.open('GET', url);
  x.responseType = 'arraybuffer';
  x.onload = function () {
    if (x.status === 200 || (x.status === 0 && x.response)) done(null, new Uint8Array(x.response));
    else done(url + ': HTTP ' + x.status);
  };
  x.onerror = function () { done(url + ': cannot be read (a file:// page needs a local server, or a browser flag)'); };
  x.send();
}

function redraw() {
  if (pending) return;
  pending = true;
  requestAnimationFrame(function () {
    pending = false;
    lastMs = api.draw();
    showStatus();
  });
}

function showStatus(extra) {
  // Under a frozen clock (headless Chromium's virtual time) a frame takes "0 ms": say so.
  var ms = lastMs > 0 ? lastMs.toFixed(2) + ' ms/frame' : 'ms/frame n/a';
  statusBox.textContent = (lastMs < 0 ? 'error: ' + api.error() : ms + ' | ' + api.status()) +
                          (extra ? ' | ' + extra : '');
  document.getElementById('flags').textContent = 'sepal-view --headless ASSET.sepal --backend ' +
      document.getElementById('backend').selectedOptions[0].text + ' ' + api.flags() + ' -o view.png';
}

function loadBytes(bytes, name) {
  if (!api.load(bytes)) { statusBox.textContent = 'error: ' + name + ': ' + api.error(); return false; }
  redraw();
  return true;
}

function base64(bytes) {
  var s = '';
  for (var i = 0; i < bytes.length; i += 0x8000) s += String.fromCharCode.apply(null, bytes.subarray(i, i + 0x8000));
  return btoa(s);
}

// ?test=1&assets=A,B&backends=gles2,gles2-fused[&orbit=DX,DY][&light=DX,DY]: the drags
// given in pixels (as the mouse would), a "flags ..." line with the resulting view, one
// "ok ASSET BACKEND W H BASE64" line per pair (or "error ..."), then "done".
function runTest(w, h) {
  var names = ['gles2', 'gles2-fused', 'gles2-fused-pixel'];
  var assets = (params.get('assets') || params.get('asset') || 'default.sepal').split(',');
  var backends = (params.get('backends') || 'gles2').split(',');
  var orbit = (params.get('orbit') || '0,0').split(',').map(Number), light = (params.get('light') || '0,0').split(',').map(Number);
  if (orbit[0] || orbit[1]) api.orbit(orbit[0], orbit[1]);
  if (light[0] || light[1]) api.light(light[0], light[1]);
  var lines = ['flags ' + api.flags()], i = 0;
  function next() {
    if (i === assets.length) { lines.push('done'); result.textContent = lines.join('\n'); return; }
    var url = assets[i++];
    fetchBytes(url, function (err, bytes) {
      if (err || !api.load(bytes)) { lines.push('error ' + url + ' ' + (err || api.error())); return next(); }
      backends.forEach(function (b) {
        var mode = names.indexOf(b);
        if (mode < 0 || !api.backend(mode) || api.draw() < 0) { lines.push('error ' + url + ' ' + b + ' ' + api.error()); return; }
        lines.push('ok ' + url + ' ' + b + ' ' + w + ' ' + h + ' ' + base64(api.read(w, h)));
      });
      next();
    });
  }
  next();
}

// A scene bundle: scene.txt, then every file it names beside it, handed to the module.
function runScene(url, w, h) {
  var dir = url.lastIndexOf('/') >= 0 ? url.slice(0, url.lastIndexOf('/') + 1) : '';
  fetchBytes(url, function (err, bytes) {
    if (err) { statusBox.textContent = result.textContent = 'error ' + err; return; }
    var text = new TextDecoder().decode(bytes), names = [];
    text.split('\n').forEach(function (line) {
      var w = line.trim().split(/\s+/);
      if (w[0] === 'material' || (w[0] === 'mesh' && /\.mesh$/.test(w[1]))) names.push(w[1]);
    });
    var left = names.length, failed = null;
    function opened() {
      if (failed || !api.sceneOpen(text)) { statusBox.textContent = result.textContent = 'error ' + (failed || api.error()); return; }
      if (params.get('test')) return sceneTest(url, w, h);
      playScene();
    }
    if (!left) return opened();
    names.forEach(function (n) {
      fetchBytes(dir + n, function (e, b) {
        if (e) failed = failed || e; else if (!api.sceneFile(n, b)) failed = failed || api.error();
        if (--left === 0) opened();
      });
    });
  });
}

// ?test=1&scene=...&time=T&backends=gles2,gles2-fused: "ok SCENE BACKEND W H BASE64" lines, "done".
function sceneTest(url, w, h) {
  var names = ['gles2', 'gles2-fused', 'gles2-fused-pixel'], t = parseFloat(params.get('time') || '0');
  var lines = [];
  (params.get('backends') || 'gles2').split(',').forEach(function (b) {
    var mode = names.indexOf(b);
    if (mode < 0 || !api.backend(mode) || api.sceneDraw(t) < 0) { lines.push('error ' + url + ' ' + b + ' ' + api.error()); return; }
    lines.push('ok ' + url + ' ' + b + ' ' + w + ' ' + h + ' ' + base64(api.read(w, h)));
  });
  lines.push('done');
  result.textContent = lines.join('\n');
}

function playScene() {
  var canvas = Module.canvas, drag = false, lx = 0, ly = 0, t0 = performance.now();
  var fixed = params.get('time') ? parseFloat(params.get('time')) : null;
  canvas.addEventListener('pointerdown', function (e) { drag = true; lx = e.clientX; ly = e.clientY; canvas.setPointerCapture(e.pointerId); });
  canvas.addEventListener('pointermove', function (e) {
    if (!drag) return;
    api.sceneOrbit(e.clientX - lx, e.clientY - ly);
    lx = e.clientX; ly = e.clientY;
  });
  canvas.addEventListener('pointerup', function () { drag = false; });
  document.getElementById('backend').addEventListener('change', function (e) { api.backend(parseInt(e.target.value, 10)); });
  function frame() {
    var t = fixed !== null ? fixed : (performance.now() - t0) / 1000;
    lastMs = api.sceneDraw(t);
    showStatus('scene t = ' + t.toFixed(1) + ' s');
    if (lastMs >= 0) requestAnimationFrame(frame);
  }
  requestAnimationFrame(frame);
}

function runBench(frames) {
  fetchBytes(params.get('asset') || 'default.sepal', function (err, bytes) {
    if (err || !api.load(bytes)) { result.textContent = 'error ' + (err || api.error()); return; }
    var times = [];
    for (var i = 0; i < frames + 2; ++i) {
      var ms = api.draw();
      if (ms < 0) { result.textContent = 'error ' + api.error(); return; }
      if (i >= 2) times.push(ms);  // two warm-up frames
    }
    times.sort(function (a, b) { return a - b; });
    var gl = Module.canvas.getContext('webgl'), info = gl && gl.getExtension('WEBGL_debug_renderer_info');
    var device = info ? gl.getParameter(info.UNMASKED_RENDERER_WEBGL) : 'WebGL';
    result.textContent = 'bench ' + frames + ' median_ms ' + times[times.length >> 1] + ' | ' + device + ' | ' + api.status();
  });
}

function start() {
  bind();
  var size = (params.get('size') || '512x512').split('x');
  var w = parseInt(size[0], 10), h = parseInt(size[1], 10);
  if (!api.init('#sepal', w, h) || (params.get('flags') && !api.scene(params.get('flags')))) {
    statusBox.textContent = result.textContent = 'error ' + api.error();
    return;
  }
  var backend = ['gles2', 'gles2-fused', 'gles2-fused-pixel'].indexOf(params.get('backend') || 'gles2');
  if (backend >= 0) { api.backend(backend); document.getElementById('backend').value = String(backend); }
  if (params.get('terms')) { api.terms(parseInt(params.get('terms'), 10)); document.getElementById('terms').value = params.get('terms'); }
  if (params.get('scene')) return runScene(params.get('scene'), w, h);
  if (params.get('test')) return runTest(w, h);
  if (params.get('bench')) return runBench(parseInt(params.get('bench'), 10));
  wire();
  var url = params.get('asset') || 'default.sepal';
  document.getElementById('url').value = url;
  fetchBytes(url, function (err, bytes) { if (err) statusBox.textContent = 'error: ' + err; else loadBytes(bytes, url); });
}

function wire() {
  var canvas = Module.canvas, drag = 0, lx = 0, ly = 0;
  canvas.addEventListener('contextmenu', function (e) { e.preventDefault(); });
  canvas.addEventListener('pointerdown', function (e) {
    drag = e.button === 2 || e.shiftKey ? 2 : e.button === 0 ? 1 : 0;
    lx = e.clientX; ly = e.clientY;
    canvas.setPointerCapture(e.pointerId);
  });
  canvas.addEventListener('pointermove', function (e) {
    if (!drag) return;
    var dx = e.clientX - lx, dy = e.clientY - ly;
    lx = e.clientX; ly = e.clientY;
    if (drag === 1) api.orbit(dx, dy); else api.light(dx, dy);
    redraw();
  });
  canvas.addEventListener('pointerup', function () { drag = 0; });
  canvas.addEventListener('wheel', function (e) { e.preventDefault(); api.zoom(e.deltaY < 0 ? 1 : -1); redraw(); });
  document.getElementById('backend').addEventListener('change', function (e) { api.backend(parseInt(e.target.value, 10)); redraw(); });
  document.getElementById('terms').addEventListener('change', function (e) {
    if (!api.terms(parseInt(e.target.value, 10) || 0)) statusBox.textContent = 'error: ' + api.error(); else redraw();
  });
  document.getElementById('reset').addEventListener('click', function () { api.reset(); redraw(); });
  document.getElementById('load').addEventListener('click', function () {
    var url = document.getElementById('url').value;
    fetchBytes(url, function (err, bytes) { if (err) statusBox.textContent = 'error: ' + err; else loadBytes(bytes, url); });
  });
  function readFile(f) {
    var r = new FileReader();
    r.onload = function () { loadBytes(new Uint8Array(r.result), f.name); };
    r.readAsArrayBuffer(f);
  }
  document.getElementById('file').addEventListener('change', function (e) { if (e.target.files[0]) readFile(e.target.files[0]); });
  document.addEventListener('dragover', function (e) { e.preventDefault(); document.body.classList.add('drop'); });
  document.addEventListener('dragleave', function () { document.body.classList.remove('drop'); });
  document.addEventListener('drop', function (e) {
    e.preventDefault();
    document.body.classList.remove('drop');
    if (e.dataTransfer.files[0]) readFile(e.dataTransfer.files[0]);
  });
}
