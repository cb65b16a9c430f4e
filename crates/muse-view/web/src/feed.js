// Decoding the live feed of `muse serve`: flights as its API shows them, its server-sent
// events, its zones and what they close. No DOM here (node's test runner loads it); the page
// inlines it after model.js with its `import` lines and `export` keywords dropped.

import { edgeKey, pushLayerPoint } from './model.js';

/**
 * A scene flight (model.js's compact form) from a flight as the API shows it. In a layered
 * airspace (stays with a `layer`), a climb or descent (stays at one node, layer after layer)
 * is one stay from above, and `z` gives the layer over time, as the Rust scene does.
 */
export function flightFromApi(scene, nodeIndex, plan) {
  const path = plan.path ?? plan.committed;
  if (!path || path.length === 0) return null;
  const rel = (t) => Date.parse(t) - scene.t0;
  const node = (id) => {
    const i = nodeIndex.get(id);
    if (i === undefined) throw new Error(`unknown node ${id}`);
    return i;
  };
  const s = [];
  const z = [];
  let lastLayer = null;
  for (const st of path) {
    const [n, a, d] = [node(st.node), rel(st.arrive), rel(st.depart)];
    const layered = st.layer !== undefined && st.layer !== null;
    if (layered) {
      pushLayerPoint(z, a, st.layer);
      pushLayerPoint(z, d, st.layer);
    }
    if (layered && s.length > 0 && s[s.length - 3] === n && lastLayer !== st.layer) s[s.length - 1] = d;
    else s.push(n, a, d);
    lastLayer = layered ? st.layer : null;
  }
  const flight = {
    id: plan.request,
    o: node(plan.origin),
    d: node(plan.destination),
    dep: rel(plan.requested_departure),
    ff: plan.free_flow_s === null || plan.free_flow_s === undefined ? null : Math.round(plan.free_flow_s * 1000),
    status: plan.status,
    operator: plan.operator ?? null,
    s,
  };
  if (z.length > 0) flight.z = z;
  return flight;
}

/**
 * A request the service did not fly, from its answer (as `GET /v1/flights/{id}` shows it),
 * in the form `addUnflown` takes; null if it is neither rejected nor cancelled.
 */
export function unflownFromApi(scene, nodeIndex, plan) {
  if (plan.status !== 'rejected' && plan.status !== 'cancelled') return null;
  const rel = (t) => Date.parse(t) - scene.t0;
  const node = (id) => {
    const i = nodeIndex.get(id);
    if (i === undefined) throw new Error(`unknown node ${id}`);
    return i;
  };
  const u = {
    id: plan.request,
    o: node(plan.origin),
    d: node(plan.destination),
    dep: rel(plan.requested_departure),
    status: plan.status,
    reason: plan.reason,
  };
  const changes = plan.changes ?? [];
  const last = changes[changes.length - 1];
  if (plan.reason === 'zone_announced' && last) {
    u.zone = last.zone;
    u.at = rel(last.announced);
  } else if (plan.cancelled_at) {
    u.at = rel(plan.cancelled_at);
  }
  return u;
}

/**
 * What each zone closes, from `GET /v1/closures`, as node and corridor indices of `scene`: a
 * Map from zone id to `{ nodes, edges }`. A node or corridor the page does not know is an
 * error naming it (the service and the page share one airspace).
 */
export function closuresFromApi(scene, nodeIndex, body) {
  const node = (zone, id) => {
    const i = nodeIndex.get(id);
    if (i === undefined) throw new Error(`zone ${zone}: unknown node ${id}`);
    return i;
  };
  const out = new Map();
  for (const z of body.zones ?? []) {
    const nodes = z.nodes.map((id) => node(z.zone, id));
    const edges = z.corridors.map((c) => {
      const e = scene.edgeIndex.get(edgeKey(node(z.zone, c.from), node(z.zone, c.to)));
      if (e === undefined) throw new Error(`zone ${z.zone}: unknown corridor ${c.id}`);
      return e;
    });
    const closes = { nodes, edges };
    if (z.layers) closes.layers = z.layers;
    out.set(z.zone, closes);
  }
  return out;
}

/**
 * Feeds `sink` the events of a server-sent-events byte stream: `sink(kind, data, id)` for
 * each event. Returns the id of the last event seen (or `lastId`).
 */
export async function readEvents(body, sink, lastId) {
  const reader = body.getReader();
  const decoder = new TextDecoder();
  let buffer = '';
  let kind = 'message';
  let data = [];
  let id = lastId;
  for (;;) {
    const { value, done } = await reader.read();
    if (done) return id;
    buffer += decoder.decode(value, { stream: true });
    let nl;
    while ((nl = buffer.indexOf('\n')) >= 0) {
      const line = buffer.slice(0, nl).replace(/\r$/, '');
      buffer = buffer.slice(nl + 1);
      if (line === '') {
        if (data.length > 0) sink(kind, data.join('\n'), id);
        kind = 'message';
        data = [];
      } else if (!line.startsWith(':')) {
        const colon = line.indexOf(':');
        const field = colon < 0 ? line : line.slice(0, colon);
        const val = colon < 0 ? '' : line.slice(colon + 1).replace(/^ /, '');
        if (field === 'event') kind = val;
        else if (field === 'data') data.push(val);
        else if (field === 'id') id = val;
      }
    }
  }
}

