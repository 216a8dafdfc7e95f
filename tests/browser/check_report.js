#!/usr/bin/env node
// check_report.js: loads a symrec HTML report in a real headless browser and checks
// that it works: no console error or uncaught exception, no network request, the 3D
// view drawn in WebGL (a screenshot of the canvas, decoded by the browser itself, shows
// the part's grey and the patches' orange on the white background; zooming and the
// patches' checkbox change what it draws), the outline plot
// rendered as SVG, the build plans' tool paths drawn in the plot for the layers that
// have them (as many as the page's data holds), the feature table with the expected
// rows and no JSON in any table cell, the page without WebGL (its note instead of the
// canvas, no error), and the page printed to PDF (A4) in at most MAX_PAGES pages
// (counted as the PDF's /Type /Page objects). With INSPECTION_ROWS, the run's
// inspection section (issue 20) too: its canvas drawn in WebGL with the deviation
// colours the data ask for (read back from the canvas: the blue of material short,
// the green of the tolerance band, the yellow to red of stock, each present when at
// least 5 % of the scan's vertices call for it), the colour scale's legend (its
// gradient, five ticks symmetric about 0 with the tolerance among them, the band
// framed where the ticks put it) and the table with INSPECTION_ROWS rows, each with
// a verdict; without it the page must have no inspection section.
//
//   node tests/browser/check_report.js REPORT.html EXPECTED_SECTION_ROWS [BROWSER] [MAX_PAGES]
//                                      [INSPECTION_ROWS]
//
// SYMREC_REPORT_PDF=FILE keeps the PDF, SYMREC_REPORT_PNG=FILE the screenshot,
// SYMREC_REPORT_INSPECT_PNG=FILE the inspection's canvas.
//
// The browser is Debian's chromium-headless-shell (or $SYMREC_BROWSER / BROWSER, any
// Chromium), driven over the DevTools protocol on a pipe (--remote-debugging-pipe:
// fd 3 in, fd 4 out, messages ended by NUL), so nothing from npm is needed. Exit 0 when
// every check passes, 1 with one line per failed check, 77 when no browser is found
// (the caller reports a skip).
'use strict';
const { spawn } = require('child_process');
const fs = require('fs');
const os = require('os');
const path = require('path');

const [, , reportArg, rowsArg, browserArg, pagesArg, inspectArg] = process.argv;
const inspectRows = inspectArg === undefined || inspectArg === '' ? -1 : parseInt(inspectArg, 10);
const maxPages = pagesArg ? parseInt(pagesArg, 10) : 4;
if (!reportArg || rowsArg === undefined) {
  console.error('usage: node check_report.js REPORT.html EXPECTED_SECTION_ROWS [BROWSER] [MAX_PAGES] [INSPECTION_ROWS]');
  process.exit(2);
}
const candidates = [browserArg, process.env.SYMREC_BROWSER, '/usr/bin/chromium-headless-shell',
  '/usr/lib/chromium-headless-shell/chromium-headless-shell', '/usr/bin/chromium'];
const browser = candidates.find((p) => p && fs.existsSync(p));
if (!browser) {
  console.log('check_report: no headless browser found (apt-get install chromium-headless-shell)');
  process.exit(77);
}
const report = path.resolve(reportArg);
const url = 'file://' + report;
const expectedRows = parseInt(rowsArg, 10);
const profile = fs.mkdtempSync(path.join(os.tmpdir(), 'symrec-browser-'));

const proc = spawn(browser, ['--headless', '--no-sandbox', '--disable-gpu',
  '--remote-debugging-pipe', '--user-data-dir=' + profile, '--use-angle=swiftshader',
  '--enable-unsafe-swiftshader', '--window-size=1200,900', '--no-first-run',
  '--disable-extensions', '--disable-background-networking', 'about:blank'],
{ stdio: ['ignore', 'ignore', 'pipe', 'pipe', 'pipe'] });
let stderr = '';
proc.stderr.on('data', (d) => { stderr += d; });

