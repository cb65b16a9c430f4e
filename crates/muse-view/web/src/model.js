// The scene and the questions asked of it: where each flight is at an instant, which are
// airborne, how busy each corridor is, what a zone is doing, which requests an id search
// finds, what the address says. No DOM here, so that node's
// test runner can load this file (`npm test`); the page inlines it with its `export`
// keywords dropped.
//
// Times are integer milliseconds from `scene.t0` (see the Rust `muse_view::Scene`).

/** Decodes a scene as embedded in the page (or built by the live feed). */
export function decodeScene(raw) {
  const scene = { ...raw, flights: [], byId: new Map(), unflown: new Map() };
  scene.edgeIndex = new Map();
  raw.edges.forEach(([a, b], i) => scene.edgeIndex.set(edgeKey(a, b), i));
  for (const f of raw.flights) addFlight(scene, f);
  const reasons = raw.reasons ?? [];
  for (const [id, o, d, dep, why] of raw.unflown ?? []) {
    addUnflown(scene, { id, o, d, dep, ...reasons[why] });
  }
  return scene;
}

/**
 * Adds (or replaces) a request with nothing to draw: `{ id, o, d, dep, status, reason,
 * zone?, at? }` (`status` `rejected` or `cancelled`; `at`, when it was cancelled).
 */
export function addUnflown(scene, u) {
  scene.unflown.set(u.id, u);
}

/** Adds (or replaces) a flight in `scene`; returns the decoded flight. */
export function addFlight(scene, raw) {
  const f = decodeFlight(raw);
  const old = scene.byId.get(f.id);
  if (old) scene.flights[scene.flights.indexOf(old)] = f;
  else scene.flights.push(f);
  scene.byId.set(f.id, f);
  return f;
}

/** Removes a flight from `scene` (a cancellation); true if it was there. */
export function removeFlight(scene, id) {
  const old = scene.byId.get(id);
  if (!old) return false;
  scene.flights.splice(scene.flights.indexOf(old), 1);
  scene.byId.delete(id);
  return true;
}

/** The key of the corridor between nodes `a` and `b`, either way round. */
export function edgeKey(a, b) {
  return a < b ? `${a}-${b}` : `${b}-${a}`;
}

/**
 * A flight from its compact form: `s` is flat `[node, arrive, depart, ...]`. Legs split
 * where a station repeats (a battery swap: on the ground between the two stays).
 */
export function decodeFlight(raw) {
  const stays = [];
  for (let i = 0; i + 2 < raw.s.length; i += 3) {
    stays.push({ node: raw.s[i], arrive: raw.s[i + 1], depart: raw.s[i + 2] });
  }
  if (stays.length === 0) throw new Error(`flight ${raw.id} has no stays`);
  const legs = [];
  let first = 0;
  for (let i = 1; i <= stays.length; i++) {
    if (i === stays.length || stays[i].node === stays[i - 1].node) {
      legs.push({ first, last: i - 1, takeoff: stays[first].arrive, landing: stays[i - 1].depart });
      first = i;
    }
  }
  const z = [];
  for (let i = 0; i + 1 < (raw.z ?? []).length; i += 2) z.push([raw.z[i], raw.z[i + 1]]);
  return {
    id: raw.id, o: raw.o, d: raw.d, dep: raw.dep, ff: raw.ff ?? null,
    status: raw.status ?? 'planned', operator: raw.operator ?? null,
    stays, legs, takeoff: stays[0].arrive, landing: stays[stays.length - 1].depart, z,
  };
}

/**
 * Adds the point `[t, layer]` to a flight's layer profile `z` (a flat array, as the scene's
 * `z`), leaving out what says nothing: a repeat, or the middle of three at one layer.
 */
export function pushLayerPoint(z, t, layer) {
  const n = z.length;
  if (n >= 2 && z[n - 2] === t && z[n - 1] === layer) return;
  if (n >= 4 && z[n - 1] === layer && z[n - 3] === layer) {
    z[n - 2] = t;
    return;
  }
  z.push(t, layer);
}

