// The map's colours and the load scale's key. No DOM here (node's test runner loads it); the
// page inlines it with its `export` keywords dropped.
//
// Each thing on the map has a style of its own that does not rest on colour alone, so that
// the map reads the same with any colour vision (the tests simulate deuteranopia and
// protanopia on these colours):
//
// - corridor load: a sequential scale from light ochre (few flights) through grey to navy
//   (the busiest), its lightness falling steadily. It runs along the blue–yellow axis, which
//   red–green colour blindness keeps, so the order survives it; the line also widens with
//   the load, and a corridor no flight uses is a thin light grey line;
// - a corridor closed by an active zone: black dashes over a white line;
// - a no-fly zone: magenta hatching inside a solid magenta outline while active, a dashed
//   outline alone while not;
// - the selected flight: its path in cyan inside a thick black casing, and a double ring
//   round its drone;
// - drones: blue dots with a white rim, flying; orange rings, hovering. In a layered airspace
//   a drone's fill is its layer's, on a scale from light yellow (the lowest) through green
//   and teal to dark violet (the highest), its lightness falling steadily (so the order
//   survives any colour vision), in a dark rim; a hovering drone keeps its orange ring
//   around it.

/** The load scale's stops, from the fewest flights to the most (sRGB). */
export const LOAD_STOPS = [
  [222, 196, 70],
  [170, 160, 110],
  [120, 122, 125],
  [62, 82, 128],
  [10, 36, 90],
];

/** The layer scale's stops, from the lowest layer to the highest (sRGB). */
export const LAYER_STOPS = [
  [250, 226, 60],
  [126, 206, 86],
  [38, 166, 130],
  [40, 118, 142],
  [62, 70, 138],
  [70, 16, 96],
];

/** The fixed colours. */
export const COLOURS = {
  unused: '#c5cbd5',
  closed: '#111111',
  closedUnder: '#ffffff',
  zone: '#b3179e',
  zoneHatch: 'rgba(179, 23, 158, 0.5)',
  selected: '#22d3ee',
  selectedCasing: '#0b1220',
  drone: '#1570ef',
  droneRim: '#ffffff',
  hover: '#f79009',
  station: '#344054',
  layerRim: '#0b1220',
};

/** The colour of layer `k` of `count` (1 up), as `[r, g, b]`: the layer scale's ends for the
 * lowest and the highest, evenly between for the others. */
export function layerRgb(k, count) {
  return rampRgb(LAYER_STOPS, count > 1 ? (Math.min(count, Math.max(1, k)) - 1) / (count - 1) : 0);
}

/** [`layerRgb`] as a CSS colour. */
export function layerColour(k, count) {
  const [r, g, b] = layerRgb(k, count);
  return `rgb(${r},${g},${b})`;
}

/** The colour at `u` in [0, 1] along `stops` (linear between them), as `[r, g, b]`. */
function rampRgb(stops, u) {
  const x = Math.min(1, Math.max(0, Number.isFinite(u) ? u : 0)) * (stops.length - 1);
  const i = Math.min(stops.length - 2, Math.floor(x));
  const f = x - i;
  return stops[i].map((v, k) => Math.round(v + (stops[i + 1][k] - v) * f));
}

/** The load scale's colour at `u` in [0, 1] (0: one flight, 1: the busiest), as `[r, g, b]`. */
export function loadRgb(u) {
  return rampRgb(LOAD_STOPS, u);
}

/** [`loadRgb`] as a CSS colour. */
export function loadColour(u) {
  const [r, g, b] = loadRgb(u);
  return `rgb(${r},${g},${b})`;
}

/**
 * Where a corridor with `flights` flights sits on a scale whose busiest corridor has `max`:
 * `null` for none (drawn as unused), else `u` in [0, 1] from one flight to `max`.
 */
export function loadPosition(flights, max) {
  if (!(flights > 0)) return null;
  return max > 1 ? (Math.min(flights, max) - 1) / (max - 1) : 1;
}

/**
 * The labelled values of the load key for a busiest corridor of `max` flights: 1, round
 * steps (1, 2 or 5 times a power of ten, at most five of them), and `max`; empty if no
 * corridor has a flight.
 */
export function loadTicks(max) {
  if (!(max >= 1)) return [];
  if (max === 1) return [1];
  const raw = (max - 1) / 5;
  const pow = 10 ** Math.floor(Math.log10(raw));
  const step = Math.max(1, [1, 2, 5, 10].map((m) => m * pow).find((s) => s >= raw));
  const ticks = [1];
  for (let v = step; v < max; v += step) {
    // Leave out a round value crowding the ends.
    if (v - 1 >= step / 2 && max - v >= step / 2) ticks.push(v);
  }
  ticks.push(max);
  return ticks;
}
