// The viewer's logic against simple oracles: `npm test` (node's own test runner, no
// dependencies). The Rust test `muse-view/tests/web.rs` runs it under `cargo test`.

import { test } from 'node:test';
import assert from 'node:assert/strict';

import {
  decodeScene, decodeFlight, legAt, isAirborne, airborneAt, positionAt, edgeLoad,
  zoneState, clock, duration, parseClock, planDetails, addFlight, removeFlight,
  findRequests, reasonText, hashClock, formatHash, parseHash, localDay, windowText,
  pushLayerPoint, layerAt, onLayer, climbingWithin, altitudeOf, altitudeProfile, corridorWays, zoneClosesAt,
} from '../src/model.js';
import {
  flightFromApi, readEvents, zonesFromEd318, unflownFromApi, closuresFromApi,
} from '../src/feed.js';
import {
  LOAD_STOPS, COLOURS, loadRgb, loadColour, loadPosition, loadTicks, LAYER_STOPS, layerRgb,
  layerColour,
} from '../src/palette.js';

const nodes = [
  { id: 'A', lon: 0, lat: 0, station: true },
  { id: 'B', lon: 1, lat: 0, station: true },
  { id: 'C', lon: 1, lat: 1, station: true },
];
const edges = [[0, 1], [1, 2]];

// A → B (hover 10 s at B? no: lands at B), swap 300 s, B → C with 5 s hover at C.
const twoLegs = {
  id: 'r1', o: 0, d: 2, dep: 0, ff: 1000, status: 'planned',
  s: [0, 0, 0, 1, 100, 100, 1, 400, 400, 2, 500, 505],
};

function scene(flights, extra = {}) {
  return decodeScene({ t0: 0, span: 10000, offset_s: 0, nodes, edges, land: [], zones: [], flights, summary: null, live: false, ...extra });
}

test('legs split at a repeated station; the ground between them is not airborne', () => {
  const f = decodeFlight(twoLegs);
  assert.equal(f.legs.length, 2);
  assert.deepEqual(f.legs.map((l) => [l.takeoff, l.landing]), [[0, 100], [400, 505]]);
  assert.ok(isAirborne(f, 0), 'take-off instant is airborne');
  assert.ok(isAirborne(f, 99));
  assert.ok(!isAirborne(f, 100), 'landing instant is not');
  assert.ok(!isAirborne(f, 250), 'on the ground swapping');
  assert.ok(isAirborne(f, 400));
  assert.ok(!isAirborne(f, 505));
  assert.equal(legAt(f, 450).takeoff, 400);
});

test('positions interpolate along corridors and hover at nodes', () => {
  const f = decodeFlight(twoLegs);
  const mid = positionAt(f, 50, nodes);
  assert.deepEqual([mid.x, mid.y, mid.hovering], [0.5, 0, false]);
  assert.equal(mid.from, 0);
  assert.equal(mid.to, 1);
  const hover = positionAt(f, 502, nodes);
  assert.deepEqual([hover.x, hover.y, hover.hovering], [1, 1, true]);
  assert.equal(positionAt(f, 250, nodes), null);
  const second = positionAt(f, 450, nodes);
  assert.deepEqual([second.x, second.y], [1, 0.5]);
});

test('airborne counts match a brute force over random flights', () => {
  // A small seeded generator (mulberry32): the seed is printed on failure.
  const seed = 20261125;
  let a = seed;
  const rand = () => {
    a = (a + 0x6d2b79f5) | 0;
    let t = Math.imul(a ^ (a >>> 15), 1 | a);
    t = (t + Math.imul(t ^ (t >>> 7), 61 | t)) ^ t;
    return ((t ^ (t >>> 14)) >>> 0) / 4294967296;
  };
  const flights = [];
  for (let k = 0; k < 300; k++) {
    let t = Math.floor(rand() * 5000);
    let at = Math.floor(rand() * 3);
    const s = [];
    const stays = 2 + Math.floor(rand() * 5);
    for (let i = 0; i < stays; i++) {
      const hover = rand() < 0.3 ? Math.floor(rand() * 50) : 0;
      s.push(at, t, t + hover);
      t += hover + 1 + Math.floor(rand() * 200);
      const swap = i > 0 && i < stays - 1 && rand() < 0.2;
      if (swap) { s.push(at, t, t); t += 1 + Math.floor(rand() * 100); }
      at = (at + 1) % 3;
    }
    flights.push({ id: `f${k}`, o: s[0], d: s[s.length - 3], dep: s[1], ff: null, status: 'planned', s });
  }
  const sc = scene(flights);
  // Oracle: airborne when inside [first, last] of a run of stays with no station repeated.
  const oracle = (raw, t) => {
    const st = [];
    for (let i = 0; i < raw.s.length; i += 3) st.push(raw.s.slice(i, i + 3));
    let start = 0;
    for (let i = 1; i <= st.length; i++) {
      if (i === st.length || st[i][0] === st[i - 1][0]) {
        if (t >= st[start][1] && t < st[i - 1][2]) return true;
        start = i;
      }
    }
    return false;
  };
  for (let t = 0; t < 7000; t += 37) {
    const want = flights.filter((raw) => oracle(raw, t)).length;
    assert.equal(airborneAt(sc.flights, t).length, want, `t=${t} seed=${seed}`);
    for (const f of airborneAt(sc.flights, t)) assert.ok(positionAt(f, t, nodes), `position of ${f.id} at ${t}`);
  }
});

