"""Fly a BlueSky scenario written by `muse export bluesky`, headless, and measure it.

The scenario's comment lines name each flight (docs/reference.md, "BlueSky scenarios"):

    # flight R000042: request r000042, leg 1/1, S012 -> S040, take-off 00:15:00.000, landing 00:31:12.480, destination 1.3512345 103.8012345

This module runs the scenario in BlueSky (the `bluesky-simulator` package), in this process,
without a network or a screen, and returns for every flight when and where BlueSky deleted it
(the scenario deletes a flight as it passes its destination), its arrival drift (BlueSky's
arrival minus MUSE's landing, in seconds) and its distance from the destination, and the
losses of separation BlueSky's conflict detection counted.

Losses of separation are counted two ways:
- *events*: BlueSky's own total (`len(bs.traf.cd.lospairs_all)`, "Total LOS" in its screen): a
  pair counts once each time it enters a loss of separation;
- *pairs*: distinct pairs of flights that were ever in a loss of separation;

and each event is listed (`losses`: the pair, the instant BlueSky's detection first saw it and
their horizontal distance then). BlueSky runs its detection every second by default; `--cd-dt-s
0.05` runs it every step, so that no loss shorter than a second goes unseen.

BlueSky keeps global state, so run one scenario per process: as a script,

    python bluesky_run.py day.scn --radius-m 41.67 --half-height-ft 15 --json out.json

prints a summary and writes the figures as JSON; `run()` is the same from Python.

BlueSky keeps its settings and a cache of its navigation database in a working folder: by
default `$MUSE_BLUESKY_WORKDIR`, else `~/.cache/muse-bluesky`. The first run builds the cache
(20 to 60 s on two cores); later runs start in 5 to 20 s.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import re
import statistics
import sys
import time
from dataclasses import asdict, dataclass, field
from pathlib import Path

#: One nautical mile in metres (BlueSky's ZONER takes nautical miles).
NM_M = 1852.0
#: One foot in metres (BlueSky's ZONEDH takes feet).
FT_M = 0.3048

FLIGHT_LINE = re.compile(
    r"^# flight (?P<callsign>\S+): request (?P<request>.*), leg (?P<leg>\d+)/(?P<legs>\d+), "
    r"(?P<origin>.*) -> (?P<destination>.*), take-off (?P<takeoff>[0-9:.]+), "
    r"landing (?P<landing>[0-9:.]+), destination (?P<lat>-?[0-9.]+) (?P<lon>-?[0-9.]+)$"
)


@dataclass
class Flight:
    """A flight (one leg of a trip) as the scenario's comment line describes it."""

    callsign: str
    request: str
    leg: int
    legs: int
    takeoff_s: float
    landing_s: float
    dest_lat: float
    dest_lon: float


@dataclass
class Arrival:
    """Where and when BlueSky deleted a flight, against MUSE's landing."""

    callsign: str
    request: str
    time_s: float
    drift_s: float
    distance_m: float


@dataclass
class Loss:
    """A loss of separation as BlueSky's conflict detection first saw it."""

    pair: list[str]
    time_s: float
    distance_m: float
    """Their horizontal distance then."""


@dataclass
class Result:
    """What a headless run measured."""

    flights: int
    arrivals: list[Arrival] = field(default_factory=list)
    not_arrived: list[str] = field(default_factory=list)
    los_events: int = 0
    los_pairs: int = 0
    losses: list[Loss] = field(default_factory=list)
    simulated_s: float = 0.0
    wall_s: float = 0.0
    init_s: float = 0.0

    def drift_stats(self) -> dict[str, float]:
        """Min, mean, median, p95 and max of the arrival drift, in seconds."""
        return _stats([a.drift_s for a in self.arrivals])

    def distance_stats(self) -> dict[str, float]:
        """Min, mean, median, p95 and max of the distance to the destination, in metres."""
        return _stats([a.distance_m for a in self.arrivals])

    def to_json(self) -> dict:
        """The result as JSON-ready data, with the statistics."""
        data = asdict(self)
        data["drift_s"] = self.drift_stats()
        data["distance_m"] = self.distance_stats()
        return data


def _stats(values: list[float]) -> dict[str, float]:
    if not values:
        return {}
    ordered = sorted(values)
    p95 = ordered[min(len(ordered) - 1, math.ceil(0.95 * len(ordered)) - 1)]
    return {
        "min": ordered[0],
        "mean": statistics.fmean(ordered),
        "median": statistics.median(ordered),
        "p95": p95,
        "max": ordered[-1],
    }


