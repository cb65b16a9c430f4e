"""MUSE from Python: exact collision-free planning of drone deliveries.

The same planner, readers, summary and verifier as the ``muse`` command line, called in
process. Inputs are lists of dicts or pandas DataFrames; a planned day comes back as a
:class:`Day`: its flights and stays as DataFrames (the command line's ``flights.csv`` and
``stays.csv``), its summary as a dict (``summary.json``) and its plans as dicts (the lines of
``plans.jsonl``). Bad input raises :class:`MuseError` with the message the command line
prints.

>>> import muse
>>> day = muse.simulate(count=200, seed=7)
>>> day.summary["planned"] + sum(day.summary["rejected"].values()) == 200
True
>>> muse.verify(day).ok
True

Keyword parameters (the paper's defaults): ``speed_kmh`` (30), ``max_flight_min`` (20),
``node_separation_s`` (5), ``edge_rule`` (``"exclusive"`` or ``"headway"``), ``headway_s``,
``max_ground_delay_s`` (0), ``battery_swap_s``, ``max_legs``, ``max_trip_min``,
``separation_m`` (0: off) and ``vertical_separation_m`` (docs/reference.md#metric-separation); layers
(docs/reference.md#layered-airspace): ``layers`` (1), ``base_altitude_m`` (60), ``layer_spacing_m`` (9.144),
``climb_mps`` (5), ``heading_rule`` (``"none"`` or ``"sectors"``).
"""

from __future__ import annotations

import csv
import io
import json
import os
from dataclasses import dataclass, field
from typing import Any, Iterable, Mapping, Sequence, Union

import pandas as pd

from . import _muse
from ._muse import MuseError

__all__ = [
    "Airspace",
    "Day",
    "MuseError",
    "Verification",
    "plan",
    "simulate",
    "verify",
]
__version__: str = _muse.__version__

PathLike = Union[str, "os.PathLike[str]"]
Table = Union[pd.DataFrame, Sequence[Mapping[str, Any]]]
ZonesArg = Union[None, PathLike, Sequence[PathLike]]

_REQUEST_COLUMNS = ("id", "origin", "destination", "departure")
_OPTIONAL_REQUEST_COLUMNS = ("submitted", "origin_customer", "destination_customer")


