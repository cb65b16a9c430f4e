// Decoding the live feed of `muse serve`: flights as its API shows them, and its
// server-sent events. No DOM here (node's test runner loads it); the page inlines it with
// its `export` keywords dropped.

/** A scene flight (model.js's compact form) from a flight as the API shows it. */
export function flightFromApi(scene, nodeIndex, plan) {
  const path = plan.path ?? plan.committed;
  if (!path || path.length === 0) return null;
  const rel = (t) => Date.parse(t) - scene.t0;
  const node = (id) => {
    const i = nodeIndex.get(id);
    if (i === undefined) throw new Error(`unknown node ${id}`);
    return i;
  };
  return {
    id: plan.request,
    o: node(plan.origin),
    d: node(plan.destination),
    dep: rel(plan.requested_departure),
    ff: plan.free_flow_s === null || plan.free_flow_s === undefined ? null : Math.round(plan.free_flow_s * 1000),
    status: plan.status,
    operator: plan.operator ?? null,
    s: path.flatMap((st) => [node(st.node), rel(st.arrive), rel(st.depart)]),
  };
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