def clock_seconds(text: str) -> float:
    """Seconds of a scenario clock `HH:MM:SS.fff` (hours may exceed 23)."""
    hours, minutes, seconds = text.split(":")
    return int(hours) * 3600 + int(minutes) * 60 + float(seconds)


def read_flights(scn: Path) -> list[Flight]:
    """The flights a scenario's `# flight` comment lines describe, in file order."""
    flights = []
    for line in scn.read_text(encoding="utf-8").splitlines():
        m = FLIGHT_LINE.match(line)
        if m:
            flights.append(
                Flight(
                    callsign=m["callsign"],
                    request=m["request"],
                    leg=int(m["leg"]),
                    legs=int(m["legs"]),
                    takeoff_s=clock_seconds(m["takeoff"]),
                    landing_s=clock_seconds(m["landing"]),
                    dest_lat=float(m["lat"]),
                    dest_lon=float(m["lon"]),
                )
            )
    return flights


def haversine_m(lat1: float, lon1: float, lat2: float, lon2: float) -> float:
    """Great-circle distance in metres (mean Earth radius)."""
    p1, p2 = math.radians(lat1), math.radians(lat2)
    dp, dl = p2 - p1, math.radians(lon2 - lon1)
    h = math.sin(dp / 2) ** 2 + math.cos(p1) * math.cos(p2) * math.sin(dl / 2) ** 2
    return 2 * 6_371_008.8 * math.asin(math.sqrt(h))


def default_workdir() -> Path:
    """BlueSky's working folder: `$MUSE_BLUESKY_WORKDIR`, else `~/.cache/muse-bluesky`."""
    env = os.environ.get("MUSE_BLUESKY_WORKDIR")
    return Path(env) if env else Path.home() / ".cache" / "muse-bluesky"


def run(
    scn: Path,
    *,
    radius_m: float | None = None,
    half_height_ft: float | None = None,
    margin_s: float = 600.0,
    workdir: Path | None = None,
    progress: bool = False,
    cd_dt_s: float | None = None,
) -> Result:
    """Flies `scn` headless in this process and measures it.

    `radius_m` (and `half_height_ft`, BlueSky's ZONEDH) switch on BlueSky's state-based
    conflict detection with that protected zone; without them no losses are counted. The run
    stops when every flight has been deleted, or `margin_s` after the last planned landing.
    With `progress`, a line on standard error every simulated hour. `cd_dt_s` sets how often
    the conflict detection runs (BlueSky's default: every second, so a loss of separation
    shorter than that may go unseen).
    """
    import bluesky as bs  # noqa: PLC0415 (BlueSky is optional: imported only to run)

    flights = read_flights(scn)
    workdir = workdir or default_workdir()
    workdir.mkdir(parents=True, exist_ok=True)
    deleted: dict[str, tuple[float, float, float]] = {}
    started = time.perf_counter()
    # Initialise first: BlueSky chooses its compiled geometry functions from its settings, so
    # none of its traffic modules may be imported before.
    bs.init(mode="sim", detached=True, workdir=str(workdir))
    init_s = time.perf_counter() - started
    from bluesky.traffic.traffic import Traffic  # noqa: PLC0415

    original_delete = Traffic.delete

    def recording_delete(self, idx):
        indices = idx if hasattr(idx, "__len__") else [idx]
        for i in indices:
            deleted[self.id[i]] = (bs.sim.simt, float(self.lat[i]), float(self.lon[i]))
        return original_delete(self, idx)

    Traffic.delete = recording_delete
    bs.stack.stack(f"IC {scn.resolve()}")
    bs.sim.step()  # loads the scenario (IC resets the simulation)
    if radius_m is not None:
        bs.stack.stack("CDMETHOD STATEBASED")
        bs.stack.stack(f"ZONER {radius_m / NM_M:.9f}")
        if half_height_ft is not None:
            bs.stack.stack(f"ZONEDH {half_height_ft:.6f}")
        if cd_dt_s is not None:
            bs.traf.asastimer.setdt(cd_dt_s)
    end = max((f.landing_s for f in flights), default=0.0) + margin_s
    ran = time.perf_counter()
    next_report = 3600.0
    losses: list[Loss] = []
    seen = 0
    while bs.sim.simt < end:
        bs.sim.step()
        if radius_m is not None and len(bs.traf.cd.lospairs_all) > seen:
            for a, b in bs.traf.cd.lospairs_all[seen:]:
                ia, ib = bs.traf.id2idx(a), bs.traf.id2idx(b)
                distance = (
                    haversine_m(bs.traf.lat[ia], bs.traf.lon[ia], bs.traf.lat[ib], bs.traf.lon[ib])
                    if ia >= 0 and ib >= 0
                    else float("nan")
                )
                losses.append(Loss(pair=[a, b], time_s=bs.sim.simt, distance_m=distance))
            seen = len(bs.traf.cd.lospairs_all)
        if len(deleted) == len(flights) and bs.traf.ntraf == 0:
            break
        if progress and bs.sim.simt >= next_report:
            next_report += 3600.0
            print(
                f"simulated {bs.sim.simt / 3600:.0f} h in {time.perf_counter() - ran:.0f} s: "
                f"{len(deleted)} arrived, {bs.traf.ntraf} flying",
                file=sys.stderr,
                flush=True,
            )
    wall_s = time.perf_counter() - ran
    Traffic.delete = original_delete

    result = Result(flights=len(flights), simulated_s=bs.sim.simt, wall_s=wall_s, init_s=init_s)
    for f in flights:
        if f.callsign not in deleted:
            result.not_arrived.append(f.callsign)
            continue
        t, lat, lon = deleted[f.callsign]
        result.arrivals.append(
            Arrival(
                callsign=f.callsign,
                request=f.request,
                time_s=t,
                drift_s=t - f.landing_s,
                distance_m=haversine_m(lat, lon, f.dest_lat, f.dest_lon),
            )
        )
    cd = bs.traf.cd
    result.los_events = len(cd.lospairs_all)
    result.los_pairs = len({frozenset(p) for p in cd.lospairs_all})
    result.losses = losses
    return result


