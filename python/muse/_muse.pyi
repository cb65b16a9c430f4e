"""Type stubs of the extension module ``muse._muse`` (the Rust side of ``import muse``)."""

from typing import Any, Sequence

__version__: str

class MuseError(ValueError):
    """An input MUSE refuses; the message names the input, line and field."""

class Airspace:
    @staticmethod
    def scenario(name: str = "singapore-77") -> Airspace: ...
    @staticmethod
    def read(path: str) -> Airspace: ...
    @staticmethod
    def from_pads_csv(
        pads: str,
        source: str,
        crs: str | None = None,
        exclude: Sequence[str] = ...,
        max_corridor_m: float | None = None,
        time_zone: str | None = None,
        utc_offset: str | None = None,
        date: str | None = None,
    ) -> Airspace: ...
    @property
    def source(self) -> str: ...
    @property
    def station_count(self) -> int: ...
    def node_columns(self) -> dict[str, list[Any]]: ...
    def edge_columns(self) -> dict[str, list[Any]]: ...
    def to_geojson(self) -> str: ...

def read_text(path: str) -> str: ...
def plan(
    requests: str,
    source: str,
    airspace: Airspace | None = None,
    zones: Sequence[str] | None = None,
    **kwargs: Any,
) -> dict[str, str]: ...
def simulate(
    count: Any,
    seed: Any,
    start: str,
    end: str,
    od: str,
    airspace: Airspace | None = None,
    zones: Sequence[str] | None = None,
    **kwargs: Any,
) -> dict[str, str]: ...
def verify(
    plans: str,
    source: str,
    airspace: Airspace | None = None,
    zones: Sequence[str] | None = None,
    **kwargs: Any,
) -> dict[str, Any]: ...
