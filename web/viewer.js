// The viewer page (docs/web.md): the library's module on a canvas, the
// controls, and `window.parallax`, the same calls for scripts and tests.
'use strict';

(() => {
  const $ = (id) => document.getElementById(id);
  const params = new URLSearchParams(location.search);
  const askedWebgl = params.get('webgl') === '1' ? 1 : 2;
  const canvas = $('canvas');
  const state = { module: null, es: 0, dirty: true, frameTimes: [], drops: 0, scene: '' };

  function showError(message) {
    const box = $('error');
    box.textContent = message || '';
    box.hidden = !message;
  }

  function escapeHtml(s) {
    return String(s).replace(/[&<>"]/g, (c) => ({ '&': '&amp;', '<': '&lt;', '>': '&gt;', '"': '&quot;' }[c]));
  }

  // The C functions (web/viewer.cpp); a failure throws the library's message.
  function api(module) {
    const call = (name, ret, types, args) => module.ccall(name, ret, types, args);
    const lastError = () => call('pxv_error', 'string', [], []);
    const check = (ok) => { if (!ok) throw new Error(lastError()); return ok; };
    return {
      start: (webgl) => check(call('pxv_start', 'number', ['number'], [webgl])),
      context: () => JSON.parse(call('pxv_context_json', 'string', [], [])),
      builtins: () => JSON.parse(call('pxv_builtin_scenes', 'string', [], [])),
      techniques: () => JSON.parse(call('pxv_techniques', 'string', [], [])),
      loadBuiltin: (name) => check(call('pxv_load_builtin', 'number', ['string'], [name])),
      loadFile: (path) => check(call('pxv_load_file', 'number', ['string'], [path])),
      setTechnique: (name, samples) => check(call('pxv_set_technique', 'number', ['string', 'number'], [name, samples])),
      orbit: (yaw, pitch) => call('pxv_orbit', null, ['number', 'number'], [yaw, pitch]),
      pan: (dx, dy) => call('pxv_pan', null, ['number', 'number'], [dx, dy]),
      dolly: (f) => call('pxv_dolly', null, ['number'], [f]),
      resetView: () => call('pxv_reset_view', null, [], []),
      camera: () => JSON.parse(call('pxv_camera_json', 'string', [], [])),
      // wait: 0 none, 1 glFinish, 2 a one-pixel read-back (web/viewer.cpp pxv_draw).
      draw: (w, h, wait = 1) => {
        const ms = call('pxv_draw', 'number', ['number', 'number', 'number'], [w, h, wait]);
        if (ms < 0) throw new Error(lastError());
        return ms;
      },
      report: () => JSON.parse(call('pxv_report_json', 'string', [], [])),
      compileAll: () => JSON.parse(call('pxv_compile_all_json', 'string', [], [])),
      // The scene from its own camera, offscreen, one sample per pixel: PNG bytes.
      renderPng: (w, h) => {
        check(call('pxv_render_png', 'number', ['string', 'number', 'number'], ['/render.png', w, h]));
        return module.FS.readFile('/render.png');
      },
      errorOverlay: (w, h) => {
        const text = call('pxv_error_overlay', 'string', ['string', 'number', 'number'], ['/overlay.png', w, h]);
        if (!text) throw new Error(lastError());
        return { stats: JSON.parse(text), png: module.FS.readFile('/overlay.png') };
      },
      // Files into the page's file system under a fresh folder; returns it.
      writeFiles: (files) => {
        const root = '/drop/' + (++state.drops);
        for (const { path, bytes } of files) {
          const parts = path.split('/').filter((p) => p && p !== '.' && p !== '..');
          let dir = root;
          module.FS.mkdirTree(dir);
          for (const p of parts.slice(0, -1)) { dir += '/' + p; module.FS.mkdirTree(dir); }
          module.FS.writeFile(dir + '/' + parts[parts.length - 1], bytes);
        }
        return root;
      },
    };
  }

  function canvasSize() {
    const ratio = Math.min(window.devicePixelRatio || 1, 2);
    const w = Math.max(1, Math.min(2048, Math.round(canvas.clientWidth * ratio)));
    const h = Math.max(1, Math.min(2048, Math.round(canvas.clientHeight * ratio)));
    if (canvas.width !== w || canvas.height !== h) { canvas.width = w; canvas.height = h; }
    return [w, h];
  }

  function median(values) {
    const s = [...values].sort((a, b) => a - b);
    return s.length ? (s.length % 2 ? s[(s.length - 1) / 2] : (s[s.length / 2 - 1] + s[s.length / 2]) / 2) : 0;
  }

  function drawNow(wait = 0) {
    const p = window.parallax;
    const [w, h] = canvasSize();
    const ms = p.draw(w, h, wait);
    state.frameTimes.push(ms);
    if (state.frameTimes.length > 30) state.frameTimes.shift();
    $('frame-time').textContent = `${w}×${h} · draw() ${ms.toFixed(1)} ms (median of ${state.frameTimes.length}: ${median(state.frameTimes).toFixed(1)} ms)`;
    return ms;
  }

  function showPlan() {
    const rows = window.parallax.report().map((r) => {
      const notes = [...new Set([...r.notes, ...r.plan_notes])].map((n) => `<li>${escapeHtml(n)}</li>`).join('');
      const predicted = r.predicted_error !== undefined
        ? `<div class="notes">predicted error ${r.predicted_error.toFixed(3)} texels, cost ×${r.predicted_cost.toFixed(2)} of normal mapping</div>` : '';
      return `<div class="object"><b>${escapeHtml(r.object)}</b> (${escapeHtml(r.material)}): ${escapeHtml(r.technique)}` +
        `<div class="variant">${escapeHtml(r.variant)}</div>${predicted}<ul class="notes">${notes}</ul></div>`;
    });
    $('plan').innerHTML = rows.join('') || '<p>No objects.</p>';
  }

  function showContext(c) {
    $('context-line').textContent = `WebGL ${c.webgl} · ${c.version} · ${c.renderer}` + (c.fallback ? ` · ${c.fallback}` : '');
    const p = (x) => `${x.bits} bits, 2^${x.range_min}..2^${x.range_max}`;
    $('context').innerHTML = '<table>' + [
      ['WebGL', c.webgl + (c.fallback ? ` (${c.fallback})` : '')],
      ['Version', c.version], ['GLSL', c.glsl_version], ['Renderer', c.renderer], ['Vendor', c.vendor],
      ['Fragment highp', c.fragment_highp ? p(c.fragment_highp_float) : 'none'],
      ['Fragment mediump', p(c.fragment_mediump_float)],
      ['Max texture', c.max_texture_size], ['Varying vectors', c.max_varying_vectors],
      ['Surface capture', c.float_capture ? 'float target' : 'packed RGBA8 passes'],
      ['Compressed formats', c.compressed_formats.join(', ') || 'none'],
      ['Extensions', c.extensions.filter((e) => !e.startsWith('GL_')).join(' ') || c.extensions.join(' ')],
    ].map(([k, v]) => `<tr><td>${escapeHtml(k)}</td><td class="mono">${escapeHtml(v)}</td></tr>`).join('') + '</table>';
    $('webgl-switch').textContent = c.webgl === 2 ? 'Use WebGL 1 (the OpenGL ES 2.0 paths)' : 'Use WebGL 2 (the OpenGL ES 3.0 paths)';
    $('webgl-switch').href = '?webgl=' + (c.webgl === 2 ? 1 : 2);
  }

  // After anything that changes what is drawn: redraw and say what was planned.
  function refresh() {
    state.dirty = true;
    hideOverlay();
  }

  function act(what, fn) {
    try {
      fn();
      showError('');
      refresh();
      return true;
    } catch (e) {
      // Opened files live under /drop/N/ in the page's file system: name them as the user did.
      showError(`${what}: ${e.message}`.replace(/\/drop\/\d+\//g, ''));
      state.dirty = true;
      return false;
    }
  }

  function hideOverlay() {
    $('overlay').hidden = true;
    $('overlay-clear').hidden = true;
    $('overlay-stats').textContent = '';
  }

  function frameLoop() {
    if (state.dirty && window.parallax) {
      state.dirty = false;
      try {
        drawNow();
        showPlan();
      } catch (e) {
        showError(`draw: ${e.message}`);
      }
    }
    requestAnimationFrame(frameLoop);
  }

  // --- input: one pointer orbits (pans with the right button or shift), two pan and pinch ---
  const pointers = new Map();
  let pinch = 0;
  canvas.addEventListener('contextmenu', (e) => e.preventDefault());
  canvas.addEventListener('pointerdown', (e) => {
    canvas.setPointerCapture(e.pointerId);
    pointers.set(e.pointerId, { x: e.clientX, y: e.clientY, button: e.button, shift: e.shiftKey });
    pinch = 0;
  });
  const release = (e) => { pointers.delete(e.pointerId); pinch = 0; };
  canvas.addEventListener('pointerup', release);
  canvas.addEventListener('pointercancel', release);
  canvas.addEventListener('pointermove', (e) => {
    const p = pointers.get(e.pointerId);
    if (!p || !window.parallax) return;
    const dx = e.clientX - p.x, dy = e.clientY - p.y;
    const h = Math.max(1, canvas.clientHeight);
    if (pointers.size === 1) {
      if (p.button === 2 || p.shift) window.parallax.pan(dx / h, dy / h);
      else window.parallax.orbit(dx * 0.4, dy * 0.4);
    } else if (pointers.size === 2) {
      const [a, b] = [...pointers.values()];
      const before = Math.hypot(a.x - b.x, a.y - b.y);
      p.x = e.clientX; p.y = e.clientY;
      const after = Math.hypot(a.x - b.x, a.y - b.y);
      if (pinch && before > 0 && after > 0) window.parallax.dolly(before / after);
      pinch = after;
      window.parallax.pan(dx / h / 2, dy / h / 2);
      refresh();
      return;
    }
    p.x = e.clientX; p.y = e.clientY;
    refresh();
  });
  canvas.addEventListener('wheel', (e) => {
    e.preventDefault();
    if (!window.parallax) return;
    window.parallax.dolly(Math.exp(Math.max(-1, Math.min(1, e.deltaY * 0.002))));
    refresh();
  }, { passive: false });
  canvas.addEventListener('keydown', (e) => {
    if (!window.parallax) return;
    const step = { ArrowLeft: [-5, 0], ArrowRight: [5, 0], ArrowUp: [0, -5], ArrowDown: [0, 5] }[e.key];
    if (step) { window.parallax.orbit(step[0], step[1]); refresh(); e.preventDefault(); }
    if (e.key === '+' || e.key === '=') { window.parallax.dolly(0.9); refresh(); }
    if (e.key === '-') { window.parallax.dolly(1.1); refresh(); }
  });
  window.addEventListener('resize', () => { state.dirty = true; });

  // --- a scene from files: chosen, or dropped (folders included) ---
  async function readEntry(entry, prefix, out) {
    if (entry.isFile) {
      const file = await new Promise((ok, bad) => entry.file(ok, bad));
      out.push({ path: prefix + file.name, bytes: new Uint8Array(await file.arrayBuffer()) });
    } else if (entry.isDirectory) {
      const reader = entry.createReader();
      for (;;) {
        const batch = await new Promise((ok, bad) => reader.readEntries(ok, bad));
        if (!batch.length) break;
        for (const e of batch) await readEntry(e, prefix + entry.name + '/', out);
      }
    }
  }

  // JPEG files become PNG through the browser's own decoder: the web build has
  // no libjpeg (docs/web.md). The library tells formats by their bytes, so
  // the file keeps its name.
  const isJpeg = (b) => b.length > 3 && b[0] === 0xff && b[1] === 0xd8 && b[2] === 0xff;
  async function jpegAsPng(bytes) {
    const bitmap = await createImageBitmap(new Blob([bytes], { type: 'image/jpeg' }),
      { colorSpaceConversion: 'none', premultiplyAlpha: 'none' });
    const c = new OffscreenCanvas(bitmap.width, bitmap.height);
    c.getContext('2d').drawImage(bitmap, 0, 0);
    bitmap.close();
    return new Uint8Array(await (await c.convertToBlob({ type: 'image/png' })).arrayBuffer());
  }

  // files: [{path, bytes}]. The scene is the one .json file (the shallowest
  // where there are several); its textures are found beside it as it names them.
  async function openFiles(files) {
    for (const f of files) {
      if (!isJpeg(f.bytes)) continue;
      try { f.bytes = await jpegAsPng(f.bytes); } catch (e) { showError(`open ${f.path}: the browser cannot decode this JPEG (${e.message})`); return false; }
    }
    const scenes = files.filter((f) => f.path.toLowerCase().endsWith('.json'))
      .sort((a, b) => a.path.split('/').length - b.path.split('/').length);
    if (!scenes.length) {
      showError('open: no scene file (.json) among ' + files.map((f) => f.path).join(', '));
      return false;
    }
    const root = window.parallax.writeFiles(files);
    const memfsPath = (f) => root + '/' + f.path.split('/').filter((p) => p && p !== '.' && p !== '..').join('/');
    // Every .json among them goes into the scene list (a folder may hold
    // several scenes, or other JSON): the first is opened.
    const select = $('scene');
    let group = select.querySelector('optgroup');
    if (!group) { group = document.createElement('optgroup'); group.label = 'Opened from files'; select.add(group); }
    group.replaceChildren(...scenes.map((f) => new Option(f.path, 'file:' + memfsPath(f))));
    const ok = act(`open ${scenes[0].path}`, () => window.parallax.loadFile(memfsPath(scenes[0])));
    if (ok) { select.value = 'file:' + memfsPath(scenes[0]); state.scene = scenes[0].path; }
    else if (scenes.length > 1) showError($('error').textContent + `\n(${scenes.length} .json files were opened: choose the scene under Scene.)`);
    return ok;
  }

  async function filesFromInput(input) {
    const out = [];
    for (const f of input.files) out.push({ path: f.webkitRelativePath || f.name, bytes: new Uint8Array(await f.arrayBuffer()) });
    input.value = '';
    return out;
  }
  $('scene-files').addEventListener('change', (e) => { state.opened = filesFromInput(e.target).then(openFiles); });
  $('scene-folder').addEventListener('change', (e) => { state.opened = filesFromInput(e.target).then(openFiles); });

  let dragDepth = 0;
  document.addEventListener('dragenter', (e) => { e.preventDefault(); dragDepth++; $('drop-veil').hidden = false; });
  document.addEventListener('dragleave', () => { if (--dragDepth <= 0) { dragDepth = 0; $('drop-veil').hidden = true; } });
  document.addEventListener('dragover', (e) => e.preventDefault());
  document.addEventListener('drop', (e) => {
    e.preventDefault();
    dragDepth = 0;
    $('drop-veil').hidden = true;
    if (!window.parallax) return;
    // The entries must be taken before the event returns.
    const entries = [...(e.dataTransfer.items || [])].map((i) => i.webkitGetAsEntry && i.webkitGetAsEntry()).filter(Boolean);
    const files = [...e.dataTransfer.files];
    state.opened = (async () => {
      const out = [];
      if (entries.length) for (const entry of entries) await readEntry(entry, '', out);
      else for (const f of files) out.push({ path: f.name, bytes: new Uint8Array(await f.arrayBuffer()) });
      return openFiles(out);
    })();
  });

  // --- controls ---
  $('scene').addEventListener('change', (e) => {
    const v = e.target.value;
    if (!v) return;
    if (v.startsWith('file:')) {
      const path = v.slice(5);
      if (act(`open ${path.replace(/^\/drop\/\d+\//, '')}`, () => window.parallax.loadFile(path))) state.scene = path;
    } else if (act(`scene ${v}`, () => window.parallax.loadBuiltin(v))) {
      state.scene = v;
    }
  });
  function applyTechnique() {
    const t = $('technique').value;
    const n = Number($('samples').value);
    $('samples-value').textContent = n ? String(n) : 'default';
    act(`technique ${t}`, () => window.parallax.setTechnique(t, n));
  }
  $('technique').addEventListener('change', () => {
    const t = window.parallax.techniques().find((x) => x.name === $('technique').value);
    $('samples').disabled = !t;
    if (t) $('samples').max = String(Math.min(t.max_samples, 256));
    applyTechnique();
  });
  $('samples').addEventListener('input', () => { $('samples-value').textContent = $('samples').value === '0' ? 'default' : $('samples').value; });
  $('samples').addEventListener('change', applyTechnique);
  $('reset-view').addEventListener('click', () => { window.parallax.resetView(); refresh(); });
  $('measure').addEventListener('click', () => {
    const times = [];
    try {
      for (let i = 0; i < 33; i++) { const ms = drawNow(2); if (i >= 3) times.push(ms); }
      $('measure-result').textContent = `median ${median(times).toFixed(2)} ms over 30 frames at ${canvas.width}×${canvas.height} (3 warm-up frames left out; each timed from the draw call to a pixel read back)`;
    } catch (e) { showError(`measure: ${e.message}`); }
  });
  $('overlay-button').addEventListener('click', () => {
    const size = Number($('overlay-size').value);
    const aspect = canvas.width / Math.max(1, canvas.height);
    const w = aspect >= 1 ? size : Math.max(1, Math.round(size * aspect));
    const h = aspect >= 1 ? Math.max(1, Math.round(size / aspect)) : size;
    $('overlay-stats').textContent = 'tracing the exact reference…';
    setTimeout(() => {
      try {
        const { stats, png } = window.parallax.errorOverlay(w, h);
        const img = $('overlay');
        if (img.src.startsWith('blob:')) URL.revokeObjectURL(img.src);
        img.src = URL.createObjectURL(new Blob([png], { type: 'image/png' }));
        img.hidden = false;
        $('overlay-clear').hidden = false;
        $('overlay-stats').innerHTML = `${w}×${h}: ${stats.pixels} pixels, hit error mean ${stats.mean.toFixed(3)}, ` +
          `p95 ${stats.p95.toFixed(3)}, max ${stats.max.toFixed(2)} texels · GPU capture ${stats.capture_ms.toFixed(0)} ms, ` +
          `reference ${stats.reference_ms.toFixed(0)} ms<div class="legend-bar"></div>0 · 1 · 4+ texels`;
        state.dirty = true;  // the canvas draws at its own size again
      } catch (e) {
        $('overlay-stats').textContent = '';
        showError(`hit error: ${e.message}`);
      }
    }, 20);
  });
  $('overlay-clear').addEventListener('click', hideOverlay);

  // --- start ---
  window.parallaxReady = createParallaxViewer({
    print: (t) => console.log(t),
    printErr: (t) => console.error(t),
  }).then((module) => {
    const p = api(module);
    // Scripts wait for a chosen or dropped scene with `await parallax.opened()`,
    // or open files themselves: `await parallax.openFiles([{path, bytes}])`.
    p.opened = () => state.opened;
    p.openFiles = (files) => (state.opened = openFiles(files));
    window.parallax = p;
    state.es = p.start(askedWebgl);
    showContext(p.context());
    for (const name of p.builtins()) $('scene').add(new Option(name, name));
    for (const t of p.techniques()) {
      if (t.min_es <= state.es) $('technique').add(new Option(`${t.name}: ${t.summary}`, t.name));
    }
    const first = params.get('scene') || 'showcase';
    $('scene').value = first;
    p.loadBuiltin(first);
    state.scene = first;
    canvas.focus();
    requestAnimationFrame(frameLoop);
    return p;
  }).catch((e) => {
    showError(`start: ${e.message}`);
    $('context-line').textContent = 'not started';
    throw e;
  });
})();
