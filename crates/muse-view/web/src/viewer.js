// The page's core: the scene, the state, the view's geometry, the clock, the selection and
// the address. Inlined after model.js, feed.js and palette.js, in one scope; draw.js,
// panels.js, input.js, start.js and live.js follow. Nothing here runs but declarations.
//
// Everything is drawn on one canvas, never one DOM node per drone, so that a day of
// 10,000 flights stays smooth. `window.museView` (start.js) lets tests (and curious users,
// from the console) drive the page.

const HOUR = 3600000;
// How often the address follows the clock while it runs, ms.
const HASH_EVERY_MS = 1000;
// The previous animation frame's timestamp.
let last = performance.now();

const $ = (id) => document.getElementById(id);

function esc(text) {
  return String(text).replace(/[&<>"']/g, (c) => ({ '&': '&amp;', '<': '&lt;', '>': '&gt;', '"': '&quot;', "'": '&#39;' })[c]);
}

const scene = decodeScene(JSON.parse($('muse-scene').textContent));
const canvas = $('map');
const ctx = canvas.getContext('2d');

const state = {
  t: 0,
  playing: false,
  speed: 300,
  load: 'day',
  layer: null, // a layered airspace: the one layer shown alone (1 up), or null for every one
  selected: null, // a request id: a flight's, or one that did not fly
  view: null, // { scale, cx, cy } in world units (see `toScreen`)
  userView: false, // panned or zoomed by the user: a resize keeps the view
  drawn: [], // [{ id, x, y, hovering }] of the last frame in view, CSS px in the canvas
  airborne: 0, // flights in the air at the last frame, in view or not
  dirty: true,
  dayLoad: null,
  dayLoadLayer: null,
  hourLoad: { at: NaN, load: null },
  shownLoad: null, // { mode, values, max } of the last frame
  closed: new Set(), // corridors closed by an active zone at the last frame
  closedNodes: new Set(), // nodes closed by an active zone at the last frame
  width: 0,
  height: 0,
  following: false, // the live page follows the service's clock (the address gives no time)
  hash: null, // the fragment last written or read, without `#`
  hashAt: -Infinity,
  lookup: null, // the live page: async (id) => whether the service knows request `id`
  pending: null, // the live page: a request the address names, not in yet
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

/** Zooms by `k` about the canvas point `(x, y)`, which stays where it is. */
function zoomAt(x, y, k) {
  const v = state.view;
  const wx = (x - state.width / 2) / v.scale + v.cx;
  const wy = (y - state.height / 2) / v.scale + v.cy;
  const scale = v.scale * k;
  state.userView = true;
  state.view = { scale, cx: wx - (x - state.width / 2) / scale, cy: wy - (y - state.height / 2) / scale };
  state.dirty = true;
}

function resetView() {
  state.userView = false;
  state.view = fitView();
  state.dirty = true;
}

// ---- time ------------------------------------------------------------------------------

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
  writeHash(false);
  requestAnimationFrame(frame);
}

/** Shows layer `k` alone (1 up), or every layer (null); returns the layer shown. */
function setLayer(k) {
  const count = scene.layers ? scene.layers.altitudes_m.length : 0;
  state.layer = Number.isInteger(k) && k >= 1 && k <= count ? k : null;
  const pick = $('layer');
  if (pick) pick.value = state.layer === null ? 'all' : String(state.layer);
  state.dirty = true;
  return state.layer;
}

// ---- selection -------------------------------------------------------------------------

/** Whether request `id` is known here: a flight on the map, or one that did not fly. */
function known(id) {
  return id !== null && (scene.byId.has(id) || scene.unflown.has(id));
}

/** Selects request `id` (null: none; an unknown id selects none); returns the selection. */
function select(id) {
  state.selected = known(id) ? id : null;
  if (state.selected !== null && state.pending === state.selected) state.pending = null;
  showDetails();
  state.dirty = true;
  writeHash(true);
  return state.selected;
}

/**
 * Shows request `id` as the search box or the address asks: its plan (the clock moved to its
 * take-off unless it is in the air or `keepTime`), or why it did not fly. Returns false if no
 * request has this id (the live page then asks the service).
 */
async function show(id, keepTime = false) {
  let found = findRequests(scene, id).exact;
  if (found === null && state.lookup && await state.lookup(id)) found = findRequests(scene, id).exact;
  if (found === null) return false;
  const f = scene.byId.get(found);
  if (f && !keepTime && !isAirborne(f, state.t)) {
    setPlaying(false);
    state.following = false;
    setT(f.takeoff);
  }
  select(found);
  return true;
}

// ---- the address -----------------------------------------------------------------------

/** The fragment the page's state calls for, without `#`: `t=HH:MM:SS&f=ID`. */
function wantedHash() {
  return formatHash(scene, state.following ? null : state.t, state.selected);
}

/** Writes the state into the address (at most once a second unless `now`), adding no history. */
function writeHash(now) {
  const at = performance.now();
  if (!now && at - state.hashAt < HASH_EVERY_MS) return;
  const h = wantedHash();
  if (h === state.hash) return;
  state.hash = h;
  state.hashAt = at;
  const url = h ? `#${h}` : `${window.location.pathname}${window.location.search}`;
  try {
    window.history.replaceState(window.history.state, '', url);
  } catch (e) {
    // A browser that refuses to rewrite this address (some do for file://): a fragment
    // navigation, which `readHash` recognises as the page's own.
    window.location.replace(`#${h}`);
  }
}

/** Follows the address: its time and its selection (none when it names none). */
async function readHash() {
  const h = window.location.hash.replace(/^#/, '');
  if (h === state.hash) return;
  state.hash = h;
  const asked = parseHash(scene, h);
  if (asked.t !== null) {
    setPlaying(false);
    state.following = false;
    setT(asked.t);
  }
  if (asked.f === null) {
    select(null);
  } else if (!await show(asked.f, asked.t !== null)) {
    state.pending = asked.f;
    select(null);
    showFindResult(asked.f);
  }
  state.dirty = true;
  writeHash(true);
}