let nextId = 1;
const waiting = new Map();
const events = [];
let listeners = [];
let buf = Buffer.alloc(0);
proc.stdio[4].on('data', (chunk) => {
  buf = Buffer.concat([buf, chunk]);
  let i;
  while ((i = buf.indexOf(0)) >= 0) {
    const msg = JSON.parse(buf.slice(0, i).toString('utf8'));
    buf = buf.slice(i + 1);
    if (msg.id && waiting.has(msg.id)) {
      const { resolve, reject } = waiting.get(msg.id);
      waiting.delete(msg.id);
      if (msg.error) reject(new Error(msg.error.message)); else resolve(msg.result);
    } else if (msg.method) {
      events.push(msg);
      listeners.forEach((l) => l(msg));
    }
  }
});
function send(method, params, sessionId) {
  const id = nextId++;
  const m = { id, method, params: params || {} };
  if (sessionId) m.sessionId = sessionId;
  proc.stdio[3].write(JSON.stringify(m) + '\0');
  return new Promise((resolve, reject) => waiting.set(id, { resolve, reject }));
}
function waitFor(pred, ms) {
  return new Promise((resolve, reject) => {
    const hit = events.find(pred);
    if (hit) { resolve(hit); return; }
    const t = setTimeout(() => reject(new Error('timed out waiting for the page')), ms);
    listeners.push((m) => { if (pred(m)) { clearTimeout(t); resolve(m); } });
  });
}

const failures = [];
function check(ok, what) { if (!ok) failures.push(what); }

