// The page: a canvas map (land, zones, corridors, stations, drones), the clock and its
// controls, the flight panel, the day's summary. Inlined after model.js, in one scope.
//
// Everything is drawn on one canvas, never one DOM node per drone, so that a day of
// 10,000 flights stays smooth. `window.museView` lets tests (and curious users, from the
// console) drive the page: set the clock, read what was drawn, select a flight.

const HOUR = 3600000;
const PICK_PX = 10;
// The previous animation frame's timestamp.
let last = performance.now();

const $ = (id) => document.getElementById(id);

function esc(text) {
  return String(text).replace(/[&<>"']/g, (c) => ({ '&': '&amp;', '<': '&lt;', '>': '&gt;', '"': '&quot;', "'": '&#39;' })[c]);
}

function loadScene() {
  const raw = JSON.parse($('muse-scene').textContent);
  return decodeScene(raw);
}

const scene = loadScene();
// The land's colour, from the style sheet (read once, not every frame).
const LAND = getComputedStyle(document.documentElement).getPropertyValue('--land').trim() || '#f3f1ea';
const canvas = $('map');
const ctx = canvas.getContext('2d');

const state = {
  t: 0,
  playing: false,
  speed: 300,
  load: 'day',
  selected: null,
  view: null, // { scale, cx, cy } in world units (see `world`)
  userView: false, // panned or zoomed by the user: a resize keeps the view
  drawn: [], // [{ id, x, y }] of the last frame, CSS px in the canvas
  dirty: true,
  dayLoad: null,
  hourLoad: { at: NaN, load: null },
  width: 0,
  height: 0,
};

// World coordinates: x = lon · cos(mid-latitude), y = −lat (north up, locally conformal).
const bounds = (() => {
  let minX = Infinity; let minY = Infinity; let maxX = -Infinity; let maxY = -Infinity;
  const add = (lon, lat) => {
    minX = Math.min(minX, lon); maxX = Math.max(maxX, lon);
    minY = Math.min(minY, lat); maxY = Math.max(maxY, lat);
  };
  // Fit the airspace (where the drones fly); the land only when there is no airspace.
  for (const n of scene.nodes) add(n.lon, n.lat);
  if (!Number.isFinite(minX)) for (const poly of scene.land) for (const [lon, lat] of poly[0]) add(lon, lat);
  if (!Number.isFinite(minX)) add(0, 0);
  return { minX, minY, maxX, maxY };
})();
const kx = Math.cos((((bounds.minY + bounds.maxY) / 2) * Math.PI) / 180);

function fitView() {
  const w = Math.max(1e-6, (bounds.maxX - bounds.minX) * kx);
  const h = Math.max(1e-6, bounds.maxY - bounds.minY);
  const scale = 0.9 * Math.min(state.width / w, state.height / h);
  return { scale, cx: ((bounds.minX + bounds.maxX) / 2) * kx, cy: -(bounds.minY + bounds.maxY) / 2 };
}

function toScreen(lon, lat) {
  const v = state.view;
  return [(lon * kx - v.cx) * v.scale + state.width / 2, (-lat - v.cy) * v.scale + state.height / 2];
}

function resize() {
  const rect = canvas.getBoundingClientRect();
  const dpr = window.devicePixelRatio || 1;
  state.width = rect.width;
  state.height = rect.height;
  canvas.width = Math.max(1, Math.round(rect.width * dpr));
  canvas.height = Math.max(1, Math.round(rect.height * dpr));
  ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
  if (!state.view || !state.userView) state.view = fitView();
  state.dirty = true;
}

// ---- drawing ---------------------------------------------------------------------------

function pathRings(rings) {
  for (const ring of rings) {
    ring.forEach(([lon, lat], i) => {
      const [x, y] = toScreen(lon, lat);
      if (i === 0) ctx.moveTo(x, y);
      else ctx.lineTo(x, y);
    });
    ctx.closePath();
  }
}

function loadNow() {
  if (state.load === 'day') {
    if (!state.dayLoad) state.dayLoad = edgeLoad(scene);
    return state.dayLoad;
  }
  if (state.load === 'hour') {
    const at = Math.floor(state.t / 10000);
    if (state.hourLoad.at !== at) state.hourLoad = { at, load: edgeLoad(scene, state.t - HOUR, state.t) };
    return state.hourLoad.load;
  }
  return null;
}

function loadColour(u) {
  // Light grey-blue (idle) to deep red (busiest).
  const a = [152, 162, 179];
  const b = [180, 35, 24];
  const c = a.map((v, i) => Math.round(v + (b[i] - v) * u));
  return `rgb(${c[0]},${c[1]},${c[2]})`;
}

function draw() {
  const t = state.t;
  ctx.clearRect(0, 0, state.width, state.height);
  // Land.
  ctx.fillStyle = LAND;
  ctx.beginPath();
  for (const poly of scene.land) pathRings(poly);
  ctx.fill('evenodd');

  // Zones: shaded while active, outlined when not, absent before their announcement.
  const closed = new Set();
  for (const z of scene.zones) {
    const s = zoneState(z, t);
    if (s === 'unannounced' || s === 'withdrawn') continue;
    ctx.beginPath();
    for (const poly of z.area) pathRings(poly);
    if (s === 'active') {
      ctx.fillStyle = 'rgba(217,45,32,0.18)';
      ctx.fill('evenodd');
      for (const e of z.edges) closed.add(e);
    }
    ctx.setLineDash(s === 'active' ? [] : [6, 4]);
    ctx.strokeStyle = 'rgba(217,45,32,0.9)';
    ctx.lineWidth = 1.5;
    ctx.stroke();
    ctx.setLineDash([]);
  }

  // Corridors, coloured by load.
  const load = loadNow();
  const max = load ? Math.max(1, ...load) : 1;
  scene.edges.forEach(([a, b], i) => {
    const [x1, y1] = toScreen(scene.nodes[a].lon, scene.nodes[a].lat);
    const [x2, y2] = toScreen(scene.nodes[b].lon, scene.nodes[b].lat);
    const u = load ? load[i] / max : 0;
    ctx.strokeStyle = closed.has(i) ? 'rgba(217,45,32,0.95)' : loadColour(u);
    ctx.lineWidth = closed.has(i) ? 2.5 : 0.8 + 3.2 * u;
    if (closed.has(i)) ctx.setLineDash([4, 3]);
    ctx.beginPath();
    ctx.moveTo(x1, y1);
    ctx.lineTo(x2, y2);
    ctx.stroke();
    ctx.setLineDash([]);
  });

  // Stations.
  ctx.fillStyle = '#344054';
  ctx.beginPath();
  for (const n of scene.nodes) {
    const [x, y] = toScreen(n.lon, n.lat);
    if (n.station) ctx.rect(x - 2.5, y - 2.5, 5, 5);
    else ctx.rect(x - 1, y - 1, 2, 2);
  }
  ctx.fill();

  // The selected flight's path.
  const sel = state.selected ? scene.byId.get(state.selected) : null;
  if (sel) {
    ctx.strokeStyle = 'rgba(217,45,32,0.85)';
    ctx.lineWidth = 3;
    ctx.beginPath();
    for (const leg of sel.legs) {
      for (let i = leg.first; i <= leg.last; i++) {
        const n = scene.nodes[sel.stays[i].node];
        const [x, y] = toScreen(n.lon, n.lat);
        if (i === leg.first) ctx.moveTo(x, y);
        else ctx.lineTo(x, y);
      }
    }
    ctx.stroke();
  }

  // Drones.
  const drawn = [];
  const moving = new Path2D();
  const hovering = new Path2D();
  let selectedAt = null;
  for (const f of scene.flights) {
    if (t < f.takeoff || t >= f.landing) continue;
    const p = positionAt(f, t, scene.nodes);
    if (!p) continue;
    const [x, y] = toScreen(p.x, p.y);
    if (x < -4 || y < -4 || x > state.width + 4 || y > state.height + 4) continue;
    drawn.push({ id: f.id, x, y, hovering: p.hovering });
    if (f.id === state.selected) selectedAt = [x, y];
    if (p.hovering) {
      hovering.moveTo(x + 5, y);
      hovering.arc(x, y, 5, 0, 2 * Math.PI);
    } else {
      moving.moveTo(x + 3.5, y);
      moving.arc(x, y, 3.5, 0, 2 * Math.PI);
    }
  }
  ctx.fillStyle = '#1570ef';
  ctx.fill(moving);
  ctx.strokeStyle = '#f79009';
  ctx.lineWidth = 2.5;
  ctx.stroke(hovering);
  if (selectedAt) {
    ctx.strokeStyle = '#d92d20';
    ctx.lineWidth = 2.5;
    ctx.beginPath();
    ctx.arc(selectedAt[0], selectedAt[1], 8, 0, 2 * Math.PI);
    ctx.stroke();
  }
  state.drawn = drawn;
  state.dirty = false;

  $('clock').textContent = clock(scene, t);
  $('airborne').textContent = `${drawn.length} in the air`;
  const slider = $('slider');
  if (document.activeElement !== slider) slider.value = String(Math.round(t / 1000));
}

// ---- panels ----------------------------------------------------------------------------

function showSummary() {
  const s = scene.summary;
  const dl = $('summary');
  const rows = [];
  const pct = (x) => `${(100 * x).toFixed(1)}%`;
  const secs = (x) => duration(x * 1000);
  if (s) {
    rows.push(['requests', s.requests]);
    rows.push(['planned', `${s.planned} (${pct(s.success_rate)})`]);
    for (const [k, v] of Object.entries(s.rejected_by_reason || {})) if (v) rows.push([`rejected: ${k.replaceAll('_', ' ')}`, v]);
    rows.push(['air delay, mean', secs(s.air_delay_s.mean)]);
    rows.push(['air delay, p95', secs(s.air_delay_s.p95)]);
    rows.push(['ground delay, mean', secs(s.ground_delay_s.mean)]);
    if (s.legs) rows.push(['legs per trip', `${s.legs.per_trip_mean.toFixed(2)} (max ${s.legs.per_trip_max})`]);
    if (s.replanning) rows.push(['delivered after replanning', `${s.replanning.delivered} (${pct(s.replanning.delivery_rate)})`]);
    rows.push(['planner', `${(s.planner_time.total_s * 1000).toFixed(1)} ms`]);
    rows.push(['labels per request', s.search.expanded_per_request.toFixed(2)]);
    const p = s.parameters;
    if (p) {
      rows.push(['speed', `${p.speed_kmh} km/h`]);
      rows.push(['battery', `${p.max_flight_min} min`]);
      if (p.battery_swap_s !== null && p.battery_swap_s !== undefined) rows.push(['battery swap', duration(p.battery_swap_s * 1000)]);
    }
  } else {
    rows.push(['flights on the map', scene.flights.length]);
  }
  rows.push(['stations', scene.nodes.filter((n) => n.station).length]);
  rows.push(['corridors', scene.edges.length]);
  const hm = (t) => clock(scene, t).replace(/^(\d\d:\d\d):\d\d/, '$1');
  $('zones').innerHTML = scene.zones.map((z) => {
    const when = z.windows.map(([a, b]) => `${hm(a)}–${hm(b)}`).join(', ') || 'not active in this day';
    const ann = z.announced !== undefined ? `; announced ${hm(z.announced)}` : '';
    return `<li><b>${esc(z.id)}</b> ${esc(z.name)}<br>active ${esc(when)}${esc(ann)}</li>`;
  }).join('') || '<li class="hint">none</li>';
  dl.innerHTML = rows.map(([k, v]) => `<dt>${esc(k)}</dt><dd>${esc(v)}</dd>`).join('');
}

function showDetails() {
  const box = $('details');
  const f = state.selected ? scene.byId.get(state.selected) : null;
  if (!f) {
    box.innerHTML = '<p class="hint">Click a drone on the map, or find a flight by its id.</p>';
    return;
  }
  const d = planDetails(scene, f);
  const c = (t) => clock(scene, t);
  const head = [
    ['status', d.status + (d.legs > 1 ? `, ${d.legs} legs` : '')],
    ['route', `${d.origin} → ${d.destination}`],
    ['requested', c(d.requested)],
    ['take-off', c(d.takeoff)],
    ['landing', c(d.landing)],
    ['airborne', duration(d.landing - d.takeoff)],
    ['air delay', d.airDelay === null ? '—' : duration(d.airDelay)],
    ['ground delay', duration(d.groundDelay)],
    ['hovering', duration(d.hover)],
  ];
  const rows = d.rows.map((r) => (r.ground
    ? `<tr class="ground"><td colspan="2">on the ground at ${esc(r.node)} (battery swap)</td><td>${c(r.from)}</td><td class="num">${duration(r.to - r.from)}</td></tr>`
    : `<tr><td>${esc(r.node)}</td><td>${c(r.arrive)}</td><td>${c(r.depart)}</td><td class="num">${r.hover > 0 ? duration(r.hover) : ''}</td></tr>`)).join('');
  box.innerHTML = `<div class="flight-id">${esc(d.id)}</div>
    <dl>${head.map(([k, v]) => `<dt>${esc(k)}</dt><dd>${esc(v)}</dd>`).join('')}</dl>
    <table><thead><tr><th>node</th><th>arrive</th><th>depart</th><th class="num">hover</th></tr></thead><tbody>${rows}</tbody></table>`;
}

function select(id) {
  state.selected = id !== null && scene.byId.has(id) ? id : null;
  showDetails();
  state.dirty = true;
  return state.selected;
}

// ---- time and controls -----------------------------------------------------------------

function setT(t) {
  state.t = Math.max(0, Math.min(scene.span, t));
  state.dirty = true;
}

function setPlaying(on) {
  state.playing = on && state.t < scene.span;
  $('play').textContent = state.playing ? '❚❚' : '▶';
  last = performance.now();
}

function frame(now) {
  if (state.playing) {
    setT(state.t + (now - last) * state.speed);
    if (state.t >= scene.span) setPlaying(false);
  }
  last = now;
  if (state.dirty) draw();
  requestAnimationFrame(frame);
}

function pick(x, y) {
  let best = null;
  let bestD = PICK_PX * PICK_PX;
  for (const d of state.drawn) {
    const dd = (d.x - x) ** 2 + (d.y - y) ** 2;
    if (dd <= bestD) { best = d; bestD = dd; }
  }
  return best;
}

function pickStation(x, y) {
  let best = null;
  let bestD = 8 * 8;
  for (const n of scene.nodes) {
    const [sx, sy] = toScreen(n.lon, n.lat);
    const dd = (sx - x) ** 2 + (sy - y) ** 2;
    if (dd <= bestD) { best = n; bestD = dd; }
  }
  return best;
}

function localXY(ev) {
  const r = canvas.getBoundingClientRect();
  return [ev.clientX - r.left, ev.clientY - r.top];
}

function wire() {
  $('title').textContent = scene.title || 'MUSE';
  document.title = `MUSE — ${scene.title || 'viewer'}`;
  $('attribution').textContent = scene.attribution || '';
  const slider = $('slider');
  slider.max = String(Math.ceil(scene.span / 1000));
  slider.addEventListener('input', () => { setT(Number(slider.value) * 1000); });
  $('play').addEventListener('click', () => setPlaying(!state.playing));
  $('speed').addEventListener('change', (e) => { state.speed = Number(e.target.value); });
  $('load').addEventListener('change', (e) => { state.load = e.target.value; state.dirty = true; });
  document.addEventListener('keydown', (e) => {
    if (e.target instanceof HTMLInputElement && e.target.id === 'find') return;
    if (e.code === 'Space') { e.preventDefault(); setPlaying(!state.playing); }
    if (e.key === 'r') { state.userView = false; state.view = fitView(); state.dirty = true; }
  });
  $('find-form').addEventListener('submit', (e) => {
    e.preventDefault();
    const id = $('find').value.trim();
    const f = scene.byId.get(id);
    if (!f) {
      $('find-message').textContent = id ? `No flight ${id} on the map (rejected, cancelled or unknown).` : '';
      return;
    }
    $('find-message').textContent = '';
    if (!isAirborne(f, state.t)) { setPlaying(false); setT(f.takeoff); }
    select(id);
  });

  let drag = null;
  canvas.addEventListener('mousedown', (e) => {
    const [x, y] = localXY(e);
    drag = { x, y, moved: false, view: { ...state.view } };
  });
  window.addEventListener('mouseup', (e) => {
    if (!drag) return;
    const wasDrag = drag.moved;
    drag = null;
    canvas.classList.remove('dragging');
    if (wasDrag) return;
    const [x, y] = localXY(e);
    const hit = pick(x, y);
    select(hit ? hit.id : null);
  });
  canvas.addEventListener('mousemove', (e) => {
    const [x, y] = localXY(e);
    if (drag) {
      if (Math.abs(x - drag.x) + Math.abs(y - drag.y) > 4) drag.moved = true;
      if (drag.moved) {
        canvas.classList.add('dragging');
        state.userView = true;
        state.view = { ...drag.view, cx: drag.view.cx - (x - drag.x) / drag.view.scale, cy: drag.view.cy - (y - drag.y) / drag.view.scale };
        state.dirty = true;
      }
    }
    const tip = $('tooltip');
    const hit = pick(x, y);
    const station = hit ? null : pickStation(x, y);
    if (hit || station) {
      tip.textContent = hit ? `${hit.id}${hit.hovering ? ' (hovering)' : ''}` : `${station.id}${station.station ? '' : ' (waypoint)'}`;
      tip.style.left = `${x + 12}px`;
      tip.style.top = `${y + 12}px`;
      tip.hidden = false;
    } else {
      tip.hidden = true;
    }
  });
  canvas.addEventListener('mouseleave', () => { $('tooltip').hidden = true; });
  canvas.addEventListener('wheel', (e) => {
    e.preventDefault();
    const [x, y] = localXY(e);
    const v = state.view;
    const k = Math.exp(-e.deltaY * 0.0015);
    const wx = (x - state.width / 2) / v.scale + v.cx;
    const wy = (y - state.height / 2) / v.scale + v.cy;
    const scale = v.scale * k;
    state.userView = true;
    state.view = { scale, cx: wx - (x - state.width / 2) / scale, cy: wy - (y - state.height / 2) / scale };
    state.dirty = true;
  }, { passive: false });
  window.addEventListener('resize', resize);
}

// ---- start -----------------------------------------------------------------------------

const museView = {
  ready: false,
  live: Boolean(scene.live),
  scene,
  /** Pauses, sets the clock to epoch ms `t`, draws; returns the drones drawn. */
  setTime(t) {
    setPlaying(false);
    setT(t - scene.t0);
    draw();
    return state.drawn.length;
  },
  time: () => scene.t0 + state.t,
  drawnCount: () => state.drawn.length,
  flightsDrawn() {
    const r = canvas.getBoundingClientRect();
    return state.drawn.map((d) => ({ id: d.id, x: r.left + d.x, y: r.top + d.y, hovering: d.hovering }));
  },
  selected: () => state.selected,
  /** What zone `id` is doing at the clock's time (`null` if there is no such zone). */
  zoneAt(id) {
    const z = scene.zones.find((zone) => zone.id === id);
    return z ? zoneState(z, state.t) : null;
  },
  select,
  play: () => setPlaying(true),
  pause: () => setPlaying(false),
  redraw() { state.dayLoad = null; state.hourLoad = { at: NaN, load: null }; state.dirty = true; },
};
window.museView = museView;

wire();
resize();
showSummary();
showDetails();
// Start where the address says (`#t=10:30&flight=r42`), else where the day's traffic starts.
const hash = new URLSearchParams(window.location.hash.slice(1));
const firstTakeoff = scene.flights.reduce((m, f) => Math.min(m, f.takeoff), Infinity);
const asked = hash.has('t') ? parseClock(scene, hash.get('t')) : null;
setT(asked ?? (Number.isFinite(firstTakeoff) ? firstTakeoff : 0));
if (hash.has('flight')) select(hash.get('flight'));
draw();
museView.ready = true;
requestAnimationFrame(frame);