/**
 * The layer of flight `f` at `t` (docs/reference.md#layered-airspace): 1 in a flat airspace; between two layers, a
 * fraction, while it climbs or descends over a vertical link; before take-off and after
 * landing, the first and last.
 */
export function layerAt(f, t) {
  const z = f.z;
  if (z.length === 0) return 1;
  if (t <= z[0][0]) return z[0][1];
  if (t >= z[z.length - 1][0]) return z[z.length - 1][1];
  let lo = 0;
  let hi = z.length - 1;
  while (hi - lo > 1) {
    const mid = (lo + hi) >> 1;
    if (z[mid][0] <= t) lo = mid;
    else hi = mid;
  }
  const [ta, ka] = z[lo];
  const [tb, kb] = z[hi];
  return ka + ((kb - ka) * (t - ta)) / (tb - ta);
}

/**
 * How long flight `f` spends climbing or descending between layers within `[from, to)`, ms
 * (0 in a flat airspace).
 */
export function climbingWithin(f, from, to) {
  let total = 0;
  for (let i = 1; i < f.z.length; i++) {
    const [ta, ka] = f.z[i - 1];
    const [tb, kb] = f.z[i];
    if (ka !== kb) total += Math.max(0, Math.min(tb, to) - Math.max(ta, from));
  }
  return total;
}

/**
 * Whether flight `f` at `t` is shown when the page shows layer `layer` alone (null: every
 * layer): at that layer, or climbing or descending to or from it.
 */
export function onLayer(f, t, layer) {
  return layer === null || Math.abs(layerAt(f, t) - layer) < 1;
}

/** The altitude, metres, at (fractional) layer `k` of `scene` (its first layer's when flat). */
export function altitudeOf(scene, k) {
  const alts = scene.layers?.altitudes_m;
  if (!alts || alts.length === 0) return null;
  const i = Math.max(0, Math.min(alts.length - 1, Math.floor(k) - 1));
  const next = alts[Math.min(alts.length - 1, i + 1)];
  return alts[i] + (next - alts[i]) * Math.max(0, k - 1 - i);
}

/**
 * The selected flight's side view: its altitude over time as `{ legs, layers, from, to }`:
 * per leg the points `[t, metres]` of a line from take-off to landing (straight between
 * them), the layers' altitudes, and the time it spans. Null in a flat airspace.
 */
export function altitudeProfile(scene, f) {
  if (!scene.layers || f.z.length === 0) return null;
  const legs = f.legs.map((leg) => {
    const pts = [[leg.takeoff, altitudeOf(scene, layerAt(f, leg.takeoff))]];
    for (const [t, k] of f.z) if (t > leg.takeoff && t < leg.landing) pts.push([t, altitudeOf(scene, k)]);
    pts.push([leg.landing, altitudeOf(scene, layerAt(f, leg.landing))]);
    return pts;
  });
  return { legs, layers: scene.layers.altitudes_m, from: f.takeoff, to: f.landing };
}

/**
 * Which way corridor `e` is flown at layer `layer` of `scene`: 3 both ways (and always in a
 * flat airspace or when every layer is shown, `layer` null), 1 from its first node to its
 * second only, 2 the other way only, 0 not at all.
 */
export function corridorWays(scene, e, layer) {
  if (layer === null || !scene.layers) return 3;
  return scene.layers.ways[layer - 1]?.[e] ?? 0;
}

/**
 * What zone `z` closes at layer `layer` (null: at any): `{ nodes, edges }`, indices. A zone
 * whose band misses the layer closes nothing there.
 */
export function zoneClosesAt(scene, z, layer) {
  if (layer === null || !scene.layers || !z.layers) return { nodes: z.nodes, edges: z.edges };
  if (!z.layers.includes(layer)) return { nodes: [], edges: [] };
  return { nodes: z.nodes, edges: z.edges.filter((e) => corridorWays(scene, e, layer) !== 0) };
}

/** The leg of `f` in the air at `t` (take-off <= t < landing), or null. */
export function legAt(f, t) {
  if (t < f.takeoff || t >= f.landing) return null;
  for (const leg of f.legs) {
    if (t >= leg.takeoff && t < leg.landing) return leg;
  }
  return null;
}