test('corridor load counts traversals by their start', () => {
  const sc = scene([twoLegs]);
  assert.deepEqual(edgeLoad(sc), [1, 1]);
  assert.deepEqual(edgeLoad(sc, 0, 100), [1, 0]);
  assert.deepEqual(edgeLoad(sc, 100, 1000), [0, 1]);
});

test('zones: unannounced, then active in their windows, idle outside', () => {
  const z = { windows: [[100, 200]], announced: 50 };
  assert.equal(zoneState(z, 10), 'unannounced');
  assert.equal(zoneState(z, 60), 'idle');
  assert.equal(zoneState(z, 100), 'active');
  assert.equal(zoneState(z, 200), 'idle');
  assert.equal(zoneState({ windows: [[0, 5]] }, 1), 'active');
});

test('clock: local time, truncated to the second, days counted past midnight', () => {
  // t0 = 2026-01-05T00:00:00Z; Singapore +08:00.
  const sc = { t0: Date.UTC(2026, 0, 5), offset_s: 8 * 3600 };
  assert.equal(clock(sc, 0), '08:00:00');
  assert.equal(clock(sc, 241 + 3600000), '09:00:00');
  assert.equal(clock(sc, 59999), '08:00:59');
  assert.equal(clock(sc, 16 * 3600000 + 1000), '00:00:01 +1d');
  assert.equal(duration(12500), '12.5 s');
  assert.equal(duration(200000), '3 min 20 s');
  assert.equal(duration(3720000), '1 h 02 min');
  assert.equal(duration(239600), '4 min 00 s', 'no 60 seconds');
  assert.equal(duration(59990), '1 min 00 s');
  assert.equal(parseClock(sc, '10:30'), 2.5 * 3600000);
  assert.equal(clock(sc, parseClock(sc, '23:59:59')), '23:59:59');
  assert.equal(parseClock(sc, '25:00'), 17 * 3600000, 'the next day');
  assert.equal(parseClock(sc, 'noon'), null);
});

test('plan details: delays, hovering and the swap on the ground', () => {
  const sc = scene([{ ...twoLegs, dep: -20 }]);
  const d = planDetails(sc, sc.byId.get('r1'));
  assert.equal(d.groundDelay, 20);
  assert.equal(d.airDelay, 505 - 1000);
  assert.equal(d.hover, 5);
  assert.equal(d.legs, 2);
  assert.deepEqual(d.rows.map((r) => (r.ground ? `ground ${r.node}` : r.node)), ['A', 'B', 'ground B', 'B', 'C']);
});

test('flights are added, replaced and removed by id', () => {
  const sc = scene([]);
  addFlight(sc, twoLegs);
  addFlight(sc, { ...twoLegs, status: 'replanned' });
  assert.equal(sc.flights.length, 1);
  assert.equal(sc.byId.get('r1').status, 'replanned');
  assert.ok(removeFlight(sc, 'r1'));
  assert.ok(!removeFlight(sc, 'r1'));
  assert.equal(sc.flights.length, 0);
});

test('a flight as the API shows it becomes a scene flight', () => {
  const sc = { t0: Date.parse('2026-01-05T00:00:00Z') };
  const index = new Map(nodes.map((n, i) => [n.id, i]));
  const raw = flightFromApi(sc, index, {
    request: 'x', origin: 'A', destination: 'B', status: 'planned', free_flow_s: 1.5,
    requested_departure: '2026-01-05T08:00:00.000+08:00',
    path: [
      { node: 'A', arrive: '2026-01-05T08:00:00.000+08:00', depart: '2026-01-05T08:00:01.000+08:00' },
      { node: 'B', arrive: '2026-01-05T08:00:02.500+08:00', depart: '2026-01-05T08:00:02.500+08:00' },
    ],
  });
  assert.deepEqual(raw.s, [0, 0, 1000, 1, 2500, 2500]);
  assert.equal(raw.ff, 1500);
  assert.equal(raw.dep, 0);
  assert.throws(() => flightFromApi(sc, index, { request: 'y', origin: 'Z', destination: 'B', path: [{ node: 'Z', arrive: '', depart: '' }] }), /unknown node Z/);
});