const DAY = 86400000;
const WEEKDAYS = ['SUN', 'MON', 'TUE', 'WED', 'THU', 'FRI', 'SAT'];

/** `+08:00` (or `Z`) as milliseconds east of UTC. */
function offsetMs(text) {
  if (text === 'Z' || text === '') return 0;
  const m = /^([+-])(\d\d):(\d\d)$/.exec(text);
  if (!m) throw new Error(`bad UTC offset ${text}`);
  return (m[1] === '-' ? -1 : 1) * (Number(m[2]) * 60 + Number(m[3])) * 60000;
}

/** `10:00:00+08:00` as [milliseconds after local midnight, offset ms]. */
function timeOfDay(text) {
  const m = /^(\d\d):(\d\d)(?::(\d\d)(?:\.\d+)?)?(Z|[+-]\d\d:\d\d)?$/.exec(text);
  if (!m) throw new Error(`bad time ${text}`);
  return [((Number(m[1]) * 60 + Number(m[2])) * 60 + Number(m[3] ?? 0)) * 1000, offsetMs(m[4] ?? 'Z')];
}

/** A circle of `radius` metres around `[lon, lat]` as one ring. */
function circleRing([lon, lat], radius) {
  const dLat = radius / 110540;
  const dLon = radius / (111320 * Math.cos((lat * Math.PI) / 180));
  const ring = [];
  for (let i = 0; i <= 72; i++) {
    const a = (2 * Math.PI * i) / 72;
    ring.push([lon + dLon * Math.sin(a), lat + dLat * Math.cos(a)]);
  }
  return ring;
}

/** The polygons (rings of [lon, lat]) of an ED-318 geometry. */
function areaOf(g) {
  if (!g) return [];
  switch (g.type) {
    case 'Polygon': return [g.coordinates.map((r) => r.map((c) => [c[0], c[1]]))];
    case 'MultiPolygon': return g.coordinates.map((p) => p.map((r) => r.map((c) => [c[0], c[1]])));
    case 'Point': return g.extent && g.extent.radius > 0 ? [[circleRing(g.coordinates, g.extent.radius)]] : [];
    case 'GeometryCollection': return g.geometries.flatMap(areaOf);
    default: return [];
  }
}

/** The active windows `[start, end)` (ms from `scene.t0`) of an ED-318 period within `[from, to)`. */
function periodWindows(scene, period, from, to) {
  const rel = (t) => Date.parse(t) - scene.t0;
  const lo = Math.max(from, period.startDateTime ? rel(period.startDateTime) : -Infinity);
  const hi = Math.min(to, period.endDateTime ? rel(period.endDateTime) : Infinity);
  if (!(lo < hi)) return [];
  if (!period.schedule || period.schedule.length === 0) return [[lo, hi]];
  const out = [];
  for (const entry of period.schedule) {
    const [start, off] = timeOfDay(entry.startTime);
    const [end] = timeOfDay(entry.endTime);
    const days = entry.day ?? ['ANY'];
    // Local days from the one before `lo` (an overnight window) to the one of `hi`.
    const first = Math.floor((scene.t0 + lo + off) / DAY) - 1;
    const last = Math.floor((scene.t0 + Math.min(hi, lo + 400 * DAY) + off) / DAY);
    for (let d = first; d <= last; d++) {
      if (!days.includes('ANY') && !days.includes(WEEKDAYS[((d % 7) + 11) % 7])) continue;
      const a = d * DAY + start - off - scene.t0;
      const b = d * DAY + end + (end <= start ? DAY : 0) - off - scene.t0;
      const s = Math.max(a, lo);
      const e = Math.min(b, hi);
      if (s < e) out.push([s, e]);
    }
  }
  return out;
}

/**
 * The zones of an ED-318 FeatureCollection (as `GET /v1/zones` serves it) in the scene's
 * form, active windows within `[from, to)`: area, windows, and the MUSE `announced` and
 * `withdrawn` instants. The nodes and corridors they close come from `GET /v1/closures`
 * (`closuresFromApi`), worked out by the service as its planner does.
 */
export function zonesFromEd318(scene, fc, from, to) {
  return (fc.features ?? []).map((f) => {
    const p = f.properties ?? {};
    const name = Array.isArray(p.name) ? (p.name[0]?.text ?? '') : (p.name ?? '');
    const periods = p.limitedApplicability ?? [];
    const windows = periods.length === 0
      ? [[from, to]]
      : periods.flatMap((per) => periodWindows(scene, per, from, to));
    windows.sort((a, b) => a[0] - b[0]);
    const merged = [];
    for (const w of windows) {
      const prev = merged[merged.length - 1];
      if (prev && w[0] <= prev[1]) prev[1] = Math.max(prev[1], w[1]);
      else merged.push([...w]);
    }
    const zone = { id: p.identifier, name, area: areaOf(f.geometry), windows: merged, nodes: [], edges: [] };
    if (p.announced) zone.announced = Date.parse(p.announced) - scene.t0;
    if (p.withdrawn) zone.withdrawn = Date.parse(p.withdrawn) - scene.t0;
    return zone;
  });
}
