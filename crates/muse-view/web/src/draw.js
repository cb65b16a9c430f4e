// Drawing the map: land, zones, corridors by load, closed corridors, stations, the selected
// flight's path, the drones; the count of drones in the air and in view; the load key. In a
// layered airspace the drones are coloured by layer, and with one layer shown alone
// (`state.layer`) only its drones, its corridors (one-way ones with an arrow), their load and
// its closures are drawn. Styles and colours are palette.js's.

// The land's colour, from the style sheet (read once, not every frame).
const LAND = getComputedStyle(document.documentElement).getPropertyValue('--land').trim() || '#f3f1ea';
const PLAIN = '#98a2b3';
let hatching = null;

/** The active zones' fill: diagonal magenta lines (made once). */
function zoneHatching() {
  if (hatching) return hatching;
  const tile = document.createElement('canvas');
  tile.width = 8;
  tile.height = 8;
  const g = tile.getContext('2d');
  g.strokeStyle = COLOURS.zoneHatch;
  g.lineWidth = 1.6;
  g.beginPath();
  // One diagonal and the two corners that continue it into the next tiles.
  g.moveTo(0, 8); g.lineTo(8, 0);
  g.moveTo(-1, 1); g.lineTo(1, -1);
  g.moveTo(7, 9); g.lineTo(9, 7);
  g.stroke();
  hatching = ctx.createPattern(tile, 'repeat');
  return hatching;
}

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

/** The day's load per corridor, at the layer shown (computed once for each). */
function dayLoad() {
  if (!state.dayLoad || state.dayLoadLayer !== state.layer) {
    state.dayLoad = edgeLoad(scene, -Infinity, Infinity, state.layer);
    state.dayLoadLayer = state.layer;
  }
  return state.dayLoad;
}

/** The load the corridors are coloured by: `{ mode, values, max }`, or null when plain. */
function loadNow() {
  let values = null;
  if (state.load === 'day') {
    values = dayLoad();
  } else if (state.load === 'hour') {
    const at = `${Math.floor(state.t / 10000)}:${state.layer}`;
    if (state.hourLoad.at !== at) state.hourLoad = { at, load: edgeLoad(scene, state.t - HOUR, state.t, state.layer) };
    values = state.hourLoad.load;
  }
  if (!values) return null;
  return { mode: state.load, values, max: values.reduce((m, v) => Math.max(m, v), 0) };
}

function segment(i) {
  const [a, b] = scene.edges[i];
  return [toScreen(scene.nodes[a].lon, scene.nodes[a].lat), toScreen(scene.nodes[b].lon, scene.nodes[b].lat)];
}

function strokeSegment(i) {
  const [[x1, y1], [x2, y2]] = segment(i);
  ctx.beginPath();
  ctx.moveTo(x1, y1);
  ctx.lineTo(x2, y2);
  ctx.stroke();
}

/** Draws the zones at `t`; returns the corridors and the nodes the active ones close. */
function drawZones(t) {
  const closed = new Set();
  const closedNodes = new Set();
  for (const z of scene.zones) {
    let s = zoneState(z, t);
    if (s === 'unannounced' || s === 'withdrawn') continue;
    const closes = zoneClosesAt(scene, z, state.layer);
    // A zone whose band misses the layer shown is drawn as one not active.
    if (s === 'active' && state.layer !== null && z.layers && !z.layers.includes(state.layer)) s = 'idle';
    ctx.beginPath();
    for (const poly of z.area) pathRings(poly);
    if (s === 'active') {
      ctx.fillStyle = zoneHatching();
      ctx.fill('evenodd');
      for (const e of closes.edges) closed.add(e);
      for (const n of closes.nodes) closedNodes.add(n);
    }
    ctx.setLineDash(s === 'active' ? [] : [6, 4]);
    ctx.strokeStyle = COLOURS.zone;
    ctx.lineWidth = s === 'active' ? 2 : 1.5;
    ctx.stroke();
    ctx.setLineDash([]);
  }
  return [closed, closedNodes];
}

/** An arrowhead in the middle of corridor `i`, pointing from its first node (`way` 1) or to it (2). */
function arrow(i, way) {
  const [[x1, y1], [x2, y2]] = way === 1 ? segment(i) : segment(i).reverse();
  const len = Math.hypot(x2 - x1, y2 - y1);
  if (len < 24) return;
  const [ux, uy] = [(x2 - x1) / len, (y2 - y1) / len];
  const [mx, my] = [(x1 + x2) / 2 + ux * 4, (y1 + y2) / 2 + uy * 4];
  ctx.beginPath();
  ctx.moveTo(mx, my);
  ctx.lineTo(mx - ux * 8 - uy * 4.5, my - uy * 8 + ux * 4.5);
  ctx.lineTo(mx - ux * 8 + uy * 4.5, my - uy * 8 - ux * 4.5);
  ctx.closePath();
  ctx.fillStyle = ctx.strokeStyle;
  ctx.fill();
}