test('server-sent events are parsed across chunk boundaries', async () => {
  const text = ': keep-alive\n\nid: 7\nevent: planned\ndata: {"a":\ndata: 1}\n\nid: 8\nevent: cancelled\ndata: {}\n\n';
  const chunks = [text.slice(0, 5), text.slice(5, 31), text.slice(31)];
  const body = new ReadableStream({
    start(c) { for (const ch of chunks) c.enqueue(new TextEncoder().encode(ch)); c.close(); },
  });
  const got = [];
  const last = await readEvents(body, (kind, data, id) => got.push([kind, data, id]), '0');
  assert.deepEqual(got, [['planned', '{"a":\n1}', '7'], ['cancelled', '{}', '8']]);
  assert.equal(last, '8');
});

test('ED-318 zones as GET /v1/zones serves them: windows, circles, announcement, withdrawal', () => {
  // t0 = Monday 2026-01-05 00:00 local (+08:00).
  const sc = { t0: Date.parse('2026-01-05T00:00:00+08:00') };
  const h = (x) => x * 3600000;
  const fc = {
    type: 'FeatureCollection',
    features: [
      { type: 'Feature', properties: { identifier: 'CBD', name: [{ text: 'CBD', lang: 'en' }],
        limitedApplicability: [{ schedule: [{ day: ['ANY'], startTime: '10:00:00+08:00', endTime: '12:00:00+08:00' }] }] },
        geometry: { type: 'Polygon', coordinates: [[[0, 0], [1, 0], [1, 1], [0, 0]]] } },
      { type: 'Feature', properties: { identifier: 'EVT', name: 'Event',
        limitedApplicability: [{ startDateTime: '2026-01-05T15:00:00.000+08:00', endDateTime: '2026-01-05T18:00:00.000+08:00' }],
        announced: '2026-01-05T14:00:00.000+08:00', withdrawn: '2026-01-05T16:30:00.000+08:00' },
        geometry: { type: 'GeometryCollection', geometries: [{ type: 'Point', coordinates: [103.8, 1.3], extent: { subType: 'Circle', radius: 1000 } }] } },
      { type: 'Feature', properties: { identifier: 'WKD', limitedApplicability: [{ schedule: [{ day: ['SAT', 'SUN'], startTime: '22:00:00+08:00', endTime: '02:00:00+08:00' }] }] } },
      { type: 'Feature', properties: { identifier: 'PERM' } },
    ],
  };
  const [cbd, evt, wkd, perm] = zonesFromEd318(sc, fc, 0, h(48));
  assert.deepEqual(cbd.windows, [[h(10), h(12)], [h(34), h(36)]]);
  assert.equal(cbd.name, 'CBD');
  assert.equal(cbd.area.length, 1);
  assert.deepEqual(evt.windows, [[h(15), h(18)]]);
  assert.equal(evt.announced, h(14));
  assert.equal(evt.withdrawn, h(16.5));
  assert.equal(zoneState(evt, h(13)), 'unannounced');
  assert.equal(zoneState(evt, h(14.5)), 'idle');
  assert.equal(zoneState(evt, h(16)), 'active');
  assert.equal(zoneState(evt, h(17)), 'withdrawn');
  const ring = evt.area[0][0];
  assert.equal(ring.length, 73);
  const [dx, dy] = [(ring[18][0] - 103.8) * 111320 * Math.cos((1.3 * Math.PI) / 180), ring[0][1] - 1.3];
  assert.ok(Math.abs(dx - 1000) < 1 && Math.abs(dy * 110540 - 1000) < 1, 'a 1 km circle');
  // Weekend nights, overnight into the next day: Sunday 2026-01-04's reaches into Monday's
  // first two hours; then Saturday 10 and Sunday 11.
  assert.deepEqual(wkd.windows, [[0, h(2)]]);
  const [, , wkdWeek] = zonesFromEd318(sc, fc, 0, h(24 * 8));
  assert.deepEqual(wkdWeek.windows, [[0, h(2)], [h(5 * 24 + 22), h(6 * 24 + 2)], [h(6 * 24 + 22), h(7 * 24 + 2)]]);
  assert.deepEqual(perm.windows, [[0, h(48)]]);
});