/** Whether `f` is in the air at `t`. */
export function isAirborne(f, t) {
  return legAt(f, t) !== null;
}

/** The flights in the air at `t`. */
export function airborneAt(flights, t) {
  return flights.filter((f) => isAirborne(f, t));
}

/**
 * Where `f` is at `t`, if airborne: `{ x, y }` in the nodes' coordinates (lon, lat), and
 * `hovering` (at a node, waiting), `vertical` (at a node, climbing, 1, or descending, −1,
 * between two layers) or the corridor `from`→`to` it flies along.
 */
export function positionAt(f, t, nodes) {
  const leg = legAt(f, t);
  if (leg === null) return null;
  const st = f.stays;
  // The last stay of the leg that has begun by `t`.
  let lo = leg.first;
  let hi = leg.last;
  while (lo < hi) {
    const mid = (lo + hi + 1) >> 1;
    if (st[mid].arrive <= t) lo = mid;
    else hi = mid - 1;
  }
  const s = st[lo];
  const n = nodes[s.node];
  if (t <= s.depart || lo === leg.last) {
    const k = layerAt(f, t);
    const vertical = Number.isInteger(k) ? 0 : Math.sign(layerAt(f, t + 1) - k);
    return { x: n.lon, y: n.lat, node: s.node, hovering: s.depart > s.arrive && vertical === 0, vertical };
  }
  const next = st[lo + 1];
  const m = nodes[next.node];
  const u = (t - s.depart) / Math.max(1, next.arrive - s.depart);
  return {
    x: n.lon + (m.lon - n.lon) * u,
    y: n.lat + (m.lat - n.lat) * u,
    from: s.node, to: next.node, hovering: false,
  };
}

/**
 * Traversals per corridor that begin in `[from, to)` (every flight, every leg), at layer
 * `layer` only unless it is null.
 */
export function edgeLoad(scene, from = -Infinity, to = Infinity, layer = null) {
  const load = new Array(scene.edges.length).fill(0);
  for (const f of scene.flights) {
    for (let i = 1; i < f.stays.length; i++) {
      const a = f.stays[i - 1];
      const b = f.stays[i];
      if (a.node === b.node || a.depart < from || a.depart >= to) continue;
      if (layer !== null && Math.round(layerAt(f, a.depart)) !== layer) continue;
      const e = scene.edgeIndex.get(edgeKey(a.node, b.node));
      if (e !== undefined) load[e] += 1;
    }
  }
  return load;
}

/** What zone `z` is doing at `t`: `unannounced`, `active`, `idle` or `withdrawn`. */
export function zoneState(z, t) {
  if (z.announced !== undefined && z.announced !== null && t < z.announced) return 'unannounced';
  if (z.withdrawn !== undefined && z.withdrawn !== null && t >= z.withdrawn) return 'withdrawn';
  return z.windows.some(([a, b]) => t >= a && t < b) ? 'active' : 'idle';
}

/** `HH:MM:SS` local time of `t` (truncated to the second), with `+1d` past midnight. */
export function clock(scene, t) {
  const local = scene.t0 + t + scene.offset_s * 1000;
  const day0 = Math.floor((scene.t0 + scene.offset_s * 1000) / 86400000);
  const day = Math.floor(local / 86400000);
  const ms = local - day * 86400000;
  const hh = Math.floor(ms / 3600000);
  const mm = Math.floor((ms % 3600000) / 60000);
  const ss = Math.floor((ms % 60000) / 1000);
  const two = (v) => String(v).padStart(2, '0');
  const plus = day > day0 ? ` +${day - day0}d` : '';
  return `${two(hh)}:${two(mm)}:${two(ss)}${plus}`;
}

/** A duration in ms as `1 h 02 min`, `3 min 20 s` or `12.5 s`. */
export function duration(ms) {
  const s = ms / 1000;
  const sign = s < 0 ? '−' : '';
  if (Math.abs(s) < 59.95) return `${s.toFixed(1)} s`;
  const total = Math.round(Math.abs(s));
  if (total < 3600) return `${sign}${Math.floor(total / 60)} min ${String(total % 60).padStart(2, '0')} s`;
  const mins = Math.floor(total / 60);
  return `${sign}${Math.floor(mins / 60)} h ${String(mins % 60).padStart(2, '0')} min`;
}

