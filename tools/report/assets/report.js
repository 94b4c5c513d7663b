// lptn report's page: builds every table and chart from the JSON the generator embedded.
// Plain JavaScript and the inlined dygraphs only: the file must work offline, in any browser.
(function () {
  'use strict';
  var R = JSON.parse(document.getElementById('report-data').textContent);
  var cycleCharts = {};  // cycle name -> its synchronized charts, for the worst-window links
  // One colour per sensor wherever a chart compares them (as on the Compare charts).
  var SENSOR_COLOR = {stator: '#1f4e9c', rotor: '#a01010', combined: '#555'};

  // --- helpers -----------------------------------------------------------------------------------

  function el(tag, attrs, children) {
    var e = document.createElement(tag);
    Object.keys(attrs || {}).forEach(function (k) { e.setAttribute(k, attrs[k]); });
    (children || []).forEach(function (c) {
      e.appendChild(typeof c === 'string' || typeof c === 'number' ? document.createTextNode(String(c)) : c);
    });
    return e;
  }

  function fixed(v, d) { return v === null || v === undefined || !isFinite(v) ? '–' : Number(v).toFixed(d); }

  function clock(s) {
    var t = Math.round(s), h = Math.floor(t / 3600), m = Math.floor(t / 60) % 60, sec = t % 60;
    return (h ? h + ':' + String(m).padStart(2, '0') : m) + ':' + String(sec).padStart(2, '0');
  }

  // One failing chart must not take the rest of the page with it.
  function guarded(what, fn) {
    try { fn(); } catch (e) { showError(what + ': ' + (e && e.stack ? e.stack : e)); }
  }

  function table(headers, rows, attrs) {
    var head = el('tr', {}, headers.map(function (h) { return el('th', {}, [h]); }));
    return el('table', attrs || {}, [head].concat(rows));
  }

  // White at or below the sensor's noise (estimated from its residual), full red at the worst region or
  // at three times the noise, whichever is larger: a sensor fitted to its noise stays pale instead
  // of showing its noise as structure, and a sensor the model misses shows where.
  function heatRange(bins, noise) {
    var v = bins.filter(function (b) { return b.n > 0; }).map(function (b) { return b.rmse; });
    var lo = noise !== null && isFinite(noise) ? noise : Math.min.apply(null, v);
    return {lo: lo, hi: Math.max(Math.max.apply(null, v), 3 * lo)};
  }

  function heat(v, range) {
    if (v === null || !isFinite(v) || !(range.hi > range.lo)) return '#fff';
    var f = Math.min(1, Math.max(0, (v - range.lo) / (range.hi - range.lo))), g = Math.round(255 - 160 * f);
    return 'rgb(255,' + g + ',' + g + ')';
  }

  // A chart container the headless test can find: data-chart names it, data-points counts the
  // points drawn (rows with at least one value).
  function chartBox(parent, name, rows, cls) {
    var legend = el('div', {class: 'legend'});
    var points = rows.filter(function (r) {
      return r.slice(1).some(function (v) { return v !== null && !(Array.isArray(v) && v[1] === null); });
    }).length;
    var box = el('div', {class: 'chart ' + (cls || ''), 'data-chart': name, 'data-points': points});
    parent.appendChild(legend);
    parent.appendChild(box);
    return {box: box, legend: legend};
  }

  // The container also records what the chart shows: data-series its series' labels, and on every
  // draw data-x-range the visible x range, so a test reads what dygraphs drew, not what was asked.
  function graph(parent, name, rows, options, cls) {
    var c = chartBox(parent, name, rows, cls);
    var base = {labelsDiv: c.legend, legend: 'always', labelsSeparateLines: false, animatedZooms: false,
                drawCallback: function (g) {
                  c.box.setAttribute('data-x-range', g.xAxisRange().map(function (v) { return v.toFixed(1); }).join(','));
                }};
    var g = new Dygraph(c.box, rows, Object.assign(base, options));
    c.box.setAttribute('data-series', g.getLabels().slice(1).join('|'));
    return g;
  }

  // --- header --------------------------------------------------------------------------------------

  function renderMeta() {
    var m = R.meta;
    document.getElementById('meta').textContent =
      m.calibration + ' (' + m.method + ', ' + m.created_utc + ', motor ' + m.motor + ', effects: ' +
      (m.effects.length ? m.effects.join(', ') : 'none') + ') on ' + m.data + ': ' + m.cycles + ' cycles, ' +
      fixed(m.hours, 1) + ' h. Generated ' + m.generated_utc + '.';
    // A calibration whose status is failed or warnings: said before anything drawn from it.
    if (m.status_caution) {
      var meta = document.getElementById('meta');
      var warnings = el('ul', {}, m.warnings.map(function (w) { return el('li', {}, [w]); }));
      meta.parentNode.insertBefore(el('div', {class: 'verdict missing', 'data-note': 'calibration-status'},
                                          ['Calibration status: ' + m.status_caution, warnings]), meta.nextSibling);
    }
  }

  // --- Compare -------------------------------------------------------------------------------------

  function metricCells(m) {
    if (!m) return [el('td', {}, ['–']), el('td', {}, ['–']), el('td', {}, ['–']), el('td', {}, ['–'])];
    return [m.rmse_k, m.mean_abs_k, m.max_abs_k, m.bias_k].map(function (v) { return el('td', {}, [fixed(v, 3)]); });
  }

  // 'unseen': a cycle the calibration never read (by name and file hash), never called train or test.
  function roleBadge(role) {
    return role ? el('span', {class: 'badge ' + role}, [role === 'unseen' ? 'never seen' : role]) : el('span', {}, ['–']);
  }

  function renderCompareTable() {
    var rows = R.cycles.map(function (c) {
      return el('tr', {class: 'role-' + (c.role || 'none')}, [
        el('td', {class: 'text'}, [el('a', {href: '#cycle-' + c.name}, [c.name])]),
        el('td', {class: 'text'}, [roleBadge(c.role)]), el('td', {}, [fixed(c.hours, 2)])
      ].concat(metricCells(c.metrics.stator), metricCells(c.metrics.rotor)));
    });
    var headers = ['cycle', 'role', 'hours', 'stator RMSE K', 'mean |e| K', 'max |e| K', 'bias K',
                   'rotor RMSE K', 'mean |e| K', 'max |e| K', 'bias K'];
    var box = document.getElementById('compare-table');
    box.appendChild(table(headers, rows, {'data-table': 'metrics'}));
    var m = R.meta, rotor = m.train_rmse_rotor_k !== null || m.test_rmse_rotor_k !== null;
    var figures = 'stator train ' + fixed(m.train_rmse_stator_k, 3) + ' K, test ' + fixed(m.test_rmse_stator_k, 3) + ' K' +
      (rotor ? '; rotor train ' + fixed(m.train_rmse_rotor_k, 3) + ' K, test ' + fixed(m.test_rmse_rotor_k, 3) + ' K' : '');
    // On data the calibration never saw its own figures describe other data: said so, not shown as this data's.
    box.appendChild(el('p', {class: 'note', 'data-note': R.check ? 'calibration-own-data' : 'calibration-pooled'}, [R.check ?
      'On the data it was fitted on (not this data), the calibration reported: ' + figures + '. This data\'s figures are the table\'s.' :
      'Calibration\'s pooled RMSE: ' + figures + '.']));
  }

  // dygraphs' custom bars: each value is [min, mean, max] of its bucket.
  function rows(cycle, keys) {
    var s = cycle.series;
    return cycle.t.map(function (t, i) {
      return [t].concat(keys.map(function (k) {
        var e = s[k];
        return e.mean[i] === null ? null : [e.lo[i], e.mean[i], e.hi[i]];
      }));
    });
  }

  // Two-axis charts get a right axis with ticks of its own; one-axis charts leave the same room
  // on the right, so that the charts of a cycle share their horizontal scale on the page.
  function axes() {
    return {x: {valueFormatter: function (v) { return 't = ' + clock(v); },
                axisLabelFormatter: function (v) { return clock(v); }},
            y2: {independentTicks: true, drawGrid: false, axisLabelWidth: 55}};
  }
  var kRightRoom = 75;

  function cycleCharts_(cycle, parent) {
    var rotor = !!cycle.series.rotor_measured;
    var temps = ['stator_measured', 'stator_model'].concat(rotor ? ['rotor_measured', 'rotor_model'] : []);
    var resid = ['stator_residual'].concat(rotor ? ['rotor_residual'] : []);
    var common = {customBars: true, axes: axes(), xlabel: ''};
    var charts = [];
    charts.push(graph(parent, 'temperature', rows(cycle, temps), Object.assign({
      labels: ['t'].concat(temps.map(function (k) { return k.replace('_', ' ') + ' °C'; })),
      colors: ['#1f4e9c', '#6fa8ff', '#a01010', '#ff7a7a'], ylabel: '°C', rightGap: kRightRoom}, common), 'tall'));
    charts.push(graph(parent, 'residual', rows(cycle, resid), Object.assign({
      labels: ['t'].concat(resid.map(function (k) { return k.replace('_', ' ') + ' K'; })),
      colors: ['#1f4e9c', '#a01010'], ylabel: 'model − measured K', rightGap: kRightRoom}, common)));
    charts.push(graph(parent, 'drive', rows(cycle, ['speed', 'torque']), Object.assign({
      labels: ['t', 'speed 1/min', 'torque N·m'], colors: ['#2b8a3e', '#8a5a00'], ylabel: '1/min', y2label: 'N·m',
      series: {'torque N·m': {axis: 'y2'}}}, common)));
    charts.push(graph(parent, 'cooling', rows(cycle, ['airflow', 'ambient']), Object.assign({
      labels: ['t', 'airflow m³/s', 'ambient °C'], colors: ['#0b7285', '#862e9c'], ylabel: 'm³/s', y2label: '°C',
      series: {'ambient °C': {axis: 'y2'}}}, common)));
    return charts;
  }

  function renderCycles() {
    var parent = document.getElementById('compare-cycles');
    R.cycles.forEach(function (cycle) {
      var block = el('div', {class: 'cycle', id: 'cycle-' + cycle.name, 'data-cycle': cycle.name}, [
        el('h3', {}, [cycle.name + ' ', roleBadge(cycle.role)]),
        el('div', {class: 'note'}, [fixed(cycle.hours, 2) + ' h, buckets of ' + fixed(cycle.bucket_s, 1) + ' s; stator RMSE ' +
          fixed(cycle.metrics.stator.rmse_k, 3) + ' K' + (cycle.metrics.rotor ? ', rotor ' + fixed(cycle.metrics.rotor.rmse_k, 3) + ' K' : '')])]);
      parent.appendChild(block);
      guarded('cycle ' + cycle.name, function () {
        var charts = cycleCharts_(cycle, block);
        cycleCharts[cycle.name] = charts;
        Dygraph.synchronize(charts, {zoom: true, selection: true, range: false});
      });
    });
  }

  function zoomTo(cycle, t0, t1) {
    var charts = cycleCharts[cycle];
    if (!charts) return;
    charts.forEach(function (g) { g.updateOptions({dateWindow: [t0, t1]}); });
    document.getElementById('cycle-' + cycle).scrollIntoView();
  }

  // --- Where it fails ------------------------------------------------------------------------------

  function renderSpeedTorque(parent, sensor) {
    var map = sensor.regions.speed_torque;
    var range = heatRange([].concat.apply([], map.cells), sensor.noise_k);
    var se = map.speed_edges, te = map.torque_edges, rowsOut = [];
    for (var j = te.length - 2; j >= 0; --j) {  // torque upwards, as on a torque-speed plane
      var cells = [el('th', {}, [fixed(te[j], 0) + ' … ' + fixed(te[j + 1], 0)])];
      for (var i = 0; i < se.length - 1; ++i) {
        var b = map.cells[i][j];
        var td = el('td', {style: 'background:' + heat(b.rmse, range), title: 'n = ' + b.n},
                    b.n ? [fixed(b.rmse, 2), el('br'), el('small', {}, ['mean ' + fixed(b.mean, 2) + ', n ' + b.n])] : ['']);
        cells.push(td);
      }
      rowsOut.push(el('tr', {}, cells));
    }
    var headers = ['torque N·m \\ speed 1/min'].concat(se.slice(0, -1).map(function (lo, i) {
      return fixed(lo, 0) + ' … ' + fixed(se[i + 1], 0);
    }));
    parent.appendChild(el('p', {class: 'note'}, [sensor.label + ' residual RMSE K (mean K, count of 1 s samples) by speed and ' +
      'torque; white at or below the sensor\'s noise (' + fixed(sensor.noise_k, 2) + ' K), full red at the worst cell or ' +
      'three times the noise, whichever is larger.']));
    parent.appendChild(table(headers, rowsOut, {class: 'heat', 'data-table': 'speed-torque'}));
  }

  function renderBand(parent, band, noise) {
    var range = heatRange(band.bins, noise);
    var rowsOut = band.bins.map(function (b) {
      return el('tr', {}, [el('td', {}, [fixed(b.lo, 2) + ' … ' + fixed(b.hi, 2)]), el('td', {}, [b.n]),
        el('td', {}, [fixed(b.mean, 3)]), el('td', {style: 'background:' + heat(b.rmse, range)}, [fixed(b.rmse, 3)])]);
    });
    parent.appendChild(el('div', {}, [el('strong', {}, [band.label + ' (' + band.unit + ')']),
      table([band.unit, 'n', 'mean K', 'RMSE K'], rowsOut, {'data-table': 'band-' + band.key})]));
  }

  function renderRegions(parent, sensor) {
    renderSpeedTorque(parent, sensor);
    var grid = el('div', {class: 'grid2'});
    parent.appendChild(grid);
    sensor.regions.bands.forEach(function (band) { renderBand(grid, band, sensor.noise_k); });
  }

  function renderWorst(parent, sensor) {
    var rowsOut = sensor.worst.map(function (w, i) {
      var link = el('a', {class: 'zoom', href: '#cycle-' + w.cycle, 'data-zoom': w.cycle, 'data-sensor': sensor.sensor,
                          'data-start': w.start_s, 'data-end': w.end_s}, [w.cycle + ' ' + clock(w.start_s) + '–' + clock(w.end_s)]);
      link.addEventListener('click', function (ev) { ev.preventDefault(); zoomTo(w.cycle, w.start_s, w.end_s); });
      return el('tr', {}, [el('td', {}, [i + 1]), el('td', {class: 'text'}, [link]), el('td', {}, [fixed(w.rmse_k, 3)]), el('td', {}, [w.n])]);
    });
    parent.appendChild(el('p', {class: 'note'}, ['The ' + rowsOut.length + ' worst non-overlapping ' + R.failures.window_s / 60 +
      '-minute windows by ' + sensor.label + ' RMSE; a link zooms that cycle\'s charts to the window (its residual chart shows ' +
      'every sensor\'s residual).']));
    parent.appendChild(table(['#', 'window', sensor.label + ' RMSE K', 'n (1 s)'], rowsOut, {'data-table': 'worst'}));
  }

  function correlationRows(r, band, firstLag, step) {
    return r.map(function (v, i) { return [(firstLag + i) * step, v, band, -band]; });
  }

  function correlationChart(parent, name, title, r, band, firstLag, step) {
    parent.appendChild(el('div', {}, [el('strong', {}, [title])]));
    graph(parent, name, correlationRows(r, band, firstLag, step), {
      labels: ['lag s', 'r', '+95 %', '−95 %'], colors: ['#1f4e9c', '#999', '#999'],
      series: {'+95 %': {strokePattern: [4, 4]}, '−95 %': {strokePattern: [4, 4]}}, includeZero: true, xlabel: 'lag s'}, 'small');
  }

  function renderCorrelations(parent, sensor) {
    var c = sensor.correlations;
    parent.appendChild(el('p', {class: 'note'}, [
      'On 1 s means of the ' + sensor.label + ' residual (n = ' + c.n + '). Autocorrelation band: ±1.96/√n, uncorrected: the band ' +
      'of white residuals, which a model that explains everything but the sensor noise would leave. Cross-correlation r(k) = ' +
      'corr(input(t), residual(t + k)), positive k: the residual follows the input. Its band is corrected for both series\' ' +
      'autocorrelation (Bartlett: ±1.96 √(Σ r_input(k) r_residual(k) / n)); uncorrected, slow inputs against slow residuals ' +
      'would cross it at every lag.']));
    var grid = el('div', {class: 'grid2'});
    parent.appendChild(grid);
    var acfBox = el('div');
    grid.appendChild(acfBox);
    guarded(sensor.label + ' autocorrelation', function () {
      correlationChart(acfBox, 'acf-' + sensor.sensor, sensor.label + ' residual autocorrelation', c.acf.r, c.acf.band, 0, c.lag_step_s);
    });
    c.cross.forEach(function (x) {
      var box = el('div');
      grid.appendChild(box);
      guarded(sensor.label + ' cross-correlation ' + x.input, function () {
        correlationChart(box, 'xcf-' + sensor.sensor + '-' + x.input, x.input + ' → ' + sensor.label + ' residual', x.r, x.band,
                         -c.max_lag_s / c.lag_step_s, c.lag_step_s);
      });
    });
  }

  function sensorSummary(sensor) {
    return sensor.label + ': RMSE ' + fixed(sensor.rmse_k, 2) + ' K = ' + fixed(sensor.error_over_noise, 1) +
      '× its noise of ' + fixed(sensor.noise_k, 2) + ' K';
  }

  // One panel per sensor, drawn when first shown: dygraphs cannot size a chart inside a hidden
  // element, and most readers look at one sensor.
  function renderFailures() {
    var f = R.failures, select = document.getElementById('sensor-select'), panels = document.getElementById('sensor-panels');
    var buttons = {}, shown = {};
    function show(key) {
      f.sensors.forEach(function (sensor) {
        var on = sensor.sensor === key;
        buttons[sensor.sensor].setAttribute('aria-pressed', on ? 'true' : 'false');
        shown[sensor.sensor].style.display = on ? '' : 'none';
      });
      var panel = shown[key];
      if (panel.getAttribute('data-drawn')) return;
      panel.setAttribute('data-drawn', 'true');
      var sensor = f.sensors.filter(function (x) { return x.sensor === key; })[0];
      var regions = el('div'), worst = el('div'), correlations = el('div');
      panel.appendChild(el('h3', {}, ['Operating regions ', el('small', {}, ['(' + sensor.label + ')'])]));
      panel.appendChild(regions);
      panel.appendChild(el('h3', {}, ['Worst windows ', el('small', {}, ['(' + sensor.label + ')'])]));
      panel.appendChild(worst);
      panel.appendChild(el('h3', {}, ['Correlations ', el('small', {}, ['(' + sensor.label + ')'])]));
      panel.appendChild(correlations);
      guarded(sensor.label + ' operating regions', function () { renderRegions(regions, sensor); });
      guarded(sensor.label + ' worst windows', function () { renderWorst(worst, sensor); });
      guarded(sensor.label + ' correlations', function () { renderCorrelations(correlations, sensor); });
    }
    f.sensors.forEach(function (sensor) {
      var b = el('button', {type: 'button', class: 'sensor', 'data-sensor-tab': sensor.sensor, 'aria-pressed': 'false'},
                 [sensorSummary(sensor)]);
      b.addEventListener('click', function () { show(sensor.sensor); });
      select.appendChild(b);
      buttons[sensor.sensor] = b;
      var panel = el('div', {class: 'sensor-panel', 'data-sensor-panel': sensor.sensor, style: 'display:none'});
      panels.appendChild(panel);
      shown[sensor.sensor] = panel;
    });
    if (f.default_sensor) show(f.default_sensor);
  }

  // --- What is missing -----------------------------------------------------------------------------

  // The verdict on the model itself, per sensor: its error against the noise its own readings show.
  function adequacyLines(a) {
    var order = ['stator', 'rotor'];
    return Object.keys(a.sensors).sort(function (x, y) {
      return (order.indexOf(x) + 1 || 99) - (order.indexOf(y) + 1 || 99);
    }).map(function (key) {
      var x = a.sensors[key], over = x.noise_k ? x.rmse_k / x.noise_k : null;
      var where = x.test_rmse_k !== null && x.test_rmse_k !== undefined && x.test_rmse_k >= x.train_rmse_k ? 'test' : 'training';
      return (key === 'stator' ? 'stator winding' : key) + ': ' + fixed(x.rmse_k, 3) + ' K on the ' + where + ' cycles = ' +
        fixed(over, 1) + '× its noise of ' + fixed(x.noise_k, 3) + ' K, ' + (x.adequate ? 'adequate' : 'something is missing' +
          (x.cycles && x.cycles.length ? ' (worst: ' + x.cycles.slice(0, 4).join(', ') + (x.cycles.length > 4 ? ', …' : '') + ')' : '') +
          (x.region ? '; largest at ' + x.region.name + ': ' + fixed(x.region.rmse_k, 2) + ' K' : '') +
          (x.follows && x.follows.length ? '; follows ' + x.follows.map(function (f) {
            return f.input + ' (r = ' + (f.correlation > 0 ? '+' : '') + fixed(f.correlation, 2) + ')'; }).join(', ') : ''));
    });
  }

  function recommendedOf(d) { return d.candidates.filter(function (c) { return c.recommended; })[0]; }

  // At the top of the page: what diagnose concluded, so that it is read before any chart.
  function renderVerdict() {
    var d = R.diagnosis, parent = document.getElementById('verdict');
    if (!d || !d.adequacy) return;
    var rec = recommendedOf(d), drift = d.drift && d.drift.found ? d.drift : null;
    var fault = (d.sensor_faults || []).filter(function (f) { return f.found; })[0];
    var cls = fault ? 'sensor' : drift ? 'drift' : d.adequacy.adequate ? 'adequate' : 'missing';
    var box = el('div', {class: 'verdict ' + cls, 'data-verdict': cls});
    // A sensor that reads wrong first: while it stands, the verdict on the model is against a faulty
    // reading, and nothing the model could add is to be trusted.
    if (fault) box.appendChild(el('p', {'data-finding': 'sensor'}, [el('strong', {}, ['A sensor reads wrong: ']),
      fault.finding + '. Inspect ' + fault.inspect + '. Nothing is recommended while it stands. Calibrate around it: ',
      el('code', {}, ['lptn calibrate --sensor-fault ' + fault.calibrate])]));
    box.appendChild(el('p', {}, [el('strong', {}, [d.adequacy.adequate ? 'The model is adequate' : 'Something is missing']),
      d.adequacy.adequate ? ': every measured sensor is within ' + (d.adequacy.adequate_within ? fixed(d.adequacy.adequate_within, 1) + ' times ' : '') + 'its noise.' : ': the model is off by more than its sensors\' noise.']));
    adequacyLines(d.adequacy).forEach(function (line) { box.appendChild(el('p', {}, [line])); });
    if (drift) box.appendChild(el('p', {}, [el('strong', {}, ['Drift: ']), drift.finding + '. Inspect ' + drift.inspect + '.']));
    if (rec) box.appendChild(el('p', {}, [el('strong', {}, ['Add: ']), rec.effect + ' — ' + rec.words +
      ' (held-out ' + fixed(rec.test_rmse_k_before, 3) + ' → ' + fixed(rec.test_rmse_k_after, 3) + ' K): ',
      el('code', {}, ['lptn calibrate --effect ' + rec.effect])]));
    else if (!d.adequacy.adequate && !drift && !fault) {
      box.appendChild(el('p', {}, ['No effect of the library and no term of the dictionary explains it: see ',
        el('a', {href: '#failures'}, ['where it fails']), ' (cycles, operating regions, the inputs the residual follows).']));
      // What each failing sensor's residual looks like in time (diagnose's shape_in_words).
      Object.keys(d.adequacy.sensors).forEach(function (key) {
        var shape = d.adequacy.sensors[key].shape;
        if (shape && shape.words) box.appendChild(el('p', {'data-shape': key}, [el('strong', {}, ['What its shape suggests: ']),
          shape.words.charAt(0).toUpperCase() + shape.words.slice(1) + '.']));
      });
    }
    parent.appendChild(box);
  }

  // At the very top where the data is not the calibration's own: which cycles it never saw, and
  // lptn check's verdict on them.
  function renderCheck() {
    var c = R.check, parent = document.getElementById('verdict');
    if (!c) return;
    var box = el('div', {class: 'verdict ' + (c.holds ? 'adequate' : 'missing'), 'data-verdict': 'check'});
    box.appendChild(el('p', {}, [el('strong', {}, ['Data this calibration never saw']), ': ' + c.summary + '.']));
    box.appendChild(el('p', {}, [el('code', {}, ['lptn check']), c.holds ?
      ': the calibration holds on this data (cooling factor ' + fixed(c.cooling_factor, 3) + ', 1 = as calibrated).' :
      ': the calibration does NOT hold on this data:']));
    c.reasons.forEach(function (r) { box.appendChild(el('p', {}, ['• ' + r])); });
    parent.appendChild(box);
  }

  // The per-cycle factor of the drifting group, with the cycles the drift names marked.
  function renderDrift(parent, drift) {
    if (!drift || !drift.factors || !drift.factors.length) return;
    parent.appendChild(el('h3', {}, ['Drift between cycles: the ' + drift.group + ' per cycle']));
    parent.appendChild(el('p', {class: drift.found ? '' : 'note'}, [drift.found ? drift.finding + '. Inspect ' + drift.inspect + '.' :
      'No drift (p = ' + fixed(drift.p_value, 2) + '): each cycle\'s factor of the ' + drift.group +
      ', the model refit with only that group scaled; 1 means as calibrated.']));
    var changed = {};
    (drift.cycles || []).forEach(function (c) { changed[c] = true; });
    var data = drift.factors.map(function (f, i) {
      return [i + 1, changed[f.cycle] ? null : f.factor, changed[f.cycle] ? f.factor : null];
    });
    var box = el('div');
    parent.appendChild(box);
    guarded('drift chart', function () {
      graph(box, 'drift', data, {labels: ['cycle', drift.group + ' factor', drift.group + ' factor (drifted)'],
        drawPoints: true, pointSize: 5, strokeWidth: 0, colors: ['#1f4e9c', '#e39b1b'], xlabel: 'cycle (in the dump\'s order)',
        ylabel: 'factor', dateWindow: [0.5, data.length + 0.5],
        axes: {x: {axisLabelFormatter: function (v) { return Number.isInteger(v) ? String(v) : ''; },
                   valueFormatter: function (v) { var f = drift.factors[v - 1]; return f ? f.cycle : String(v); }}}}, 'small');
    });
  }

  // Each checked sensor's per-cycle offset (mean reading minus the model's), the faulty cycles marked.
  function renderSensorFaults(parent, faults) {
    (faults || []).forEach(function (f) {
      if (!f.offsets || !f.offsets.length) return;
      parent.appendChild(el('h3', {}, ['The ' + f.sensor + ' sensor per cycle: mean reading minus the model']));
      parent.appendChild(el('p', {class: f.found ? '' : 'note'}, [f.found ? 'Sensor fault: ' + f.finding + '.' :
        'No sensor fault: ' + f.finding + '.']));
      var faulty = {};
      (f.cycles || []).forEach(function (c) { faulty[c] = true; });
      var data = f.offsets.map(function (o, i) {
        return [i + 1, faulty[o.cycle] ? null : o.offset_k, faulty[o.cycle] ? o.offset_k : null];
      });
      var box = el('div');
      parent.appendChild(box);
      guarded('sensor chart', function () {
        graph(box, 'sensor-' + f.sensor, data, {labels: ['cycle', 'offset K', 'offset K (faulty)'],
          drawPoints: true, pointSize: 5, strokeWidth: 0, colors: ['#1f4e9c', '#c0392b'], xlabel: 'cycle (in the dump\'s order)',
          ylabel: 'reading − model, K', dateWindow: [0.5, data.length + 0.5],
          axes: {x: {axisLabelFormatter: function (v) { return Number.isInteger(v) ? String(v) : ''; },
                     valueFormatter: function (v) { var o = f.offsets[v - 1]; return o ? o.cycle : String(v); }}}}, 'small');
      });
    });
  }

  function renderDiagnosis() {
    var parent = document.getElementById('diagnosis'), d = R.diagnosis;
    if (!d) {
      parent.appendChild(el('p', {}, ['No diagnosis given. Run ', el('code', {}, ['lptn diagnose --json > diagnosis.json']),
        ' with this calibration and data, then ', el('code', {}, ['lptn report … --diagnosis diagnosis.json']),
        ' to see which effects the residual points at.']));
      return;
    }
    parent.appendChild(el('p', {}, ['Residual RMSE as diagnosed: ' + fixed(d.rmse_k, 3) + ' K.']));
    if (d.adequacy) {
      parent.appendChild(el('h3', {}, ['The model against its sensors\' noise: ' +
        (d.adequacy.adequate ? 'adequate' : 'something is missing')]));
      var list = el('ul', {'data-list': 'adequacy'});
      adequacyLines(d.adequacy).forEach(function (line) { list.appendChild(el('li', {}, [line])); });
      parent.appendChild(list);
    }
    parent.appendChild(el('h3', {}, ['Candidates: the library\'s effects, the dictionary\'s best terms']));
    var rowsOut = d.candidates.map(function (c) {
      var cls = c.recommended ? 'recommended' : c.significant ? 'significant' : '';
      return el('tr', {class: cls}, [el('td', {class: 'text'}, [c.effect]), el('td', {class: 'text'}, [c.kind || 'library']),
        el('td', {class: 'text'}, [c.words || '']),
        el('td', {}, [fixed(c.statistic, 1) + (c.threshold !== null && c.threshold !== undefined ? ' / ' + fixed(c.threshold, 1) : '')]),
        el('td', {}, [fixed(c.refit_rmse_k, 3)]),
        el('td', {}, [c.kind === 'drift' || c.kind === 'sensor' ? '–' : fixed(c.test_rmse_k_before, 3) + ' → ' + fixed(c.test_rmse_k_after, 3)]),
        el('td', {class: 'text'}, [c.recommended ? 'recommended' : (c.verdict || (c.significant ? 'significant' : 'not significant'))])]);
    });
    parent.appendChild(table(['effect or term', 'kind', 'in words (refit)', 'LR / threshold', 'refit train RMSE K',
                              'held-out K before → after', 'verdict'], rowsOut, {'data-table': 'diagnosis'}));
    renderSensorFaults(parent, d.sensor_faults);
    renderDrift(parent, d.drift);
    parent.appendChild(el('p', {class: 'note'}, ['Evidence for the leading candidates: each sensor\'s mean residual over ' +
      'quantile bins of the candidate\'s signature. For an effect of the library, what it would add (from common/lptn/effects); ' +
      'for a term of the dictionary, how much diagnose\'s refit with it changes the sensor reading against this calibration, which a residual (model − measured) ' +
      'follows with slope −1 where the term is what is missing. A flat line means that residual does not follow it. The title ' +
      'names the sensor whose bin means spread most, as a multiple of its noise.']));
    var grid = el('div', {class: 'grid2'});
    parent.appendChild(grid);
    d.evidence.forEach(function (ev) {
      var box = el('div', {'data-evidence': ev.effect});
      grid.appendChild(box);
      guarded('evidence ' + ev.effect, function () {
        var most = ev.sensors.filter(function (x) { return x.sensor === ev.most; })[0];
        box.appendChild(el('div', {}, [el('strong', {}, [ev.effect + ': residual vs ' + ev.label]),
          most ? ' — shows most on the ' + most.label + ' (spread ' + fixed(most.trend_over_noise, 1) + '× its noise' +
            ev.sensors.filter(function (x) { return x !== most; }).map(function (x) {
              return '; ' + x.label + ' ' + fixed(x.trend_over_noise, 1) + '×';
            }).join('') + ')' : '']));
        if (ev.words) box.appendChild(el('div', {class: 'note'}, [ev.words]));
        var bins = ev.sensors.length ? ev.sensors[0].bins : [];
        var data = [];
        bins.forEach(function (b, i) {
          var means = ev.sensors.map(function (x) { return x.bins[i].n > 0 ? x.bins[i].mean : null; });
          if (means.some(function (v) { return v !== null; })) data.push([(b.lo + b.hi) / 2].concat(means));
        });
        graph(box, 'evidence-' + ev.effect, data, {labels: [ev.label + ' ' + ev.unit].concat(ev.sensors.map(function (x) {
          return x.label + ' mean residual K'; })), drawPoints: true, pointSize: 3, strokeWidth: 1,
          xlabel: ev.label + ' (' + ev.unit + ')', ylabel: 'K', colors: ev.sensors.map(function (x) { return SENSOR_COLOR[x.sensor]; })}, 'small');
      });
    });
  }

  // --- History -------------------------------------------------------------------------------------

  // Each sensor's error, and both pooled, on train (solid) and test (dashed) cycles per revision.
  var HISTORY_SERIES = [
    {key: 'stator', label: 'stator'}, {key: 'rotor', label: 'rotor'}, {key: 'combined', label: 'combined'}];

  function renderHistory() {
    var h = R.history, parent = document.getElementById('history-body');
    parent.appendChild(el('p', {class: 'note'}, ['Calibrations in ' + h.dir + ' by creation time' +
      (h.skipped ? ' (' + h.skipped + ' other JSON files skipped)' : '') + ': the RMSE of each sensor on the train ' +
      '(solid) and test (dashed) cycles, and the combined figure: the RMS over both sensors\' residuals, every 0.1 s sample ' +
      'of either counting once, √((n_stator e_stator² + n_rotor e_rotor²) / (n_stator + n_rotor)). A sensor measured on ' +
      'neither side of a calibration has no point.']));
    function value(r, side, key) { var v = r[side + '_rmse_' + key + '_k']; return v === undefined ? null : v; }
    var columns = [], labels = ['run'], colors = [], series = {};
    var rotor = h.runs.some(function (r) { return value(r, 'train', 'rotor') !== null || value(r, 'test', 'rotor') !== null; });
    HISTORY_SERIES.forEach(function (s) {
      if (s.key === 'combined' && !rotor) return;  // the stator's own figure again
      ['train', 'test'].forEach(function (side) {
        if (!h.runs.some(function (r) { return value(r, side, s.key) !== null; })) return;
        var label = side + ' RMSE ' + s.label + ' K';
        columns.push({side: side, key: s.key});
        labels.push(label);
        colors.push(SENSOR_COLOR[s.key]);
        series[label] = side === 'test' ? {strokePattern: [6, 4]} : {};
      });
    });
    var data = h.runs.map(function (r, i) {
      return [i + 1].concat(columns.map(function (c) { return value(r, c.side, c.key); }));
    });
    guarded('history chart', function () {
      graph(parent, 'history', data, {labels: labels, drawPoints: true, pointSize: 4, colors: colors, series: series,
        xlabel: 'run', ylabel: 'RMSE K', includeZero: true, connectSeparatedPoints: true, strokeWidth: 2,
        dateWindow: [0.5, h.runs.length + 0.5],  // room for the first and last run's points and labels
        axes: {x: {axisLabelFormatter: function (v) { return Number.isInteger(v) ? String(v) : ''; }}}}, 'small');
    });
    var rowsOut = h.runs.map(function (r, i) {
      return el('tr', {class: r.current ? 'significant' : ''}, [el('td', {}, [i + 1]), el('td', {class: 'text'}, [r.file]),
        el('td', {class: 'text'}, [r.created_utc]), el('td', {class: 'text'}, [r.method]),
        el('td', {class: 'text'}, [r.effects.length ? r.effects.join(', ') : 'paper only'])].concat(
        ['stator', 'rotor', 'combined'].reduce(function (cells, key) {
          return cells.concat(['train', 'test'].map(function (side) { return el('td', {}, [fixed(value(r, side, key), 3)]); }));
        }, [])));
    });
    parent.appendChild(table(['run', 'file', 'created', 'method', 'effects', 'train stator K', 'test stator K',
                              'train rotor K', 'test rotor K', 'train combined K', 'test combined K'], rowsOut,
                             {'data-table': 'history'}));
  }

  // --- Fleet -----------------------------------------------------------------------------------------

  function percent(factor) {
    var p = Math.round(1000 * (factor - 1)) / 10;  // one decimal, and no "-0.0"
    return (p > 0 ? '+' : p < 0 ? '' : '±') + p.toFixed(1) + ' %';
  }

  function renderFleet() {
    var f = R.fleet, parent = document.getElementById('fleet-body');
    var outliers = f.motors.filter(function (m) { return m.outlier; });
    parent.appendChild(el('div', {class: 'verdict ' + (outliers.length ? 'missing' : 'adequate'), 'data-verdict': 'fleet'},
      [el('p', {}, [outliers.length
        ? 'Outlier' + (outliers.length > 1 ? 's' : '') + ': ' + outliers.map(function (m) {
            return m.id + ' ' + m.reason; }).join('; ') + '.'
        : (f.threshold_t === null ? 'Too few motors to tell the fleet\'s spread: no motor tested.'
                                  : 'No motor cools unlike the rest of the fleet.')])]));
    // x: the motors in order; two series, so that the outliers stand out in colour.
    var data = f.motors.map(function (m, i) {
      var bar = [m.cooling_factor, m.cooling_factor_std];
      return [i + 1, m.outlier ? null : bar, m.outlier ? bar : null];
    });
    var ids = f.motors.map(function (m) { return m.id; });
    function motorAt(v) { return Number.isInteger(v) && v >= 1 && v <= ids.length ? ids[v - 1] : ''; }
    // Each motor a dot with its own whisker: dygraphs' error bars would join neighbours into a band,
    // as if the motors were a time series. y_top and y_bottom are the bar's ends, as fractions of
    // the plot's height (dygraphs' layout sets them when errorBars is on).
    function whiskers(e) {
      var ctx = e.drawingContext, area = e.plotArea;
      ctx.strokeStyle = e.color;
      ctx.fillStyle = e.color;
      ctx.lineWidth = 1.5;
      e.points.forEach(function (p) {
        if (p.yval === null || isNaN(p.canvasy)) return;
        var top = area.y + area.h * p.y_top, bottom = area.y + area.h * p.y_bottom;
        ctx.beginPath();
        ctx.moveTo(p.canvasx, top); ctx.lineTo(p.canvasx, bottom);
        ctx.moveTo(p.canvasx - 6, top); ctx.lineTo(p.canvasx + 6, top);
        ctx.moveTo(p.canvasx - 6, bottom); ctx.lineTo(p.canvasx + 6, bottom);
        ctx.stroke();
        ctx.beginPath();
        ctx.arc(p.canvasx, p.canvasy, 4, 0, 2 * Math.PI);
        ctx.fill();
      });
    }
    var lo = Math.min.apply(null, f.motors.map(function (m) { return m.cooling_factor - 3 * m.cooling_factor_std; }));
    var hi = Math.max.apply(null, f.motors.map(function (m) { return m.cooling_factor + 3 * m.cooling_factor_std; }));
    var pad = 0.1 * Math.max(hi - lo, 0.05);
    guarded('fleet chart', function () {
      graph(parent, 'fleet', data, {labels: ['motor', 'cooling factor', 'outlier'], errorBars: true, sigma: 2,
        plotter: whiskers, colors: ['#1f4e9c', '#c00'], valueRange: [Math.min(lo, 1) - pad, Math.max(hi, 1) + pad],
        dateWindow: [0.5, ids.length + 0.5], xlabel: 'motor', ylabel: 'cooling factor (±2σ)',
        // The type's own cooling, 1, as a reference line.
        underlayCallback: function (ctx, area, g) {
          var y = g.toDomYCoord(1);
          ctx.strokeStyle = '#888';
          ctx.setLineDash([4, 4]);
          ctx.beginPath(); ctx.moveTo(area.x, y); ctx.lineTo(area.x + area.w, y); ctx.stroke();
          ctx.setLineDash([]);
        },
        axes: {x: {valueFormatter: motorAt, axisLabelWidth: 80, drawGrid: false,
                   ticker: function () { return ids.map(function (id, i) { return {v: i + 1, label: id}; }); }}}}, 'tall');
    });
    var rows = f.motors.map(function (m) {
      return el('tr', {class: m.outlier ? 'outlier' : ''}, [el('td', {class: 'text'}, [m.id]),
        el('td', {}, [fixed(m.cooling_factor, 3)]), el('td', {}, [fixed(m.cooling_factor_std, 3)]),
        el('td', {}, [percent(m.cooling_factor)]), el('td', {}, [fixed(m.t, 2)]), el('td', {}, [m.cycles]),
        el('td', {}, [fixed(m.rmse_stator_k, 3)]), el('td', {}, [fixed(m.rmse_rotor_k, 3)]),
        el('td', {class: 'text'}, [(m.outlier ? 'OUTLIER: ' : '') + m.reason])]);
    });
    parent.appendChild(table(['motor', 'cooling factor', 'std', 'vs type', 't', 'cycles', 'stator RMSE K', 'rotor RMSE K',
                              'verdict'], rows, {'data-table': 'fleet'}));
    parent.appendChild(el('p', {class: 'note'}, [f.file + ': motor type ' + f.motor + ', ' + f.motors.length +
      ' motors, ' + f.rounds + ' rounds of the shared fit and the factors; outlier test at family rate ' +
      fixed(100 * f.family_alpha, 0) + ' %' + (f.threshold_t === null ? '' : ', |t| > ' + fixed(f.threshold_t, 2)) +
      '. RMSE: each motor\'s cycles with its own factor.']));
  }

  // A page of a fleet alone (lptn report --fleet without --data): only its section.
  if (!R.cycles) {
    ['compare', 'failures', 'missing', 'history'].forEach(function (id) { document.getElementById(id).style.display = 'none'; });
    document.querySelector('nav').style.display = 'none';
    document.getElementById('meta').textContent = 'Fleet calibration ' + R.fleet.file + ' (motor ' + R.fleet.motor + ', ' +
      R.fleet.created_utc + '). Generated ' + R.generated_utc + '.';
  } else {
    guarded('header', renderMeta);
    guarded('check', renderCheck);
    guarded('verdict', renderVerdict);
    guarded('metrics table', renderCompareTable);
    guarded('compare charts', renderCycles);
    guarded('where it fails', renderFailures);
    guarded('diagnosis', renderDiagnosis);
    guarded('history', renderHistory);
  }
  if (R.fleet) guarded('fleet', renderFleet);
  else {
    document.getElementById('fleet').style.display = 'none';
    document.getElementById('fleet-link').style.display = 'none';
  }
  document.body.setAttribute('data-rendered', 'true');
})();