async function main() {
  const { targetId } = await send('Target.createTarget', { url: 'about:blank' });
  const { sessionId } = await send('Target.attachToTarget', { targetId, flatten: true });
  await send('Runtime.enable', {}, sessionId);
  await send('Log.enable', {}, sessionId);
  await send('Page.enable', {}, sessionId);
  await send('Network.enable', {}, sessionId);
  await send('Page.navigate', { url }, sessionId);
  await waitFor((m) => m.method === 'Page.loadEventFired' && m.sessionId === sessionId, 20000);
  // let the script and one animation frame run
  await new Promise((r) => setTimeout(r, 500));
  const evaluate = async (expr) => {
    const r = await send('Runtime.evaluate', { expression: expr, returnByValue: true }, sessionId);
    if (r.exceptionDetails) throw new Error('evaluate failed: ' + r.exceptionDetails.text);
    return r.result.value;
  };
  await send('Emulation.setDeviceMetricsOverride',
    { width: 1200, height: 900, deviceScaleFactor: 1, mobile: false }, sessionId);
  // the 3D view as the screen shows it: a screenshot of the canvas's box
  const box = await evaluate(`(function(){ var cv = document.getElementById('view');
    if (!cv || cv.hidden) return null; cv.scrollIntoView(); var r = cv.getBoundingClientRect();
    return { x: r.left + window.scrollX, y: r.top + window.scrollY, w: r.width, h: r.height }; })()`);
  let shot = null;
  if (box && box.w > 0) {
    await new Promise((r) => setTimeout(r, 200));
    shot = (await send('Page.captureScreenshot', { format: 'png', captureBeyondViewport: true,
      clip: { x: box.x, y: box.y, width: box.w, height: box.h, scale: 1 } }, sessionId)).data;
    if (process.env.SYMREC_REPORT_PNG) fs.writeFileSync(process.env.SYMREC_REPORT_PNG, Buffer.from(shot, 'base64'));
  }
  const v = await evaluate(`(function(){
    var cv = document.getElementById('view');
    var cells = Array.prototype.filter.call(document.querySelectorAll('td'),
      function (td) { return /[{[]\s*"|"\s*:/.test(td.textContent); }).length;
    var plot = document.getElementById('layer-plot');
    var svg = plot ? plot.querySelector('svg') : null;
    var rows = document.querySelectorAll('#feature-table tbody tr');
    var classes = Array.prototype.map.call(rows, function (r) { return r.cells[1].textContent; });
    // the build plans: select the run layer of each plan layer in turn (at most 12 of
    // them) and count the tool paths drawn against the paths in the page's data
    var data = JSON.parse(document.getElementById('report-data').textContent);
    var sel = document.getElementById('layer-select'), planned = 0, drawn = 0, want = 0, bad = [];
    (data.plans || []).forEach(function (p) {
      p.layers.forEach(function (q, k) {
        if (!sel || k % Math.max(1, Math.ceil(p.layers.length / 12)) !== 0) return;
        sel.value = String(q.rf); sel.dispatchEvent(new Event('change'));
        var n = plot.querySelectorAll('svg polyline.tp').length, w = 0;
        (data.plans || []).forEach(function (p2) { p2.layers.forEach(function (q2) {
          if (q.rf >= q2.rf && q.rf <= q2.rl) q2.paths.forEach(function (t) { if (t.p.length >= 4) w++; }); }); });
        planned++; drawn += n; want += w;
        if (n !== w || n === 0) bad.push('layer ' + q.rf + ': ' + n + ' of ' + w + ' paths drawn');
      });
    });
    var replaced = (data.plans || []).filter(function (p) { return p.replace; }).length;
    var noPlan = document.getElementById('no-plan');
    return { planned: planned, pathsDrawn: drawn, pathsWanted: want, planProblems: bad,
      replaced: replaced, allReplace: (data.plans || []).length > 0 && replaced === data.plans.length,
      noPlanText: noPlan ? noPlan.textContent : '',
      rendered: document.body.getAttribute('data-rendered'),
      view: document.body.getAttribute('data-view'),
      redrawMs: document.body.getAttribute('data-redraw-ms'), jsonCells: cells,
      gl: document.body.getAttribute('data-gl'),
      svg: !!svg,
      polylines: svg ? svg.querySelectorAll('polyline').length : 0,
      rows: rows.length, classes: classes, title: document.title,
      advice: document.querySelectorAll('#advice-table tbody tr').length };
  })()`);
  const problems = events.filter((m) => m.sessionId === sessionId && (
    m.method === 'Runtime.exceptionThrown' ||
    (m.method === 'Runtime.consoleAPICalled' && (m.params.type === 'error' || m.params.type === 'assert')) ||
    (m.method === 'Log.entryAdded' && m.params.entry.level === 'error')));
  problems.forEach((p) => failures.push('console error: ' + JSON.stringify(p.params).slice(0, 300)));
  const requests = events.filter((m) => m.sessionId === sessionId &&
    m.method === 'Network.requestWillBeSent' && !m.params.request.url.startsWith('file://') &&
    !m.params.request.url.startsWith('data:') && !m.params.request.url.startsWith('about:'));
  requests.forEach((r) => failures.push('network request: ' + r.params.request.url));
  check(v.rendered === '1', 'the page script did not finish (data-rendered not set)');
  check(v.view === 'webgl', `the 3D view is not drawn in WebGL (data-view '${v.view}')`);
  // the controls answer: three wheel steps in make the part cover more of the canvas,
  // hiding the patches takes their orange away (the canvas read back by the page)
  if (v.view === 'webgl') {
    const r = await send('Runtime.evaluate', { awaitPromise: true, returnByValue: true,
      expression: `(async function () {
        var cv = document.getElementById('view'), box = document.getElementById('show-patches');
        function frames() { return new Promise(function (r) { requestAnimationFrame(function () { requestAnimationFrame(r); }); }); }
        function count() { var c = document.createElement('canvas'); c.width = cv.width; c.height = cv.height;
          var g = c.getContext('2d'); g.drawImage(cv, 0, 0); var d = g.getImageData(0, 0, c.width, c.height).data, n = { ink: 0, orange: 0 };
          for (var i = 0; i < d.length; i += 4) { if (d[i] < 245 || d[i+1] < 245 || d[i+2] < 245) n.ink++;
            if (d[i] > 90 && d[i] - d[i+2] > 60 && d[i] - d[i+1] > 40) n.orange++; } return n; }
        var a = count();
        for (var k = 0; k < 3; k++) cv.dispatchEvent(new WheelEvent('wheel', { deltaY: -1, cancelable: true }));
        await frames(); var b = count();
        box.checked = false; box.dispatchEvent(new Event('change')); await frames(); var c = count();
        box.checked = true; box.dispatchEvent(new Event('change'));
        document.getElementById('reset-view').click(); await frames();
        return { before: a, zoomed: b, hidden: c }; })()` }, sessionId);
    const z = r.exceptionDetails ? null : r.result.value;
    check(z && z.zoomed.ink > z.before.ink, `zooming in did not enlarge the part (${JSON.stringify(z)})`);
    check(z && (expectedRows === 0 || (z.zoomed.orange > 0 && z.hidden.orange === 0)),
      `hiding the patches did not take their orange away (${JSON.stringify(z)})`);
  }
  check(v.jsonCells === 0, `${v.jsonCells} table cells show JSON`);
  // the inspection: canvas colours against the data's deviations, legend, table
  v.inspection = await evaluate(`(function(){
    var sec = document.getElementById('inspection');
    if (!sec) return null;
    var data = JSON.parse(document.getElementById('report-data').textContent).inspection;
    var cv = document.getElementById('inspect-view'), want = { blue: 0, green: 0, warm: 0 }, got = { blue: 0, green: 0, warm: 0, all: 0 };
    if (data && data.scan) {
      var t = atob(data.deviation), u = new Uint8Array(t.length);
      for (var i = 0; i < t.length; i++) u[i] = t.charCodeAt(i);
      var dev = new Float32Array(u.buffer, 0, data.scan.nv), tol = data.tolerance_mm;
      for (var i = 0; i < dev.length; i++) want[dev[i] < -tol ? 'blue' : dev[i] > tol ? 'warm' : 'green'] += 1 / dev.length;
    }
    if (cv && !cv.hidden) {
      var c = document.createElement('canvas'); c.width = cv.width; c.height = cv.height;
      var g = c.getContext('2d'); g.drawImage(cv, 0, 0); var d = g.getImageData(0, 0, c.width, c.height).data;
      got.all = d.length / 4;
      for (var i = 0; i < d.length; i += 4) { var R = d[i], G = d[i+1], B = d[i+2];
        if (B > R + 30 && B > G - 60 && !(G > B + 20)) got.blue++;
        else if (G > R + 30 && G > B + 20) got.green++;
        else if (R > B + 60 && R > 90) got.warm++; }
    }
    var ticks = Array.prototype.map.call(document.querySelectorAll('#inspect-scale .tick'), function (e) {
      return { v: parseFloat(e.textContent), left: parseFloat(e.style.left) }; });
    var band = document.getElementById('inspect-band'), bar = document.querySelector('#inspect-scale .scale-bar');
    var rows = Array.prototype.map.call(document.querySelectorAll('#inspection-table tbody tr'),
      function (r) { return r.cells[1].textContent; });
    return { view: document.body.getAttribute('data-inspect-view'), canvas: !!cv, want: want, got: got,
      tol: data ? data.tolerance_mm : null, ticks: ticks,
      band: band ? { left: parseFloat(band.style.left), width: parseFloat(band.style.width) } : null,
      gradient: bar ? getComputedStyle(bar).backgroundImage : '', rows: rows,
      png: cv && !cv.hidden ? cv.toDataURL('image/png').split(',')[1] : '' };
  })()`);
  const ins = v.inspection;
  if (ins && process.env.SYMREC_REPORT_INSPECT_PNG) fs.writeFileSync(process.env.SYMREC_REPORT_INSPECT_PNG, Buffer.from(ins.png, 'base64'));
  if (ins) delete ins.png;
  if (inspectRows < 0) {
    check(ins === null, 'an inspection section on the page of a run without inspection');
  } else if (!ins) {
    failures.push('no inspection section on the page');
  } else {
    check(ins.canvas && ins.view === 'webgl', `inspection view: canvas ${ins.canvas}, data-inspect-view '${ins.view}'`);
    ['blue', 'green', 'warm'].forEach((k) => check(ins.want[k] < 0.05 || ins.got[k] > 200,
      `inspection view: ${(100 * ins.want[k]).toFixed(1)} % of the vertices call for ${k} but ${ins.got[k]} pixels show it`));
    check(ins.got.blue + ins.got.green + ins.got.warm > 0.03 * ins.got.all,
      `inspection view: deviation colours on only ${ins.got.blue + ins.got.green + ins.got.warm} of ${ins.got.all} pixels`);
    check(/linear-gradient/.test(ins.gradient), `colour scale: no gradient ('${ins.gradient.slice(0, 80)}')`);
    const tv = ins.ticks.map((t) => t.v);
    check(tv.length === 5 && Math.abs(tv[0] + tv[4]) < 1e-9 && tv[2] === 0 && tv[0] < -ins.tol &&
      Math.abs(tv[3] - ins.tol) < 0.005 && Math.abs(tv[1] + ins.tol) < 0.005,
      `colour scale ticks ${JSON.stringify(tv)} (tolerance ${ins.tol} mm)`);
    check(ins.band && tv.length === 5 && Math.abs(ins.band.left - ins.ticks[1].left) < 0.02 &&
      Math.abs(ins.band.left + ins.band.width - ins.ticks[3].left) < 0.02,
      `tolerance band ${JSON.stringify(ins.band)} not between the ticks ${JSON.stringify(ins.ticks)}`);
    check(ins.rows.length === inspectRows && ins.rows.every((r) => /^(pass|machine|rework)$/.test(r)),
      `inspection table rows ${JSON.stringify(ins.rows)}, expected ${inspectRows} with verdicts`);
  }
  // the screenshot decoded by the browser: pixels of the part's grey (#a8b0bc, shaded)
  // and of the patches' orange (#e8601c, shaded) against the white background
  v.pixels = { part: 0, patch: 0, ink: 0, all: 0 };
  if (shot) {
    const { targetId: t2 } = await send('Target.createTarget', { url: 'about:blank' });
    const { sessionId: s2 } = await send('Target.attachToTarget', { targetId: t2, flatten: true });
    const r = await send('Runtime.evaluate', { awaitPromise: true, returnByValue: true,
      expression: `new Promise(function (ok, no) { var im = new Image(); im.onerror = no;
        im.onload = function () { var c = document.createElement('canvas'); c.width = im.width;
          c.height = im.height; var g = c.getContext('2d'); g.drawImage(im, 0, 0);
          var d = g.getImageData(0, 0, c.width, c.height).data, n = { part: 0, patch: 0, ink: 0, all: d.length / 4 };
          for (var i = 0; i < d.length; i += 4) { var R = d[i], G = d[i+1], B = d[i+2];
            if (R < 245 || G < 245 || B < 245) n.ink++;
            if (R > 90 && R - B > 60 && R - G > 40) n.patch++;
            else if (Math.abs(R - G) < 20 && B >= R && B - R < 30 && R > 40 && R < 235) n.part++; }
          ok(n); }; im.src = 'data:image/png;base64,${shot}'; })` }, s2);
    if (r.exceptionDetails) failures.push('screenshot not decoded: ' + r.exceptionDetails.text);
    else v.pixels = r.result.value;
  }
  check(v.pixels.part > 0.03 * v.pixels.all,
    `3D view: the part's grey on ${v.pixels.part} of ${v.pixels.all} pixels of the screenshot`);
  check(expectedRows === 0 || v.pixels.patch > 50,
    `3D view: the patches' orange on only ${v.pixels.patch} pixels of the screenshot`);
  // without WebGL (getContext gives nothing, as in a browser without it): the note in
  // the canvas's place, the rest of the page drawn, no error
  {
    const { targetId: t3 } = await send('Target.createTarget', { url: 'about:blank' });
    const { sessionId: s3 } = await send('Target.attachToTarget', { targetId: t3, flatten: true });
    await send('Runtime.enable', {}, s3);
    await send('Page.enable', {}, s3);
    await send('Page.addScriptToEvaluateOnNewDocument', { source:
      'HTMLCanvasElement.prototype.getContext = function () { return null; };' }, s3);
    await send('Page.navigate', { url }, s3);
    await waitFor((m) => m.method === 'Page.loadEventFired' && m.sessionId === s3, 20000);
    const r = await send('Runtime.evaluate', { returnByValue: true, expression: `({
      view: document.body.getAttribute('data-view'), rendered: document.body.getAttribute('data-rendered'),
      note: !document.getElementById('view-fallback').hidden, canvas: !document.getElementById('view').hidden })` }, s3);
    const f = (r.result && r.result.value) || {};
    check(f.view === 'fallback' && f.note && !f.canvas && f.rendered === '1',
      `without WebGL: view '${f.view}', note shown ${f.note}, canvas shown ${f.canvas}, page drawn ${f.rendered}`);
    events.filter((m) => m.sessionId === s3 && m.method === 'Runtime.exceptionThrown')
      .forEach((m) => failures.push('without WebGL: ' + JSON.stringify(m.params).slice(0, 300)));
  }
  // printed: A4, the page count within the bound
  const pdf = Buffer.from((await send('Page.printToPDF', { paperWidth: 8.27, paperHeight: 11.69,
    preferCSSPageSize: true, printBackground: false }, sessionId)).data, 'base64');
  if (process.env.SYMREC_REPORT_PDF) fs.writeFileSync(process.env.SYMREC_REPORT_PDF, pdf);
  v.pages = (pdf.toString('latin1').match(/\/Type\s*\/Page(?![a-zA-Z])/g) || []).length;
  check(v.pages >= 1 && v.pages <= maxPages, `printed to ${v.pages} A4 pages, expected 1 to ${maxPages}`);
  check(v.svg && v.polylines > 0, `outline plot not rendered (svg ${v.svg}, ${v.polylines} polylines)`);
  check(v.rows === expectedRows, `feature table has ${v.rows} rows, expected ${expectedRows}`);
  check(v.classes.every((c) => c.length > 0), 'a feature row without a damage class');
  check(/^symrec report: run \d+/.test(v.title), `title '${v.title}'`);
  v.planProblems.forEach((p) => failures.push('tool paths: ' + p));
  check(!v.allReplace || /No build plan/.test(v.noPlanText),
    'every section advised replace but the page does not say there is no build plan');
  return v;
}

