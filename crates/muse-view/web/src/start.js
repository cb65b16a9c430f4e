// `window.museView`, and the start: where the address says, else where the day's traffic
// starts.

const museView = {
  ready: false,
  live: Boolean(scene.live),
  scene,
  /** Pauses, sets the clock to epoch ms `t`, draws; returns the drones drawn (in view). */
  setTime(t) {
    setPlaying(false);
    state.following = false;
    setT(t - scene.t0);
    draw();
    return state.drawn.length;
  },
  time: () => scene.t0 + state.t,
  /** The drones drawn at the last frame: those in view. */
  drawnCount: () => state.drawn.length,
  /** The flights in the air at the last frame, in view or not. */
  airborneCount: () => state.airborne,
  flightsDrawn() {
    const r = canvas.getBoundingClientRect();
    return state.drawn.map((d) => ({ id: d.id, x: r.left + d.x, y: r.top + d.y, hovering: d.hovering }));
  },
  /** Corridor `i`: its middle on the page (CSS px) and the tooltip's text there. */
  corridor(i) {
    const r = canvas.getBoundingClientRect();
    const [[x1, y1], [x2, y2]] = segment(i);
    return { x: r.left + (x1 + x2) / 2, y: r.top + (y1 + y2) / 2, text: corridorText(i) };
  },
  /** The corridors closed by an active zone at the last frame (indices, sorted). */
  closedCorridors: () => [...state.closed].sort((a, b) => a - b),
  /** The nodes closed by an active zone at the last frame (indices, sorted). */
  closedNodes: () => [...state.closedNodes].sort((a, b) => a - b),
  /** The view's scale, CSS px per world unit (it grows as one zooms in). */
  scale: () => state.view.scale,
  selected: () => state.selected,
  /** What zone `id` is doing at the clock's time (`null` if there is no such zone). */
  zoneAt(id) {
    const z = scene.zones.find((zone) => zone.id === id);
    return z ? zoneState(z, state.t) : null;
  },
  select,
  resetView,
  /**
   * A layered airspace: shows layer `k` alone (null: every layer) and draws; returns the
   * drones drawn (in view).
   */
  setLayer(k) {
    setLayer(k);
    draw();
    return state.drawn.length;
  },
  /** The layer shown alone, or null for every layer. */
  layer: () => state.layer,
  /** The (fractional) layer of flight `id` at the clock's time, or null if it is not in the scene. */
  layerOf(id) {
    const f = scene.byId.get(id);
    return f ? layerAt(f, state.t) : null;
  },
  /**
   * The side view drawn for the selected flight: its legs' points as `[epoch ms, metres]`,
   * the layers' altitudes, and on the page (CSS px) where instant `t` (epoch ms) is along it;
   * null when no side view is drawn.
   */
  profile() {
    const canvas = document.getElementById('profile');
    if (!canvas) return null;
    const r = canvas.getBoundingClientRect();
    const geo = profileGeometry(r);
    if (!geo) return null;
    return {
      legs: geo.profile.legs.map((leg) => leg.map(([t, m]) => [scene.t0 + t, m])),
      layers: geo.profile.layers,
      box: [r.left, r.top, r.width, r.height],
      xAt: (t) => r.left + geo.x(t - scene.t0),
      yAt: (m) => r.top + geo.y(m),
    };
  },
  play: () => setPlaying(true),
  pause: () => setPlaying(false),
  redraw() { state.dayLoad = null; state.hourLoad = { at: NaN, load: null }; state.shownLoad = null; state.dirty = true; },
};
window.museView = museView;

// The legend's keys take their colours from palette.js.
for (const [name, value] of Object.entries(COLOURS)) {
  document.documentElement.style.setProperty(`--c-${name.replace(/[A-Z]/g, (c) => `-${c.toLowerCase()}`)}`, value);
}
wire();
resize();
showSummary();
showDetails();
const firstTakeoff = scene.flights.reduce((m, f) => Math.min(m, f.takeoff), Infinity);
setT(Number.isFinite(firstTakeoff) ? firstTakeoff : 0);
state.following = Boolean(scene.live);
draw();
// The address (`#t=10:30:00&f=r42`) goes first, once this script has run to its end (the
// live page's wiring included); then the page is ready.
Promise.resolve().then(readHash).finally(() => {
  draw();
  museView.ready = true;
  requestAnimationFrame(frame);
});
