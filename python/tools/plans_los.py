"""Losses of separation of MUSE's plans flown exactly, counted as BlueSky counts them.

Reads the `flights.geojson` that `muse simulate` / `muse plan` write (each flight a LineString,
or a MultiLineString of its legs, whose positions carry `[lon, lat, altitude, unix time]`),
flies every flight exactly as planned (straight between its nodes at cruise speed, in place
while it hovers, outside the airspace before take-off and after landing), and every second
counts the pairs of flights closer than a protected radius (and, when the positions carry
altitudes, closer than a half height vertically): the same sampling and the same two counts as
BlueSky's conflict detection in `bluesky_run.py` (events: a pair entering a loss of separation;
pairs: distinct pairs ever in one). Set beside BlueSky's counts, it separates what the plans'
geometry gives (MUSE's node rule keeps two drones `tau` apart in time at a node, which is
`tau x v` apart in space only when they fly in line) from what BlueSky's dynamics add.

    python plans_los.py day/flights.geojson --radius-m 41.6667 [--origin-unix T]
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from pathlib import Path

import numpy as np

#: Earth radius BlueSky's flat-earth approximations use (metres).
R_EARTH = 6_371_000.0


def legs(path: Path) -> list[np.ndarray]:
    """Every leg of every flight: an array of rows `[lon, lat, altitude, unix time]`."""
    data = json.loads(path.read_text(encoding="utf-8"))
    out = []
    for feature in data["features"]:
        geometry = feature.get("geometry") or {}
        if geometry.get("type") == "LineString":
            parts = [geometry["coordinates"]]
        elif geometry.get("type") == "MultiLineString":
            parts = geometry["coordinates"]
        else:
            continue
        out.extend(np.array(p, dtype=float) for p in parts if len(p) >= 2)
    return out


def count(
    path: Path, radius_m: float, half_height_m: float, origin: float | None = None
) -> tuple[int, int, int]:
    """(events, distinct pairs, legs) of losses of separation, sampled every second from
    `origin` (unix seconds; default: the first take-off floored to the minute)."""
    flown = legs(path)
    if not flown:
        return 0, 0, 0
    start = origin if origin is not None else math.floor(min(f[0, 3] for f in flown) / 60) * 60
    end = max(f[-1, 3] for f in flown)
    lat0 = math.radians(float(np.mean([f[0, 1] for f in flown])))
    before: set[tuple[int, int]] = set()
    ever: set[tuple[int, int]] = set()
    events = 0
    for t in np.arange(start, end + 1.0, 1.0):
        ids, xs, ys, zs = [], [], [], []
        for i, f in enumerate(flown):
            if f[0, 3] <= t <= f[-1, 3]:
                ids.append(i)
                xs.append(np.interp(t, f[:, 3], f[:, 0]))
                ys.append(np.interp(t, f[:, 3], f[:, 1]))
                zs.append(np.interp(t, f[:, 3], f[:, 2]))
        now: set[tuple[int, int]] = set()
        if len(ids) > 1:
            x = np.radians(np.array(xs)) * R_EARTH * math.cos(lat0)
            y = np.radians(np.array(ys)) * R_EARTH
            z = np.array(zs)
            d = np.hypot(x[:, None] - x[None, :], y[:, None] - y[None, :])
            close = (d < radius_m) & (np.abs(z[:, None] - z[None, :]) < half_height_m)
            a, b = np.nonzero(np.triu(close, k=1))
            now = {(ids[i], ids[j]) for i, j in zip(a, b, strict=True)}
        events += len(now - before)
        ever |= now
        before = now
    return events, len(ever), len(flown)


def main(argv: list[str] | None = None) -> int:
    """Command line: print the counts."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("flights", type=Path, help="flights.geojson of a day")
    parser.add_argument("--radius-m", type=float, required=True, help="protected radius, metres")
    parser.add_argument(
        "--half-height-m", type=float, default=4.572, help="protected half height, metres"
    )
    parser.add_argument("--origin-unix", type=float, help="first sample, unix seconds")
    args = parser.parse_args(argv)
    events, pairs, flown = count(args.flights, args.radius_m, args.half_height_m, args.origin_unix)
    print(
        f"{flown} legs flown as planned: {events} loss-of-separation events, {pairs} distinct "
        f"pairs at {args.radius_m} m (sampled every second)"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
