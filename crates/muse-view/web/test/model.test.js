// The viewer's logic against simple oracles: `npm test` (node's own test runner, no
// dependencies). The Rust test `muse-view/tests/web.rs` runs it under `cargo test`.

import { test } from 'node:test';
import assert from 'node:assert/strict';

import {
  decodeScene, decodeFlight, legAt, isAirborne, airborneAt, positionAt, edgeLoad,
  zoneState, clock, duration, parseClock, planDetails, addFlight, removeFlight,
} from '../src/model.js';
import { flightFromApi, readEvents, zonesFromEd318 } from '../src/feed.js';

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
