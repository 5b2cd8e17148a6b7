/* hovox view - the page's script (src/viewer/assets/viewer.js, embedded by the build into the
 * pages hovox writes). Plain JavaScript, no library: it reads the data document the page carries
 * (#hovox-data), draws a stack's layers from their PNG files next to the page (never reading
 * their pixels back: a page opened from file:// may not) and everything else from the images the
 * page carries inside. window.hovoxView is the page's state, for tests and the curious. */
(function () {
  'use strict';

  var D = JSON.parse(document.getElementById('hovox-data').textContent);
  var app = document.getElementById('app');
  var api = window.hovoxView = { kind: D.kind, ready: false, errors: [] };

  /* ---- small helpers ------------------------------------------------------------------------ */

  function el(tag, attrs, kids) {
    var e = document.createElement(tag);
    if (attrs) {
      for (var k in attrs) {
        if (!Object.prototype.hasOwnProperty.call(attrs, k)) continue;
        var v = attrs[k];
        if (k === 'text') e.textContent = v;
        else if (k === 'class') e.className = v;
        else if (k.slice(0, 2) === 'on') e.addEventListener(k.slice(2), v);
        else if (v !== null && v !== undefined && v !== false) e.setAttribute(k, v === true ? '' : v);
      }
    }
    (kids || []).forEach(function (c) {
      if (c === null || c === undefined) return;
      e.appendChild(typeof c === 'string' || typeof c === 'number' ? document.createTextNode(String(c)) : c);
    });
    return e;
  }

  function num(v, digits) {
    if (v === null || v === undefined || typeof v !== 'number' || !isFinite(v)) return '-';
    var d = digits === undefined ? 4 : digits;
    var s = v.toFixed(d);
    return s.indexOf('.') >= 0 ? s.replace(/0+$/, '').replace(/\.$/, '') : s;
  }

  function mm(v) { return num(v, 3) + ' mm'; }

  /* a fraction in a table: four decimals, always */
  function frac(v) { return typeof v === 'number' && isFinite(v) ? v.toFixed(4) : '-'; }

  function signed(v) {
    if (typeof v !== 'number' || !isFinite(v)) return '-';
    var t = Math.abs(v).toFixed(4);
    return +t === 0 ? '0.0000' : (v > 0 ? '+' : '\u2212') + t;
  }

  function swatch(color) { return el('span', { class: 'swatch', style: 'background:' + color }); }

  function hexRgb(c) {
    return [parseInt(c.slice(1, 3), 16), parseInt(c.slice(3, 5), 16), parseInt(c.slice(5, 7), 16)];
  }

  /* a path relative to the page, each part URL-encoded (names may hold spaces, '#', '?') */
  function url(base, file) {
    var parts = (base + file).split('/');
    return parts.map(function (p) { return p === '..' || p === '.' ? p : encodeURIComponent(p); }).join('/');
  }

  function kvTable(rows) {
    return el('table', { class: 'kv' }, rows.filter(function (r) { return r && r[1] !== undefined && r[1] !== null; })
      .map(function (r) { return el('tr', null, [el('th', { text: r[0] }), el('td', { text: String(r[1]) })]); }));
  }

  function keysTable(rows) {
    return el('table', { class: 'keys' }, rows.map(function (r) {
      return el('tr', null, [el('td', { text: r[0] }), el('td', { text: r[1] })]);
    }));
  }

  /* ---- a zoomable, pannable canvas -------------------------------------------------------------
   * The content is a grid of sw x sh cells; a cell is `scale` device pixels wide and scale * aspect
   * tall. At scale 1 and an integral aspect every cell is drawn by nearest sampling exactly. */

  function Zoom(box, opts) {
    var z = this;
    z.box = box;
    z.canvas = el('canvas');
    box.appendChild(z.canvas);
    z.ctx = z.canvas.getContext('2d');
    z.sw = 1; z.sh = 1; z.aspect = 1;
    z.scale = 1; z.ox = 0; z.oy = 0;
    z.fitted = true;
    z.draw = opts.draw;
    z.onmove = opts.onmove || function () {};
    z.onclick = opts.onclick || function () {};
    z.onchange = opts.onchange || function () {};
    var drag = null;
    z.canvas.addEventListener('pointerdown', function (ev) {
      drag = { x: ev.clientX, y: ev.clientY, ox: z.ox, oy: z.oy, moved: false };
      z.canvas.setPointerCapture(ev.pointerId);
    });
    z.canvas.addEventListener('pointermove', function (ev) {
      var p = z.cellAt(ev);
      z.onmove(p, ev);
      if (!drag) return;
      var dpr = window.devicePixelRatio || 1;
      var dx = (ev.clientX - drag.x) * dpr, dy = (ev.clientY - drag.y) * dpr;
      if (Math.abs(dx) + Math.abs(dy) > 3) drag.moved = true;
      if (drag.moved) {
        z.ox = Math.round(drag.ox + dx);
        z.oy = Math.round(drag.oy + dy);
        z.fitted = false;
        z.redraw();
      }
    });
    z.canvas.addEventListener('pointerup', function (ev) {
      if (drag && !drag.moved) z.onclick(z.cellAt(ev), ev);
      drag = null;
    });
    z.canvas.addEventListener('pointerleave', function () { z.onmove(null); });
    z.canvas.addEventListener('wheel', function (ev) {
      ev.preventDefault();
      var r = z.canvas.getBoundingClientRect(), dpr = window.devicePixelRatio || 1;
      z.zoomAt(ev.deltaY < 0 ? 1.25 : 0.8, (ev.clientX - r.left) * dpr, (ev.clientY - r.top) * dpr);
    }, { passive: false });
    if (window.ResizeObserver) new ResizeObserver(function () { z.resize(); }).observe(box);
    window.addEventListener('resize', function () { z.resize(); });
    z.resize();
  }

  Zoom.prototype.resize = function () {
    var dpr = window.devicePixelRatio || 1;
    /* the canvas on whole device pixels, or the browser resamples what it shows */
    var r = this.box.getBoundingClientRect();
    var fx = (Math.ceil(r.left * dpr - 1e-6) - r.left * dpr) / dpr, fy = (Math.ceil(r.top * dpr - 1e-6) - r.top * dpr) / dpr;
    this.canvas.style.left = fx + 'px';
    this.canvas.style.top = fy + 'px';
    var w = Math.max(1, Math.floor((this.box.clientWidth - fx) * dpr)), h = Math.max(1, Math.floor((this.box.clientHeight - fy) * dpr));
    this.canvas.style.width = w / dpr + 'px';
    this.canvas.style.height = h / dpr + 'px';
    if (w !== this.canvas.width || h !== this.canvas.height) {
      this.canvas.width = w;
      this.canvas.height = h;
    }
    if (this.fitted) this.fit(); else this.redraw();
  };

  Zoom.prototype.setContent = function (sw, sh, aspect, keep) {
    var same = sw === this.sw && sh === this.sh && aspect === this.aspect;
    this.sw = sw; this.sh = sh; this.aspect = aspect;
    if (!same && !keep) this.fitted = true;
    if (this.fitted) this.fit(); else this.redraw();
  };

  Zoom.prototype.fit = function () {
    var cw = this.canvas.width, ch = this.canvas.height;
    var s = Math.min(cw / this.sw, ch / (this.sh * this.aspect)) * 0.96;
    if (!(s > 0) || !isFinite(s)) s = 1;
    if (s > 1) s = Math.floor(s); /* integral magnification keeps every cell the same size */
    this.scale = s;
    this.ox = Math.round((cw - this.sw * s) / 2);
    this.oy = Math.round((ch - this.sh * s * this.aspect) / 2);
    this.fitted = true;
    this.redraw();
  };

  Zoom.prototype.set = function (scale, ox, oy) {
    this.scale = scale;
    this.ox = Math.round(ox);
    this.oy = Math.round(oy);
    this.fitted = false;
    this.redraw();
  };

  Zoom.prototype.zoomAt = function (f, px, py) {
    var s = this.scale * f;
    if (s > 0.8 && s < 1.25) s = 1;
    else if (s > 1) s = f > 1 ? Math.ceil(s) : Math.floor(s);
    s = Math.min(Math.max(s, 1 / 64), 256);
    if (px === undefined) { px = this.canvas.width / 2; py = this.canvas.height / 2; }
    var cx = (px - this.ox) / this.scale, cy = (py - this.oy) / (this.scale * this.aspect);
    this.set(s, px - cx * s, py - cy * s * this.aspect);
  };

  Zoom.prototype.cellAt = function (ev) {
    var r = this.canvas.getBoundingClientRect(), dpr = window.devicePixelRatio || 1;
    var px = (ev.clientX - r.left) * dpr, py = (ev.clientY - r.top) * dpr;
    return { x: (px - this.ox) / this.scale, y: (py - this.oy) / (this.scale * this.aspect) };
  };

  /* cell coordinates to canvas pixels */
  Zoom.prototype.toX = function (x) { return this.ox + x * this.scale; };
  Zoom.prototype.toY = function (y) { return this.oy + y * this.scale * this.aspect; };

  Zoom.prototype.redraw = function () {
    var ctx = this.ctx;
    ctx.setTransform(1, 0, 0, 1, 0, 0);
    ctx.clearRect(0, 0, this.canvas.width, this.canvas.height);
    ctx.imageSmoothingEnabled = this.scale < 1;
    this.draw(ctx, this);
    this.onchange(this);
  };

  /* Draw the visible part of an image (or canvas) of sw x sh cells: whole source cells only, so
   * nearest sampling keeps cell edges on the same device pixels. */
  Zoom.prototype.image = function (ctx, img) {
    var s = this.scale, a = this.aspect;
    var x0 = Math.max(0, Math.floor(-this.ox / s)), y0 = Math.max(0, Math.floor(-this.oy / (s * a)));
    var x1 = Math.min(this.sw, Math.ceil((this.canvas.width - this.ox) / s));
    var y1 = Math.min(this.sh, Math.ceil((this.canvas.height - this.oy) / (s * a)));
    if (x1 <= x0 || y1 <= y0) return;
    ctx.drawImage(img, x0, y0, x1 - x0, y1 - y0, this.ox + x0 * s, this.oy + y0 * s * a, (x1 - x0) * s, (y1 - y0) * s * a);
  };

  function zoomButtons(getZoom) {
    return [
      el('button', { title: 'zoom out (-)', text: '\u2212', onclick: function () { getZoom().zoomAt(0.8); } }),
      el('button', { title: 'fit (f)', text: 'fit', onclick: function () { getZoom().fit(); } }),
      el('button', { title: 'one layer pixel per screen pixel across (1)', text: '1:1', onclick: function () {
        var z = getZoom();
        z.zoomAt(1 / z.scale);
      } }),
      el('button', { title: 'zoom in (+)', text: '+', onclick: function () { getZoom().zoomAt(1.25); } })
    ];
  }

  /* Sum of colour x grey image per channel (fractions: sum p_j colour_j), into a new canvas. Works on
   * images from other files: compositing never reads pixels back. */
  function composite(images, colors, w, h) {
    var out = document.createElement('canvas');
    out.width = w; out.height = h;
    var o = out.getContext('2d');
    o.fillStyle = '#000';
    o.fillRect(0, 0, w, h);
    var tmp = document.createElement('canvas');
    tmp.width = w; tmp.height = h;
    var t = tmp.getContext('2d');
    for (var j = 0; j < images.length; ++j) {
      t.globalCompositeOperation = 'copy';
      t.drawImage(images[j], 0, 0);
      t.globalCompositeOperation = 'multiply';
      t.fillStyle = colors[j];
      t.fillRect(0, 0, w, h);
      o.globalCompositeOperation = 'lighter';
      o.drawImage(tmp, 0, 0);
    }
    return out;
  }

  function loadImage(src) {
    return new Promise(function (resolve, reject) {
      var img = new Image();
      img.onload = function () { resolve(img); };
      img.onerror = function () { reject(new Error('cannot load ' + decodeURIComponent(src.slice(0, 200)))); };
      img.src = src;
    });
  }

  function header(title, meta) {
    document.title = title;
    app.appendChild(el('header', null, [el('h1', { text: title }), el('span', { class: 'meta', text: meta })]));
  }

  /* ==== stacks and trays ======================================================================== */

  function stackPage() {
    var N = D.index.length, W = D.width, H = D.height;
    var sx = D.pixel_mm[0], sy = D.pixel_mm[1];
    var aspect = Math.abs(sy) / sx; /* a row's height in column widths: 2 on the J750 */
    var tray = D.kind === 'tray', fractions = D.mode === 'fractions';
    var chanColors = fractions ? D.channels.map(function (c) { return c.color; }) : null;
    var st = { li: 0, chan: -1, outlines: true, axis: 'row', part: 0, cut: 0, exag: 1, drawn: -1, sideDrawn: null };

    header(D.title, (tray ? 'tray' : 'stack') + ' \u00b7 ' + D.mode + ' \u00b7 ' + N + ' layer' + (N === 1 ? '' : 's') +
      ' of ' + W + ' \u00d7 ' + H + ' pixels \u00b7 ' + num(sx, 5) + ' \u00d7 ' + num(Math.abs(sy), 5) + ' mm (' +
      num(D.dpi[0], 1) + ' \u00d7 ' + num(D.dpi[1], 1) + ' dpi) \u00b7 ' + num(D.layer_height_mm, 4) + ' mm layers');

    var layout = el('div', { class: 'layout' });
    var main = el('div', { class: 'main' });
    var side = el('div', { class: 'side' });
    layout.appendChild(main);
    layout.appendChild(side);
    app.appendChild(layout);

    /* -- the layer toolbar -- */
    var slider = el('input', { type: 'range', min: 0, max: N - 1, value: 0, step: 1, 'aria-label': 'layer',
      oninput: function () { setLayer(+slider.value); } });
    var numBox = el('input', { type: 'number', min: D.index[0], max: D.index[N - 1], value: D.index[0],
      'aria-label': 'layer index', onchange: function () {
        var want = +numBox.value, best = 0;
        for (var i = 0; i < N; ++i) if (Math.abs(D.index[i] - want) < Math.abs(D.index[best] - want)) best = i;
        setLayer(best);
      } });
    var zLabel = el('span', { class: 'value' });
    var zoomLabel = el('span', { class: 'value' });
    var chanSel = null;
    if (fractions) {
      chanSel = el('select', { 'aria-label': 'material shown', onchange: function () {
        st.chan = +chanSel.value; layerZoom.redraw(); sideRedraw(); } },
      [el('option', { value: -1, text: 'all materials' })].concat(D.channels.map(function (c, j) {
        return el('option', { value: j, text: c.name + ' only' });
      })));
    }
    var outlineBtn = el('button', { class: 'on', title: 'outlines, part boxes and names, the cut (o)', text: 'outlines',
      onclick: function () { toggleOutlines(); } });
    main.appendChild(el('div', { class: 'toolbar' }, [
      el('button', { title: 'previous layer (\u2190)', text: '\u25c0', onclick: function () { step(-1); } }),
      el('span', { class: 'grow' }, [slider]),
      el('button', { title: 'next layer (\u2192)', text: '\u25b6', onclick: function () { step(1); } }),
      el('label', { text: 'layer' }), numBox, zLabel
    ].concat([el('span', { text: '\u2003' })], zoomButtons(function () { return layerZoom; }), [zoomLabel, outlineBtn, chanSel])));

    var layerBox = el('div', { class: 'canvas-box' });
    var note = el('div', { class: 'note', text: 'loading\u2026' });
    layerBox.appendChild(note);
    main.appendChild(layerBox);
    var status = el('div', { class: 'status', text: '\u00a0' });
    main.appendChild(status);

    /* -- the side-view toolbar -- */
    var rowBtn = el('button', { title: 'cut along a row: x\u2013z (s switches)', text: 'x\u2013z', onclick: function () { setAxis('row'); } });
    var colBtn = el('button', { title: 'cut along a column: y\u2013z (s switches)', text: 'y\u2013z', onclick: function () { setAxis('col'); } });
    var cutSlider = el('input', { type: 'range', min: 0, max: 0, value: 0, step: 1, 'aria-label': 'cut',
      oninput: function () { setCut(+cutSlider.value); } });
    var cutLabel = el('span', { class: 'value' });
    var partSel = null;
    if (D.parts.length > 1) {
      partSel = el('select', { 'aria-label': 'part', onchange: function () { setPart(+partSel.value); } },
        D.parts.map(function (p, i) { return el('option', { value: i, text: partLabel(i) }); }));
    }
    var exagSel = el('select', { title: 'stretch the height', 'aria-label': 'height stretch', onchange: function () {
      st.exag = +exagSel.value; sideRedraw(true); } },
    [1, 2, 4, 8, 16].map(function (v) { return el('option', { value: v, text: 'z \u00d7' + v }); }));
    main.appendChild(el('div', { class: 'toolbar' }, [el('label', { text: 'side view' }), rowBtn, colBtn, partSel,
      el('span', { class: 'grow' }, [cutSlider]), cutLabel, exagSel].concat(zoomButtons(function () { return sideZoom; }))));
    var sideBox = el('div', { class: 'canvas-box side-view' });
    var sideNote = el('div', { class: 'note' });
    sideBox.appendChild(sideNote);
    main.appendChild(sideBox);

    /* -- layer images, loaded when shown (the next and previous ones ahead) -- */
    var cache = new Map(), order = [];
    function entry(li) {
      var e = cache.get(li);
      if (e) return e;
      e = { li: li, state: 'loading', img: null, chans: null, err: null };
      cache.set(li, e);
      order.push(li);
      var srcs = D.files.map(function (list) { return url(D.base, list[li]); });
      e.promise = Promise.all(srcs.map(loadImage)).then(function (imgs) {
        e.chans = imgs;
        e.img = fractions ? composite(imgs, chanColors, W, H) : imgs[0];
        e.state = 'ok';
      }, function (err) {
        e.state = 'error';
        e.err = err.message;
        api.errors.push(err.message);
      });
      /* keep the memory of a few big layers at most */
      var limit = Math.max(3, Math.min(24, Math.floor(4e8 / (W * H * 4 * (fractions ? D.channels.length + 1 : 1)))));
      while (order.length > limit) {
        var old = order.shift();
        if (Math.abs(old - st.li) > 1) cache.delete(old); else order.push(old);
        if (order.length <= limit || order.every(function (k) { return Math.abs(k - st.li) <= 1; })) break;
      }
      return e;
    }

    function shown(e) {
      if (!e || e.state !== 'ok') return null;
      if (!fractions || st.chan < 0) return e.img;
      return e.chans[st.chan];
    }

    var layerZoom = new Zoom(layerBox, {
      draw: function (ctx, z) {
        var e = cache.get(st.li);
        var img = shown(e);
        if (img) z.image(ctx, img);
        drawOverlay(ctx, z);
      },
      onchange: function (z) { zoomLabel.textContent = z.scale >= 1 ? num(z.scale, 0) + ':1' : '1:' + num(1 / z.scale, 1); },
      onmove: function (p) { showStatus(p); },
      onclick: function (p, ev) { if (ev.shiftKey) cutAt(p); }
    });
    layerZoom.setContent(W, H, aspect);

    function partName(p) { return p.name + (tray && p.copy ? ' #' + p.copy : ''); }
    function partLabel(i) { return (tray ? (i + 1) + ': ' : '') + partName(D.parts[i]); }

    function inLayers(p, li) { return li >= p.layers[0] && li < p.layers[1]; }

    function drawOverlay(ctx, z) {
      if (!st.outlines) return;
      var cut = currentCut();
      if (cut) { /* where the side view cuts */
        ctx.save();
        ctx.strokeStyle = '#46e0ff';
        ctx.setLineDash([6, 4]);
        ctx.lineWidth = 1;
        ctx.beginPath();
        if (cut.axis === 'row') {
          var y = Math.round(z.toY(cut.pos + 0.5)) + 0.5;
          ctx.moveTo(z.toX(cut.from), y); ctx.lineTo(z.toX(cut.to), y);
        } else {
          var x = Math.round(z.toX(cut.pos + 0.5)) + 0.5;
          ctx.moveTo(x, z.toY(cut.from)); ctx.lineTo(x, z.toY(cut.to));
        }
        ctx.stroke();
        ctx.restore();
      }
      ctx.save();
      ctx.font = Math.round(12 * (window.devicePixelRatio || 1)) + 'px system-ui, sans-serif';
      ctx.textBaseline = 'bottom';
      D.parts.forEach(function (p, i) {
        var on = inLayers(p, st.li);
        if (!tray && !on) return;
        var b = p.box_px;
        ctx.globalAlpha = on ? 1 : 0.45;
        if (tray) { /* the part's box on the plate */
          ctx.strokeStyle = '#ffcf3f';
          ctx.setLineDash([4, 4]);
          ctx.lineWidth = 1;
          ctx.strokeRect(Math.round(z.toX(b[0])) + 0.5, Math.round(z.toY(b[1])) + 0.5, Math.round(b[2] * z.scale),
            Math.round(b[3] * z.scale * z.aspect));
        }
        ctx.setLineDash([]);
        ctx.strokeStyle = i === st.part ? '#ffcf3f' : '#ffe699';
        ctx.lineWidth = 1.5;
        ctx.beginPath();
        p.outline.forEach(function (loop) {
          for (var k = 0; k < loop.length; k += 2) {
            var X = z.toX(loop[k]), Y = z.toY(loop[k + 1]);
            if (k === 0) ctx.moveTo(X, Y); else ctx.lineTo(X, Y);
          }
          ctx.closePath();
        });
        ctx.stroke();
        if (tray) {
          var label = partLabel(i), tx = Math.round(z.toX(b[0])) + 2, ty = Math.round(z.toY(b[1])) - 2;
          var tw = ctx.measureText(label).width;
          ctx.fillStyle = 'rgba(0,0,0,0.7)';
          ctx.fillRect(tx - 2, ty - 16 * (window.devicePixelRatio || 1), tw + 4, 16 * (window.devicePixelRatio || 1));
          ctx.fillStyle = '#ffcf3f';
          ctx.fillText(label, tx, ty);
        }
      });
      ctx.restore();
    }

    function showStatus(p) {
      if (!p) { status.textContent = '\u00a0'; return; }
      var c = Math.floor(p.x), r = Math.floor(p.y);
      if (c < 0 || r < 0 || c >= W || r >= H) { status.textContent = '\u00a0'; return; }
      var x = D.origin_mm[0] + (c + 0.5) * sx, y = D.origin_mm[1] + (r + 0.5) * sy;
      var s = 'column ' + c + ', row ' + r + ' \u00b7 x ' + mm(x) + ', y ' + mm(y) + ', z ' + mm(D.z_mm[st.li]);
      D.parts.forEach(function (pt) {
        var b = pt.box_px;
        if (tray && c >= b[0] && c < b[0] + b[2] && r >= b[1] && r < b[1] + b[3]) s += ' \u00b7 part ' + partLabel(D.parts.indexOf(pt));
      });
      status.textContent = s + ' \u00b7 shift-click: cut here';
    }

    /* -- layers -- */
    function setLayer(li) {
      li = Math.max(0, Math.min(N - 1, li | 0));
      st.li = li;
      slider.value = li;
      numBox.value = D.index[li];
      zLabel.textContent = 'z ' + mm(D.z_mm[li]) + ' (' + (li + 1) + ' of ' + N + ')';
      var e = entry(li);
      if (li + 1 < N) entry(li + 1);
      if (li > 0) entry(li - 1);
      note.textContent = 'loading ' + D.files[0][li] + '\u2026';
      note.className = 'note';
      note.hidden = e.state === 'ok';
      layerZoom.redraw();
      sideRedraw();
      e.promise.then(function () {
        if (st.li !== li) return;
        if (e.state === 'error') {
          note.hidden = false;
          note.className = 'note error';
          note.textContent = e.err + ' (is the stack next to this page?)';
        } else {
          note.hidden = true;
        }
        layerZoom.redraw();
        st.drawn = li;
        api.drawnLayer = li;
      });
    }

    function step(d) { setLayer(st.li + d); }

    function toggleOutlines() {
      st.outlines = !st.outlines;
      outlineBtn.className = st.outlines ? 'on' : '';
      layerZoom.redraw();
    }

    /* -- side views -- */
    var cutImages = new Map(); /* cut index -> canvas (composited) */
    function cutsOf(part, axis) {
      var list = [];
      D.cuts.forEach(function (c, i) { if (c.part === part && c.axis === axis) list.push(i); });
      return list;
    }
    function currentList() { return cutsOf(st.part, st.axis); }
    function currentCut() { var l = currentList(); return l.length ? D.cuts[l[Math.min(st.cut, l.length - 1)]] : null; }
    function currentCutIndex() { var l = currentList(); return l.length ? l[Math.min(st.cut, l.length - 1)] : -1; }

    function cutImage(ci) {
      var got = cutImages.get(ci);
      if (got) return got;
      var c = D.cuts[ci];
      got = { state: 'loading', img: null, chans: null };
      cutImages.set(ci, got);
      got.promise = Promise.all(c.images.map(loadImage)).then(function (imgs) {
        got.chans = imgs;
        got.img = fractions ? composite(imgs, chanColors, c.w, c.h) : imgs[0];
        got.state = 'ok';
      }, function (err) { got.state = 'error'; api.errors.push(err.message); });
      return got;
    }

    var sideZoom = new Zoom(sideBox, {
      draw: function (ctx, z) {
        var ci = currentCutIndex();
        if (ci < 0) return;
        var c = D.cuts[ci], g = cutImage(ci);
        if (g.state === 'ok') z.image(ctx, fractions && st.chan >= 0 ? g.chans[st.chan] : g.img);
        /* the current layer */
        var k = layerSample(c, st.li);
        if (k >= 0 && st.outlines) {
          var y = Math.round(z.toY(c.h - 1 - k + 0.5)) + 0.5;
          ctx.save();
          ctx.strokeStyle = '#ffcf3f';
          ctx.setLineDash([6, 4]);
          ctx.beginPath(); ctx.moveTo(z.ox, y); ctx.lineTo(z.toX(c.w), y); ctx.stroke();
          ctx.restore();
        }
      },
      onmove: function (p) {
        var c = currentCut();
        if (!p || !c) return;
        var k = c.h - 1 - Math.floor(p.y), li = pickLayer(c, k);
        var t = Math.floor(p.x);
        if (li < 0 || t < 0 || t >= c.w) { status.textContent = '\u00a0'; return; }
        var along = pick(c.from, c.to, D.cut_step, t);
        status.textContent = 'side view: ' + (c.axis === 'row' ? 'column ' + along + ', row ' + c.pos : 'column ' + c.pos +
          ', row ' + along) + ' \u00b7 layer ' + D.index[li] + ', z ' + mm(D.z_mm[li]) + ' \u00b7 click: show this layer';
      },
      onclick: function (p) {
        var c = currentCut();
        if (!p || !c) return;
        var li = pickLayer(c, c.h - 1 - Math.floor(p.y));
        if (li >= 0) setLayer(li);
      }
    });

    function pick(lo, hi, s, k) { var a = lo + k * s, n = Math.min(s, hi - a); return a + Math.floor((n - 1) / 2); }
    function pickLayer(c, k) { return k >= 0 && k < c.h ? pick(c.l0, c.l1, D.cut_step, k) : -1; }
    function layerSample(c, li) {
      if (li < c.l0 || li >= c.l1) return -1;
      var k = Math.floor((li - c.l0) / D.cut_step);
      return pick(c.l0, c.l1, D.cut_step, k) === li ? k : Math.min(k, c.h - 1);
    }

    function sideRedraw(refit) {
      var ci = currentCutIndex();
      rowBtn.className = st.axis === 'row' ? 'on' : '';
      colBtn.className = st.axis === 'col' ? 'on' : '';
      var list = currentList();
      cutSlider.max = Math.max(0, list.length - 1);
      cutSlider.value = Math.min(st.cut, list.length - 1);
      if (ci < 0) {
        sideNote.hidden = false;
        sideNote.textContent = 'no side view (the part has no layers here)';
        cutLabel.textContent = '';
        sideZoom.redraw();
        return;
      }
      var c = D.cuts[ci];
      var pitch = c.axis === 'row' ? sx : Math.abs(sy);
      var mmPos = c.axis === 'row' ? D.origin_mm[1] + (c.pos + 0.5) * sy : D.origin_mm[0] + (c.pos + 0.5) * sx;
      cutLabel.textContent = (c.axis === 'row' ? 'row ' + c.pos + ', y ' : 'column ' + c.pos + ', x ') + mm(mmPos) +
        ' (' + (Math.min(st.cut, list.length - 1) + 1) + ' of ' + list.length + ')' +
        (D.cut_step > 1 ? ' \u00b7 one pixel and layer in ' + D.cut_step : '');
      var g = cutImage(ci);
      sideNote.hidden = g.state === 'ok';
      sideNote.textContent = 'loading\u2026';
      sideZoom.setContent(c.w, c.h, D.layer_height_mm / pitch * st.exag, !refit);
      if (refit) sideZoom.fit();
      g.promise.then(function () {
        if (currentCutIndex() !== ci) return;
        sideNote.hidden = true;
        sideZoom.redraw();
        st.sideDrawn = ci;
        api.sideDrawn = ci;
      });
    }

    function setAxis(axis) {
      var old = currentCut();
      st.axis = axis;
      st.cut = nearestCut(old ? (axis === 'row' ? midRow(old) : midCol(old)) : 0);
      sideRedraw(true);
      layerZoom.redraw();
    }
    function midRow(c) { return c.axis === 'row' ? c.pos : Math.floor((c.from + c.to) / 2); }
    function midCol(c) { return c.axis === 'col' ? c.pos : Math.floor((c.from + c.to) / 2); }
    function nearestCut(pos) {
      var list = currentList(), best = 0;
      for (var i = 0; i < list.length; ++i) if (Math.abs(D.cuts[list[i]].pos - pos) < Math.abs(D.cuts[list[best]].pos - pos)) best = i;
      return best;
    }
    function setCut(i) { st.cut = Math.max(0, i | 0); sideRedraw(); layerZoom.redraw(); }
    function setPart(p) {
      st.part = p;
      if (partSel) partSel.value = p;
      st.cut = Math.floor(currentList().length / 2);
      sideRedraw(true);
      layerZoom.redraw();
      highlightPart();
    }
    function cutAt(p) { /* the part under the point, and its cut nearest to it */
      var c = Math.floor(p.x), r = Math.floor(p.y);
      D.parts.forEach(function (pt, i) {
        var b = pt.box_px;
        if (c >= b[0] && c < b[0] + b[2] && r >= b[1] && r < b[1] + b[3]) st.part = i;
      });
      if (partSel) partSel.value = st.part;
      st.cut = nearestCut(st.axis === 'row' ? r : c);
      sideRedraw(true);
      layerZoom.redraw();
      highlightPart();
    }

    /* -- the side panel: summary, legend, materials, parts, warnings, keys -- */
    var info = D.info || {};
    side.appendChild(el('h2', { text: 'stack' }));
    side.appendChild(kvTable([
      ['written by', info.generator], ['printer', info.profile], ['mode', D.mode + (info.halftone ? ' (' + info.halftone + ')' : '')],
      ['method', info.method], ['layers', N + (N > 1 ? ' (index ' + D.index[0] + ' to ' + D.index[N - 1] + ')' : '')],
      ['image', W + ' \u00d7 ' + H + ' pixels, ' + D.bit_depth + '-bit'],
      ['pixel', num(sx, 5) + ' \u00d7 ' + num(Math.abs(sy), 5) + ' mm' +
        (aspect === 1 ? ' (square)' : ' (a row is ' + num(aspect, 3) + ' columns tall)')],
      ['layer height', mm(D.layer_height_mm)], ['mesh', info.mesh], ['model', info.model],
      ['plate used', info.utilisation !== undefined ? num(100 * info.utilisation, 2) + '%' : undefined],
      ['object pixels', info.object_pixels], ['stack at', D.base === '' ? 'this page\u2019s directory' : D.base]
    ]));
    if (D.palette && D.palette.length) {
      side.appendChild(el('h2', { text: 'colours' }));
      side.appendChild(el('ul', { class: 'legend' }, D.palette.map(function (p) {
        return el('li', null, [swatch(p.color), (p.name === null ? 'unnamed' : p.name) + '  (' + p.index + ')']);
      })));
    } else if (fractions) {
      side.appendChild(el('h2', { text: 'colours' }));
      side.appendChild(el('ul', { class: 'legend' }, D.channels.map(function (c) {
        return el('li', null, [swatch(c.color), c.name + ': its colour \u00d7 its fraction, summed']);
      })));
    }
    if (!tray && D.materials && D.materials.length) {
      side.appendChild(el('h2', { text: 'materials: target and achieved fractions' }));
      side.appendChild(el('table', null, [el('tr', null, [el('th', { text: 'material' }), el('th', { class: 'num', text: 'target' }),
        el('th', { class: 'num', text: 'achieved' }), el('th', { class: 'num', text: 'difference' })])].concat(
        D.materials.map(function (m) {
          var diff = typeof m.achieved === 'number' && typeof m.target === 'number' ? m.achieved - m.target : null;
          return el('tr', null, [el('td', null, [swatch(m.color), m.name]), el('td', { class: 'num', text: frac(m.target) }),
            el('td', { class: 'num', text: frac(m.achieved) }), el('td', { class: 'num', text: signed(diff) })]);
        }))));
    }
    var partDivs = [];
    if (tray) {
      side.appendChild(el('h2', { text: D.parts.length + ' part' + (D.parts.length === 1 ? '' : 's') }));
      D.parts.forEach(function (p, i) {
        var f = p.info || {};
        var mats = f.materials || {};
        var rows = Object.keys(mats).map(function (k) {
          var m = mats[k] || {};
          return el('tr', null, [el('td', { text: k + (m.resin && m.resin !== k ? ' \u2192 ' + m.resin : '') }),
            el('td', { class: 'num', text: frac(m.target) }), el('td', { class: 'num', text: frac(m.achieved) })]);
        });
        var d = el('div', { class: 'part' }, [
          el('div', { class: 'name', text: 'part ' + partLabel(i), title: 'show its side view', onclick: function () { setPart(i); } }),
          kvTable([['mesh', f.mesh], ['model', f.model], ['at', f.at_mm ? f.at_mm.map(function (v) { return num(v, 3); }).join(', ') + ' mm' : undefined],
            ['rotation', f.rotation !== undefined ? f.rotation + '\u00b0' : undefined], ['lift', f.lift_layers !== undefined ? f.lift_layers + ' layers' : undefined],
            ['box', f.box_mm ? f.box_mm.map(function (v) { return num(v, 2); }).join(', ') + ' mm' : undefined],
            ['image', p.box_px.join(', ') + ' px'], ['layers', f.layers ? f.layers[0] + ' to ' + (f.layers[1] - 1) : undefined],
            ['object pixels', f.object_pixels]]),
          el('table', null, [el('tr', null, [el('th', { text: 'material' }), el('th', { class: 'num', text: 'target' }),
            el('th', { class: 'num', text: 'achieved' })])].concat(rows))
        ]);
        partDivs.push(d);
        side.appendChild(d);
      });
      if (info.resin_colors_note) side.appendChild(el('p', { class: 'meta', text: info.resin_colors_note }));
    }
    function highlightPart() { partDivs.forEach(function (d, i) { d.className = 'part' + (i === st.part ? ' current' : ''); }); }
    if (D.warnings && D.warnings.length) {
      side.appendChild(el('h2', { text: 'warnings' }));
      side.appendChild(el('ul', { class: 'warnings' }, D.warnings.map(function (w) { return el('li', { text: w }); })));
    }
    side.appendChild(el('h2', { text: 'keys' }));
    side.appendChild(keysTable([
      ['\u2190 \u2192  \u2193 \u2191', 'previous / next layer'], ['PgDn PgUp', '10 layers down / up'], ['Home End', 'first / last layer'],
      ['+ \u2212', 'zoom in / out'], ['f  1', 'fit / one pixel per screen pixel across'], ['drag, wheel', 'pan, zoom'],
      ['o', 'outlines, names and the cut line on / off'], ['s', 'side view: x\u2013z / y\u2013z'], ['[ ]', 'previous / next cut'],
      ['shift-click', 'cut through the point'], ['click side view', 'show that layer']
    ]));
    side.appendChild(el('p', { class: 'meta', text: 'True aspect: each layer pixel is drawn ' +
      (aspect === 1 ? 'square' : num(aspect, 3) + ' times as tall as it is wide') +
      ', as the printer places it; below 1:1 pixels are averaged, from 1:1 up each one is a block.' }));

    document.addEventListener('keydown', function (ev) {
      var t = ev.target;
      if (t && (t.tagName === 'INPUT' || t.tagName === 'SELECT' || t.tagName === 'TEXTAREA') && t.type !== 'button') {
        if (t !== slider || (ev.key !== 'PageUp' && ev.key !== 'PageDown')) return;
      }
      if (ev.ctrlKey || ev.metaKey || ev.altKey) return;
      var k = ev.key, done = true;
      if (k === 'ArrowRight' || k === 'ArrowUp') step(1);
      else if (k === 'ArrowLeft' || k === 'ArrowDown') step(-1);
      else if (k === 'PageUp') step(10);
      else if (k === 'PageDown') step(-10);
      else if (k === 'Home') setLayer(0);
      else if (k === 'End') setLayer(N - 1);
      else if (k === '+' || k === '=') layerZoom.zoomAt(1.25);
      else if (k === '-') layerZoom.zoomAt(0.8);
      else if (k === 'f' || k === '0') layerZoom.fit();
      else if (k === '1') layerZoom.zoomAt(1 / layerZoom.scale);
      else if (k === 'o') toggleOutlines();
      else if (k === 's') setAxis(st.axis === 'row' ? 'col' : 'row');
      else if (k === '[') setCut(st.cut - 1);
      else if (k === ']') setCut(Math.min(st.cut + 1, currentList().length - 1));
      else done = false;
      if (done) ev.preventDefault();
    });

    api.layers = N;
    api.layer = function () { return st.li; };
    api.setLayer = setLayer;
    api.drawnLayer = -1;
    api.sideDrawn = -1;
    api.layerZoom = layerZoom;
    api.sideZoom = sideZoom;
    api.layerCanvas = layerZoom.canvas;
    api.sideCanvas = sideZoom.canvas;
    api.setCut = function (axis, i, part) { if (part !== undefined) setPart(part); setAxis(axis); setCut(i); return currentCutIndex(); };
    api.setChannel = function (c) { st.chan = c; if (chanSel) chanSel.value = c; layerZoom.redraw(); sideRedraw(); };
    api.setOutlines = function (on) { if (!!on !== st.outlines) toggleOutlines(); };
    api.state = st;

    st.part = 0;
    st.cut = Math.floor(currentList().length / 2);
    setLayer(0);
    sideRedraw(true);
    highlightPart();
    api.ready = true;
  }

  /* ==== models ==================================================================================== */

  function modelPage() {
    var dims = D.dims, vox = D.voxel_mm, org = D.origin_mm, m = D.materials.length;
    var cols = D.materials.map(function (x) { return hexRgb(x.color); });
    header(D.title, 'model \u00b7 ' + dims.join(' \u00d7 ') + ' voxels of ' + vox.map(function (v) { return num(v, 4); }).join(' \u00d7 ') +
      ' mm \u00b7 ' + m + ' material' + (m === 1 ? '' : 's') + ' \u00b7 ' + D.occupied + ' occupied voxels');
    var layout = el('div', { class: 'layout' });
    var main = el('div', { class: 'main model-main' });
    var side = el('div', { class: 'side' });
    layout.appendChild(main);
    layout.appendChild(side);
    app.appendChild(layout);
    var grid = el('div', { class: 'model-grid' });
    main.appendChild(grid);
    var status = el('div', { class: 'status', text: '\u00a0' });
    main.appendChild(status);
    var U = [1, 0, 0], V = [2, 2, 1], AX = ['x', 'y', 'z'];
    var at = [0, 0, 0]; /* the voxel the three views go through (offsets from the box's first) */
    var cross = true;   /* draw where the views cut each other */
    var panels = [];

    function sample(n, q, k) { var a = k * q, c = Math.min(q, n - a); return a + Math.floor((c - 1) / 2); }

    /* the atlases' grey values, read back (images carried in the page are ours to read) */
    function decode(src) {
      return loadImage(src).then(function (img) {
        var c = document.createElement('canvas');
        c.width = img.width; c.height = img.height;
        var x = c.getContext('2d');
        x.drawImage(img, 0, 0);
        var d = x.getImageData(0, 0, img.width, img.height).data, out = new Uint8Array(img.width * img.height);
        for (var i = 0; i < out.length; ++i) out[i] = d[4 * i];
        return { w: img.width, h: img.height, v: out };
      });
    }

    D.axes.forEach(function (A, a) {
      var P = { a: a, A: A, idx: Math.floor(A.slices.length / 2), atl: null, canvas: null };
      var u = U[a], v = V[a];
      var slider = el('input', { type: 'range', min: 0, max: A.slices.length - 1, value: P.idx, 'aria-label': AX[a] + ' slice',
        oninput: function () { setSlice(a, +slider.value); } });
      var label = el('span', { class: 'value' });
      var box = el('div', { class: 'canvas-box' });
      var note = el('div', { class: 'note', text: 'decoding\u2026' });
      box.appendChild(note);
      var panel = el('div', { class: 'slice-panel' }, [el('div', { class: 'toolbar' }, [
        el('label', { text: AX[u] + '\u2013' + AX[v] }), el('span', { class: 'grow' }, [slider]), label]),
        box, el('div', { class: 'toolbar' }, zoomButtons(function () { return P.zoom; }))]);
      grid.appendChild(panel);
      P.slider = slider; P.label = label; P.note = note;
      P.zoom = new Zoom(box, {
        draw: function (ctx, z) {
          if (P.canvas) z.image(ctx, P.canvas);
          if (!cross) return;
          /* where the other two views cut this one */
          ctx.save();
          ctx.strokeStyle = 'rgba(70,224,255,0.8)';
          ctx.setLineDash([5, 4]);
          var ku = Math.floor(at[u] / D.step), kv = A.h - 1 - Math.floor(at[v] / D.step);
          var X = Math.round(z.toX(ku + 0.5)) + 0.5, Y = Math.round(z.toY(kv + 0.5)) + 0.5;
          ctx.beginPath(); ctx.moveTo(X, z.toY(0)); ctx.lineTo(X, z.toY(A.h));
          ctx.moveTo(z.toX(0), Y); ctx.lineTo(z.toX(A.w), Y); ctx.stroke();
          ctx.restore();
        },
        onmove: function (p) { showVoxel(P, p); },
        onclick: function (p) {
          var t = voxelAt(P, p);
          if (!t) return;
          at = t.ijk;
          panels.forEach(function (Q) { if (Q !== P) { Q.idx = nearest(Q, at[Q.a]); drawSlice(Q); } else Q.zoom.redraw(); });
        }
      });
      P.zoom.setContent(A.w, A.h, (vox[v] / vox[u]));
      panels.push(P);
    });

    function nearest(P, i) {
      var s = P.A.slices, b = 0;
      for (var k = 0; k < s.length; ++k) if (Math.abs(s[k] - i) < Math.abs(s[b] - i)) b = k;
      return b;
    }

    function voxelAt(P, p) {
      if (!p) return null;
      var x = Math.floor(p.x), y = Math.floor(p.y), A = P.A;
      if (x < 0 || y < 0 || x >= A.w || y >= A.h) return null;
      var ijk = [0, 0, 0];
      ijk[P.a] = A.slices[P.idx];
      ijk[U[P.a]] = sample(dims[U[P.a]], D.step, x);
      ijk[V[P.a]] = sample(dims[V[P.a]], D.step, A.h - 1 - y);
      return { x: x, y: y, ijk: ijk };
    }

    /* occupancy and fractions of sample (x, y) of the slice shown */
    function values(P, x, y) {
      var A = P.A, tx = (P.idx % A.cols) * A.w, ty = Math.floor(P.idx / A.cols) * A.h;
      var at2 = (ty + y) * P.atl[0].w + tx + x;
      return P.atl.map(function (g) { return g.v[at2]; });
    }

    function showVoxel(P, p) {
      var t = voxelAt(P, p);
      if (!t || !P.atl) { status.textContent = '\u00a0'; return; }
      var vals = values(P, t.x, t.y);
      var w = [0, 1, 2].map(function (k) { return org[k] + t.ijk[k] * vox[k]; });
      var s = 'voxel ' + t.ijk.join(', ') + ' \u00b7 x ' + mm(w[0]) + ', y ' + mm(w[1]) + ', z ' + mm(w[2]) + ' \u00b7 ';
      if (!vals[0]) s += 'empty';
      else if (!m) s += 'occupied';
      else s += D.materials.map(function (x, j) { return x.name + ' ' + num(vals[1 + j] / 255, 3); }).join(', ');
      status.textContent = s;
    }

    /* sum p_j colour_j / sum p_j over the occupied samples (hv_render's colour of a voxel) */
    function drawSlice(P) {
      var A = P.A;
      P.slider.value = P.idx;
      var k = A.slices[P.idx];
      P.label.textContent = AX[P.a] + ' ' + mm(org[P.a] + k * vox[P.a]) + ' (' + k + ')';
      if (!P.atl) return;
      if (!P.canvas) {
        P.canvas = document.createElement('canvas');
        P.canvas.width = A.w; P.canvas.height = A.h;
      }
      var ctx = P.canvas.getContext('2d'), img = ctx.createImageData(A.w, A.h), d = img.data;
      for (var y = 0; y < A.h; ++y)
        for (var x = 0; x < A.w; ++x) {
          var vals = values(P, x, y), o = 4 * (y * A.w + x);
          if (!vals[0]) { d[o + 3] = 0; continue; }
          var r = 0, g = 0, b = 0, sum = 0;
          for (var j = 0; j < m; ++j) {
            var pj = vals[1 + j] / 255;
            r += pj * cols[j][0]; g += pj * cols[j][1]; b += pj * cols[j][2]; sum += pj;
          }
          if (sum > 0) { r /= sum; g /= sum; b /= sum; } else { r = g = b = 0.7 * 255; }
          d[o] = Math.round(r); d[o + 1] = Math.round(g); d[o + 2] = Math.round(b); d[o + 3] = 255;
        }
      ctx.putImageData(img, 0, 0);
      P.zoom.redraw();
      P.drawn = P.idx;
    }

    function setSlice(a, i) {
      var P = panels[a];
      P.idx = Math.max(0, Math.min(P.A.slices.length - 1, i | 0));
      at[a] = P.A.slices[P.idx];
      drawSlice(P);
      panels.forEach(function (Q) { if (Q !== P) Q.zoom.redraw(); });
    }

    panels.forEach(function (P) { at[P.a] = P.A.slices[P.idx]; });
    var loading = panels.map(function (P) {
      return Promise.all(P.A.images.map(decode)).then(function (atl) {
        P.atl = atl;
        P.note.hidden = true;
        drawSlice(P);
      }, function (err) { P.note.textContent = err.message; api.errors.push(err.message); });
    });

    if (D.renders.length) {
      main.appendChild(el('div', { class: 'renders' }, D.renders.map(function (r) {
        return el('figure', null, [el('img', { src: r.image, width: r.w, height: r.h, alt: r.name }), el('figcaption', { text: r.name })]);
      })));
    }

    side.appendChild(el('h2', { text: 'model' }));
    side.appendChild(kvTable([['file', D.file], ['voxels', dims.join(' \u00d7 ') + ' (the occupied box)'],
      ['voxel size', vox.map(function (v) { return num(v, 4); }).join(' \u00d7 ') + ' mm'],
      ['box from', org.map(function (v) { return num(v, 3); }).join(', ') + ' mm (first voxel centre)'],
      ['occupied', D.occupied + ' voxels'],
      ['slices', D.axes.map(function (A) { return A.slices.length + ' ' + A.axis; }).join(', ') +
        (D.step > 1 ? ', one voxel in ' + D.step + ' in the plane' : '')]]));
    if (m) {
      side.appendChild(el('h2', { text: 'materials: mean fraction over the occupied voxels' }));
      side.appendChild(el('table', null, D.materials.map(function (x) {
        var props = x.properties || {};
        var ptxt = Object.keys(props).map(function (k) { return k + ' ' + props[k][0] + (props[k][1] ? ' ' + props[k][1] : ''); }).join(', ');
        return el('tr', null, [el('td', null, [swatch(x.color), x.name]), el('td', { class: 'num', text: frac(x.mean) }),
          el('td', { class: 'meta', text: ptxt })]);
      })));
    } else {
      side.appendChild(el('p', { text: 'No material table: the occupancy alone, in grey.' }));
    }
    side.appendChild(el('h2', { text: 'keys' }));
    document.addEventListener('keydown', function (ev) {
      if (ev.key === 'o' && !(ev.target && ev.target.tagName === 'INPUT' && ev.target.type !== 'range')) api.setOutlines(!cross);
    });
    side.appendChild(keysTable([['slider', 'move a view through its axis'], ['click', 'the other two views through that voxel'],
      ['o', 'the lines where the views cut each other on / off'],
      ['drag, wheel', 'pan, zoom'], ['hover', 'the voxel and its fractions below']]));
    side.appendChild(el('p', { class: 'meta', text: 'Colour: \u03a3 p\u2c7c colour\u2c7c / \u03a3 p\u2c7c of the materials\u2019 display colours, ' +
      'fractions stored in 8 bits; empty voxels are transparent.' }));

    api.setSlice = setSlice;
    api.setOutlines = function (on) { cross = !!on; panels.forEach(function (P) { P.zoom.redraw(); }); };
    api.panels = panels;
    api.values = function (a, x, y) { return values(panels[a], x, y); };
    Promise.all(loading).then(function () { api.ready = true; });
  }

  if (D.kind === 'model') modelPage(); else stackPage();
})();
