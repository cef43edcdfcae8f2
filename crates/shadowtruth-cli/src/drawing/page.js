// index.html's behaviour (src/report/html.rs): sorting the runs table, filtering it, and the
// image viewer that flips or slides between the reference, a run's shadows and its error map,
// with zoom. Offline: everything is in the page and its folder.
(function () {
  'use strict';
  var runs = document.getElementById('runs');
  var body = runs.tBodies[0];

  // Sorting: click a header; numbers sort as numbers (data-v holds the exact value).
  Array.prototype.forEach.call(runs.tHead.rows[0].cells, function (th, col) {
    th.addEventListener('click', function () {
      var rows = Array.prototype.slice.call(body.rows);
      var dir = th.dataset.dir === 'asc' ? -1 : 1;
      th.dataset.dir = dir === 1 ? 'asc' : 'desc';
      rows.sort(function (a, b) {
        var x = a.cells[col].dataset.v || a.cells[col].textContent;
        var y = b.cells[col].dataset.v || b.cells[col].textContent;
        var nx = parseFloat(x), ny = parseFloat(y);
        if (!isNaN(nx) && !isNaN(ny)) return dir * (nx - ny);
        return dir * x.localeCompare(y);
      });
      rows.forEach(function (r) { body.appendChild(r); });
    });
  });

  // Filters: each select keeps the rows whose attribute matches (or all).
  var filters = Array.prototype.slice.call(document.querySelectorAll('#filters select'));
  function applyFilters() {
    var shown = 0;
    Array.prototype.forEach.call(body.rows, function (row) {
      var keep = filters.every(function (f) { return f.value === '' || row.dataset[f.name] === f.value; });
      row.hidden = !keep;
      if (keep) shown += 1;
    });
    var count = document.getElementById('shown');
    count.textContent = shown + ' of ' + body.rows.length + ' runs shown';
    count.dataset.shown = shown;
  }
  filters.forEach(function (f) { f.addEventListener('change', applyFilters); });

  // The viewer.
  var viewer = document.getElementById('viewer');
  var base = document.getElementById('view-base');
  var over = document.getElementById('view-over');
  var slider = document.getElementById('view-slider');
  var zoom = document.getElementById('view-zoom');
  var caption = document.getElementById('view-caption');
  var images = { reference: '', technique: '', error: '' };
  var mode = 'reference';

  function setZoom() {
    var z = parseFloat(zoom.value);
    [base, over].forEach(function (img) {
      if (img.naturalWidth) img.style.width = (img.naturalWidth * z) + 'px';
    });
  }
  function show(newMode) {
    mode = newMode;
    var sliding = mode === 'slide';
    base.src = images[sliding ? 'reference' : mode];
    over.hidden = !sliding;
    slider.hidden = !sliding;
    if (sliding) {
      over.src = images.technique;
      over.style.clipPath = 'inset(0 ' + (100 - slider.value) + '% 0 0)';
    }
    viewer.dataset.mode = mode;
    Array.prototype.forEach.call(document.querySelectorAll('#view-modes button'), function (b) {
      b.setAttribute('aria-pressed', b.dataset.mode === mode ? 'true' : 'false');
    });
  }
  Array.prototype.forEach.call(document.querySelectorAll('#view-modes button'), function (b) {
    b.addEventListener('click', function () { show(b.dataset.mode); });
  });
  slider.addEventListener('input', function () {
    over.style.clipPath = 'inset(0 ' + (100 - slider.value) + '% 0 0)';
  });
  zoom.addEventListener('change', setZoom);
  base.addEventListener('load', setZoom);
  over.addEventListener('load', setZoom);
  document.addEventListener('keydown', function (e) {
    if (viewer.hidden || e.target.tagName === 'SELECT' || e.target.tagName === 'INPUT') return;
    var key = { '1': 'reference', '2': 'technique', '3': 'error', '4': 'slide' }[e.key];
    if (key) show(key);
  });
  Array.prototype.forEach.call(document.querySelectorAll('button.view'), function (b) {
    b.addEventListener('click', function () {
      images = { reference: b.dataset.reference, technique: b.dataset.technique, error: b.dataset.error };
      caption.textContent = b.dataset.caption;
      viewer.hidden = false;
      show(mode);
      viewer.scrollIntoView();
    });
  });

  // How many images loaded (read by tests and shown to the reader).
  function imagesStatus() {
    var imgs = Array.prototype.slice.call(document.images).filter(function (i) { return i.getAttribute('src'); });
    var ok = imgs.filter(function (i) { return i.complete && i.naturalWidth > 0; }).length;
    var s = document.getElementById('status');
    s.textContent = 'images loaded: ' + ok + '/' + imgs.length + '; runs: ' + body.rows.length;
    s.dataset.loaded = ok;
    s.dataset.total = imgs.length;
  }
  window.addEventListener('load', imagesStatus);
  applyFilters();
})();