class Airspace:
    """An airspace: stations (pads) and waypoints joined by corridors (docs/reference.md#airspace).

    Make one with :meth:`scenario` (built in), :meth:`read` (a GeoJSON file) or
    :meth:`from_pads` (built from pads by the rule of docs/reference.md#airspace-from-pads).
    """

    __slots__ = ("_inner",)

    def __init__(self, inner: _muse.Airspace) -> None:
        self._inner = inner

    @classmethod
    def scenario(cls, name: str = "singapore-77") -> "Airspace":
        """A built-in scenario: ``singapore-77`` (the paper's) or ``singapore-all``."""
        return cls(_muse.Airspace.scenario(name))

    @classmethod
    def read(cls, path: PathLike) -> "Airspace":
        """An airspace GeoJSON file, as ``muse airspace build`` writes it."""
        return cls(_muse.Airspace.read(os.fspath(path)))

    @classmethod
    def from_pads(
        cls,
        pads: Union[Table, PathLike],
        *,
        crs: str | None = None,
        exclude: Sequence[PathLike] = (),
        max_corridor_m: float | None = None,
        time_zone: str | None = None,
        utc_offset: str | None = None,
        date: str | None = None,
    ) -> "Airspace":
        """The airspace of a set of pads, as ``muse airspace build --pads`` builds it.

        ``pads``: a DataFrame or list of dicts with ``id``, ``lon``, ``lat`` (and optionally
        ``name``), or the path of a pads CSV or GeoJSON file. ``crs``: the plane corridors are
        drawn in (``utm``, the default, ``EPSG:3414``, ...); ``exclude``: GeoJSON files of
        polygons no pad may lie in and no corridor may cross; ``max_corridor_m``: the longest
        corridor; ``time_zone`` (an IANA name such as ``Europe/Vienna``) or ``utc_offset``
        (``+01:00``), with ``date`` (``YYYY-MM-DD``, default 2026-01-05): the day its requests
        are planned on, so that clock times are the place's own.

        >>> pads = [{"id": "A", "lon": 103.80, "lat": 1.30},
        ...         {"id": "B", "lon": 103.81, "lat": 1.30},
        ...         {"id": "C", "lon": 103.80, "lat": 1.31}]
        >>> Airspace.from_pads(pads).station_count
        3
        """
        if isinstance(pads, (str, os.PathLike)):
            path = os.fspath(pads)
            text, source = _muse.read_text(path), path
        else:
            text = _csv(_records(pads, "pads"), ("id", "lon", "lat"), ("name",), "pads")
            source = "pads"
        inner = _muse.Airspace.from_pads_csv(
            text,
            source,
            crs,
            [os.fspath(p) for p in exclude],
            max_corridor_m,
            time_zone,
            utc_offset,
            date,
        )
        return cls(inner)

    @property
    def source(self) -> str:
        """Where the airspace came from."""
        return self._inner.source

    @property
    def station_count(self) -> int:
        """The number of stations (pads)."""
        return self._inner.station_count

    @property
    def nodes(self) -> pd.DataFrame:
        """The nodes: ``id``, ``kind`` (station or waypoint), ``name``, ``lon``, ``lat``."""
        return pd.DataFrame(self._inner.node_columns())

    @property
    def edges(self) -> pd.DataFrame:
        """The corridors: ``id``, ``from``, ``to``, ``length_m``."""
        return pd.DataFrame(self._inner.edge_columns())

    def to_geojson(self) -> str:
        """The airspace as GeoJSON (docs/reference.md#airspace)."""
        return self._inner.to_geojson()

    def write(self, path: PathLike) -> None:
        """Writes the airspace GeoJSON to ``path``, which must not exist yet."""
        with open(os.fspath(path), "x", encoding="utf-8") as f:
            f.write(self.to_geojson())

    def __repr__(self) -> str:
        return repr(self._inner)


@dataclass(frozen=True)
class Day:
    """A planned day: what ``muse plan`` and ``muse simulate`` write, in memory."""

    flights: pd.DataFrame
    """One row per request (``flights.csv``): status, reason, times, delays, distance."""
    stays: pd.DataFrame
    """One row per stay of every flight (``stays.csv``): node, arrival, departure, hover."""
    summary: dict[str, Any]
    """The day's summary (``summary.json``)."""
    plans: list[dict[str, Any]]
    """One dict per request (the lines of ``plans.jsonl``), paths included."""
    files: Mapping[str, str] = field(default_factory=dict, repr=False)
    """The texts of the command line's files, by name: ``plans.jsonl``, ``summary.json``,
    ``flights.csv``, ``stays.csv``, byte for byte as ``muse plan`` writes them."""
    airspace: Airspace | None = field(default=None, repr=False)
    zones: ZonesArg = field(default=None, repr=False)
    params: dict[str, Any] = field(default_factory=dict, repr=False)

    def plans_jsonl(self) -> str:
        """The plans as JSON Lines, as ``plans.jsonl`` holds them."""
        return self.files["plans.jsonl"]

    def write(self, folder: PathLike) -> None:
        """Writes ``plans.jsonl``, ``summary.json``, ``flights.csv`` and ``stays.csv`` into
        ``folder`` (created; files already there are not overwritten), so that ``muse
        verify`` and ``muse view`` read the day."""
        folder = os.fspath(folder)
        os.makedirs(folder, exist_ok=True)
        taken = [n for n in self.files if os.path.lexists(os.path.join(folder, n))]
        if taken:
            raise FileExistsError(f"{folder}: {', '.join(taken)} already there; not overwritten")
        for name, text in self.files.items():
            with open(os.path.join(folder, name), "x", encoding="utf-8") as f:
                f.write(text)