test('requests that did not fly are decoded with their reason and found by the search', () => {
  const sc = decodeScene({
    t0: 0, span: 10000, offset_s: 0, nodes, edges, land: [], zones: [], summary: null, live: false,
    flights: [twoLegs, { ...twoLegs, id: 'R100' }],
    unflown: [['r10', 0, 2, 50, 0], ['x-r1', 1, 0, 60, 1], ['r2', 0, 1, 70, 0]],
    reasons: [{ status: 'rejected', reason: 'no_feasible_plan' }, { status: 'cancelled', reason: 'zone_announced', zone: 'EVT', at: 3600000 }],
  });
  assert.deepEqual(sc.unflown.get('x-r1'), { id: 'x-r1', o: 1, d: 0, dep: 60, status: 'cancelled', reason: 'zone_announced', zone: 'EVT', at: 3600000 });
  assert.equal(reasonText(sc, sc.unflown.get('r10')), 'traffic and no-fly zones leave no plan');
  assert.equal(reasonText(sc, sc.unflown.get('x-r1')), 'zone EVT, announced at 01:00:00, left it no plan before take-off');
  assert.equal(reasonText(sc, { reason: 'cancelled_by_operator' }), 'its operator cancelled it before take-off');
  assert.equal(reasonText(sc, { reason: 'something_new' }), 'something new');
  // Case aside; the id's own case first; those starting with the text, then the shorter.
  assert.deepEqual(findRequests(sc, ' R1 '), { exact: 'r1', matches: ['r1', 'r10', 'R100', 'x-r1'], total: 4 });
  assert.deepEqual(findRequests(sc, 'r100'), { exact: 'R100', matches: ['R100'], total: 1 });
  assert.equal(findRequests(sc, 'R1', 2).matches.length, 2);
  assert.equal(findRequests(sc, 'R1', 2).total, 4);
  assert.deepEqual(findRequests(sc, 'zz'), { exact: null, matches: [], total: 0 });
  assert.deepEqual(findRequests(sc, '  '), { exact: null, matches: [], total: 0 });
});

test('the address: time and selection written, and read back', () => {
  // t0 = 2026-01-05T00:00:00Z, 08:00 in Singapore.
  const sc = { t0: Date.UTC(2026, 0, 5), offset_s: 8 * 3600 };
  const h = 3600000;
  assert.equal(hashClock(sc, 2.25 * h + 1999), '10:15:01');
  assert.equal(hashClock(sc, 17 * h), '25:00:00', 'the next day counts on');
  assert.equal(formatHash(sc, 0.25 * h, 'r:42'), 't=08:15:00&f=r%3A42');
  assert.equal(formatHash(sc, null, 'r42'), 'f=r42');
  assert.equal(formatHash(sc, 0, null), 't=08:00:00');
  for (const t of [0, 1000, 2.25 * h, 17 * h, 40 * h]) {
    assert.equal(parseHash(sc, `#${formatHash(sc, t, 'a.b')}`).t, t);
  }
  assert.deepEqual(parseHash(sc, '#t=08:15:00&f=r%3A42'), { t: 0.25 * h, f: 'r:42' });
  assert.deepEqual(parseHash(sc, 't=10:30&flight=r3841'), { t: 2.5 * h, f: 'r3841' }, 'the older spelling');
  assert.deepEqual(parseHash(sc, ''), { t: null, f: null });
  assert.deepEqual(parseHash(sc, '#t=noon&f='), { t: null, f: null });
});

test('zone windows are dated, and clipped ends said so', () => {
  // t0 = Monday 2026-01-05 08:00 local (+08:00).
  const sc = { t0: Date.parse('2026-01-05T08:00:00+08:00'), offset_s: 8 * 3600 };
  const h = 3600000;
  assert.equal(localDay(sc, 0), 'Mon 5 Jan');
  assert.equal(localDay(sc, 16 * h), 'Tue 6 Jan');
  assert.equal(windowText(sc, [2 * h, 4 * h], 0, 24 * h), 'Mon 5 Jan 10:00–12:00');
  assert.equal(windowText(sc, [14 * h, 18 * h], 0, 24 * h), 'Mon 5 Jan 22:00 – Tue 6 Jan 02:00');
  assert.equal(windowText(sc, [0, 2 * h], 0, 24 * h), 'until Mon 5 Jan 10:00');
  assert.equal(windowText(sc, [20 * h, 24 * h], 0, 24 * h), 'from Tue 6 Jan 04:00');
  assert.equal(windowText(sc, [0, 24 * h], 0, 24 * h), 'all the time shown');
});