/**
 * The instant (ms from `t0`) of local clock time `hh:mm[:ss]` on the scene's first day
 * (hours past 23 run into the next days), or null if `text` is not one.
 */
export function parseClock(scene, text) {
  const m = /^(\d{1,3}):(\d{2})(?::(\d{2}))?$/.exec(text.trim());
  if (!m) return null;
  const [h, min, sec] = [Number(m[1]), Number(m[2]), Number(m[3] ?? 0)];
  if (min > 59 || sec > 59) return null;
  const local0 = scene.t0 + scene.offset_s * 1000;
  const midnight = Math.floor(local0 / 86400000) * 86400000;
  return midnight + ((h * 60 + min) * 60 + sec) * 1000 - local0;
}

/**
 * The plan of `f` as rows for a table: each stay (node, arrival, departure, hover; in a
 * layered airspace its layers on arrival and departure, and the time climbing or descending
 * there, which is not hovering), and between legs the time on the ground; plus take-off,
 * landing and delays.
 */
export function planDetails(scene, f) {
  const rows = [];
  f.legs.forEach((leg, k) => {
    if (k > 0) {
      const prev = f.legs[k - 1];
      rows.push({ ground: true, node: scene.nodes[f.stays[leg.first].node].id, from: prev.landing, to: leg.takeoff });
    }
    for (let i = leg.first; i <= leg.last; i++) {
      const s = f.stays[i];
      const layers = scene.layers ? [layerAt(f, s.arrive), layerAt(f, s.depart)].map(Math.round) : null;
      // A climb or descent at the node is not hovering.
      const climb = climbingWithin(f, s.arrive, s.depart);
      rows.push({ ground: false, leg: k + 1, node: scene.nodes[s.node].id, arrive: s.arrive, depart: s.depart, hover: s.depart - s.arrive - climb, climb, layers });
    }
  });
  const airborne = f.landing - f.takeoff;
  return {
    id: f.id,
    status: f.status,
    origin: scene.nodes[f.o].id,
    destination: scene.nodes[f.d].id,
    requested: f.dep,
    takeoff: f.takeoff,
    landing: f.landing,
    groundDelay: f.takeoff - f.dep,
    airDelay: f.ff === null || f.status === 'diverted' ? null : airborne - f.ff,
    legs: f.legs.length,
    hover: f.stays.reduce((sum, s) => sum + (s.depart - s.arrive), 0) - climbingWithin(f, -Infinity, Infinity),
    climb: climbingWithin(f, -Infinity, Infinity),
    rows,
  };
}

/**
 * The search box: the requests whose id contains `text`, case aside, among the flights and
 * the requests that did not fly. `exact` is the id typed (in its own case if there is one,
 * else in any), or null; `matches` the first `limit` ids containing it, those that start
 * with it first, then the shorter, then in order; `total` how many contain it.
 */
export function findRequests(scene, text, limit = 10) {
  const q = text.trim();
  if (q === '') return { exact: null, matches: [], total: 0 };
  const lower = q.toLowerCase();
  let exact = scene.byId.has(q) || scene.unflown.has(q) ? q : null;
  const hits = [];
  const consider = (id) => {
    const l = id.toLowerCase();
    const at = l.indexOf(lower);
    if (at < 0) return;
    if (exact === null && l === lower) exact = id;
    hits.push([at === 0 ? 0 : 1, id.length, id]);
  };
  for (const id of scene.byId.keys()) consider(id);
  for (const id of scene.unflown.keys()) consider(id);
  hits.sort((a, b) => a[0] - b[0] || a[1] - b[1] || (a[2] < b[2] ? -1 : Number(a[2] > b[2])));
  return { exact, matches: hits.slice(0, limit).map((h) => h[2]), total: hits.length };
}

