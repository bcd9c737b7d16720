// Draws the figures of a `tearflow report` page from window.TEARFLOW_DATA with Chart.js
// (inlined before this script). One page shows one run or several overlaid (the runs are
// told apart by dash pattern, the landmarks by colour). After drawing, each figure's PNG is
// put into the page (img.figure-png) so that `tearflow report --png` can save it, and
// body[data-rendered] counts the figures; script errors are listed in #script-errors.
'use strict';
(function () {
  const errors = document.getElementById('script-errors');
  window.addEventListener('error', (e) => { errors.textContent += e.message + '\n'; });
  const data = window.TEARFLOW_DATA;
  const figures = document.getElementById('figures');
  // One style per run: a study with rigid counterparts (docs/study.md) has twice its variants.
  const dashes = [[], [6, 4], [2, 3], [10, 3, 2, 3], [12, 6], [4, 2, 1, 2], [1, 5], [8, 2, 8, 6]];
  const palette = ['#1f77b4', '#ff7f0e', '#2ca02c', '#d62728', '#9467bd', '#8c564b',
                   '#e377c2', '#7f7f7f', '#bcbd22', '#17becf'];
  const multi = data.runs.length > 1;
  let drawn = 0;

  function figure(name, title, config, into) {
    const box = document.createElement('section');
    box.className = 'figure';
    box.innerHTML = '<h3></h3><div class="canvas"><canvas></canvas></div>' +
                    '<img class="figure-png" alt="" hidden>';
    box.querySelector('h3').textContent = title;
    (into || figures).appendChild(box);
    config.options = Object.assign({animation: false, responsive: true,
                                    maintainAspectRatio: false,
                                    devicePixelRatio: 2}, config.options || {});
    const chart = new Chart(box.querySelector('canvas'), config);
    const png = box.querySelector('img');
    png.dataset.name = name;
    png.src = chart.toBase64Image('image/png', 1);
    drawn += 1;
  }

  function axes(x, y, linear) {
    return {scales: {x: {type: linear ? 'linear' : 'category', title: {display: true, text: x}},
                     y: {title: {display: true, text: y}}},
            plugins: {legend: {position: 'right'}}};
  }

  function label(run, name) { return multi ? run.name + ': ' + name : name; }

  // Time series of `column` for the landmarks `names` of every run.
  function series(name, title, names, column, unit) {
    const datasets = [];
    data.runs.forEach((run, r) => {
      names.filter((n) => run.series[n]).forEach((n, i) => {
        const s = run.series[n];
        datasets.push({label: label(run, n), showLine: true, pointRadius: 0, borderWidth: 1.5,
                       borderColor: palette[i % palette.length],
                       borderDash: dashes[r % dashes.length],
                       data: s.time_s.map((t, k) => ({x: t - s.time_s[0], y: s[column][k]}))});
      });
    });
    if (datasets.length)
      figure(name, title, {type: 'scatter', data: {datasets},
                           options: axes('time in the analysed cycle [s]', unit, true)});
  }

  const aorta = ['inlet', 'AAo', 'DAo_prox', 'DAo_dist', 'outlet'];
  const stations = [1, 2, 3, 4, 5];
  const tl = stations.map((k) => 'TL' + k), fl = stations.map((k) => 'FL' + k);
  series('flow_aorta', 'Flow rate, undivided aorta', aorta, 'flow_mL_per_s', 'Q [mL/s]');
  series('flow_TL', 'Flow rate, true lumen along the dissection', tl, 'flow_mL_per_s',
         'Q [mL/s]');
  series('flow_FL', 'Flow rate, false lumen along the dissection', fl, 'flow_mL_per_s',
         'Q [mL/s]');

  // dP(t) = P_TL - P_FL at the paired stations.
  const dp = [];
  data.runs.forEach((run, r) => {
    stations.filter((k) => run.series['TL' + k] && run.series['FL' + k]).forEach((k, i) => {
      const t = run.series['TL' + k], f = run.series['FL' + k];
      dp.push({label: label(run, 'station ' + k), showLine: true, pointRadius: 0,
               borderWidth: 1.5, borderColor: palette[i], borderDash: dashes[r % dashes.length],
               data: t.time_s.map((x, j) => ({x: x - t.time_s[0], y: t.mean_pressure_mmHg[j] -
                                                     f.mean_pressure_mmHg[j]}))});
    });
  });
  if (dp.length)
    figure('pressure_difference', 'TL - FL pressure difference dP(t)',
           {type: 'scatter', data: {datasets: dp},
            options: axes('time in the analysed cycle [s]', 'dP [mmHg]', true)});

  // Peak-systolic pressure over the inlet's along each lumen.
  const along = ['inlet', 'S1', 'S2', 'S3', 'S4', 'S5', 'outlet'];
  const normalised = [];
  data.runs.forEach((run, r) => {
    const p = run.metrics.peak_systolic_pressure_over_inlet || {};
    [['TL', tl, palette[0]], ['FL', fl, palette[3]]].forEach(([lumen, names, colour]) => {
      const values = ['inlet', ...names, 'outlet'].map((n) => (n in p ? p[n] : null));
      if (values.some((v, i) => v !== null && i > 0 && i < 6))
        normalised.push({label: label(run, lumen), data: values, borderColor: colour,
                         backgroundColor: colour, borderDash: dashes[r % dashes.length],
                         spanGaps: true});
    });
  });
  if (normalised.length)
    figure('normalised_pressure', 'Peak-systolic pressure over the inlet\'s, along TL and FL',
           {type: 'line', data: {labels: along, datasets: normalised},
            options: axes('landmark (Sk: station k)', 'P / P_inlet [-]', false)});

  series('area_change_aorta', 'Relative area change, undivided aorta', aorta, 'area_over_A_0',
         'A(t) / A_0 [-]');
  series('area_change_lumina', 'Relative area change, TL and FL', [...tl, ...fl],
         'area_over_A_0', 'A(t) / A_0 [-]');

  // The flap's displacement toward the FL at the stations (FSI runs), from the cycle's start.
  const flap = [];
  data.runs.forEach((run, r) => {
    stations.forEach((k, i) => {
      const s = run.series['TL' + k];
      const d = s && s.flap_displacement_toward_FL_mm;
      if (!d || d.some((v) => v === null || !Number.isFinite(v))) return;
      flap.push({label: label(run, 'station ' + k), showLine: true, pointRadius: 0,
                 borderWidth: 1.5, borderColor: palette[i], borderDash: dashes[r % dashes.length],
                 data: s.time_s.map((t, j) => ({x: t - s.time_s[0], y: d[j] - d[0]}))});
    });
  });
  if (flap.length)
    figure('flap_displacement', 'Flap displacement toward the FL at the stations, from the ' +
           'cycle\'s start', {type: 'scatter', data: {datasets: flap},
            options: axes('time in the analysed cycle [s]', 'displacement [mm]', true)});

  // A_max per landmark, one bar per run.
  const names = [];
  data.runs.forEach((run) => Object.keys(run.metrics.landmarks || {}).forEach((n) => {
    if (!names.includes(n)) names.push(n);
  }));
  const bars = data.runs.map((run, r) => ({
    label: run.name, backgroundColor: palette[r % palette.length],
    data: names.map((n) => (run.metrics.landmarks[n] ? run.metrics.landmarks[n].A_max_mm2 : null))
  }));
  if (names.length)
    figure('maximum_area', 'Maximum cross-sectional area per landmark',
           {type: 'bar', data: {labels: names, datasets: bars},
            options: axes('landmark', 'A_max [mm^2]', false)});

  // Simulation against 4D-flow MRI (`tearflow report --mri`): the Bland-Altman plot of every
  // landmark's frame pairs (difference against mean, colour per landmark) with the pooled
  // bias and limits of agreement, and per landmark both flow waveforms on the MRI frames.
  if (data.mri) {
    const mri = data.mri, into = document.getElementById('mri-figures');
    const points = mri.landmarks.map((n, i) => {
      const p = mri.pairs[n];
      return {label: n, pointRadius: 3, borderColor: palette[i % palette.length],
              backgroundColor: palette[i % palette.length],
              data: p.mean_mL_per_s.map((m, k) => ({x: m, y: p.difference_mL_per_s[k]}))};
    });
    const all = points.flatMap((d) => d.data.map((p) => p.x));
    const lo = Math.min(...all), hi = Math.max(...all);
    const pooled = mri.pooled, loa = pooled.limits_of_agreement_mL_per_s;
    [[pooled.bias_mL_per_s, 'mean difference', []], [loa[0], 'bias - 1.96 SD', [6, 4]],
     [loa[1], 'bias + 1.96 SD', [6, 4]]].forEach(([y, name, dash]) => {
      points.push({label: name + ' (' + y.toFixed(2) + ')', showLine: true, pointRadius: 0,
                   borderColor: '#000', borderWidth: 1.5, borderDash: dash,
                   data: [{x: lo, y}, {x: hi, y}]});
    });
    const options = axes('(Q_MRI + Q_sim) / 2 [mL/s]', 'Q_MRI - Q_sim [mL/s]', true);
    options.plugins.legend.position = 'bottom'; // the lines' labels carry their values
    figure('mri_bland_altman', 'Bland-Altman: MRI - simulation against their mean, all landmarks',
           {type: 'scatter', data: {datasets: points}, options}, into);
    mri.landmarks.forEach((n, i) => {
      const p = mri.pairs[n], colour = palette[i % palette.length];
      const line = (column, label, dash, radius) => ({
        label, showLine: true, pointRadius: radius, borderWidth: 1.5, borderColor: colour,
        backgroundColor: colour, borderDash: dash,
        data: p.time_s.map((t, k) => ({x: t, y: p[column][k]}))});
      figure('mri_flow_' + n, 'Flow rate at ' + n + ': simulation and MRI',
             {type: 'scatter',
              data: {datasets: [line('simulation_mL_per_s', 'simulation', [], 0),
                                line('mri_mL_per_s', 'MRI', [6, 4], 3)]},
              options: axes('time from the first MRI frame [s]', 'Q [mL/s]', true)}, into);
    });
  }

  document.body.dataset.rendered = String(drawn);
})();
