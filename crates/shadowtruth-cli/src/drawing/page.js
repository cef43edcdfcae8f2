// index.html's behaviour (drawing/html.rs): the runs table drawn a page at a time from its data,
// sorted and filtered; the image viewer that flips or slides between the reference, a run's
// shadows and its error map, with zoom, opened from a run's button or a point of a chart.
// Offline: everything is in the page and its folder.
(function () {
  'use strict';
  var runs = document.getElementById('runs');
  var body = runs.tBodies[0];
  var headers = runs.tHead.rows[0].cells;
  // The runs, drawn a page at a time (a report may hold ten thousand).
  var data = JSON.parse(document.getElementById('runs-data').textContent);
  var PAGE = 100;
  var order = data.map(function (_, i) { return i; });
  var shownRuns = order;
  var page = 0;

  function cellValue(c) { return Array.isArray(c) ? c[1] : c; }
  function cellText(c) { return Array.isArray(c) ? c[0] : String(c); }
  function viewButton(i) {
    var f = data[i].figures;
    if (!f) return null;
    var b = document.createElement('button');
    b.className = 'view';
    b.dataset.run = i;
    b.dataset.reference = f.reference;
    b.dataset.technique = f.technique;
    b.dataset.error = f.error;
    b.dataset.caption = f.caption;
    b.textContent = 'view';
    b.addEventListener('click', function () { openRun(i); });
    return b;
  }
  function render() {
    var pages = Math.max(1, Math.ceil(shownRuns.length / PAGE));
    page = Math.min(page, pages - 1);
    var rows = document.createDocumentFragment();
    shownRuns.slice(page * PAGE, (page + 1) * PAGE).forEach(function (i) {
      var run = data[i], tr = document.createElement('tr');
      ['scene', 'camera', 'light', 'technique', 'resolution'].forEach(function (k) { tr.dataset[k] = run[k]; });
      tr.dataset.run = i;
      run.cells.forEach(function (c, col) {
        var td = document.createElement('td');
        td.className = headers[col].className; // left-aligned where its header is
        td.textContent = cellText(c);
        tr.appendChild(td);
      });
      var last = document.createElement('td');
      last.className = 'l';
      var b = viewButton(i);
      if (b) {
        last.appendChild(b);
        var f = data[i].figures;
        [['visibility', f.technique], ['errors', f.error]].forEach(function (l) {
          var a = document.createElement('a');
          a.href = l[1];
          a.textContent = l[0];
          last.appendChild(document.createTextNode(' '));
          last.appendChild(a);
        });
      }
      tr.appendChild(last);
      rows.appendChild(tr);
    });
    body.textContent = '';
    body.appendChild(rows);
    var at = document.getElementById('page-at');
    at.textContent = 'page ' + (page + 1) + ' of ' + pages + ' (' + PAGE + ' runs a page)';
    at.dataset.page = page + 1;
    at.dataset.pages = pages;
    document.getElementById('page-prev').disabled = page === 0;
    document.getElementById('page-next').disabled = page + 1 >= pages;
  }
  document.getElementById('page-prev').addEventListener('click', function () { page -= 1; render(); });
  document.getElementById('page-next').addEventListener('click', function () { page += 1; render(); });

  // Sorting: click a header; numbers sort as numbers (exact values, not the rounded text).
  Array.prototype.forEach.call(headers, function (th, col) {
    if (col === headers.length - 1) return; // the figures column: nothing to sort by
    th.addEventListener('click', function () {
      var dir = th.dataset.dir === 'asc' ? -1 : 1;
      th.dataset.dir = dir === 1 ? 'asc' : 'desc';
      order.sort(function (a, b) {
        var x = cellValue(data[a].cells[col]), y = cellValue(data[b].cells[col]);
        if (typeof x === 'number' && typeof y === 'number') return dir * (x - y);
        return dir * String(x).localeCompare(String(y));
      });
      applyFilters();
    });
  });

  // Filters: each select keeps the runs whose value matches (or all).
  var filters = Array.prototype.slice.call(document.querySelectorAll('#filters select'));
  function applyFilters() {
    shownRuns = order.filter(function (i) {
      return filters.every(function (f) { return f.value === '' || data[i][f.name] === f.value; });
    });
    var count = document.getElementById('shown');
    count.textContent = shownRuns.length + ' of ' + data.length + ' runs shown';
    count.dataset.shown = shownRuns.length;
    render();
  }
  filters.forEach(function (f) { f.addEventListener('change', function () { page = 0; applyFilters(); }); });

  // The viewer: run A (opened from a row's button or a chart's point) against B, the reference
  // or a pinned run; flipped (keys 1–3) or slid (4) with a divider; one stage, so zoom and pan
  // are shared; the pixel under the cursor read from both.
  var viewer = document.getElementById('viewer');
  var stage = document.getElementById('view-stage');
  var base = document.getElementById('view-base');
  var over = document.getElementById('view-over');
  var divider = document.getElementById('view-divider');
  var slider = document.getElementById('view-slider');
  var zoom = document.getElementById('view-zoom');
  var caption = document.getElementById('view-caption');
  var pin = document.getElementById('view-pin');
  var readout = document.getElementById('view-pixel');
  var runA = null, runB = null;
  var mode = 'reference';
  // The error map's colours (drawing/palette.rs): the class of a pixel.
  var CLASSES = { 'D55E00': 'false shadow', '0072B2': 'false lit', 'CC79A7': 'uncertain' };

  function images() {
    var a = data[runA].figures;
    var b = runB === null ? null : data[runB].figures;
    return { reference: b ? b.technique : a.reference, technique: a.technique, error: a.error,
             bError: b ? b.error : null };
  }
  function setZoom() {
    var z = parseFloat(zoom.value);
    [base, over].forEach(function (img) {
      if (img.naturalWidth) img.style.width = (img.naturalWidth * z) + 'px';
    });
    placeDivider();
  }
  function placeDivider() {
    divider.hidden = mode !== 'slide';
    divider.style.left = (base.clientWidth * slider.value / 100) + 'px';
    divider.style.height = base.clientHeight + 'px';
    over.style.clipPath = 'inset(0 ' + (100 - slider.value) + '% 0 0)';
  }
  function show(newMode) {
    mode = newMode;
    var sliding = mode === 'slide', im = images();
    base.src = im[sliding ? 'reference' : mode];
    over.hidden = !sliding;
    slider.hidden = !sliding;
    if (sliding) over.src = im.technique;
    placeDivider();
    viewer.dataset.mode = mode;
    Array.prototype.forEach.call(document.querySelectorAll('#view-modes button[data-mode]'), function (b) {
      b.setAttribute('aria-pressed', b.dataset.mode === mode ? 'true' : 'false');
    });
  }
  function describe() {
    var a = data[runA].figures.caption;
    caption.textContent = runB === null ? a : 'A: ' + a + '  ·  B: ' + data[runB].figures.caption;
    document.querySelector('#view-modes button[data-mode=reference]').textContent =
      runB === null ? '1 reference' : '1 B shadows';
    pin.textContent = runB === null ? 'pin as B, to compare with the next run' : 'unpin B';
    viewer.dataset.run = runA;
    viewer.dataset.compare = runB === null ? '' : runB;
  }
  Array.prototype.forEach.call(document.querySelectorAll('#view-modes button[data-mode]'), function (b) {
    b.addEventListener('click', function () { show(b.dataset.mode); });
  });
  pin.addEventListener('click', function () {
    runB = runB === null ? runA : null;
    describe();
    show(mode);
  });
  slider.addEventListener('input', placeDivider);
  zoom.addEventListener('change', setZoom);
  base.addEventListener('load', setZoom);
  over.addEventListener('load', setZoom);
  document.addEventListener('keydown', function (e) {
    if (viewer.hidden || e.target.tagName === 'SELECT' || e.target.tagName === 'INPUT') return;
    var key = { '1': 'reference', '2': 'technique', '3': 'error', '4': 'slide' }[e.key];
    if (key) show(key);
  });
  function openRun(i) {
    if (!data[i].figures) return;
    runA = i;
    describe();
    viewer.hidden = false;
    show(mode);
    viewer.scrollIntoView();
  }

  // The pixel under the cursor. Reading an image's pixels needs the browser to allow it for
  // files (it does for pages served over HTTP): otherwise only the position is shown.
  var pixels = {};
  function pixelsOf(src, img) {
    if (!(src in pixels)) {
      try {
        var c = document.createElement('canvas');
        c.width = img.naturalWidth; c.height = img.naturalHeight;
        var g = c.getContext('2d');
        g.drawImage(img, 0, 0);
        pixels[src] = { w: c.width, d: g.getImageData(0, 0, c.width, c.height).data };
      } catch (e) {
        pixels[src] = null;
      }
    }
    return pixels[src];
  }
  function loaded(src, then) {
    if (src in pixels) return then(pixels[src]);
    var img = new Image();
    img.onload = function () { then(pixelsOf(src, img)); };
    img.src = src;
  }
  function hex(p, k) {
    return [p.d[k], p.d[k + 1], p.d[k + 2]].map(function (v) { return (v < 16 ? '0' : '') + v.toString(16); })
      .join('').toUpperCase();
  }
  stage.addEventListener('mousemove', function (e) {
    if (runA === null || !base.naturalWidth) return;
    var r = base.getBoundingClientRect(), z = parseFloat(zoom.value);
    var x = Math.floor((e.clientX - r.left) / z), y = Math.floor((e.clientY - r.top) / z);
    if (x < 0 || y < 0 || x >= base.naturalWidth || y >= base.naturalHeight) return;
    var im = images();
    var at = 'pixel (' + x + ', ' + y + ')';
    readout.dataset.x = x;
    readout.dataset.y = y;
    loaded(im.error, function (errA) {
      loaded(im.technique, function (visA) {
        loaded(im.reference, function (visB) {
          var finish = function (errB) {
            if (!errA || !visA || !visB) {
              readout.textContent = at + ' (values: serve the folder over HTTP, e.g. python3 -m http.server)';
              return;
            }
            var k = 4 * (y * errA.w + x);
            var classOf = function (p) { return p ? CLASSES[hex(p, k)] || 'agrees with the reference' : null; };
            var a = classOf(errA), b = runB === null ? 'the reference' : classOf(errB);
            readout.textContent = at + ': A ' + a + ' (grey ' + visA.d[k] + '), B ' + b + ' (grey ' + visB.d[k] + ')';
            readout.dataset.a = a;
            readout.dataset.b = b;
          };
          if (im.bError) loaded(im.bError, finish); else finish(null);
        });
      });
    });
  });
  // The answer's charts: a point opens its run.
  Array.prototype.forEach.call(document.querySelectorAll('.cost-chart circle[data-run]'), function (c) {
    c.addEventListener('click', function () { openRun(Number(c.dataset.run)); });
  });

  // How many images loaded (read by tests and shown to the reader).
  function imagesStatus() {
    var imgs = Array.prototype.slice.call(document.images).filter(function (i) { return i.getAttribute('src'); });
    var ok = imgs.filter(function (i) { return i.complete && i.naturalWidth > 0; }).length;
    var s = document.getElementById('status');
    s.textContent = 'images loaded: ' + ok + '/' + imgs.length + '; runs: ' + data.length;
    s.dataset.loaded = ok;
    s.dataset.total = imgs.length;
  }
  window.addEventListener('load', imagesStatus);
  applyFilters();
})();