@dataclass(frozen=True)
class Verification:
    """What ``verify`` found: ``ok`` when every rule holds for every flight."""

    ok: bool
    flights: int
    """The flights checked (those that fly)."""
    lines: int
    """The plans read."""
    violations: list[str]
    """Each violation, as ``muse verify`` prints it."""
    separation: dict[str, Any] = field(default_factory=dict)
    """How close the flights come in metres, as a summary's ``separation``: ``closest_m``,
    ``closest`` (``requests``, ``at``, ``near``), ``pairs_under_m`` and ``vertical_m``."""

    def __bool__(self) -> bool:
        return self.ok

    def __str__(self) -> str:
        if self.ok:
            return f"OK: {self.flights} flights checked of {self.lines} plans, every rule holds"
        listed = "".join(f"\n  {v}" for v in self.violations[:20])
        more = len(self.violations) - 20
        tail = f"\n  ... and {more} more" if more > 0 else ""
        return (
            f"FAILED: {len(self.violations)} violation(s) among the {self.flights} flights "
            f"checked{listed}{tail}"
        )


def plan(
    requests: Union[Table, PathLike],
    airspace: Airspace | None = None,
    zones: ZonesArg = None,
    **params: Any,
) -> Day:
    """Plans requests first come, first served (docs/reference.md#requests and #planning), exactly, as ``muse plan``.

    ``requests``: a DataFrame or list of dicts with ``id``, ``origin``, ``destination``,
    ``departure`` (RFC 3339, local ``HH:MM[:SS]``, or a ``datetime``/``Timestamp`` with its
    offset) and optionally ``submitted``; or the path of a requests CSV. ``airspace``: the
    Singapore default when ``None``. ``zones``: the airspace's own when ``None``; ``[]`` for
    none; else zone files (ED-318 or ED-269 GeoJSON). ``params``: flight parameters and
    layers (see the module's documentation).
    """
    if isinstance(requests, (str, os.PathLike)):
        path = os.fspath(requests)
        text, source = _muse.read_text(path), path
    else:
        rows = _records(requests, "requests")
        text = _csv(rows, _REQUEST_COLUMNS, _OPTIONAL_REQUEST_COLUMNS, "requests")
        source = "requests"
    out = _muse.plan(text, source, _inner(airspace), _zones(zones), **params)
    return _day(out, airspace, zones, params)


def simulate(
    count: int = 5000,
    seed: int = 1,
    *,
    start: str = "08:00",
    end: str = "20:00",
    od: str = "uniform",
    airspace: Airspace | None = None,
    zones: ZonesArg = None,
    **params: Any,
) -> Day:
    """Generates a seeded day of demand and plans it, as ``muse simulate`` (same seed, same
    requests, same plans): ``count`` requests departing uniformly in ``[start, end)`` (local
    time) between random station pairs (``od="in-range"``: only pairs within the battery's
    range). ``count`` is 1 to 10,000,000 and ``seed`` 0 to 2**64 - 1, as ``--count`` and
    ``--seed``; anything else raises :class:`MuseError`.
    """
    out = _muse.simulate(
        count, seed, start, end, od, _inner(airspace), _zones(zones), **params
    )
    return _day(out, airspace, zones, params)


