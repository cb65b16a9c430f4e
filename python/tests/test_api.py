"""``import muse``: the package plans, simulates and verifies exactly as the command line
does, takes lists of dicts and DataFrames, and raises the command line's messages."""

import json
import pathlib

import pandas as pd
import pytest

import muse

SEED = 11


def _without_timing(summary: dict) -> dict:
    """A summary without the fields that measure this run's wall time."""
    return {k: v for k, v in summary.items() if k != "planner_time"}


def test_simulate_is_muse_simulate(tmp_path, muse_cli):
    print(f"seed {SEED}")
    day = muse.simulate(count=300, seed=SEED)
    muse_cli("simulate", "--count", 300, "--seed", SEED, "--out", tmp_path / "cli")
    cli = tmp_path / "cli"
    assert day.files["plans.jsonl"] == (cli / "plans.jsonl").read_text()
    assert day.files["flights.csv"] == (cli / "flights.csv").read_text()
    assert day.files["stays.csv"] == (cli / "stays.csv").read_text()
    expected = json.loads((cli / "summary.json").read_text())
    assert _without_timing(day.summary) == _without_timing(expected)
    # The tables as DataFrames: one row per request, instants with their offset.
    assert len(day.flights) == 300 == len(day.plans)
    planned = day.flights[day.flights.status == "planned"]
    assert len(planned) == day.summary["planned"] > 0
    assert str(planned.takeoff.dt.tz) == "UTC+08:00"
    assert (planned.landing >= planned.takeoff).all()
    assert set(day.stays.request) == set(planned.request)


def test_verify_accepts_a_day_and_finds_a_conflict(tmp_path):
    day = muse.simulate(count=200, seed=SEED)
    checked = muse.verify(day)
    assert checked.ok and bool(checked)
    assert checked.flights == day.summary["planned"]
    assert checked.lines == 200 and checked.violations == []
    # The same day read back from files.
    day.write(tmp_path / "day")
    assert muse.verify(tmp_path / "day" / "plans.jsonl").ok
    # Two copies of one flight under two ids meet everywhere on their path.
    flown = next(p for p in day.plans if p["status"] == "planned")
    twin = dict(flown, request=flown["request"] + "-twin")
    found = muse.verify([flown, twin])
    assert not found.ok
    assert found.flights == 2
    assert any(flown["path"][0]["node"] in v for v in found.violations), found.violations
    # Flown on one path, the twins are 0 m apart: the separation report says so.
    assert found.separation["closest_m"] == 0.0
    assert found.separation["pairs_under_m"] == {"10": 1, "20": 1, "30": 1}


def test_separation_keeps_the_flights_apart_in_metres():
    # The default day: 45 pairs closer than 30 m without the rule.
    day = muse.simulate(count=5000, seed=1, separation_m=30)
    assert day.params["separation_m"] == 30
    checked = muse.verify(day)
    assert checked.ok, checked
    assert checked.separation["pairs_under_m"]["30"] == 0
    assert checked.separation["closest_m"] >= 30
    plain = muse.simulate(count=5000, seed=1)
    # Checked with the rule, the day planned without it breaks it wherever it comes close.
    broken = muse.verify(plain, separation_m=30)
    under = muse.verify(plain).separation["pairs_under_m"]["30"]
    assert under == 45 and len(broken.violations) == under
    with pytest.raises(muse.MuseError, match="separation_m: 1001"):
        muse.simulate(count=10, separation_m=1001)


def test_plan_reads_dicts_dataframes_and_files(tmp_path, muse_cli):
    rows = [
        {"id": "r1", "origin": "S001", "destination": "S002", "departure": "08:00"},
        {"id": "r2", "origin": "S002", "destination": "S001", "departure": "08:00:30"},
        {"id": "r3", "origin": "S003", "destination": "S010", "departure": "09:15"},
    ]
    from_dicts = muse.plan(rows)
    frame = pd.DataFrame(rows)
    frame["departure"] = pd.to_datetime(
        ["2026-01-05T08:00:00+08:00", "2026-01-05T08:00:30+08:00", "2026-01-05T09:15:00+08:00"]
    )
    from_frame = muse.plan(frame)
    assert from_frame.files["plans.jsonl"] == from_dicts.files["plans.jsonl"]
    path = tmp_path / "requests.csv"
    path.write_text(
        "id,origin,destination,departure\n"
        + "".join(f"{r['id']},{r['origin']},{r['destination']},{r['departure']}\n" for r in rows)
    )
    from_file = muse.plan(path)
    muse_cli("plan", "--requests", path, "--out", tmp_path / "cli")
    assert from_file.files["plans.jsonl"] == (tmp_path / "cli" / "plans.jsonl").read_text()
    assert from_file.files["plans.jsonl"] == from_dicts.files["plans.jsonl"]
    assert list(from_dicts.flights.request) == ["r1", "r2", "r3"]


