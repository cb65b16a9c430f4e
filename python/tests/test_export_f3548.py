"""`muse export f3548` read back with the InterUSS `uas_standards` F3548-21 types.

A small simulated day is exported, and every operational intent is parsed with
`uas_standards.astm.f3548.v21.api.OperationalIntent` (which refuses missing required fields
and values outside the standard's enums), then checked against what the standard asks of an
Accepted intent: its state and priority, UUIDv4 ids, units and altitude reference, RFC 3339
UTC times in order, outlines (one per volume, positive radius, distinct polygon vertices)
and the vertex limit. A layered day must export both layers' altitude bands.

The muse binary is `$MUSE_BIN`, else `<repo>/target/debug/muse` (build it first with
`cargo build`). Run with: `python -m pytest python/tests/test_export_f3548.py`.
"""

import json
import re
import subprocess
from datetime import datetime
from pathlib import Path

import pytest
from implicitdict import ImplicitDict
from uas_standards.astm.f3548.v21 import api, constants

from conftest import muse_bin

REQUESTS = 120
UUID4 = re.compile(r"^[0-9a-f]{8}-[0-9a-f]{4}-4[0-9a-f]{3}-[89ab][0-9a-f]{3}-[0-9a-f]{12}$")
RFC3339_Z = re.compile(r"^\d{4}-\d{2}-\d{2}T\d{2}:\d{2}:\d{2}(\.\d+)?Z$")
RESULT = re.compile(r"(\d+) of (\d+) flights' pairs intersect in 4-D at buffer ([\d.]+) m")


def muse(*args: str) -> str:
    """Runs muse; its standard output and error together."""
    done = subprocess.run(
        [str(muse_bin()), *args], capture_output=True, text=True, timeout=120, check=False
    )
    said = done.stdout + done.stderr
    assert done.returncode == 0, f"muse {' '.join(args)} exited {done.returncode}:\n{said}"
    return said


def simulate(folder: Path, *extra: str) -> Path:
    muse("simulate", "--count", str(REQUESTS), "--out", str(folder), *extra)
    plans = folder / "plans.jsonl"
    assert plans.is_file(), f"muse simulate wrote no {plans}"
    return plans


def export(plans: Path, out: Path, buffer_m: float) -> tuple[dict, tuple[int, int]]:
    """Exports at `buffer_m`: the file read back, and the pairs (intersecting, all) said."""
    said = muse("export", "f3548", "--plans", str(plans), "--buffer-m", str(buffer_m),
                "--out", str(out))
    found = RESULT.search(said)
    assert found, f"no intersection count in:\n{said}"
    assert float(found.group(3)) == buffer_m
    return json.loads(out.read_text()), (int(found.group(1)), int(found.group(2)))


def planned_requests(plans: Path) -> list[str]:
    records = [json.loads(line) for line in plans.read_text().splitlines() if line.strip()]
    return [r["request"] for r in records if r.get("path")]


def parse_time(t: api.Time) -> datetime:
    assert t.format == api.TimeFormat.RFC3339
    assert RFC3339_Z.match(str(t.value)), f"not RFC 3339 UTC with Z: {t.value}"
    return t.value.datetime


def check_volume(v: api.Volume4D, buffer_m: float) -> int:
    """Checks one volume; its polygon vertices."""
    v3 = v.volume
    circle = v3.get("outline_circle")
    polygon = v3.get("outline_polygon")
    assert (circle is None) != (polygon is None), "exactly one outline"
    vertices = 0
    if circle is not None:
        assert circle.radius.units == api.RadiusUnits.M
        assert circle.radius.value == pytest.approx(max(buffer_m, 0.01))
        assert -90 <= circle.center.lat <= 90 and -180 <= circle.center.lng <= 180
    else:
        points = [(p.lat, p.lng) for p in polygon.vertices]
        assert len(points) >= 3
        assert len(set(points)) == len(points), "vertices may not be duplicated"
        assert all(-90 <= lat <= 90 and -180 <= lng <= 180 for lat, lng in points)
        vertices = len(points)
    for a in (v3.altitude_lower, v3.altitude_upper):
        assert a.reference == api.AltitudeReference.W84
        assert a.units == api.AltitudeUnits.M
    assert v3.altitude_lower.value < v3.altitude_upper.value
    assert parse_time(v.time_start) < parse_time(v.time_end)
    return vertices


