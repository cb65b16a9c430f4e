// The live view of `muse serve`: the flights come from the service's events stream
// (`GET /v1/events` from id 0: every event the service holds, then each new one as it is
// made durable), the zones from `GET /v1/zones` and what they close from `GET
// /v1/closures`, and the clock follows the service's. A search for a request the page has
// not seen asks `GET /v1/flights/{id}` (a rejected request makes no event). Inlined last; it
// does nothing on a page written by `muse simulate` or `muse view`.
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
  let clockKnown = false; // `offset` has been read from the service
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
      const u = d.plan ? unflownFromApi(scene, nodeIndex, d.plan) : null;
      if (u) addUnflown(scene, u);
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
    if (state.selected === d.flight || state.pending === d.flight) select(d.flight);
    $('flights-count').textContent = plural(scene.flights.length, 'flight');
    showSummary();
    if (!resync) resync = setTimeout(() => { resync = null; syncClock(); }, 500);
  }

  async function syncClock() {
    try {
      const h = await (await fetch('/healthz', { headers: auth })).json();
      offset = Date.parse(h.now) - Date.now();
      clockKnown = true;
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
  // and `withdrawn` instants), their windows within the time the page shows, so that zones
  // announced (or withdrawn) while the page is open appear (or go); and what each closes
  // (`GET /v1/closures`, asked again whenever a zone the page has not seen appears).
  let closures = new Map(scene.zones.map((z) => [z.id, { nodes: z.nodes, edges: z.edges, layers: z.layers }]));
  async function syncZones() {
    try {
      const fc = await (await fetch('/v1/zones', { headers: auth })).json();
      const zones = zonesFromEd318(scene, fc, 0, scene.span);
      if (zones.some((z) => !closures.has(z.id))) {
        const res = await fetch('/v1/closures', { headers: auth });
        if (!res.ok) throw new Error(`closures: HTTP ${res.status}`);
        closures = closuresFromApi(scene, nodeIndex, await res.json());
      }
      scene.zones = zones.map((z) => ({ ...z, ...(closures.get(z.id) ?? { nodes: [], edges: [] }) }));
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
  $('now').addEventListener('click', () => { state.following = true; setPlaying(true); });
  museView.follow = (on) => { state.following = on; };
  museView.events = 0;

  // A request the page has not seen (rejected ones make no event): ask the service for every
  // request rejected within the time shown (so that an id typed in another case, or in part,
  // is found too), then for that id.
  const planOf = (plan) => {
    const raw = flightFromApi(scene, nodeIndex, plan);
    if (raw) {
      addFlight(scene, raw);
      return true;
    }
    const u = unflownFromApi(scene, nodeIndex, plan);
    if (u) addUnflown(scene, u);
    return Boolean(u);
  };
  async function loadRejected() {
    const iso = (t) => new Date(scene.t0 + t).toISOString();
    let after = null;
    do {
      const q = new URLSearchParams({ status: 'rejected', from: iso(0), to: iso(scene.span), limit: '2000' });
      if (after !== null) q.set('after', after);
      const res = await fetch(`/v1/flights?${q}`, { headers: auth });
      if (!res.ok) throw new Error(`rejected requests: HTTP ${res.status}`);
      const page = await res.json();
      for (const plan of page.flights) planOf(plan);
      after = page.next_after;
    } while (after !== null && after !== undefined);
  }
  state.lookup = async (id) => {
    try {
      await loadRejected();
      let found = findRequests(scene, id).exact !== null;
      if (!found) {
        const res = await fetch(`/v1/flights/${encodeURIComponent(id)}`, { headers: auth });
        // Not found (404), or not an id the service takes (400): none.
        found = res.ok && planOf(await res.json());
      }
      museView.redraw();
      return found;
    } catch (e) {
      console.warn(`looking up ${id}`, e);
      return false;
    }
  };

  // Follow the service's clock, at real speed, until the user scrubs.
  setInterval(() => {
    // Nothing to follow before the service has said what time it is.
    if (!clockKnown) return;
    // A service runs for days: the day shown grows with its clock.
    if (now() > scene.span) {
      scene.span = now() + HOUR;
      $('slider').max = String(Math.ceil(scene.span / 1000));
    }
    if (state.following && connected) { setT(now()); }
  }, 250);
  setInterval(syncClock, 10000);
  setInterval(syncZones, 5000);
  syncZones();
  syncClock().then(() => {
    if (!state.following) return;
    setT(now());
    setPlaying(true);
  });
  stream();
}

startLive();