test('a rejected or cancelled answer of the service, and what zones close', () => {
  const sc = decodeScene({ t0: Date.parse('2026-01-05T00:00:00Z'), span: 1, offset_s: 0, nodes, edges, land: [], zones: [], flights: [], summary: null, live: true });
  const index = new Map(nodes.map((n, i) => [n.id, i]));
  const base = { request: 'q', origin: 'A', destination: 'C', requested_departure: '2026-01-05T08:00:00.000+08:00' };
  assert.deepEqual(unflownFromApi(sc, index, { ...base, status: 'rejected', reason: 'out_of_range' }),
    { id: 'q', o: 0, d: 2, dep: 0, status: 'rejected', reason: 'out_of_range' });
  assert.deepEqual(unflownFromApi(sc, index, {
    ...base, status: 'cancelled', reason: 'zone_announced',
    changes: [{ zone: 'EVT', announced: '2026-01-05T07:30:00.000+08:00', airborne: false, outcome: 'cancelled' }],
  }), { id: 'q', o: 0, d: 2, dep: 0, status: 'cancelled', reason: 'zone_announced', zone: 'EVT', at: -1800000 });
  assert.equal(unflownFromApi(sc, index, { ...base, status: 'cancelled', reason: 'cancelled_by_operator', cancelled_at: '2026-01-05T08:00:01.000+08:00' }).at, 1000);
  assert.equal(unflownFromApi(sc, index, { ...base, status: 'planned' }), null);
  const closures = closuresFromApi(sc, index, { zones: [
    { zone: 'Z1', nodes: ['B'], corridors: [{ id: 'C-B', from: 'C', to: 'B' }] },
    { zone: 'Z2', nodes: [], corridors: [] },
  ] });
  assert.deepEqual(closures.get('Z1'), { nodes: [1], edges: [1] });
  assert.deepEqual(closures.get('Z2'), { nodes: [], edges: [] });
  assert.throws(() => closuresFromApi(sc, index, { zones: [{ zone: 'Z3', nodes: [], corridors: [{ id: 'A-C', from: 'A', to: 'C' }] }] }), /zone Z3: unknown corridor A-C/);
  assert.throws(() => closuresFromApi(sc, index, { zones: [{ zone: 'Z4', nodes: ['Q'], corridors: [] }] }), /zone Z4: unknown node Q/);
});

// Colour vision: each sRGB colour seen with deuteranopia and protanopia, simulated with the
// full-severity matrices of Machado, Oliveira and Fernandes (2009) on linear RGB, and
// compared in CIELAB (D65).
const SIMULATIONS = {
  normal: [[1, 0, 0], [0, 1, 0], [0, 0, 1]],
  deuteranopia: [[0.367322, 0.860646, -0.227968], [0.280085, 0.672501, 0.047413], [-0.011820, 0.042940, 0.968881]],
  protanopia: [[0.152286, 1.052583, -0.204868], [0.114503, 0.786281, 0.099216], [-0.003882, -0.048116, 1.051998]],
};

function seenAs(matrix, rgb) {
  const lin = rgb.map((c) => { const v = c / 255; return v <= 0.04045 ? v / 12.92 : ((v + 0.055) / 1.055) ** 2.4; });
  const [r, g, b] = matrix.map((row) => Math.min(1, Math.max(0, row[0] * lin[0] + row[1] * lin[1] + row[2] * lin[2])));
  const [x, y, z] = [
    (0.4124 * r + 0.3576 * g + 0.1805 * b) / 0.95047,
    0.2126 * r + 0.7152 * g + 0.0722 * b,
    (0.0193 * r + 0.1192 * g + 0.9505 * b) / 1.08883,
  ];
  const f = (t) => (t > 216 / 24389 ? Math.cbrt(t) : ((24389 / 27) * t + 16) / 116);
  return [116 * f(y) - 16, 500 * (f(x) - f(y)), 200 * (f(y) - f(z))];
}

const distance = (p, q) => Math.hypot(p[0] - q[0], p[1] - q[1], p[2] - q[2]);
const hex = (css) => [1, 3, 5].map((i) => parseInt(css.slice(i, i + 2), 16));