function drawCorridors(load, closed) {
  ctx.lineCap = 'butt';
  scene.edges.forEach((_, i) => {
    if (closed.has(i)) return;
    const way = corridorWays(scene, i, state.layer);
    // Not flown at the layer shown: not drawn.
    if (way === 0) return;
    const u = load ? loadPosition(load.values[i], load.max) : null;
    if (!load) {
      ctx.strokeStyle = PLAIN;
      ctx.lineWidth = 1;
    } else if (u === null) {
      ctx.strokeStyle = COLOURS.unused;
      ctx.lineWidth = 0.8;
    } else {
      ctx.strokeStyle = loadColour(u);
      ctx.lineWidth = 1.2 + 3.3 * u;
    }
    strokeSegment(i);
    if (way !== 3) {
      if (u === null || !load) ctx.strokeStyle = PLAIN;
      arrow(i, way);
    }
  });
  // Closed corridors: black dashes on a white line, over everything else.
  for (const i of closed) {
    ctx.strokeStyle = COLOURS.closedUnder;
    ctx.lineWidth = 4.5;
    strokeSegment(i);
    ctx.strokeStyle = COLOURS.closed;
    ctx.lineWidth = 2.5;
    ctx.setLineDash([6, 4]);
    strokeSegment(i);
    ctx.setLineDash([]);
  }
}

function drawStations(closedNodes) {
  ctx.fillStyle = COLOURS.station;
  ctx.beginPath();
  for (const n of scene.nodes) {
    const [x, y] = toScreen(n.lon, n.lat);
    if (n.station) ctx.rect(x - 2.5, y - 2.5, 5, 5);
    else ctx.rect(x - 1, y - 1, 2, 2);
  }
  ctx.fill();
  // Nodes closed by an active zone: a ring of black dashes on white, as closed corridors.
  for (const [colour, width, dash] of [[COLOURS.closedUnder, 4.5, []], [COLOURS.closed, 2, [3, 2]]]) {
    ctx.strokeStyle = colour;
    ctx.lineWidth = width;
    ctx.setLineDash(dash);
    for (const i of closedNodes) {
      const [x, y] = toScreen(scene.nodes[i].lon, scene.nodes[i].lat);
      ctx.beginPath();
      ctx.arc(x, y, 7, 0, 2 * Math.PI);
      ctx.stroke();
    }
  }
  ctx.setLineDash([]);
}

/** The selected flight's path: cyan in a black casing. */
function drawSelectedPath(f) {
  ctx.beginPath();
  for (const leg of f.legs) {
    for (let i = leg.first; i <= leg.last; i++) {
      const n = scene.nodes[f.stays[i].node];
      const [x, y] = toScreen(n.lon, n.lat);
      if (i === leg.first) ctx.moveTo(x, y);
      else ctx.lineTo(x, y);
    }
  }
  ctx.lineJoin = 'round';
  ctx.lineCap = 'round';
  ctx.strokeStyle = COLOURS.selectedCasing;
  ctx.lineWidth = 8;
  ctx.stroke();
  ctx.strokeStyle = COLOURS.selected;
  ctx.lineWidth = 4;
  ctx.stroke();
  ctx.lineJoin = 'miter';
  ctx.lineCap = 'butt';
}

/** Draws the airborne drones that are in view; returns how many are airborne in all. */
/**
 * Draws the airborne drones that are in view (at the layer shown, if one is); returns how
 * many are airborne in all, at any layer.
 */
