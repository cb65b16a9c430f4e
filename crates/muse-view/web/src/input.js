// Input: the controls, the keys, the search box, and the map under a mouse, a pen or fingers
// (pointer events): drag or one finger to pan, the wheel or two fingers to zoom, a click or a
// tap to select, and a tooltip on what the mouse is over — a drone, a node or a corridor.

// How near a drone a click (or a tap) must be, CSS px.
const PICK_PX = 10;
const TAP_PX = 18;

function pick(x, y, radius) {
  let best = null;
  let bestD = radius * radius;
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

/** The corridor nearest `(x, y)` within 5 px, as its index, or null. */
function pickCorridor(x, y) {
  let best = null;
  let bestD = 5 * 5;
  scene.edges.forEach((_, i) => {
    const [[x1, y1], [x2, y2]] = segment(i);
    const [dx, dy] = [x2 - x1, y2 - y1];
    const len2 = dx * dx + dy * dy;
    const u = len2 > 0 ? Math.max(0, Math.min(1, ((x - x1) * dx + (y - y1) * dy) / len2)) : 0;
    const dd = (x1 + u * dx - x) ** 2 + (y1 + u * dy - y) ** 2;
    if (dd <= bestD) { best = i; bestD = dd; }
  });
  return best;
}

/** What the tooltip says about corridor `i`: its ends, its flights, whether it is closed. */
function corridorText(i) {
  const [a, b] = scene.edges[i];
  const flights = (n) => `${n} flight${n === 1 ? '' : 's'}`;
  const day = dayLoad()[i];
  let text = `${scene.nodes[a].id}–${scene.nodes[b].id}: ${flights(day)} in the whole day`;
  if (state.load === 'hour' && state.hourLoad.load) text += `, ${flights(state.hourLoad.load[i])} in the past hour`;
  if (state.closed.has(i)) {
    const zones = scene.zones.filter((z) => zoneState(z, state.t) === 'active' && z.edges.includes(i)).map((z) => z.id);
    text += `; closed now by ${zones.join(', ')}`;
  }
  return text;
}

/** The tooltip's text at canvas point `(x, y)`, or null. */
function tooltipAt(x, y) {
  const hit = pick(x, y, PICK_PX);
  if (hit) {
    const doing = { 1: ' (climbing)', '-1': ' (descending)' }[hit.vertical] ?? (hit.hovering ? ' (hovering)' : '');
    const layer = scene.layers ? `, layer ${Math.round(layerAt(scene.byId.get(hit.id), state.t))}` : '';
    return `${hit.id}${doing}${layer}`;
  }
  const station = pickStation(x, y);
  if (station) {
    const i = scene.nodes.indexOf(station);
    const closing = state.closedNodes.has(i)
      ? `; closed now by ${scene.zones.filter((z) => zoneState(z, state.t) === 'active' && z.nodes.includes(i)).map((z) => z.id).join(', ')}`
      : '';
    return `${station.id}${station.station ? '' : ' (waypoint)'}${closing}`;
  }
  const corridor = pickCorridor(x, y);
  return corridor === null ? null : corridorText(corridor);
}

function showTooltip(x, y) {
  const tip = $('tooltip');
  const text = tooltipAt(x, y);
  if (text === null) {
    tip.hidden = true;
    return;
  }
  tip.textContent = text;
  tip.hidden = false;
  // Keep it inside the map.
  const left = Math.min(x + 12, Math.max(0, state.width - tip.offsetWidth - 4));
  const top = y + 12 + tip.offsetHeight > state.height ? y - 12 - tip.offsetHeight : y + 12;
  tip.style.left = `${left}px`;
  tip.style.top = `${top}px`;
}

function localXY(ev) {
  const r = canvas.getBoundingClientRect();
  return [ev.clientX - r.left, ev.clientY - r.top];
}

/** Pan, pinch and select with pointer events: one pointer pans, two zoom about their middle. */
function wirePointers() {
  const down = new Map(); // pointerId → [x, y]
  let gesture = null; // { start: [x, y], view, moved, pinch: { d, mid } | null, radius }
  const restart = () => {
    const pts = [...down.values()];
    gesture = {
      start: pts[0], view: { ...state.view }, moved: gesture ? gesture.moved : false,
      radius: gesture ? gesture.radius : PICK_PX, pinch: null,
    };
    if (pts.length >= 2) {
      const [[x1, y1], [x2, y2]] = pts;
      gesture.pinch = { d: Math.max(1, Math.hypot(x2 - x1, y2 - y1)), mid: [(x1 + x2) / 2, (y1 + y2) / 2] };
    }
  };
  canvas.addEventListener('pointerdown', (e) => {
    if (e.pointerType === 'mouse' && e.button !== 0) return;
    canvas.setPointerCapture(e.pointerId);
    const first = down.size === 0;
    down.set(e.pointerId, localXY(e));
    if (first) gesture = null;
    restart();
    if (first) gesture.radius = e.pointerType === 'mouse' ? PICK_PX : TAP_PX;
  });
  canvas.addEventListener('pointermove', (e) => {
    const [x, y] = localXY(e);
    if (!down.has(e.pointerId)) {
      if (e.pointerType === 'mouse') showTooltip(x, y);
      return;
    }
    down.set(e.pointerId, [x, y]);
    const g = gesture;
    const v = g.view;
    if (g.pinch && down.size >= 2) {
      const [[x1, y1], [x2, y2]] = [...down.values()];
      const mid = [(x1 + x2) / 2, (y1 + y2) / 2];
      const scale = v.scale * (Math.hypot(x2 - x1, y2 - y1) / g.pinch.d);
      // The world point first under the fingers' middle stays under it.
      const wx = (g.pinch.mid[0] - state.width / 2) / v.scale + v.cx;
      const wy = (g.pinch.mid[1] - state.height / 2) / v.scale + v.cy;
      state.view = { scale, cx: wx - (mid[0] - state.width / 2) / scale, cy: wy - (mid[1] - state.height / 2) / scale };
      g.moved = true;
    } else {
      const [dx, dy] = [x - g.start[0], y - g.start[1]];
      if (Math.abs(dx) + Math.abs(dy) > 4) g.moved = true;
      if (!g.moved) return;
      state.view = { ...v, cx: v.cx - dx / v.scale, cy: v.cy - dy / v.scale };
    }
    canvas.classList.add('dragging');
    state.userView = true;
    state.dirty = true;
    $('tooltip').hidden = true;
  });
  const up = (e) => {
    if (!down.has(e.pointerId)) return;
    down.delete(e.pointerId);
    if (down.size > 0) {
      restart();
      return;
    }
    canvas.classList.remove('dragging');
    const g = gesture;
    gesture = null;
    if (e.type === 'pointercancel' || g.moved) return;
    const [x, y] = localXY(e);
    const hit = pick(x, y, g.radius);
    select(hit ? hit.id : null);
  };
  canvas.addEventListener('pointerup', up);
  canvas.addEventListener('pointercancel', up);
  canvas.addEventListener('pointerleave', (e) => { if (e.pointerType === 'mouse') $('tooltip').hidden = true; });
  canvas.addEventListener('wheel', (e) => {
    e.preventDefault();
    const [x, y] = localXY(e);
    zoomAt(x, y, Math.exp(-e.deltaY * 0.0015));
  }, { passive: false });
}

/**
 * A layered airspace: the layer picker (every layer, coloured, or one alone) and the layers'
 * colours in the legend. Hidden when flat.
 */
function wireLayers() {
  if (!scene.layers) return;
  const alts = scene.layers.altitudes_m;
  const pick = $('layer');
  pick.innerHTML = '<option value="all">all, by colour</option>'
    + alts.map((m, i) => `<option value="${i + 1}">${i + 1} only (${Math.round(m)} m)</option>`).join('');
  pick.addEventListener('change', (e) => { setLayer(e.target.value === 'all' ? null : Number(e.target.value)); });
  $('layer-pick').hidden = false;
  const rule = scene.layers.heading_rule === 'sectors' ? ', each flown in its own headings' : '';
  $('legend-layers').innerHTML = `<span class="key layers">${alts.map((_, i) => `<i style="background:${layerColour(i + 1, alts.length)}"></i>`).join('')}</span>`
    + `drone's layer, lowest (${Math.round(alts[0])} m) to highest (${Math.round(alts[alts.length - 1])} m)${esc(rule)}`;
  $('legend-layers').hidden = false;
  $('legend-drone').hidden = true;
  $('legend-one-way').hidden = scene.layers.heading_rule !== 'sectors';
}

function wire() {
  $('title').textContent = scene.title || 'MUSE';
  document.title = `MUSE — ${scene.title || 'viewer'}`;
  $('attribution').textContent = scene.attribution || '';
  const slider = $('slider');
  slider.max = String(Math.ceil(scene.span / 1000));
  slider.addEventListener('input', () => { state.following = false; setT(Number(slider.value) * 1000); });
  $('play').addEventListener('click', () => setPlaying(!state.playing));
  $('speed').addEventListener('change', (e) => { state.speed = Number(e.target.value); });
  $('load').addEventListener('change', (e) => { state.load = e.target.value; state.dirty = true; });
  wireLayers();
  $('details').addEventListener('click', profileClick);
  document.addEventListener('keydown', (e) => {
    if (e.target instanceof HTMLInputElement && e.target.id === 'find') return;
    if (e.code === 'Space') { e.preventDefault(); setPlaying(!state.playing); }
    if (e.key === 'r') resetView();
  });
  $('find-form').addEventListener('submit', (e) => {
    e.preventDefault();
    find($('find').value);
  });
  $('find').addEventListener('input', suggest);
  $('find-list').addEventListener('click', (e) => {
    const id = e.target instanceof HTMLElement ? e.target.dataset.id : undefined;
    if (id) {
      $('find').value = id;
      find(id);
    }
  });
  wirePointers();
  window.addEventListener('resize', resize);
  window.addEventListener('hashchange', () => { readHash(); });
}