test('the load scale keeps its order and the other styles stand apart, with any colour vision', () => {
  for (const [vision, m] of Object.entries(SIMULATIONS)) {
    const ramp = Array.from({ length: 11 }, (_, i) => seenAs(m, loadRgb(i / 10)));
    ramp.slice(1).forEach((c, i) => {
      assert.ok(c[0] < ramp[i][0] - 4, `${vision}: lightness falls along the scale (${i / 10}: ${ramp[i][0]}, then ${c[0]})`);
      assert.ok(distance(c, ramp[i]) > 7, `${vision}: steps of a tenth are told apart (${i / 10})`);
    });
    const fine = Array.from({ length: 101 }, (_, i) => seenAs(m, loadRgb(i / 100)));
    // Drawn as lines like the corridors: far from every colour of the scale.
    for (const name of ['closed', 'selected', 'selectedCasing', 'unused']) {
      const c = seenAs(m, hex(COLOURS[name]));
      const nearest = Math.min(...fine.map((r) => distance(c, r)));
      assert.ok(nearest > 25, `${vision}: ${name} is ${nearest.toFixed(1)} from the load scale`);
    }
    const styles = ['zone', 'closed', 'selected', 'drone', 'hover'];
    for (const a of styles) {
      for (const b of styles.filter((s) => s > a)) {
        const d = distance(seenAs(m, hex(COLOURS[a])), seenAs(m, hex(COLOURS[b])));
        assert.ok(d > 20, `${vision}: ${a} and ${b} are ${d.toFixed(1)} apart`);
      }
    }
  }
  assert.equal(loadColour(0), `rgb(${LOAD_STOPS[0].join(',')})`);
  assert.equal(loadColour(1), `rgb(${LOAD_STOPS[LOAD_STOPS.length - 1].join(',')})`);
});

test('the load key: where a corridor sits on the scale, and the values labelled', () => {
  assert.equal(loadPosition(0, 10), null, 'no flight: drawn as unused');
  assert.equal(loadPosition(1, 10), 0);
  assert.equal(loadPosition(10, 10), 1);
  assert.equal(loadPosition(4, 7), 0.5);
  assert.equal(loadPosition(1, 1), 1);
  assert.deepEqual(loadTicks(0), []);
  assert.deepEqual(loadTicks(1), [1]);
  assert.deepEqual(loadTicks(3), [1, 2, 3]);
  assert.deepEqual(loadTicks(37), [1, 10, 20, 30, 37]);
  assert.deepEqual(loadTicks(81), [1, 20, 40, 60, 81]);
  for (let max = 1; max < 3000; max += 7) {
    const t = loadTicks(max);
    assert.equal(t[0], 1);
    assert.equal(t[t.length - 1], max);
    assert.ok(t.length <= 7, `${max}: ${t}`);
    assert.ok(t.every((v, i) => i === 0 || v > t[i - 1]) && t.every(Number.isInteger), `${max}: ${t}`);
  }
});

// A layered day as the Rust scene gives it (muse-view's scene tests use the same flight):
// three layers 60 m, 69.144 m and 78.288 m apart; A up to layer 3, along to C, down at C, a
// swap at C, and back to B at layer 1.
const layers = { altitudes_m: [60, 69.144, 78.288], heading_rule: 'sectors', ways: [[1, 3], [0, 3], [2, 0]] };
const climbing = {
  id: 'c1', o: 0, d: 1, dep: 0, ff: 1000, status: 'planned',
  s: [0, 0, 3658, 1, 123658, 123658, 2, 243658, 247316, 2, 547316, 547316, 1, 667316, 667316],
  z: [0, 1, 1829, 2, 3658, 3, 243658, 3, 245487, 2, 247316, 1, 667316, 1],
};

