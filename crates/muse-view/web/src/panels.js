// The side panel: the day's summary, the no-fly zones with their dated windows, the search
// for a request, and the selected request — a flight's plan, or why a request did not fly.

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
    const o = s.optimizer;
    if (o) {
      rows.push(['planned by FCFS', `${o.fcfs.planned}, delay ${secs(o.fcfs.mean_delay_s)}`]);
      rows.push(['planned, optimised', `${o.optimized.planned}, delay ${secs(o.optimized.mean_delay_s)}`]);
      rows.push(['displaced by the optimiser', o.displaced]);
      rows.push(['optimiser', `${o.iterations} steps, ${o.time_s.toFixed(1)} s`]);
    }
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
    if (scene.unflown.size) rows.push(['requests that did not fly', scene.unflown.size]);
  }
  if (scene.layers) {
    const alts = scene.layers.altitudes_m;
    rows.push(['layers', `${alts.length}, ${Math.round(alts[0])}–${Math.round(alts[alts.length - 1])} m`]);
    rows.push(['heading rule', scene.layers.heading_rule]);
  }
  rows.push(['stations', scene.nodes.filter((n) => n.station).length]);
  rows.push(['corridors', scene.edges.length]);
  dl.innerHTML = rows.map(([k, v]) => `<dt>${esc(k)}</dt><dd>${esc(v)}</dd>`).join('');
  showZones();
}

/** The zones, each with its windows within the time shown, dated. */
function showZones() {
  const at = (t) => `${localDay(scene, t)} ${clock(scene, t).slice(0, 5)}`;
  $('zones').innerHTML = scene.zones.map((z) => {
    const windows = z.windows.filter(([a, b]) => b > 0 && a < scene.span);
    const when = windows.map((w) => windowText(scene, w, 0, scene.span)).join('; ') || 'not active in the time shown';
    const ann = z.announced !== undefined && z.announced !== null ? `; announced ${at(z.announced)}` : '';
    const gone = z.withdrawn !== undefined && z.withdrawn !== null ? `; withdrawn ${at(z.withdrawn)}` : '';
    return `<li><b>${esc(z.id)}</b> ${esc(z.name)}<br>active ${esc(when)}${esc(ann)}${esc(gone)}</li>`;
  }).join('') || '<li class="hint">none</li>';
}

function rowsHtml(rows) {
  return `<dl>${rows.map(([k, v]) => `<dt>${esc(k)}</dt><dd>${esc(v)}</dd>`).join('')}</dl>`;
}

/** A pad's id, or what stands for none (an unserved request's customer with no pad in reach). */
function padName(n) {
  return n === null || n === undefined ? 'no pad in reach' : scene.nodes[n].id;
}

function showDetails() {
  const box = $('details');
  const id = state.selected;
  const f = id !== null ? scene.byId.get(id) : undefined;
  const u = id !== null ? scene.unflown.get(id) : undefined;
  const c = (t) => clock(scene, t);
  if (u && !f) {
    box.innerHTML = `<div class="flight-id">${esc(u.id)}</div>
      <p class="reason"><b>${esc(u.status)}</b>: ${esc(reasonText(scene, u))} (<code>${esc(u.reason)}</code>).</p>
      ${rowsHtml([['route', `${padName(u.o)} → ${padName(u.d)}`], ['requested', c(u.dep)]])}`;
    return;
  }
  if (!f) {
    box.innerHTML = '<p class="hint">Click a drone on the map, or find a request by its id.</p>';
    return;
  }
  const d = planDetails(scene, f);
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
  if (scene.layers) head.push(['climbing and descending', duration(d.climb)]);
  // A layered airspace: each stay's layer (`1→3` for a climb there), and the side view.
  const layered = Boolean(scene.layers);
  const layerCell = (r) => {
    if (!layered) return '';
    const [a, b] = r.layers;
    return `<td class="num">${a === b ? a : `${a}→${b}`}</td>`;
  };
  const rows = d.rows.map((r) => (r.ground
    ? `<tr class="ground"><td colspan="${layered ? 3 : 2}">on the ground at ${esc(r.node)} (battery swap)</td><td>${c(r.from)}</td><td class="num">${duration(r.to - r.from)}</td></tr>`
    : `<tr><td>${esc(r.node)}</td>${layerCell(r)}<td>${c(r.arrive)}</td><td>${c(r.depart)}</td><td class="num">${r.hover > 0 ? duration(r.hover) : ''}</td></tr>`)).join('');
  const side = layered
    ? '<h3 class="profile-title">Altitude over time <span class="hint">(click to move the clock)</span></h3><canvas id="profile" aria-label="The flight\'s altitude over time"></canvas>'
    : '';
  box.innerHTML = `<div class="flight-id">${esc(d.id)}</div>${rowsHtml(head)}${side}
    <table><thead><tr><th>node</th>${layered ? '<th class="num">layer</th>' : ''}<th>arrive</th><th>depart</th><th class="num">hover</th></tr></thead><tbody>${rows}</tbody></table>`;
  if (layered) drawProfile();
}

// ---- the search ------------------------------------------------------------------------

/** Lists `ids` under the search box as buttons (none: the list is emptied). */
function showSuggestions(ids, total) {
  const more = total > ids.length ? `<li class="hint">and ${total - ids.length} more</li>` : '';
  $('find-list').innerHTML = ids.map((id) => {
    const u = scene.unflown.get(id);
    const note = u && !scene.byId.has(id) ? ` <span class="hint">${esc(u.status)}</span>` : '';
    return `<li><button type="button" data-id="${esc(id)}">${esc(id)}</button>${note}</li>`;
  }).join('') + more;
}

/** After a search for `text` found no request of that id: says so, with the near ids. */
function showFindResult(text) {
  const { matches, total } = findRequests(scene, text);
  $('find-message').textContent = matches.length
    ? `No request ${text}. Ids containing it:`
    : `No request ${text}, nor any id containing it.`;
  showSuggestions(matches, total);
}

/** While typing: the ids containing the text, as suggestions. */
function suggest() {
  const text = $('find').value;
  $('find-message').textContent = '';
  if (text.trim() === '') {
    showSuggestions([], 0);
    return;
  }
  const { matches, total } = findRequests(scene, text);
  showSuggestions(matches, total);
}

/** Shows request `text` from the search box, or says why not. */
async function find(text) {
  const id = text.trim();
  $('find-message').textContent = '';
  showSuggestions([], 0);
  if (id === '') return;
  if (!await show(id)) showFindResult(id);
}