const timer = setTimeout(() => { failures.push('timed out'); finish(null); }, 40000);
function finish(v) {
  clearTimeout(timer);
  try { proc.kill('SIGKILL'); } catch (e) { /* gone */ }
  fs.rmSync(profile, { recursive: true, force: true });
  if (failures.length) {
    failures.forEach((f) => console.log('check_report: FAIL: ' + f));
    process.exit(1);
  }
  console.log(`check_report: ok: ${url}: WebGL view drawn (${v.pixels.part} part, ` +
    `${v.pixels.patch} patch pixels of ${v.pixels.all}; ${v.gl}; render ${v.redrawMs} ms), ` +
    `${v.pages} A4 pages printed, ${v.polylines} outline ` +
    `polylines, ${v.rows} feature rows (${v.classes.join(', ')}), ${v.advice} advice rows, ` +
    `tool paths drawn in ${v.planned} plan layers (${v.pathsDrawn} paths)` +
    (v.replaced ? `, ${v.replaced} section(s) advised replace` : '') +
    (v.inspection ? `; inspection drawn (${v.inspection.got.blue} blue, ${v.inspection.got.green} ` +
      `green, ${v.inspection.got.warm} warm pixels), scale ${v.inspection.ticks.map((t) => t.v).join(' ')} mm, ` +
      `${v.inspection.rows.length} section rows (${v.inspection.rows.join(', ')})` : ''));
  process.exit(0);
}
main().then(finish, (e) => {
  failures.push(e.message + (stderr ? ' (browser: ' + stderr.split('\n')[0] + ')' : ''));
  finish(null);
});