def test_errors_carry_the_command_lines_messages(tmp_path, muse_cli):
    path = tmp_path / "requests.csv"
    path.write_text("id,origin,destination,departure\nr1,S001,S999,08:00\n")
    cli = muse_cli("plan", "--requests", path, "--out", tmp_path / "out", check=False)
    assert cli.returncode == 2
    with pytest.raises(muse.MuseError) as raised:
        muse.plan(path)
    assert cli.stderr.strip() == f"error: {raised.value}"
    assert "line 2" in str(raised.value) and "destination" in str(raised.value)
    # Rows given in memory are named `requests`, their lines counted as in the file.
    with pytest.raises(muse.MuseError, match=r"^requests: line 2: field `destination`"):
        muse.plan([{"id": "r1", "origin": "S001", "destination": "S999", "departure": "08:00"}])
    with pytest.raises(muse.MuseError, match="unknown column"):
        muse.plan([{"id": "r1", "from": "S001", "destination": "S002", "departure": "08:00"}])
    # The command line's ranges, in the same words.
    with pytest.raises(muse.MuseError) as raised:
        muse.simulate(count=10, speed_kmh=5000)
    assert str(raised.value) == "speed_kmh: 5000 must be a speed in km/h from 1 to 1000"
    cli = muse_cli("simulate", "--speed-kmh", 5000, check=False)
    assert cli.returncode == 2 and "must be a speed in km/h from 1 to 1000" in cli.stderr
    with pytest.raises(muse.MuseError, match="layers 65: must be a whole number of layers"):
        muse.simulate(count=10, layers=65)
    with pytest.raises(muse.MuseError, match="unknown parameter `speedkmh`"):
        muse.simulate(count=10, speedkmh=30)
    with pytest.raises(muse.MuseError, match="heading_rule"):
        muse.simulate(count=10, layers=2, heading_rule="north")
    assert issubclass(muse.MuseError, ValueError)


def test_layers_and_parameters_reach_the_planner():
    layered = muse.simulate(count=200, seed=SEED, layers=2, heading_rule="sectors")
    assert "layer" in layered.stays.columns
    assert set(layered.stays.layer) == {1, 2}
    assert layered.summary["world"]["layers"]["count"] == 2
    assert muse.verify(layered).ok
    fast = muse.simulate(count=200, seed=SEED, speed_kmh=60)
    assert fast.summary["parameters"]["speed_kmh"] == 60
    assert fast.summary["planned"] > muse.simulate(count=200, seed=SEED).summary["planned"]


def test_airspace_from_pads_is_muse_airspace_build(tmp_path, muse_cli):
    pads = pd.DataFrame(
        {
            "id": ["A", "B", "C", "D"],
            "lon": [103.800, 103.810, 103.800, 103.812],
            "lat": [1.300, 1.300, 1.310, 1.311],
        }
    )
    airspace = muse.Airspace.from_pads(pads)
    assert airspace.station_count == 4
    assert list(airspace.nodes.id) == ["A", "B", "C", "D"]
    assert len(airspace.edges) >= 3
    pads.to_csv(tmp_path / "pads.csv", index=False)
    muse_cli("airspace", "build", "--pads", tmp_path / "pads.csv", "--out", tmp_path / "a.geojson")
    assert airspace.to_geojson() == (tmp_path / "a.geojson").read_text()
    read = muse.Airspace.read(tmp_path / "a.geojson")
    day = muse.plan(
        [{"id": "r1", "origin": "A", "destination": "D", "departure": "08:00"}], airspace=read
    )
    assert day.summary["planned"] == 1
    assert muse.verify(day).ok
    with pytest.raises(muse.MuseError, match="pads"):
        muse.Airspace.from_pads([{"id": "A", "lon": 103.8, "lat": 1.3}])


