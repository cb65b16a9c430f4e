// The side view of a layered airspace (docs/reference.md#layered-airspace): the selected flight's altitude over time,
// from its take-off to its landing, on the layers' altitudes, with the clock's instant marked;
// a click on it moves the clock there. Drawn in the request's panel by `drawProfile`, which
// `draw` calls every frame (it does nothing unless a flight with a profile is selected).

// The side view's margins, CSS px: the altitudes' labels on the left, the times under it.
const PROFILE_MARGIN = { left: 58, right: 8, top: 8, bottom: 18 };

/** The side view's geometry for the selected flight: `{ profile, x(t), y(m), t(x) }`, or null. */
function profileGeometry(box) {
  const f = state.selected ? scene.byId.get(state.selected) : null;
  const profile = f ? altitudeProfile(scene, f) : null;
  if (!profile) return null;
  const m = PROFILE_MARGIN;
  const w = Math.max(1, box.width - m.left - m.right);
  const h = Math.max(1, box.height - m.top - m.bottom);
  const alts = profile.layers;
  const gap = alts.length > 1 ? (alts[alts.length - 1] - alts[0]) / (alts.length - 1) : 10;
  const [lo, hi] = [alts[0] - gap / 2, alts[alts.length - 1] + gap / 2];
  const span = Math.max(1, profile.to - profile.from);
  return {
    profile,
    x: (t) => m.left + ((t - profile.from) / span) * w,
    y: (alt) => m.top + (1 - (alt - lo) / (hi - lo)) * h,
    t: (x) => profile.from + Math.max(0, Math.min(1, (x - m.left) / w)) * span,
  };
}

/** Draws the side view of the selected flight, if it has one, at the clock's instant. */
function drawProfile() {
  const canvas = $('profile');
  if (!canvas) return;
  const rect = canvas.getBoundingClientRect();
  const dpr = window.devicePixelRatio || 1;
  if (canvas.width !== Math.round(rect.width * dpr) || canvas.height !== Math.round(rect.height * dpr)) {
    canvas.width = Math.max(1, Math.round(rect.width * dpr));
    canvas.height = Math.max(1, Math.round(rect.height * dpr));
  }
  const g = canvas.getContext('2d');
  g.setTransform(dpr, 0, 0, dpr, 0, 0);
  g.clearRect(0, 0, rect.width, rect.height);
  const geo = profileGeometry(rect);
  if (!geo) return;
  const { profile } = geo;
  const count = profile.layers.length;
  // The layers: a line and a label each (every other one past 12 layers).
  g.font = '11px system-ui, sans-serif';
  g.textBaseline = 'middle';
  g.textAlign = 'right';
  const every = count > 12 ? Math.ceil(count / 12) : 1;
  profile.layers.forEach((alt, i) => {
    const y = geo.y(alt);
    g.strokeStyle = '#eaecf0';
    g.lineWidth = 1;
    g.beginPath();
    g.moveTo(PROFILE_MARGIN.left, y);
    g.lineTo(rect.width - PROFILE_MARGIN.right, y);
    g.stroke();
    if (i % every === 0 || i === count - 1) {
      g.fillStyle = layerColour(i + 1, count);
      g.beginPath();
      g.arc(8, y, 4, 0, 2 * Math.PI);
      g.fill();
      g.strokeStyle = COLOURS.layerRim;
      g.stroke();
      g.fillStyle = '#667085';
      g.fillText(`${i + 1}: ${Math.round(alt)} m`, PROFILE_MARGIN.left - 4, y);
    }
  });
  // The take-off and landing times under it.
  g.textBaseline = 'alphabetic';
  const bottom = rect.height - 4;
  g.textAlign = 'left';
  g.fillText(clock(scene, profile.from).slice(0, 5), PROFILE_MARGIN.left, bottom);
  g.textAlign = 'right';
  g.fillText(clock(scene, profile.to).slice(0, 5), rect.width - PROFILE_MARGIN.right, bottom);
  // The flight, leg by leg (on the ground between legs: nothing drawn).
  g.lineJoin = 'round';
  for (const [colour, width] of [[COLOURS.selectedCasing, 4.5], [COLOURS.selected, 2]]) {
    g.strokeStyle = colour;
    g.lineWidth = width;
    g.beginPath();
    for (const leg of profile.legs) {
      leg.forEach(([t, alt], i) => {
        if (i === 0) g.moveTo(geo.x(t), geo.y(alt));
        else g.lineTo(geo.x(t), geo.y(alt));
      });
    }
    g.stroke();
  }
  // The clock's instant, while the flight is in the air.
  const f = scene.byId.get(state.selected);
  if (isAirborne(f, state.t)) {
    const x = geo.x(state.t);
    g.strokeStyle = COLOURS.hover;
    g.lineWidth = 1.5;
    g.beginPath();
    g.moveTo(x, PROFILE_MARGIN.top);
    g.lineTo(x, rect.height - PROFILE_MARGIN.bottom);
    g.stroke();
    g.fillStyle = layerColour(Math.round(layerAt(f, state.t)), count);
    g.strokeStyle = COLOURS.layerRim;
    g.lineWidth = 1;
    g.beginPath();
    g.arc(x, geo.y(altitudeOf(scene, layerAt(f, state.t))), 4.5, 0, 2 * Math.PI);
    g.fill();
    g.stroke();
  }
}

/** A click on the side view: the clock moves to the instant under it. */
function profileClick(e) {
  const canvas = $('profile');
  if (!canvas || e.target !== canvas) return;
  const rect = canvas.getBoundingClientRect();
  const geo = profileGeometry(rect);
  if (!geo) return;
  setPlaying(false);
  state.following = false;
  setT(Math.round(geo.t(e.clientX - rect.left)));
}