def verify(
    plans: Union[Day, PathLike, Iterable[Mapping[str, Any]]],
    airspace: Airspace | None = None,
    zones: ZonesArg = None,
    **params: Any,
) -> Verification:
    """Checks plans against every rule, independently of the planner, as ``muse verify``.

    ``plans``: a :class:`Day` (checked on its own airspace, zones and parameters unless
    others are given), the path of a plans file (JSON Lines), or dicts as its lines.
    """
    if isinstance(plans, Day):
        text, source = plans.plans_jsonl(), "plans"
        airspace = plans.airspace if airspace is None else airspace
        zones = plans.zones if zones is None else zones
        params = {**plans.params, **params}
    elif isinstance(plans, (str, os.PathLike)):
        source = os.fspath(plans)
        text = _muse.read_text(source)
    else:
        text, source = "".join(json.dumps(p) + "\n" for p in plans), "plans"
    out = _muse.verify(text, source, _inner(airspace), _zones(zones), **params)
    return Verification(
        ok=out["ok"],
        flights=out["flights"],
        lines=out["lines"],
        violations=list(out["violations"]),
        separation=json.loads(out["separation"]),
    )


def _inner(airspace: Airspace | None) -> "_muse.Airspace | None":
    if airspace is None:
        return None
    if not isinstance(airspace, Airspace):
        raise TypeError(
            f"airspace: expected a muse.Airspace (Airspace.read(path) for a file), "
            f"not {type(airspace).__name__}"
        )
    return airspace._inner


def _zones(zones: ZonesArg) -> list[str] | None:
    if zones is None:
        return None
    if isinstance(zones, (str, os.PathLike)):
        return [os.fspath(zones)]
    return [os.fspath(z) for z in zones]


def _records(table: Table, what: str) -> list[Mapping[str, Any]]:
    if isinstance(table, pd.DataFrame):
        return table.to_dict("records")
    rows = list(table)
    for i, row in enumerate(rows):
        if not isinstance(row, Mapping):
            raise TypeError(
                f"{what}: row {i} is a {type(row).__name__}, not a dict of columns"
            )
    return rows


def _cell(value: Any) -> str:
    if value is None:
        return ""
    if isinstance(value, float) and value != value:  # NaN: a missing cell in pandas
        return ""
    if hasattr(value, "isoformat") and hasattr(value, "utcoffset"):
        if value.utcoffset() is None:
            raise MuseError(
                f"{value!r}: a date and time needs its UTC offset (or give local HH:MM:SS)"
            )
        return value.isoformat(timespec="milliseconds")
    return str(value)


def _csv(
    rows: Sequence[Mapping[str, Any]],
    required: Sequence[str],
    optional: Sequence[str],
    what: str,
) -> str:
    """The rows as the CSV file the command line reads; a row's line is its index + 2."""
    present = set().union(*(row.keys() for row in rows)) if rows else set(required)
    unknown = sorted(present - set(required) - set(optional))
    if unknown:
        raise MuseError(
            f"{what}: unknown column(s) {', '.join(unknown)}; expected "
            f"{', '.join(required)} and optionally {', '.join(optional)}"
        )
    columns = list(required) + [c for c in optional if c in present]
    out = io.StringIO()
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow(columns)
    for row in rows:
        writer.writerow([_cell(row.get(c)) for c in columns])
    return out.getvalue()


_TIME_COLUMNS = ("requested_departure", "takeoff", "landing", "arrive", "depart")


def _table(text: str) -> pd.DataFrame:
    """A CSV table of the command line's, its instants as timezone-aware Timestamps."""
    table = pd.read_csv(io.StringIO(text), keep_default_na=False, na_values=[""])
    for column in _TIME_COLUMNS:
        if column in table:
            table[column] = pd.to_datetime(table[column], format="ISO8601")
    return table


def _day(
    out: Mapping[str, str], airspace: Airspace | None, zones: ZonesArg, params: dict
) -> Day:
    return Day(
        flights=_table(out["flights"]),
        stays=_table(out["stays"]),
        summary=json.loads(out["summary"]),
        plans=[json.loads(line) for line in out["plans"].splitlines() if line],
        files={
            "plans.jsonl": out["plans"],
            "summary.json": out["summary"],
            "flights.csv": out["flights"],
            "stays.csv": out["stays"],
        },
        airspace=airspace,
        zones=zones,
        params=dict(params),
    )
