"""The service's archive files open in pandas (docs/service.md#retention-without-forgetting):
``muse serve --archive-after-days 1`` answers a day of requests, is started again two days
later on its clock, and moves that day to ``archive/flights-DAY.csv.gz`` and
``events-DAY.csv.gz``; pandas reads both as they are, with the ``flights`` table's columns and
one row per flight answered, and the service still answers each archived id."""

import json
import signal
import subprocess
import time
import urllib.error
import urllib.request

import pandas as pd

from conftest import muse_bin

DAY_ONE = "2026-03-02T06:00:00+08:00"
TWO_DAYS_LATER = "2026-03-04T06:00:00+08:00"
FLIGHTS = 24


def serve(data, clock):
    """Starts ``muse serve`` on ``data`` with its clock at ``clock``; returns (process, base URL)."""
    p = subprocess.Popen(
        [str(muse_bin()), "serve", "--listen", "127.0.0.1:0", "--data", str(data),
         "--clock", clock, "--archive-after-days", "1"],
        stdout=subprocess.PIPE, text=True,
    )
    for line in p.stdout:
        if line.startswith("listening on "):
            return p, line.split()[-1]
    raise AssertionError(f"muse serve ended: {p.wait()}")


def stop(p):
    p.send_signal(signal.SIGTERM)
    assert p.wait(timeout=20) == 0


def call(base, path, body=None):
    request = urllib.request.Request(
        base + path,
        data=None if body is None else json.dumps(body).encode(),
        headers={"content-type": "application/json"},
        method="GET" if body is None else "POST",
    )
    try:
        with urllib.request.urlopen(request, timeout=20) as r:
            return r.status, json.load(r)
    except urllib.error.HTTPError as e:
        return e.code, json.load(e)


def test_archive_files_open_in_pandas(tmp_path):
    data = tmp_path / "data"
    p, base = serve(data, DAY_ONE)
    try:
        _, airspace = call(base, "/v1/airspace")
        stations = [f["properties"]["id"] for f in airspace["features"]
                    if f["properties"].get("kind") == "station"]
        answers = {}
        for k in range(FLIGHTS):
            body = {
                "id": f"a{k}",
                "origin": stations[k],
                "destination": stations[k + 1],
                # 06:10 to about 15:00 on day one: every flight lands that day.
                "departure": f"2026-03-02T{6 + k * 22 // 60:02d}:{(10 + k * 22) % 60:02d}:00+08:00",
            }
            code, answer = call(base, "/v1/flights", body)
            assert code in (200, 201), answer
            answers[body["id"]] = answer
    finally:
        stop(p)

    p, base = serve(data, TWO_DAYS_LATER)
    try:
        flights = data / "archive" / "flights-2026-03-02.csv.gz"
        for _ in range(200):
            _, listed = call(base, "/v1/flights")
            if not listed["flights"]:
                break
            time.sleep(0.05)
        assert listed["flights"] == [], "every flight of day one is archived"
        table = pd.read_csv(flights)
        assert list(table.columns) == [
            "seq", "id", "operator", "origin", "destination", "departure_ms", "answered_ms",
            "plan", "reason", "free_flow_ms", "expanded", "status", "takeoff_ms",
            "landing_ms", "holds_until_ms", "cancelled_ms", "changes", "crc",
        ]
        assert sorted(table["id"]) == sorted(answers)
        assert list(table["seq"]) == list(range(1, FLIGHTS + 1))
        planned = table[table["status"] == "planned"]
        assert len(planned) == sum(a["status"] == "planned" for a in answers.values())
        assert all(json.loads(plan)[0][0] == origin
                   for plan, origin in zip(planned["plan"], planned["origin"]))
        events = pd.read_csv(data / "archive" / "events-2026-03-02.csv.gz")
        assert set(events["flight_seq"]) == set(planned["seq"])
        # Archived, and still answered as first answered.
        for flight_id, answer in answers.items():
            assert call(base, f"/v1/flights/{flight_id}") == (200, answer)
    finally:
        stop(p)