const REASONS = {
  out_of_range: 'even the free-flow path, ignoring traffic and zones, takes longer than the battery allows',
  unreachable: 'no path of corridors joins its origin and destination',
  no_feasible_plan: 'traffic and no-fly zones leave no plan',
  departure_in_past: "its departure was earlier than the service's clock",
  zone_announced: 'a no-fly zone announced before its take-off left it no plan',
  cancelled_by_operator: 'its operator cancelled it before take-off',
  unserved: 'a customer has no pad within the last mile, or both customers share one',
};

/** Why request `u` (see `addUnflown`) did not fly, in words. */
export function reasonText(scene, u) {
  if (u.reason === 'zone_announced' && u.zone) {
    const when = u.at !== undefined && u.at !== null ? `, announced at ${clock(scene, u.at)},` : '';
    return `zone ${u.zone}${when} left it no plan before take-off`;
  }
  if (u.reason === 'cancelled_by_operator' && u.at !== undefined && u.at !== null) {
    return `its operator cancelled it at ${clock(scene, u.at)}, before take-off`;
  }
  return REASONS[u.reason] ?? String(u.reason ?? 'unknown').replaceAll('_', ' ');
}

/**
 * `HH:MM:SS` of `t`, hours counted from the local midnight of the scene's first day (past 23
 * on the next days), as the address gives it; `parseClock` reads it back.
 */
export function hashClock(scene, t) {
  const local0 = scene.t0 + scene.offset_s * 1000;
  const midnight = Math.floor(local0 / 86400000) * 86400000;
  const s = Math.floor((local0 + t - midnight) / 1000);
  const two = (v) => String(v).padStart(2, '0');
  return `${two(Math.floor(s / 3600))}:${two(Math.floor((s % 3600) / 60))}:${two(s % 60)}`;
}

/** The address's fragment (without `#`) for clock `t` (null: none) and the selection. */
export function formatHash(scene, t, selected) {
  const parts = [];
  if (t !== null) parts.push(`t=${hashClock(scene, t)}`);
  if (selected) parts.push(`f=${encodeURIComponent(selected)}`);
  return parts.join('&');
}

/**
 * What the address's fragment asks for: `t` (ms from `t0`; null if absent or not a time)
 * and `f` the request id (null if absent). `flight=` is read as `f=`.
 */
export function parseHash(scene, hash) {
  const p = new URLSearchParams(hash.replace(/^#/, ''));
  const t = p.has('t') ? parseClock(scene, p.get('t')) : null;
  const f = p.get('f') ?? p.get('flight');
  return { t, f: f === null || f === '' ? null : f };
}

const WEEKDAY = ['Sun', 'Mon', 'Tue', 'Wed', 'Thu', 'Fri', 'Sat'];
const MONTH = ['Jan', 'Feb', 'Mar', 'Apr', 'May', 'Jun', 'Jul', 'Aug', 'Sep', 'Oct', 'Nov', 'Dec'];

/** The local date of `t`, e.g. `Mon 5 Jan`. */
export function localDay(scene, t) {
  const d = new Date(scene.t0 + t + scene.offset_s * 1000);
  return `${WEEKDAY[d.getUTCDay()]} ${d.getUTCDate()} ${MONTH[d.getUTCMonth()]}`;
}

/**
 * Window `[a, b)` of a zone, dated: `Mon 5 Jan 10:00–12:00`, or across midnight `Sat 10 Jan
 * 22:00 – Sun 11 Jan 02:00`. Windows are clipped to the time shown, `[lo, hi)`: an end at
 * its edge reads `from …` or `until …`.
 */
export function windowText(scene, [a, b], lo, hi) {
  const at = (t) => `${localDay(scene, t)} ${clock(scene, t).slice(0, 5)}`;
  if (a <= lo && b >= hi) return 'all the time shown';
  if (a <= lo) return `until ${at(b)}`;
  if (b >= hi) return `from ${at(a)}`;
  if (localDay(scene, a) === localDay(scene, b)) return `${at(a)}–${clock(scene, b).slice(0, 5)}`;
  return `${at(a)} – ${at(b)}`;
}
