// The gapack page: a config editor, the jobs list and a job's live view,
// on the same /api/v1 as scripts use. Plain JavaScript, no build step.
'use strict';
(function () {
  const $ = (id) => document.getElementById(id);
  const API = '/api/v1';
  const FINAL = ['succeeded', 'failed', 'cancelled'];
  // Above this many particles the packing is shown as the run's PNG.
  const MAX_DRAWN = 100000;
  const sleep = (ms) => new Promise((done) => setTimeout(done, ms));

  // Measurements the browser tests read (time to first draw, frame times).
  const stats = { firstDraw: null, fetchParse: null, frames: [], disksDrawn: 0 };
  window.gapackStats = stats;

  // ------------------------------------------------------------ formats

  /** As the CLI prints times: `0.4 ms`, `812.3 ms`, `3.21 s`. */
  function duration(seconds) {
    if (!(seconds >= 0)) return '';
    return seconds < 1 ? (seconds * 1e3).toFixed(1) + ' ms' : seconds.toFixed(2) + ' s';
  }
  const porosity = (v) => (typeof v === 'number' ? v.toFixed(4) : '');
  const clock = (ms) => new Date(ms).toLocaleString();
  function bytes(n) {
    if (n < 1024) return n + ' B';
    if (n < 1024 * 1024) return (n / 1024).toFixed(1) + ' KB';
    return (n / 1024 / 1024).toFixed(1) + ' MB';
  }
  function count(n) {
    return Math.round(n).toLocaleString('en-US');
  }
  /** What a config's particles are called: `particles` with a [shape]
   * table (superellipses, polygons), else `disks`. */
  const particlesOf = (config) => (/^\s*\[shape\]\s*(#.*)?$/m.test(config || '') ? 'particles' : 'disks');
  function elapsed(job) {
    if (!job.started_ms) return '';
    const end = job.finished_ms || Date.now();
    return duration(Math.max(0, end - job.started_ms) / 1e3);
  }
  /** A job's progress in words, from its last progress event. */
  function progressWords(p) {
    if (!p) return '';
    if (p.event === 'generation') {
      const what = p.stage === 'layering' ? 'RMS error' : 'best';
      return 'generation ' + p.index + ' · ' + what + ' ' + porosity(p.best) + ' · mean ' + porosity(p.mean);
    }
    if (p.event === 'progress') return p.stage + ' · ' + count(p.done) + ' done';
    if (p.event === 'stage') return p.stage + (p.total != null ? ' · ' + count(p.total) + ' expected' : '');
    return '';
  }

  // ------------------------------------------------------------ API

  let token = sessionStorage.getItem('gapack-token') || '';
  function headers(extra) {
    const h = Object.assign({}, extra || {});
    if (token) h.Authorization = 'Bearer ' + token;
    return h;
  }
  function askToken() {
    $('token-form').hidden = false;
    $('token').focus();
  }
  $('token-form').addEventListener('submit', (e) => {
    e.preventDefault();
    token = $('token').value.trim();
    sessionStorage.setItem('gapack-token', token);
    $('token-form').hidden = true;
    showWho();
    route();
  });
  $('sign-out').addEventListener('click', () => {
    token = '';
    sessionStorage.removeItem('gapack-token');
    $('who').hidden = true;
    askToken();
    route();
  });
  /** Say who the token signs in as (the server's `admin` without one). */
  async function showWho() {
    const r = await call('GET', '/me');
    if (r.status !== 200) {
      $('who').hidden = true;
      return;
    }
    $('who-name').textContent = r.data.name + (r.data.role === 'admin' ? ' (admin)' : '');
    $('sign-out').hidden = !token;
    $('who').hidden = false;
  }
  /** A call to the API: `{status, data}` with the JSON (or text) answer. */
  async function call(method, path, body, contentType) {
    const init = { method, headers: headers(contentType ? { 'Content-Type': contentType } : {}) };
    if (body !== undefined) init.body = body;
    let res;
    try {
      res = await fetch(API + path, init);
    } catch (e) {
      return { status: 0, data: { error: 'the server cannot be reached (' + e.message + ')' } };
    }
    if (res.status === 401) askToken();
    const type = res.headers.get('Content-Type') || '';
    const data = type.includes('json') ? await res.json() : await res.text();
    return { status: res.status, data };
  }
  /** A URL for a job's file that an <img> or a download can use: the file's
   * own, or with a token (which a plain link cannot carry) a blob's. */
  async function fileUrl(id, name) {
    const url = API + '/jobs/' + id + '/files/' + name.split('/').map(encodeURIComponent).join('/');
    if (!token) return url;
    const res = await fetch(url, { headers: headers() });
    return URL.createObjectURL(await res.blob());
  }
  function pageError(message) {
    const box = $('page-error');
    box.textContent = message || '';
    box.hidden = !message;
  }

  /** Follow a job's Server-Sent Events (fetched, so that a token can be
   * sent), resuming with Last-Event-ID after a dropped connection, until
   * `onEvent` says the job has ended or `signal` aborts. */
  async function follow(id, onEvent, signal) {
    let last = 0;
    for (let attempt = 0; attempt < 100 && !signal.aborted; attempt++) {
      try {
        const extra = last ? { 'Last-Event-ID': String(last) } : {};
        const res = await fetch(API + '/jobs/' + id + '/events', { headers: headers(extra), signal });
        if (res.status === 404) return;
        if (!res.ok) throw new Error('HTTP ' + res.status);
        const reader = res.body.getReader();
        const decoder = new TextDecoder();
        let buffer = '';
        for (;;) {
          const { value, done } = await reader.read();
          if (done) break;
          buffer += decoder.decode(value, { stream: true }).replace(/\r\n/g, '\n');
          let cut;
          while ((cut = buffer.indexOf('\n\n')) >= 0) {
            const block = buffer.slice(0, cut);
            buffer = buffer.slice(cut + 2);
            let name = 'message';
            let data = '';
            for (const line of block.split('\n')) {
              if (!line || line.startsWith(':')) continue;
              const colon = line.indexOf(':');
              const key = colon < 0 ? line : line.slice(0, colon);
              let value = colon < 0 ? '' : line.slice(colon + 1);
              if (value.startsWith(' ')) value = value.slice(1);
              if (key === 'event') name = value;
              else if (key === 'data') data += (data ? '\n' : '') + value;
              else if (key === 'id') last = Number(value) || last;
            }
            if (data && onEvent(name, JSON.parse(data))) {
              reader.cancel().catch(() => {});
              return;
            }
          }
        }
      } catch (e) {
        if (signal.aborted) return;
      }
      await sleep(1000);
    }
  }

  // ------------------------------------------------------------ routing

  const views = ['view-new', 'view-jobs', 'view-job'];
  let leave = () => {};
  function show(view) {
    for (const v of views) $(v).hidden = v !== view;
    for (const [nav, v] of [['nav-new', 'view-new'], ['nav-jobs', 'view-jobs']]) {
      if (v === view) $(nav).setAttribute('aria-current', 'page');
      else $(nav).removeAttribute('aria-current');
    }
  }
  function route() {
    leave();
    leave = () => {};
    pageError('');
    const hash = location.hash || '#/new';
    if (hash.startsWith('#/job/')) leave = jobView(decodeURIComponent(hash.slice(6)));
    else if (hash === '#/jobs') leave = jobsView();
    else leave = newView();
  }
  window.addEventListener('hashchange', route);

  // ------------------------------------------------------------ new job

  let examples = null;
  const editor = $('config');
  const gutter = $('gutter');
  let badLine = 0;
  function renderGutter() {
    const lines = editor.value.split('\n').length;
    let html = '';
    for (let i = 1; i <= lines; i++) html += i === badLine ? '<span class="bad">' + i + '</span>' : '<span>' + i + '</span>';
    gutter.innerHTML = html;
    gutter.scrollTop = editor.scrollTop;
  }
  editor.addEventListener('input', () => {
    badLine = 0;
    sessionStorage.setItem('gapack-draft', editor.value);
    renderGutter();
  });
  editor.addEventListener('scroll', () => {
    gutter.scrollTop = editor.scrollTop;
  });
  editor.addEventListener('keydown', (e) => {
    // Tab indents; Escape then Tab leaves the editor (keyboard users).
    if (e.key === 'Tab' && !e.shiftKey && !editor.dataset.escape) {
      e.preventDefault();
      document.execCommand('insertText', false, '    ');
    }
    editor.dataset.escape = e.key === 'Escape' ? '1' : '';
  });
  $('example').addEventListener('change', () => {
    const chosen = (examples || []).find((x) => x.name === $('example').value);
    if (chosen) {
      editor.value = chosen.config;
      badLine = 0;
      clearConfigMessages();
      renderGutter();
    }
  });
  function clearConfigMessages() {
    $('config-error').hidden = true;
    $('validation').hidden = true;
  }
  /** Show a refused config at its line: the message, the line marked, the
   * caret moved there. */
  function configError(data) {
    const box = $('config-error');
    box.textContent = '';
    if (data && data.line) {
      const where = document.createElement('strong');
      where.textContent = 'Line ' + data.line + ', column ' + data.column + (data.key ? ' · ' + data.key : '');
      box.append(where, document.createElement('br'), data.message || data.error);
      badLine = data.line;
      renderGutter();
      const lines = editor.value.split('\n');
      let offset = 0;
      for (let i = 0; i < data.line - 1 && i < lines.length; i++) offset += lines[i].length + 1;
      offset += Math.max(0, (data.column || 1) - 1);
      editor.setSelectionRange(offset, offset);
      editor.scrollTop = Math.max(0, (data.line - 4) * 18);
      gutter.scrollTop = editor.scrollTop;
    } else {
      box.textContent = (data && data.error) || String(data);
    }
    box.hidden = false;
    $('validation').hidden = true;
  }
  function query() {
    const params = new URLSearchParams();
    if ($('kind').value) params.set('kind', $('kind').value);
    if ($('seed').value !== '') params.set('seed', $('seed').value);
    const q = params.toString();
    return q ? '?' + q : '';
  }
  $('validate').addEventListener('click', async () => {
    clearConfigMessages();
    const r = await call('POST', '/validate' + query(), editor.value, 'application/toml');
    if (r.status !== 200) return configError(r.data);
    const v = r.data;
    const e = v.estimates;
    const box = $('validation');
    box.textContent = '';
    const head = document.createElement('strong');
    head.textContent = 'Valid: ' + v.kind + ', seed ' + v.seed;
    const plan = document.createElement('pre');
    plan.textContent = v.plan.join('\n');
    const est = document.createElement('p');
    est.id = 'estimates';
    let words = 'Estimates: about ' + count(e.disks) + ' ' + particlesOf(editor.value) + ' (at most ' + count(e.max_disks) + '), memory at most ' + bytes(e.peak_bytes);
    if (e.packings != null) words += ', ' + count(e.packings) + (e.packings === 1 ? ' packing' : ' packings at most');
    if (e.seconds != null) words += ', time about ' + duration(e.seconds) + ' (a guide at 10⁶ disks/s on one core)';
    est.textContent = words + '.';
    box.append(head, plan, est);
    for (const w of v.warnings) {
      const p = document.createElement('p');
      p.className = 'warnings';
      p.textContent = 'Warning: ' + w;
      box.append(p);
    }
    box.hidden = false;
  });
  $('submit').addEventListener('click', async () => {
    clearConfigMessages();
    $('submit').disabled = true;
    const r = await call('POST', '/jobs' + query(), editor.value, 'application/toml');
    $('submit').disabled = false;
    if (r.status !== 201) return configError(r.data);
    location.hash = '#/job/' + r.data.id;
  });
  function newView() {
    show('view-new');
    if (!examples) {
      call('GET', '/examples').then((r) => {
        if (r.status !== 200) return pageError(r.data.error || 'cannot load the examples');
        examples = r.data;
        const select = $('example');
        select.textContent = '';
        for (const x of examples) {
          const o = document.createElement('option');
          o.value = x.name;
          o.textContent = x.name;
          select.append(o);
        }
        if (!editor.value) {
          const draft = sessionStorage.getItem('gapack-draft');
          editor.value = draft || examples[0].config;
          if (draft) select.value = '';
        }
        renderGutter();
      });
    }
    renderGutter();
    return () => {};
  }
  /** Open the editor with `config` (from "Run again" with edits, say). */
  function editConfig(config) {
    editor.value = config;
    sessionStorage.setItem('gapack-draft', config);
    location.hash = '#/new';
  }

  // ------------------------------------------------------------ jobs list

  function jobsView() {
    show('view-jobs');
    const rows = new Map();
    const body = $('jobs-table').tBodies[0];
    let stopped = false;
    async function poll() {
      const r = await call('GET', '/jobs?limit=50');
      if (stopped) return;
      if (r.status !== 200) {
        pageError(r.data.error || 'cannot list the jobs');
        return;
      }
      pageError('');
      const jobs = r.data.jobs;
      $('jobs-empty').hidden = jobs.length > 0;
      let before = body.firstChild;
      for (const job of jobs) {
        let row = rows.get(job.id);
        if (!row) {
          row = body.insertRow(-1);
          row.dataset.id = job.id;
          for (let i = 0; i < 6; i++) row.insertCell(-1);
          const a = document.createElement('a');
          a.href = '#/job/' + job.id;
          a.textContent = job.id.slice(0, 8);
          a.title = job.id;
          row.cells[0].append(a);
          row.cells[1].textContent = job.kind;
          const state = document.createElement('span');
          state.className = 'state';
          row.cells[2].append(state);
          row.cells[4].textContent = clock(job.created_ms);
          rows.set(job.id, row);
        }
        // Newest first: keep the rows in the list's order.
        if (row !== before) body.insertBefore(row, before);
        before = row.nextSibling;
        const state = row.cells[2].firstChild;
        state.textContent = job.state;
        state.className = 'state ' + job.state;
        row.cells[3].textContent = FINAL.includes(job.state) && job.summary && job.summary.porosity != null
          ? 'porosity ' + porosity(job.summary.porosity) + ' · ' + count(job.summary.particles) + (job.summary.particle_shape ? ' particles' : ' disks')
          : progressWords(job.progress);
        row.cells[5].textContent = elapsed(job);
      }
      const listed = new Set(jobs.map((j) => j.id));
      for (const [id, row] of rows) {
        if (!listed.has(id)) {
          row.remove();
          rows.delete(id);
        }
      }
    }
    let timer = null;
    const tick = async () => {
      await poll();
      if (!stopped) timer = setTimeout(tick, 1000);
    };
    tick();
    return () => {
      stopped = true;
      clearTimeout(timer);
    };
  }

  // ------------------------------------------------------------ one job

  function jobView(id) {
    show('view-job');
    const abort = new AbortController();
    let job = null;
    let ended = false;
    let total = null;
    let counted = 0;
    const points = [];
    let target = null;
    let chart = null;
    $('job-id').textContent = id;
    for (const el of ['job-kind', 'job-seed', 'job-elapsed', 'job-progress-text']) $(el).textContent = '';
    setState('');
    $('job-progress').value = 0;
    $('job-error').hidden = true;
    $('warnings').textContent = '';
    $('results').hidden = true;
    $('convergence-box').hidden = true;
    $('cancel').disabled = true;
    const ticker = setInterval(() => {
      if (job && !ended) $('job-elapsed').textContent = elapsed(job);
    }, 250);
    const redrawChart = () => {
      if (chart) chart.draw(points, ended ? null : total, target);
    };
    window.addEventListener('resize', redrawChart);

    function setState(state) {
      const el = $('job-state');
      el.textContent = state;
      el.className = 'state ' + state;
      $('cancel').disabled = !state || FINAL.includes(state);
    }
    function progress(fraction, words) {
      $('job-progress').value = Math.max(0, Math.min(1, fraction));
      $('job-progress-text').textContent = words;
    }
    function onEvent(name, data) {
      if (name === 'state') {
        setState(data.state);
        if (data.state === 'running' && job && !job.started_ms) job.started_ms = Date.now();
        if (FINAL.includes(data.state)) {
          finish();
          return true;
        }
      } else if (name === 'stage') {
        total = data.total;
        counted = 0;
        progress(0, data.stage + (total != null ? ' · ' + count(total) + ' expected' : ''));
      } else if (name === 'progress') {
        progress(total ? data.done / total : 0, data.stage + ' · ' + count(data.done) + (total ? ' of about ' + count(total) : ''));
      } else if (name === 'generation') {
        points.push({ index: data.index, best: data.best, mean: data.mean });
        const what = data.stage === 'layering' ? 'RMS error ' : 'best ';
        progress(total ? data.index / total : 0, 'generation ' + data.index + (total ? ' of ' + total : '') + ' · ' + what + porosity(data.best) + ' · ' + count(data.evaluations) + ' evaluations');
        if (chart) chart.draw(points, total, target);
      } else if (name === 'well' || name === 'run') {
        counted += 1;
        progress(total ? counted / total : 0, counted + (total ? ' of ' + total : '') + (name === 'well' ? ' wells packed' : ' runs done'));
      } else if (name === 'warning') {
        const li = document.createElement('li');
        li.textContent = data.message;
        $('warnings').append(li);
      }
      return false;
    }
    async function finish() {
      ended = true;
      const r = await call('GET', '/jobs/' + id);
      if (r.status !== 200 || abort.signal.aborted) return;
      job = r.data;
      $('job-elapsed').textContent = elapsed(job);
      if (job.state === 'succeeded') progress(1, 'done');
      if (job.error) {
        $('job-error').textContent = job.error;
        $('job-error').hidden = false;
      }
      // Ended: the axis spans the generations run, not those allowed.
      if (chart && points.length) chart.draw(points, null, target);
      results(id, job, abort.signal);
    }

    (async () => {
      const r = await call('GET', '/jobs/' + id);
      if (abort.signal.aborted) return;
      if (r.status !== 200) return pageError(r.data.error || 'no such job');
      job = r.data;
      $('job-kind').textContent = job.kind;
      $('job-seed').textContent = job.seed == null ? "the config's" : String(job.seed);
      $('again-seed').value = String((job.seed == null ? 0 : job.seed) + 1);
      setState(job.state);
      $('job-elapsed').textContent = elapsed(job);
      if (job.kind === 'optimise' || job.kind === 'layer') {
        $('convergence-box').hidden = false;
        target = job.kind === 'optimise' ? targetPorosity(job.config) : 0;
        chart = convergenceChart($('convergence'), job.kind === 'layer' ? 'profile RMS error' : 'porosity');
        chart.draw(points, null, target);
      }
      follow(id, onEvent, abort.signal);
    })();

    $('cancel').onclick = async () => {
      $('cancel').disabled = true;
      const r = await call('POST', '/jobs/' + id + '/cancel');
      if (r.status >= 400) pageError(r.data.error);
    };
    $('again').onclick = async () => {
      if (!job) return;
      const seed = $('again-seed').value;
      const body = { kind: job.kind, config: job.config };
      if (seed !== '') body.seed = Number(seed);
      const r = await call('POST', '/jobs', JSON.stringify(body), 'application/json');
      if (r.status !== 201) {
        if (r.data && r.data.line) return editConfig(job.config);
        return pageError(r.data.error);
      }
      location.hash = '#/job/' + r.data.id;
    };
    return () => {
      abort.abort();
      clearInterval(ticker);
      window.removeEventListener('resize', redrawChart);
      if (chart) chart.stop();
      packingViewer.stop();
    };
  }

  /** The target porosity of an optimise config (its [optimise] table). */
  function targetPorosity(config) {
    const table = /^\s*\[optimise\]\s*$/m.exec(config || '');
    if (!table) return null;
    const rest = config.slice(table.index + table[0].length);
    const next = /^\s*\[/m.exec(rest);
    const body = next ? rest.slice(0, next.index) : rest;
    const m = /^\s*target_porosity\s*=\s*([-+0-9.eE_]+)/m.exec(body);
    return m ? Number(m[1].replace(/_/g, '')) : null;
  }

  /** A finished job's results: its words, packing, charts, summary, files. */
  async function results(id, job, signal) {
    $('results').hidden = false;
    $('job-lines').textContent = (job.summary && job.summary.lines ? job.summary.lines : []).join('\n');
    $('charts').textContent = '';
    $('summary').textContent = '';
    $('files').textContent = '';
    $('packing-box').hidden = true;
    const r = await call('GET', '/jobs/' + id + '/files');
    if (signal.aborted || r.status !== 200) return;
    const names = r.data.files.map((f) => f.name);
    for (const f of r.data.files) {
      const li = document.createElement('li');
      const a = document.createElement('a');
      a.textContent = f.name;
      a.href = f.url;
      a.download = f.name.replace(/\//g, '_');
      if (token) {
        a.addEventListener('click', async (e) => {
          e.preventDefault();
          const link = document.createElement('a');
          link.href = await fileUrl(id, f.name);
          link.download = a.download;
          link.click();
        });
      }
      const size = document.createElement('span');
      size.className = 'size';
      size.textContent = bytes(f.bytes);
      li.append(a, size);
      $('files').append(li);
    }
    // The packing: drawn from its data up to MAX_DRAWN particles, else its PNG.
    const particles = job.summary && job.summary.particles;
    const shaped = !!(job.summary && job.summary.particle_shape);
    $('packing-png').alt = 'The packing (an image: too many ' + (shaped ? 'particles' : 'disks') + ' to draw here)';
    if (names.includes('packing.csv') && particles != null && particles <= MAX_DRAWN) {
      $('packing-box').hidden = false;
      $('packing').hidden = false;
      $('packing-png').hidden = true;
      const t0 = performance.now();
      const p = await call('GET', '/jobs/' + id + '/packing');
      if (signal.aborted) return;
      if (p.status === 200) {
        stats.fetchParse = performance.now() - t0;
        packingViewer.show(p.data, t0);
      }
    } else if (names.includes('packing.png')) {
      $('packing-box').hidden = false;
      $('packing').hidden = true;
      $('packing-png').hidden = false;
      $('packing-png').src = await fileUrl(id, 'packing.png');
    }
    // The run's charts: every SVG but the packing's own drawing (a study's
    // runs' charts stay in its list of files: there may be hundreds).
    for (const name of names) {
      if (!name.endsWith('.svg') || name === 'packing.svg' || name.startsWith('runs/')) continue;
      const fig = document.createElement('figure');
      const cap = document.createElement('figcaption');
      cap.textContent = name.replace(/\.svg$/, '').replace(/_/g, ' ');
      const img = document.createElement('img');
      img.alt = 'Chart ' + name;
      img.loading = 'lazy';
      img.width = 800;
      img.height = 500;
      fig.append(cap, img);
      $('charts').append(fig);
      fileUrl(id, name).then((url) => {
        img.src = url;
      });
    }
    if (names.includes('summary.json')) {
      const url = await fileUrl(id, 'summary.json');
      const res = await fetch(url, { headers: headers() });
      if (signal.aborted || !res.ok) return;
      summaryTable(await res.json());
    }
  }

  /** summary.json as rows of key and value, nested keys joined by dots. */
  function summaryTable(summary) {
    const table = $('summary');
    const add = (key, value) => {
      const row = table.insertRow(-1);
      const th = document.createElement('th');
      th.scope = 'row';
      th.textContent = key;
      row.append(th);
      row.insertCell(-1).textContent = value;
    };
    const walk = (prefix, value) => {
      if (value && typeof value === 'object' && !Array.isArray(value)) {
        for (const [k, v] of Object.entries(value)) walk(prefix ? prefix + '.' + k : k, v);
      } else if (Array.isArray(value)) {
        add(prefix, value.length > 8 ? value.length + ' values' : JSON.stringify(value));
      } else if (typeof value === 'number') {
        const key = prefix.split('.').pop();
        if (key === 'seconds') add(prefix, duration(value));
        else if (key === 'porosity' || key.endsWith('_porosity') || key === 'psd_ks') add(prefix, porosity(value));
        else add(prefix, String(value));
      } else {
        add(prefix, value == null ? '' : String(value));
      }
    };
    walk('', summary);
  }

  // ------------------------------------------------------------ charts

  /** The convergence chart: best and mean against generation, the target
   * as a line; redrawn as generations arrive. The canvas keeps its size. */
  function convergenceChart(canvas, what) {
    let pending = null;
    function draw(points, generations, target) {
      if (pending) return;
      pending = requestAnimationFrame(() => {
        pending = null;
        paint(points, generations, target);
      });
    }
    function paint(points, generations, target) {
      const ratio = window.devicePixelRatio || 1;
      const w = canvas.clientWidth;
      const h = canvas.clientHeight;
      canvas.width = Math.round(w * ratio);
      canvas.height = Math.round(h * ratio);
      const g = canvas.getContext('2d');
      g.setTransform(ratio, 0, 0, ratio, 0, 0);
      g.clearRect(0, 0, w, h);
      const pad = { left: 78, right: 16, top: 30, bottom: 40 };
      const pw = w - pad.left - pad.right;
      const ph = h - pad.top - pad.bottom;
      const xmax = Math.max(1, generations || 0, points.length ? points[points.length - 1].index : 0);
      const values = [];
      for (const p of points) values.push(p.best, p.mean);
      if (target != null) values.push(target);
      let lo = values.length ? Math.min(...values) : 0;
      let hi = values.length ? Math.max(...values) : 1;
      if (hi - lo < 1e-6) {
        lo -= 0.005;
        hi += 0.005;
      }
      const span = hi - lo;
      lo -= span * 0.08;
      hi += span * 0.08;
      const X = (i) => pad.left + (i / xmax) * pw;
      const Y = (v) => pad.top + (1 - (v - lo) / (hi - lo)) * ph;
      g.font = '12px system-ui, sans-serif';
      g.strokeStyle = '#d0d5da';
      g.fillStyle = '#5b6570';
      g.lineWidth = 1;
      // Axes and ticks.
      g.textAlign = 'right';
      g.textBaseline = 'middle';
      for (let k = 0; k <= 4; k++) {
        const v = lo + ((hi - lo) * k) / 4;
        const y = Y(v);
        g.beginPath();
        g.moveTo(pad.left, y);
        g.lineTo(pad.left + pw, y);
        g.stroke();
        g.fillText(v.toFixed(4), pad.left - 6, y);
      }
      g.textAlign = 'center';
      g.textBaseline = 'top';
      const step = Math.max(1, Math.ceil(xmax / 8));
      for (let i = 0; i <= xmax; i += step) g.fillText(String(i), X(i), pad.top + ph + 6);
      g.fillText('generation', pad.left + pw / 2, pad.top + ph + 22);
      g.save();
      g.translate(14, pad.top + ph / 2);
      g.rotate(-Math.PI / 2);
      g.fillText(what, 0, 0);
      g.restore();
      // Target, mean, best.
      if (target != null) {
        g.strokeStyle = '#b3261e';
        g.setLineDash([6, 4]);
        g.beginPath();
        g.moveTo(pad.left, Y(target));
        g.lineTo(pad.left + pw, Y(target));
        g.stroke();
        g.setLineDash([]);
      }
      const line = (key, colour, width) => {
        g.strokeStyle = colour;
        g.fillStyle = colour;
        g.lineWidth = width;
        g.beginPath();
        points.forEach((p, i) => (i ? g.lineTo(X(p.index), Y(p[key])) : g.moveTo(X(p.index), Y(p[key]))));
        g.stroke();
        for (const p of points) {
          g.beginPath();
          g.arc(X(p.index), Y(p[key]), 2.5, 0, 2 * Math.PI);
          g.fill();
        }
      };
      line('mean', '#9aa5b1', 1.5);
      line('best', '#1f5fa8', 2);
      // Legend above the plot, where it covers nothing.
      g.textAlign = 'left';
      g.textBaseline = 'middle';
      let x = pad.left;
      const key = (label, colour, dash) => {
        g.strokeStyle = colour;
        g.lineWidth = 2;
        g.setLineDash(dash);
        g.beginPath();
        g.moveTo(x, 14);
        g.lineTo(x + 22, 14);
        g.stroke();
        g.setLineDash([]);
        g.fillStyle = '#1d2125';
        g.fillText(label, x + 28, 14);
        x += 40 + g.measureText(label).width;
      };
      key('best', '#1f5fa8', []);
      key('mean', '#9aa5b1', []);
      if (target != null) key('target ' + porosity(target), '#b3261e', [6, 4]);
      canvas.dataset.points = String(points.length);
    }
    return {
      draw,
      stop() {
        if (pending) cancelAnimationFrame(pending);
        pending = null;
      },
    };
  }

  // ------------------------------------------------------------ particle shapes

  /** Particles that are not disks, from the packing view's `shapes`
   * columns: a superellipse |x'/a|^α + |y'/b|^β ≤ 1 or a convex polygon
   * (counter-clockwise about its centroid) rounded by a disk of radius ρ, in
   * the particle's own axes (x', y'), turned by `angle` counter-clockwise.
   * Their outlines drawn and hit, and the measures hover shows. */
  const shapes = (function () {
    const TAU = 2 * Math.PI;
    // A superellipse's outline at parameters t = 2πk/n, scaled to a = b = 1:
    // (sgn(cos t)|cos t|^(2/α), sgn(sin t)|sin t|^(2/β)), by exponents and n
    // (a bounded cache: a packing of many exponents computes the rest anew).
    const units = new Map();
    function unit(alpha, beta, n) {
      const key = alpha + ' ' + beta + ' ' + n;
      let u = units.get(key);
      if (u) return u;
      u = new Float64Array(2 * n);
      for (let k = 0; k < n; k++) {
        const c = Math.cos((TAU * k) / n);
        const s = Math.sin((TAU * k) / n);
        u[2 * k] = Math.sign(c) * Math.pow(Math.abs(c), 2 / alpha);
        u[2 * k + 1] = Math.sign(s) * Math.pow(Math.abs(s), 2 / beta);
      }
      if (units.size < 4096) units.set(key, u);
      return u;
    }

    /** Per particle of `data`: its kind (0 a disk, 1 a superellipse, 2 a
     * rounded polygon), its turn (cos, sin), and its reach, the radius of a
     * circle about its centre that holds it (a disk's radius). */
    function prepare(data) {
      const n = data.x.length;
      const sh = data.shapes;
      const geo = { kind: new Uint8Array(n), cos: new Float64Array(n), sin: new Float64Array(n), reach: Float64Array.from(data.r) };
      if (!sh) return geo;
      for (let i = 0; i < n; i++) {
        geo.cos[i] = Math.cos(sh.angle[i]);
        geo.sin[i] = Math.sin(sh.angle[i]);
        if (sh.a && sh.a[i] != null) {
          // Convex: inside its bounding box [-a, a] × [-b, b].
          geo.kind[i] = 1;
          geo.reach[i] = Math.hypot(sh.a[i], sh.b[i]);
        } else if (sh.vertices && sh.vertices[i]) {
          geo.kind[i] = 2;
          let far = 0;
          for (const [x, y] of sh.vertices[i]) far = Math.max(far, Math.hypot(x, y));
          geo.reach[i] = far + sh.rounding[i];
        }
      }
      return geo;
    }

    /** Add particle i's outline to `path`: centred on canvas point (X, Y),
     * at `scale` canvas pixels a mm, `px` its reach in pixels (the detail:
     * 8 to 96 points a superellipse, a polygon's corners as arcs once they
     * show). Each outline ends where it began, without closePath (which
     * costs Chromium a walk of the whole path: quadratic over a packing). */
    function trace(path, data, geo, i, X, Y, scale, px) {
      const sh = data.shapes;
      const c = geo.cos[i];
      const s = geo.sin[i];
      // Own axes to the canvas: turned by the angle, y down.
      const toX = (u, v) => X + (c * u - s * v) * scale;
      const toY = (u, v) => Y - (s * u + c * v) * scale;
      if (geo.kind[i] === 1) {
        const n = px < 2.5 ? 8 : px < 5 ? 12 : px < 12 ? 24 : px < 40 ? 48 : 96;
        const u = unit(sh.alpha[i], sh.beta[i], n);
        const a = sh.a[i];
        const b = sh.b[i];
        path.moveTo(toX(a * u[0], b * u[1]), toY(a * u[0], b * u[1]));
        for (let k = 1; k < n; k++) path.lineTo(toX(a * u[2 * k], b * u[2 * k + 1]), toY(a * u[2 * k], b * u[2 * k + 1]));
        path.lineTo(toX(a * u[0], b * u[1]), toY(a * u[0], b * u[1]));
        return;
      }
      const v = sh.vertices[i];
      const m = v.length;
      const rho = sh.rounding[i] * scale;
      if (rho < 0.5) {
        v.forEach(([x, y], k) => (k ? path.lineTo(toX(x, y), toY(x, y)) : path.moveTo(toX(x, y), toY(x, y))));
        path.lineTo(toX(v[0][0], v[0][1]), toY(v[0][0], v[0][1]));
        return;
      }
      // Each corner an arc of radius ρ between the outward normals of its
      // two edges (canvas angles are the world's negated: y is down).
      const turn = sh.angle[i];
      let x0 = 0;
      let y0 = 0;
      for (let k = 0; k < m; k++) {
        const [px0, py0] = v[(k + m - 1) % m];
        const [qx, qy] = v[k];
        const [rx, ry] = v[(k + 1) % m];
        const t0 = Math.atan2(-(qx - px0), qy - py0) + turn;
        let t1 = Math.atan2(-(rx - qx), ry - qy) + turn;
        if (t1 < t0) t1 += TAU;
        const X0 = toX(qx, qy);
        const Y0 = toY(qx, qy);
        if (k === 0) {
          x0 = X0 + rho * Math.cos(t0);
          y0 = Y0 - rho * Math.sin(t0);
          path.moveTo(x0, y0);
        }
        path.arc(X0, Y0, rho, -t0, -t1, true);
      }
      path.lineTo(x0, y0);
    }

    /** Whether particle i holds the point (x, y) (mm). */
    function contains(data, geo, i, x, y) {
      const dx = x - data.x[i];
      const dy = y - data.y[i];
      const reach = geo.reach[i];
      if (dx * dx + dy * dy > reach * reach) return false;
      if (geo.kind[i] === 0) return true;
      const sh = data.shapes;
      // In the particle's own axes: turned back by its angle.
      const u = geo.cos[i] * dx + geo.sin[i] * dy;
      const v = -geo.sin[i] * dx + geo.cos[i] * dy;
      if (geo.kind[i] === 1) {
        return Math.pow(Math.abs(u / sh.a[i]), sh.alpha[i]) + Math.pow(Math.abs(v / sh.b[i]), sh.beta[i]) <= 1;
      }
      // Inside the polygon, or within ρ of it.
      const p = sh.vertices[i];
      const m = p.length;
      let inside = true;
      let near = Infinity;
      for (let k = 0; k < m; k++) {
        const [ax, ay] = p[k];
        const [bx, by] = p[(k + 1) % m];
        const ex = bx - ax;
        const ey = by - ay;
        if (ex * (v - ay) - ey * (u - ax) < 0) inside = false;
        const t = Math.max(0, Math.min(1, ((u - ax) * ex + (v - ay) * ey) / (ex * ex + ey * ey)));
        near = Math.min(near, Math.hypot(u - ax - t * ex, v - ay - t * ey));
      }
      return inside || near <= sh.rounding[i];
    }

    /** Particle i's aspect ratio (greatest over least width, the Feret
     * diameters) and Riley's sphericity √(D_inscribed / D_enclosing), as the
     * library measures them (summary.json's particle_shape, the shape chart):
     * - a superellipse is symmetric about its centre: its greatest width is
     *   twice its farthest point's distance R and its least twice its nearest
     *   boundary line's d, its largest inscribed and smallest enclosing
     *   circles centred: aspect R/d, sphericity √(d/R). R and d are taken on
     *   the outline at 4,096 parameters (a quadrant, mirrored): within 10⁻⁵.
     * - a polygon rounded by ρ: (diameter + 2ρ) / (least width + 2ρ), the
     *   least width at an edge, exactly; sphericity √((r_in + ρ) / (r_out +
     *   ρ)), r_in the polygon's Chebyshev radius (the centre equidistant from
     *   three edges), r_out its vertices' smallest enclosing circle (Welzl). */
    function measures(data, i) {
      const sh = data.shapes;
      if (sh.a && sh.a[i] != null) {
        const [a, b, alpha, beta] = [sh.a[i], sh.b[i], sh.alpha[i], sh.beta[i]];
        const q = 1024;
        let far = 0;
        let near = Infinity;
        let px = a;
        let py = 0;
        for (let k = 0; k <= q; k++) {
          const t = (Math.PI / 2) * (k / q);
          // The quadrant's ends exactly on the axes.
          const x = a * Math.pow(k === q ? 0 : Math.cos(t), 2 / alpha);
          const y = b * Math.pow(k === q ? 1 : Math.sin(t), 2 / beta);
          far = Math.max(far, Math.hypot(x, y));
          if (k) near = Math.min(near, Math.abs(px * y - py * x) / Math.hypot(x - px, y - py));
          px = x;
          py = y;
        }
        return { aspect: far / near, sphericity: Math.min(1, Math.sqrt(near / far)) };
      }
      const v = sh.vertices[i];
      const rho = sh.rounding[i];
      const m = v.length;
      let diameter = 0;
      for (let j = 0; j < m; j++) for (let k = j + 1; k < m; k++) diameter = Math.max(diameter, Math.hypot(v[j][0] - v[k][0], v[j][1] - v[k][1]));
      // Edge k: inward unit normal n and offset c, inside n·x ≥ c.
      const edges = v.map(([ax, ay], k) => {
        const [bx, by] = v[(k + 1) % m];
        const len = Math.hypot(bx - ax, by - ay);
        const nx = -(by - ay) / len;
        const ny = (bx - ax) / len;
        return [nx, ny, nx * ax + ny * ay];
      });
      let least = Infinity;
      for (const [nx, ny, c] of edges) {
        let deepest = 0;
        for (const [x, y] of v) deepest = Math.max(deepest, nx * x + ny * y - c);
        least = Math.min(least, deepest);
      }
      return {
        aspect: (diameter + 2 * rho) / (least + 2 * rho),
        sphericity: Math.min(1, Math.sqrt((chebyshev(v, edges) + rho) / (enclosing(v) + rho))),
      };
    }

    /** Radius of the largest circle inside the convex polygon `v` (edges as
     * `measures` gives them): the best centre equidistant from three edges. */
    function chebyshev(v, edges) {
      const size = Math.max(...v.map(([x, y]) => Math.hypot(x, y)));
      const m = edges.length;
      let best = 0;
      for (let i = 0; i < m; i++) {
        for (let j = i + 1; j < m; j++) {
          for (let k = j + 1; k < m; k++) {
            // n·x − r = c for the three edges, by Cramer's rule.
            const [a, b, c] = [edges[i], edges[j], edges[k]];
            const det3 = (p, q, r) => p[0] * (q[1] * r[2] - q[2] * r[1]) - p[1] * (q[0] * r[2] - q[2] * r[0]) + p[2] * (q[0] * r[1] - q[1] * r[0]);
            const rows = [a, b, c].map((e) => [e[0], e[1], -1]);
            const d = det3(...rows);
            if (d === 0) continue;
            const rhs = [a[2], b[2], c[2]];
            const col = (n) => rows.map((row, r) => row.map((x, k2) => (k2 === n ? rhs[r] : x)));
            const x = det3(...col(0)) / d;
            const y = det3(...col(1)) / d;
            const r = det3(...col(2)) / d;
            if (!(Number.isFinite(r) && r > best)) continue;
            if (edges.every(([nx, ny, off]) => nx * x + ny * y - off >= r - 1e-12 * size)) best = r;
          }
        }
      }
      return best;
    }

    /** Radius of the smallest circle holding the points `v` (Welzl's
     * incremental construction). */
    function enclosing(v) {
      const inside = (c, r, p) => Math.hypot(p[0] - c[0], p[1] - c[1]) <= r * (1 + 1e-12);
      let c = v[0];
      let r = 0;
      for (let i = 1; i < v.length; i++) {
        if (inside(c, r, v[i])) continue;
        c = v[i];
        r = 0;
        for (let j = 0; j < i; j++) {
          if (inside(c, r, v[j])) continue;
          c = [(v[i][0] + v[j][0]) / 2, (v[i][1] + v[j][1]) / 2];
          r = Math.hypot(v[i][0] - v[j][0], v[i][1] - v[j][1]) / 2;
          for (let k = 0; k < j; k++) {
            if (inside(c, r, v[k])) continue;
            [c, r] = circumcircle(v[i], v[j], v[k]);
          }
        }
      }
      return r;
    }
    /** The circle through three points (the widest pair's when collinear). */
    function circumcircle(a, b, c) {
      const [abx, aby, acx, acy] = [b[0] - a[0], b[1] - a[1], c[0] - a[0], c[1] - a[1]];
      const d = 2 * (abx * acy - aby * acx);
      if (d === 0) {
        const pairs = [[a, b], [a, c], [b, c]];
        const len = ([p, q]) => Math.hypot(p[0] - q[0], p[1] - q[1]);
        const [p, q] = pairs.reduce((x, y) => (len(y) > len(x) ? y : x));
        return [[(p[0] + q[0]) / 2, (p[1] + q[1]) / 2], len([p, q]) / 2];
      }
      const b2 = abx * abx + aby * aby;
      const c2 = acx * acx + acy * acy;
      const ux = (acy * b2 - aby * c2) / d;
      const uy = (abx * c2 - acx * b2) / d;
      return [[a[0] + ux, a[1] + uy], Math.hypot(ux, uy)];
    }

    return { prepare, trace, contains, measures };
  })();

  // ------------------------------------------------------------ packing

  /** The packing on a canvas: pan, zoom, hover for a particle's data. A
   * grid of the particles finds the one under the pointer without a scan. */
  const packingViewer = (function () {
    const canvas = $('packing');
    const tip = $('hover');
    let data = null;
    let geo = null;
    let measured = null;
    let grid = null;
    let view = null;
    let pending = null;
    let drag = null;
    let colours = null;
    const PALETTE = ['#4e79a7', '#f28e2b', '#59a14f', '#e15759', '#76b7b2', '#edc948', '#b07aa1', '#ff9da7', '#9c755f', '#bab0ac'];

    function show(packing, t0) {
      data = packing;
      geo = shapes.prepare(data);
      measured = null;
      const n = data.x.length;
      const what = data.shapes ? 'particle' : 'disk';
      canvas.setAttribute('aria-label', 'The packing: drag to pan, wheel to zoom, hover a ' + what + ' for its data');
      // Colours: by material, or by diameter in 12 shades (light small, dark large).
      const shades = 12;
      colours = new Uint8Array(n);
      let rmin = Infinity;
      let rmax = 0;
      for (let i = 0; i < n; i++) {
        rmin = Math.min(rmin, data.r[i]);
        rmax = Math.max(rmax, data.r[i]);
      }
      for (let i = 0; i < n; i++) {
        colours[i] = data.material.length
          ? data.material[i] % PALETTE.length
          : rmax > rmin
            ? Math.min(shades - 1, Math.floor(((data.r[i] - rmin) / (rmax - rmin)) * shades))
            : shades - 1;
      }
      const fills = data.material.length
        ? PALETTE
        : Array.from({ length: shades }, (_, k) => {
            const t = k / (shades - 1);
            return 'rgb(' + Math.round(198 - 150 * t) + ',' + Math.round(219 - 120 * t) + ',' + Math.round(239 - 60 * t) + ')';
          });
      data.fills = fills;
      buildGrid(geo.reach.reduce((m, v) => Math.max(m, v), 0));
      resize();
      fit();
      paint();
      stats.firstDraw = performance.now() - t0;
      stats.disksDrawn = n;
      canvas.dataset.disks = String(n);
    }
    /** The grid: cells of twice the greatest reach (a particle's enclosing
     * radius; a disk's radius). */
    function buildGrid(rmax) {
      const [[x0, y0], [x1, y1]] = data.bounds;
      const n = data.x.length;
      const cell = Math.max(2 * rmax, 1e-9);
      const cols = Math.max(1, Math.min(4096, Math.ceil((x1 - x0) / cell)));
      const rows = Math.max(1, Math.min(4096, Math.ceil((y1 - y0) / cell)));
      const cw = (x1 - x0) / cols || 1;
      const ch = (y1 - y0) / rows || 1;
      const key = (i) => {
        const cx = Math.min(cols - 1, Math.max(0, Math.floor((data.x[i] - x0) / cw)));
        const cy = Math.min(rows - 1, Math.max(0, Math.floor((data.y[i] - y0) / ch)));
        return cy * cols + cx;
      };
      const start = new Uint32Array(cols * rows + 1);
      for (let i = 0; i < n; i++) start[key(i) + 1]++;
      for (let c = 0; c < cols * rows; c++) start[c + 1] += start[c];
      const fill = start.slice(0, cols * rows);
      const items = new Uint32Array(n);
      for (let i = 0; i < n; i++) items[fill[key(i)]++] = i;
      grid = { x0, y0, cw, ch, cols, rows, start, items, reach: Math.ceil(rmax / Math.min(cw, ch)) + 1 };
    }
    function resize() {
      const ratio = window.devicePixelRatio || 1;
      const w = canvas.parentElement.clientWidth;
      const [[x0, y0], [x1, y1]] = data.bounds;
      const aspect = (y1 - y0) / Math.max(1e-12, x1 - x0);
      const h = Math.round(Math.min(Math.max(w * aspect, 160), window.innerHeight * 0.7));
      canvas.style.height = h + 'px';
      canvas.width = Math.round(w * ratio);
      canvas.height = Math.round(h * ratio);
    }
    function fit() {
      const [[x0, y0], [x1, y1]] = data.bounds;
      const w = canvas.width;
      const h = canvas.height;
      const margin = 8 * (window.devicePixelRatio || 1);
      const scale = Math.min((w - 2 * margin) / Math.max(1e-12, x1 - x0), (h - 2 * margin) / Math.max(1e-12, y1 - y0));
      view = { scale, ox: (w - scale * (x1 - x0)) / 2 - scale * x0, oy: (h + scale * (y1 - y0)) / 2 + scale * y0 };
    }
    const sx = (x) => view.ox + view.scale * x;
    const sy = (y) => view.oy - view.scale * y;
    function paint() {
      if (!data) return;
      const t = performance.now();
      const g = canvas.getContext('2d');
      const w = canvas.width;
      const h = canvas.height;
      g.setTransform(1, 0, 0, 1, 0, 0);
      g.fillStyle = '#ffffff';
      g.fillRect(0, 0, w, h);
      const n = data.x.length;
      const paths = data.fills.map(() => new Path2D());
      const edges = new Path2D();
      const s = view.scale;
      let drawn = 0;
      for (let i = 0; i < n; i++) {
        const r = geo.reach[i] * s;
        const x = sx(data.x[i]);
        const y = sy(data.y[i]);
        if (x + r < 0 || x - r > w || y + r < 0 || y - r > h) continue;
        if (r < 0.6) {
          paths[colours[i]].rect(x - 0.6, y - 0.6, 1.2, 1.2);
        } else if (geo.kind[i]) {
          // A superellipse or a rounded polygon: its outline.
          shapes.trace(paths[colours[i]], data, geo, i, x, y, s, r);
          if (r > 3) shapes.trace(edges, data, geo, i, x, y, s, r);
        } else {
          paths[colours[i]].moveTo(x + r, y);
          paths[colours[i]].arc(x, y, r, 0, 2 * Math.PI);
          if (r > 3) {
            edges.moveTo(x + r, y);
            edges.arc(x, y, r, 0, 2 * Math.PI);
          }
        }
        drawn++;
      }
      paths.forEach((p, k) => {
        g.fillStyle = data.fills[k];
        g.fill(p);
      });
      g.strokeStyle = 'rgba(29,33,37,0.55)';
      g.lineWidth = 1;
      g.stroke(edges);
      // The domain's outline.
      g.strokeStyle = '#1d2125';
      g.lineWidth = 2;
      g.beginPath();
      data.outline.forEach(([x, y], k) => (k ? g.lineTo(sx(x), sy(y)) : g.moveTo(sx(x), sy(y))));
      g.closePath();
      g.stroke();
      canvas.dataset.drawn = String(drawn);
      stats.frames.push(performance.now() - t);
      if (stats.frames.length > 600) stats.frames.shift();
    }
    function redraw() {
      if (pending) return;
      pending = requestAnimationFrame(() => {
        pending = null;
        paint();
      });
    }
    /** The particle under canvas pixel (px, py), or -1. */
    function particleAt(px, py) {
      const x = (px - view.ox) / view.scale;
      const y = (view.oy - py) / view.scale;
      const cx = Math.floor((x - grid.x0) / grid.cw);
      const cy = Math.floor((y - grid.y0) / grid.ch);
      let best = -1;
      for (let j = cy - grid.reach; j <= cy + grid.reach; j++) {
        if (j < 0 || j >= grid.rows) continue;
        for (let i = cx - grid.reach; i <= cx + grid.reach; i++) {
          if (i < 0 || i >= grid.cols) continue;
          const c = j * grid.cols + i;
          for (let k = grid.start[c]; k < grid.start[c + 1]; k++) {
            const d = grid.items[k];
            if (shapes.contains(data, geo, d, x, y)) best = d;
          }
        }
      }
      return best;
    }
    function pixel(e) {
      const rect = canvas.getBoundingClientRect();
      const ratio = canvas.width / rect.width;
      return [(e.clientX - rect.left) * ratio, (e.clientY - rect.top) * ratio, e.clientX - rect.left, e.clientY - rect.top];
    }
    function hover(e) {
      if (!data) return;
      const [px, py, cssX, cssY] = pixel(e);
      const d = particleAt(px, py);
      if (d < 0) {
        tip.hidden = true;
        return;
      }
      const f = (v) => v.toFixed(4);
      let words = 'id ' + d + ' · x ' + f(data.x[d]) + ' · y ' + f(data.y[d]) + ' · r ' + f(data.r[d]) + ' mm';
      if (geo.kind[d]) {
        // Its turn, and its measures (computed once for the particle hovered).
        if (!measured || measured.id !== d) measured = Object.assign({ id: d }, shapes.measures(data, d));
        const degrees = (data.shapes.angle[d] * 180) / Math.PI;
        words += ' · angle ' + degrees.toFixed(2) + '° · aspect ' + measured.aspect.toFixed(3) + ' · sphericity ' + measured.sphericity.toFixed(3);
      }
      if (data.material.length) words += ' · ' + data.materials[data.material[d]];
      tip.textContent = words;
      tip.dataset.id = String(d);
      tip.hidden = false;
      const wide = canvas.clientWidth;
      // On one line if it fits the canvas (a particle's words are long: at
      // phone width they wrap, within the canvas).
      tip.style.whiteSpace = '';
      tip.style.maxWidth = '';
      if (tip.offsetWidth > wide) {
        tip.style.whiteSpace = 'normal';
        tip.style.maxWidth = wide + 'px';
      }
      tip.style.left = Math.min(cssX + 14, Math.max(0, wide - tip.offsetWidth)) + 'px';
      tip.style.top = cssY + 14 + 'px';
    }
    function zoom(factor, px, py) {
      view.ox = px - (px - view.ox) * factor;
      view.oy = py - (py - view.oy) * factor;
      view.scale *= factor;
      redraw();
    }
    canvas.addEventListener('pointerdown', (e) => {
      if (!data) return;
      drag = { x: e.clientX, y: e.clientY };
      canvas.setPointerCapture(e.pointerId);
    });
    canvas.addEventListener('pointermove', (e) => {
      if (!data) return;
      if (drag) {
        const ratio = canvas.width / canvas.getBoundingClientRect().width;
        view.ox += (e.clientX - drag.x) * ratio;
        view.oy += (e.clientY - drag.y) * ratio;
        drag = { x: e.clientX, y: e.clientY };
        tip.hidden = true;
        redraw();
      } else {
        hover(e);
      }
    });
    const release = () => {
      drag = null;
    };
    canvas.addEventListener('pointerup', release);
    canvas.addEventListener('pointercancel', release);
    canvas.addEventListener('pointerleave', () => {
      tip.hidden = true;
    });
    canvas.addEventListener(
      'wheel',
      (e) => {
        if (!data) return;
        e.preventDefault();
        const [px, py] = pixel(e);
        zoom(Math.exp(-e.deltaY * 0.0015), px, py);
      },
      { passive: false },
    );
    canvas.addEventListener('keydown', (e) => {
      if (!data) return;
      const step = 40 * (window.devicePixelRatio || 1);
      const mid = [canvas.width / 2, canvas.height / 2];
      const keys = {
        '+': () => zoom(1.25, ...mid),
        '=': () => zoom(1.25, ...mid),
        '-': () => zoom(0.8, ...mid),
        '0': () => {
          fit();
          redraw();
        },
        ArrowLeft: () => ((view.ox += step), redraw()),
        ArrowRight: () => ((view.ox -= step), redraw()),
        ArrowUp: () => ((view.oy += step), redraw()),
        ArrowDown: () => ((view.oy -= step), redraw()),
      };
      if (keys[e.key]) {
        e.preventDefault();
        keys[e.key]();
      }
    });
    window.addEventListener('resize', () => {
      if (!data || canvas.hidden) return;
      resize();
      fit();
      redraw();
    });
    return {
      show,
      stop() {
        if (pending) cancelAnimationFrame(pending);
        pending = null;
        data = null;
        geo = null;
        measured = null;
        tip.hidden = true;
      },
      /** For the browser tests: the page position of particle `i`'s centre. */
      centre(i) {
        const rect = canvas.getBoundingClientRect();
        const ratio = rect.width / canvas.width;
        return [rect.left + sx(data.x[i]) * ratio, rect.top + sy(data.y[i]) * ratio];
      },
      /** For the browser tests: pan by (dx, dy) canvas pixels, drawn at once. */
      panBy(dx, dy) {
        view.ox += dx;
        view.oy += dy;
        paint();
      },
    };
  })();
  window.gapackViewer = packingViewer;

  $('config').value = '';
  showWho();
  route();
})();
