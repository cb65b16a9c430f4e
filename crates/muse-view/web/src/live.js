// The live view of `muse serve`: the flights come from the service's events stream
// (`GET /v1/events` from id 0: every event the service holds, then each new one as it is
// made durable), and the clock follows the service's. Inlined after viewer.js; it does
// nothing on a page written by `muse simulate` or `muse view`.
//
// A token (`?token=…` in the page's address) is sent as `Authorization: Bearer`: an
// authority sees every flight, an operator its own. The decoding is in feed.js.

function startLive() {
  if (!scene.live) return;
  const token = new URLSearchParams(window.location.search).get('token');
  const auth = token ? { Authorization: `Bearer ${token}` } : {};
  const nodeIndex = new Map(scene.nodes.map((n, i) => [n.id, i]));
  const recent = [];
  let offset = 0; // the service's clock minus this machine's
  let following = true;
  let connected = false;
  let resync = null; // a pending refresh of the service's figures after events

  $('live').hidden = false;
  $('now').hidden = false;
  $('speed').value = '1';
  state.speed = 1;

  const status = (text) => { $('status').textContent = text; };
  const plural = (n, word) => `${n} ${word}${n === 1 ? '' : 's'}`;
  const now = () => Date.now() + offset - scene.t0;

  function showEvents() {
    $('events').innerHTML = recent.map((e) => `<li><button type="button" data-id="${esc(e.flight)}">${esc(e.flight)}</button> ${esc(e.kind)}${e.zone ? ` (zone ${esc(e.zone)})` : ''}</li>`).join('');
  }

  function onEvent(kind, data) {
    let d;
    try { d = JSON.parse(data); } catch (e) { console.warn('bad event data', e); return; }
    if (kind === 'cancelled' || !d.plan) {
      removeFlight(scene, d.flight);
    } else {
      const raw = flightFromApi(scene, nodeIndex, { ...d.plan, operator: d.operator });
      if (raw) {
        const f = addFlight(scene, raw);
        if (f.landing > scene.span) {
          scene.span = f.landing + HOUR;
          $('slider').max = String(Math.ceil(scene.span / 1000));
        }
      } else {
        removeFlight(scene, d.flight);
      }
    }
    if (d.zone && !scene.zones.some((z) => z.id === d.zone)) syncZones();
    recent.unshift({ flight: d.flight, kind, zone: d.zone });
    if (recent.length > 30) recent.pop();
    showEvents();
    museView.redraw();
    museView.events += 1;
    if (state.selected === d.flight) select(scene.byId.has(d.flight) ? d.flight : null);
    $('flights-count').textContent = plural(scene.flights.length, 'flight');
    showSummary();
    if (!resync) resync = setTimeout(() => { resync = null; syncClock(); }, 500);
  }

  async function syncClock() {
    try {
      const h = await (await fetch('/healthz', { headers: auth })).json();
      offset = Date.parse(h.now) - Date.now();
      $('service').textContent = `${h.airspace} · ${plural(h.flights, 'flight')} held`;
    } catch (e) {
      status('service unreachable');
    }
  }

  async function stream() {
    let lastId = '0';
    for (;;) {
      try {
        const res = await fetch('/v1/events', { headers: { ...auth, 'Last-Event-ID': lastId } });
        if (res.status === 401 || res.status === 403) {
          status(`not allowed (${res.status}): open this page as /?token=YOUR_TOKEN`);
          return;
        }
        if (!res.ok) throw new Error(`events: HTTP ${res.status}`);
        connected = true;
        status('live');
        museView.connected = true;
        lastId = await readEvents(res.body, onEvent, lastId);
      } catch (e) {
        console.warn('events stream interrupted; reconnecting', e);
      }
      connected = false;
      museView.connected = false;
      status('reconnecting…');
      await new Promise((r) => { setTimeout(r, 2000); });
    }
  }

  // Zones: every zone the service knows (`GET /v1/zones`, ED-318 with the MUSE `announced`
  // and `withdrawn` instants), resolved here over a wide stretch of days, so that zones
  // announced (or withdrawn) while the page is open appear (or go). The corridors a zone
  // closes are known for the zones of the start only (worked out by `muse serve`).
  const closedBy = new Map(scene.zones.map((z) => [z.id, z]));
  async function syncZones() {
    try {
      const fc = await (await fetch('/v1/zones', { headers: auth })).json();
      scene.zones = zonesFromEd318(scene, fc, -7 * DAY, scene.span + 7 * DAY).map((z) => {
        const known = closedBy.get(z.id);
        return known ? { ...z, nodes: known.nodes, edges: known.edges } : z;
      });
      showSummary();
      museView.redraw();
      museView.zonesSynced += 1;
    } catch (e) {
      console.warn('zones unavailable', e);
    }
  }
  museView.zonesSynced = 0;

  $('events').addEventListener('click', (e) => {
    const id = e.target instanceof HTMLElement ? e.target.dataset.id : undefined;
    if (id) select(id);
  });
  $('now').addEventListener('click', () => { following = true; setPlaying(true); });
  $('slider').addEventListener('input', () => { following = false; });
  museView.follow = (on) => { following = on; };
  museView.events = 0;

  // Follow the service's clock, at real speed, until the user scrubs.
  setInterval(() => {
    // A service runs for days: the day shown grows with its clock.
    if (now() > scene.span) {
      scene.span = now() + HOUR;
      $('slider').max = String(Math.ceil(scene.span / 1000));
    }
    if (following && connected) { setT(now()); }
  }, 250);
  setInterval(syncClock, 10000);
  setInterval(syncZones, 5000);
  syncZones();
  syncClock().then(() => { setT(now()); setPlaying(true); });
  stream();
}

startLive();