def check_intents(doc: dict, plans: Path, buffer_m: float) -> list[api.OperationalIntent]:
    entries = doc["operational_intents"]
    assert [e["request"] for e in entries] == planned_requests(plans)
    intents = []
    for entry in entries:
        oi = ImplicitDict.parse(entry["operational_intent"], api.OperationalIntent)
        ref, details = oi.reference, oi.details
        assert ref.state == api.OperationalIntentState.Accepted
        assert details.priority == 0
        assert UUID4.match(ref.id) and UUID4.match(ref.subscription_id)
        assert ref.version >= 1 and ref.manager
        assert ref.uss_base_url.startswith("https://") and not ref.uss_base_url.endswith("/")
        assert details.volumes, "an Accepted intent needs at least one volume"
        assert not details.off_nominal_volumes, "none while Accepted"
        vertices = sum(check_volume(v, buffer_m) for v in details.volumes)
        assert vertices <= constants.OiMaxVertices
        starts = [parse_time(v.time_start) for v in details.volumes]
        ends = [parse_time(v.time_end) for v in details.volumes]
        assert starts == sorted(starts)
        assert parse_time(ref.time_start) == min(starts)
        assert parse_time(ref.time_end) == max(ends)
        intents.append(oi)
    ids = [oi.reference.id for oi in intents]
    assert len(set(ids)) == len(ids), "ids are unique"
    return intents


@pytest.fixture(scope="module")
def day(tmp_path_factory) -> Path:
    return simulate(tmp_path_factory.mktemp("flat"))


def test_every_intent_of_a_day_parses_as_an_f3548_operational_intent(day, tmp_path):
    doc, (intersecting, pairs) = export(day, tmp_path / "intents.json", 10.0)
    intents = check_intents(doc, day, 10.0)
    # The paper's 20-minute battery leaves many Singapore requests out of range; a fifth or
    # more still fly.
    assert len(intents) >= REQUESTS // 5, "a small day has flights"
    n = len(intents)
    assert pairs == n * (n - 1) // 2 and 0 <= intersecting <= pairs
    bands = {
        (v.volume.altitude_lower.value, v.volume.altitude_upper.value)
        for oi in intents
        for v in oi.details.volumes
    }
    assert bands == {(57.0, 63.0)}, "one layer at 60 m, ± 3 m"


def test_a_wider_buffer_never_separates_flights(day, tmp_path):
    counts = []
    for b in (0.0, 10.0, 30.0):
        doc, (intersecting, _) = export(day, tmp_path / f"b{b}.json", b)
        check_intents(doc, day, b)
        counts.append(intersecting)
    assert counts == sorted(counts)


def test_a_layered_day_exports_both_layers_bands(tmp_path):
    plans = simulate(tmp_path / "layered", "--layers", "2")
    doc, _ = export(plans, tmp_path / "intents.json", 10.0)
    intents = check_intents(doc, plans, 10.0)
    bands = {
        (round(v.volume.altitude_lower.value, 3), round(v.volume.altitude_upper.value, 3))
        for oi in intents
        for v in oi.details.volumes
    }
    # Layer 1 at 60 m and layer 2 at 69.144 m, ± 3 m; a climb spans both.
    assert (57.0, 63.0) in bands
    assert (66.144, 72.144) in bands
    assert (57.0, 72.144) in bands
    assert bands <= {(57.0, 63.0), (66.144, 72.144), (57.0, 72.144)}