function drawDrones(t, drawn) {
  const moving = new Path2D();
  const hovering = new Path2D();
  // In a layered airspace: the drones' dots per layer, coloured by it.
  const count = scene.layers ? scene.layers.altitudes_m.length : 0;
  const dots = Array.from({ length: count }, () => new Path2D());
  let airborne = 0;
  let selectedAt = null;
  for (const f of scene.flights) {
    if (t < f.takeoff || t >= f.landing) continue;
    const p = positionAt(f, t, scene.nodes);
    if (!p) continue;
    airborne += 1;
    if (!onLayer(f, t, state.layer)) continue;
    const [x, y] = toScreen(p.x, p.y);
    if (x < 0 || y < 0 || x > state.width || y > state.height) continue;
    drawn.push({ id: f.id, x, y, hovering: p.hovering, vertical: p.vertical ?? 0 });
    if (f.id === state.selected) selectedAt = [x, y];
    if (count > 0) {
      const k = Math.min(count, Math.max(1, Math.round(layerAt(f, t))));
      dots[k - 1].moveTo(x + 3.5, y);
      dots[k - 1].arc(x, y, 3.5, 0, 2 * Math.PI);
    }
    if (p.hovering) {
      const r = count > 0 ? 6 : 5;
      hovering.moveTo(x + r, y);
      hovering.arc(x, y, r, 0, 2 * Math.PI);
    } else if (count === 0) {
      moving.moveTo(x + 3.5, y);
      moving.arc(x, y, 3.5, 0, 2 * Math.PI);
    }
  }
  ctx.fillStyle = COLOURS.drone;
  ctx.fill(moving);
  ctx.strokeStyle = COLOURS.droneRim;
  ctx.lineWidth = 1;
  ctx.stroke(moving);
  dots.forEach((dot, i) => {
    ctx.fillStyle = layerColour(i + 1, count);
    ctx.fill(dot);
    ctx.strokeStyle = COLOURS.layerRim;
    ctx.stroke(dot);
  });
  ctx.strokeStyle = COLOURS.hover;
  ctx.lineWidth = 2.5;
  ctx.stroke(hovering);
  if (selectedAt) {
    for (const [colour, width] of [[COLOURS.selectedCasing, 5], [COLOURS.selected, 2.5]]) {
      ctx.strokeStyle = colour;
      ctx.lineWidth = width;
      ctx.beginPath();
      ctx.arc(selectedAt[0], selectedAt[1], 9, 0, 2 * Math.PI);
      ctx.stroke();
    }
  }
  return airborne;
}

function draw() {
  const t = state.t;
  ctx.clearRect(0, 0, state.width, state.height);
  ctx.fillStyle = LAND;
  ctx.beginPath();
  for (const poly of scene.land) pathRings(poly);
  ctx.fill('evenodd');

  const [closed, closedNodes] = drawZones(t);
  const load = loadNow();
  drawCorridors(load, closed);
  drawStations(closedNodes);
  const sel = state.selected ? scene.byId.get(state.selected) : null;
  if (sel) drawSelectedPath(sel);
  const drawn = [];
  state.airborne = drawDrones(t, drawn);
  state.drawn = drawn;
  state.closed = closed;
  state.closedNodes = closedNodes;
  state.dirty = false;

  $('clock').textContent = clock(scene, t);
  const where = state.layer === null ? '' : ` at layer ${state.layer}`;
  $('airborne').textContent = `${state.airborne} in the air, ${drawn.length}${where} in view`;
  drawProfile();
  const slider = $('slider');
  if (document.activeElement !== slider) slider.value = String(Math.round(t / 1000));
  showLoadKey(load);
}

/** The load key on the map: what the colours count, and their values. */
function showLoadKey(load) {
  const box = $('load-key');
  const key = load ? `${load.mode}:${load.max}` : 'plain';
  if (state.shownLoad === key) return;
  state.shownLoad = key;
  if (!load) {
    box.hidden = true;
    return;
  }
  box.hidden = false;
  const what = load.mode === 'day' ? 'flights per corridor, whole day' : 'flights per corridor, past hour';
  const ticks = loadTicks(load.max);
  // With one flight at most, one colour is used: the busiest's.
  const gradient = load.max > 1
    ? LOAD_STOPS.map((c, i) => `rgb(${c.join(',')}) ${(100 * i) / (LOAD_STOPS.length - 1)}%`).join(', ')
    : `${loadColour(1)}, ${loadColour(1)}`;
  const pos = (v) => (load.max > 1 ? (100 * (v - 1)) / (load.max - 1) : 50);
  const labels = ticks.map((v) => `<span style="left:${pos(v)}%">${v}</span>`).join('');
  box.innerHTML = `<div class="key-title">${esc(what)}</div>
    <div class="key-row"><span class="key-unused" title="no flight"></span><span class="key-zero">0</span>
    ${ticks.length ? `<div class="key-scale"><div class="key-bar" style="background: linear-gradient(to right, ${gradient})"></div><div class="key-ticks">${labels}</div></div>` : '<span class="hint">no flight yet</span>'}</div>`;
}