test('a layered flight: its layer over time, fractional while it climbs, and which layer shows it', () => {
  const f = decodeFlight(climbing);
  assert.equal(f.legs.length, 2, 'the climb at A is one stay from above; the swap at C splits');
  assert.deepEqual(f.z.slice(0, 3), [[0, 1], [1829, 2], [3658, 3]]);
  assert.equal(layerAt(f, 0), 1);
  assert.equal(layerAt(f, 914.5), 1.5, 'half way up the first vertical link');
  assert.equal(layerAt(f, 100000), 3);
  assert.equal(layerAt(f, 246401.5), 1.5, 'half way down the last');
  assert.equal(layerAt(f, 400000), 1, 'on the ground at the swap: layer 1');
  assert.equal(layerAt(f, 1e9), 1);
  assert.equal(layerAt(decodeFlight(twoLegs), 50), 1, 'flat: always layer 1');
  assert.ok(onLayer(f, 914.5, 1) && onLayer(f, 914.5, 2) && !onLayer(f, 914.5, 3), 'climbing: both layers');
  assert.ok(onLayer(f, 100000, 3) && !onLayer(f, 100000, 2) && onLayer(f, 100000, null));
  // The oracle: layerAt by brute force over the stays' layers, at every 97 ms.
  const stays = [[0, 1, 0, 0], [0, 2, 1829, 1829], [0, 3, 3658, 3658], [1, 3, 123658, 123658],
    [2, 3, 243658, 243658], [2, 2, 245487, 245487], [2, 1, 247316, 247316], [2, 1, 547316, 547316], [1, 1, 667316, 667316]];
  for (let t = 0; t < 667316; t += 97) {
    let i = 0;
    while (i + 1 < stays.length && stays[i + 1][2] <= t) i++;
    const [n, k, , dep] = stays[i];
    const next = stays[i + 1];
    const want = t <= dep || next[0] !== n ? k : k + ((next[1] - k) * (t - dep)) / (next[2] - dep);
    assert.ok(Math.abs(layerAt(f, t) - want) < 1e-9, `${t}: ${layerAt(f, t)} against ${want}`);
  }
});

test('the profile is kept short as it is built, and the API\'s layered stays give the scene\'s flight', () => {
  const z = [];
  for (const [t, k] of [[0, 1], [0, 1], [10, 1], [20, 1], [30, 2], [40, 2], [50, 2]]) pushLayerPoint(z, t, k);
  assert.deepEqual(z, [0, 1, 20, 1, 30, 2, 50, 2]);
  const sc = decodeScene({ t0: Date.parse('2026-01-05T00:00:00Z'), span: 1, offset_s: 0, nodes, edges, layers, land: [], zones: [], flights: [], summary: null, live: true });
  const index = new Map(nodes.map((n, i) => [n.id, i]));
  const at = (ms) => new Date(sc.t0 + ms).toISOString();
  const path = [['A', 1, 0], ['A', 2, 1829], ['A', 3, 3658], ['B', 3, 123658], ['C', 3, 243658], ['C', 2, 245487],
    ['C', 1, 247316], ['C', 1, 547316], ['B', 1, 667316]].map(([node, layer, t]) => ({ node, layer, arrive: at(t), depart: at(t) }));
  const raw = flightFromApi(sc, index, {
    request: 'c1', origin: 'A', destination: 'B', requested_departure: at(0), free_flow_s: 1, status: 'planned', path,
  });
  assert.deepEqual(raw.s, climbing.s);
  assert.deepEqual(raw.z, climbing.z);
  const flat = flightFromApi(sc, index, { request: 'f', origin: 'A', destination: 'B', requested_departure: at(0), status: 'planned', path: path.map(({ layer, ...st }) => st) });
  assert.equal(flat.z, undefined, 'a flat answer has no profile');
  const closures = closuresFromApi(sc, index, { zones: [{ zone: 'LOW', nodes: ['B'], corridors: [{ id: 'A-B', from: 'A', to: 'B' }], layers: [1, 2], vertical_links: [] }] });
  assert.deepEqual(closures.get('LOW'), { nodes: [1], edges: [0], layers: [1, 2] });
});