def test_an_airspace_in_vienna_plans_on_vienna_time(tmp_path, muse_cli):
    pads = pathlib.Path(__file__).resolve().parents[2] / "examples" / "vienna-pads.csv"
    airspace = muse.Airspace.from_pads(pads, time_zone="Europe/Vienna")
    muse_cli(
        "airspace", "build", "--pads", pads, "--time-zone", "Europe/Vienna",
        "--out", tmp_path / "v.geojson",
    )
    assert airspace.to_geojson() == (tmp_path / "v.geojson").read_text()
    ids = list(airspace.nodes.id)
    day = muse.plan(
        [{"id": "r1", "origin": ids[0], "destination": ids[1], "departure": "09:30"}],
        airspace=muse.Airspace.read(tmp_path / "v.geojson"),
    )
    assert day.plans[0]["requested_departure"] == "2026-01-05T09:30:00.000+01:00"
    summer = muse.Airspace.from_pads(pads, time_zone="Europe/Vienna", date="2026-07-06")
    assert '"utc_offset": "+02:00"' in summer.to_geojson()
    with pytest.raises(muse.MuseError, match="time_zone: `Mars/Olympus` is not a time zone"):
        muse.Airspace.from_pads(pads, time_zone="Mars/Olympus")
    with pytest.raises(muse.MuseError, match="date: a date needs a time zone"):
        muse.Airspace.from_pads(pads, date="2026-07-06")


def test_zones_none_and_files(tmp_path):
    # The default's CBD zone closes 10:00-12:00: a flight through it waits or goes round.
    own = muse.simulate(count=300, seed=SEED, start="10:00", end="12:00")
    open_sky = muse.simulate(count=300, seed=SEED, start="10:00", end="12:00", zones=[])
    assert own.summary["provenance"]["zones"] != []
    assert open_sky.summary["provenance"]["zones"] == []
    assert muse.verify(own).ok
    # Planned without the zone, the day breaks it when checked with it.
    broken = muse.verify(open_sky.plans)
    assert not broken.ok
    assert all(v.startswith("zone rule violated") for v in broken.violations)
    with pytest.raises(muse.MuseError, match="missing.geojson"):
        muse.simulate(count=10, zones=[tmp_path / "missing.geojson"])


def test_bad_counts_seeds_and_missing_files_raise_muse_error(tmp_path, muse_cli):
    # `count` and `seed` take the values `--count` and `--seed` take, refused in their words.
    requests = "must be a whole number of requests from 1 to 10000000"
    cli = muse_cli("simulate", "--count", 0, "--out", tmp_path / "zero", check=False)
    assert cli.returncode == 2 and requests in cli.stderr
    for count in (0, -5, 10**7 + 1, 10**30, 2.5):
        with pytest.raises(muse.MuseError) as raised:
            muse.simulate(count=count)
        assert str(raised.value) == f"count {count}: {requests}"
    seeds = "must be a whole number from 0 to 18446744073709551615"
    cli = muse_cli("simulate", "--seed", -1, "--out", tmp_path / "seed", check=False)
    assert cli.returncode == 2 and seeds in cli.stderr
    for seed in (-1, 2**64):
        with pytest.raises(muse.MuseError) as raised:
            muse.simulate(count=10, seed=seed)
        assert str(raised.value) == f"seed {seed}: {seeds}"
    # The largest seed is a seed.
    assert muse.simulate(count=10, seed=2**64 - 1).summary["provenance"]["seed"] == 2**64 - 1
    # A file that is not there: the command line's message, naming the file.
    missing = tmp_path / "missing.csv"
    cli = muse_cli("plan", "--requests", missing, "--out", tmp_path / "out", check=False)
    assert cli.returncode == 2
    with pytest.raises(muse.MuseError) as raised:
        muse.plan(missing)
    assert cli.stderr.strip() == f"error: {raised.value}"
    assert str(missing) in str(raised.value)
    with pytest.raises(muse.MuseError, match="missing.jsonl: cannot read"):
        muse.verify(tmp_path / "missing.jsonl")
    with pytest.raises(muse.MuseError, match="missing-pads.csv: cannot read"):
        muse.Airspace.from_pads(tmp_path / "missing-pads.csv")


def test_pads_across_the_180th_meridian_are_refused():
    fiji = [
        {"id": "F1", "lon": 179.95, "lat": -17.0},
        {"id": "F2", "lon": -179.95, "lat": -17.05},
        {"id": "F3", "lon": 179.9, "lat": -17.1},
    ]
    with pytest.raises(muse.MuseError, match="both sides of the ±180° meridian"):
        muse.Airspace.from_pads(fiji)