def summary(result: Result) -> str:
    """A few lines saying what the run measured."""
    d = result.drift_stats()
    m = result.distance_stats()
    lines = [
        f"{result.flights} flights, {len(result.arrivals)} arrived, "
        f"{len(result.not_arrived)} not arrived",
    ]
    if d:
        lines.append(
            "arrival drift vs MUSE's landing (s): "
            f"min {d['min']:+.2f}, mean {d['mean']:+.2f}, median {d['median']:+.2f}, "
            f"p95 {d['p95']:+.2f}, max {d['max']:+.2f}"
        )
        lines.append(
            f"distance from the destination at deletion (m): median {m['median']:.2f}, "
            f"max {m['max']:.2f}"
        )
    lines.append(
        f"losses of separation: {result.los_events} events, {result.los_pairs} distinct pairs"
    )
    for loss in result.losses[:20]:
        lines.append(
            f"  {' and '.join(loss.pair)} at {loss.time_s:.2f} s, {loss.distance_m:.1f} m apart"
        )
    lines.append(
        f"simulated {result.simulated_s:.0f} s in {result.wall_s:.1f} s wall "
        f"(BlueSky start-up {result.init_s:.1f} s)"
    )
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    """Command line: fly a scenario, print the summary, optionally write JSON."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("scenario", type=Path, help="the .scn file muse export bluesky wrote")
    parser.add_argument(
        "--radius-m", type=float, help="protected radius in metres (switches on detection)"
    )
    parser.add_argument(
        "--half-height-ft", type=float, help="protected half height in feet (ZONEDH)"
    )
    parser.add_argument(
        "--margin-s", type=float, default=600.0, help="run on this long after the last landing"
    )
    parser.add_argument("--workdir", type=Path, help="BlueSky's working folder")
    parser.add_argument(
        "--progress", action="store_true", help="say every simulated hour how far it got"
    )
    parser.add_argument(
        "--cd-dt-s",
        type=float,
        help="run the conflict detection this often, seconds (BlueSky's default: 1)",
    )
    parser.add_argument("--json", type=Path, help="write the figures to this file")
    args = parser.parse_args(argv)
    result = run(
        args.scenario,
        radius_m=args.radius_m,
        half_height_ft=args.half_height_ft,
        margin_s=args.margin_s,
        workdir=args.workdir,
        progress=args.progress,
        cd_dt_s=args.cd_dt_s,
    )
    print(summary(result))
    if args.json:
        args.json.write_text(json.dumps(result.to_json(), indent=1), encoding="utf-8")
    return 0


if __name__ == "__main__":
    sys.exit(main())