test('one layer alone: its corridors and their ways, its load, its closures; the side view', () => {
  const sc = scene([climbing], { layers });
  assert.deepEqual([0, 1].map((e) => corridorWays(sc, e, null)), [3, 3], 'every layer: drawn both ways');
  assert.deepEqual([1, 2, 3].map((k) => [0, 1].map((e) => corridorWays(sc, e, k))), [[1, 3], [0, 3], [2, 0]]);
  assert.deepEqual(edgeLoad(sc), [1, 2], 'A→B on A-B; B→C and C→B on B-C');
  assert.deepEqual(edgeLoad(sc, -Infinity, Infinity, 3), [1, 1], 'at layer 3: A→B and B→C');
  assert.deepEqual(edgeLoad(sc, -Infinity, Infinity, 1), [0, 1], 'at layer 1: C→B after the swap');
  assert.deepEqual(edgeLoad(sc, -Infinity, Infinity, 2), [0, 0]);
  const z = { nodes: [1], edges: [0, 1], layers: [2, 3] };
  assert.deepEqual(zoneClosesAt(sc, z, null), { nodes: [1], edges: [0, 1] });
  assert.deepEqual(zoneClosesAt(sc, z, 1), { nodes: [], edges: [] }, 'outside its band');
  assert.deepEqual(zoneClosesAt(sc, z, 2), { nodes: [1], edges: [1] }, 'A-B is not flown at layer 2');
  assert.deepEqual(zoneClosesAt(sc, z, 3), { nodes: [1], edges: [0] });
  const f = sc.byId.get('c1');
  assert.equal(altitudeOf(sc, 1), 60);
  assert.ok(Math.abs(altitudeOf(sc, 2.5) - 73.716) < 1e-9);
  assert.equal(altitudeOf(sc, 3), 78.288);
  const p = altitudeProfile(sc, f);
  assert.deepEqual(p.legs.map((leg) => leg.map(([t]) => t)), [[0, 1829, 3658, 243658, 245487, 247316], [547316, 667316]]);
  assert.deepEqual(p.legs[0].map(([, m]) => m), [60, 69.144, 78.288, 78.288, 69.144, 60]);
  assert.deepEqual([p.from, p.to], [0, 667316]);
  assert.equal(altitudeProfile(scene([twoLegs]), decodeFlight(twoLegs)), null, 'flat: no side view');
  const rows = planDetails(sc, f).rows.filter((r) => !r.ground).map((r) => `${r.node} ${r.layers.join('→')}`);
  assert.deepEqual(rows, ['A 1→3', 'B 3→3', 'C 3→1', 'C 1→1', 'B 1→1']);
  const d = planDetails(sc, f);
  const stays = d.rows.filter((r) => !r.ground);
  assert.deepEqual(stays.map((r) => [r.climb, r.hover]), [[3658, 0], [0, 0], [3658, 0], [0, 0], [0, 0]], 'climbing is not hovering');
  assert.deepEqual([d.climb, d.hover], [7316, 0]);
  const rawWaits = { ...climbing, id: 'w', s: [0, 0, 5658, 1, 123658, 123658], z: [0, 1, 1000, 1, 2829, 2, 3829, 2, 5658, 3, 123658, 3] };
  const waits = decodeFlight(rawWaits);
  const w = planDetails(scene([rawWaits], { layers }), waits);
  assert.deepEqual([w.climb, w.hover, w.rows[0].hover], [3658, 2000, 2000], 'a second at layer 1 and one at layer 2');
  assert.equal(climbingWithin(waits, 2000, 3000), 829);
});

test('the layer scale keeps its order and its steps apart, with any colour vision', () => {
  for (const [vision, m] of Object.entries(SIMULATIONS)) {
    for (const count of [2, 4, 8]) {
      const ramp = Array.from({ length: count }, (_, i) => seenAs(m, layerRgb(i + 1, count)));
      ramp.slice(1).forEach((c, i) => {
        assert.ok(c[0] < ramp[i][0] - 6, `${vision}, ${count} layers: lightness falls from layer ${i + 1} (${ramp[i][0]}, then ${c[0]})`);
        assert.ok(distance(c, ramp[i]) > 10, `${vision}, ${count} layers: layers ${i + 1} and ${i + 2} told apart`);
      });
    }
    const rim = seenAs(m, hex(COLOURS.layerRim));
    const lightest = seenAs(m, layerRgb(1, 8));
    assert.ok(distance(rim, lightest) > 60, `${vision}: the rim stands out from the lightest layer`);
  }
  assert.deepEqual(layerRgb(1, 4), LAYER_STOPS[0]);
  assert.deepEqual(layerRgb(4, 4), LAYER_STOPS[LAYER_STOPS.length - 1]);
  assert.equal(layerColour(9, 8), layerColour(8, 8), 'clamped');
});

test('at a node, a layered drone climbing or descending is not hovering', () => {
  const f = decodeFlight(climbing);
  const up = positionAt(f, 914.5, nodes);
  assert.deepEqual([up.node, up.hovering, up.vertical], [0, false, 1]);
  const down = positionAt(f, 246401.5, nodes);
  assert.deepEqual([down.node, down.hovering, down.vertical], [2, false, -1]);
  const waits = decodeFlight({ ...climbing, s: [0, 0, 5658, 1, 123658, 123658], z: [0, 1, 1000, 1, 2829, 2, 3829, 2, 5658, 3, 123658, 3] });
  assert.deepEqual([positionAt(waits, 500, nodes).hovering, positionAt(waits, 3000, nodes).hovering], [true, true], 'waiting at layers 1 and 2');
  assert.equal(positionAt(waits, 2000, nodes).hovering, false);
  assert.equal(positionAt(decodeFlight(twoLegs), 502, nodes).vertical, 0, 'flat: never vertical');
});
