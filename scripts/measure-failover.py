#!/usr/bin/env python3
"""Measures `muse serve` on PostgreSQL as docs/service.md reports it, in one run:

- ``load``: ``muse load`` closed loop (16 clients) and paced (2,000 requests/s by 16 clients)
  against a fresh SQLite data folder, through the leader of a fresh PostgreSQL store (one
  standby following), and through that standby (its writes sent on to the leader); the modes
  interleaved, ``--reps`` times.
- ``takeover``: a leader is filled with ``--flights`` flights booked ahead (all still holding
  their reservations: departures spread over ``--horizon-days``), two standbys are started on
  the same store, then the leader is killed with SIGKILL ``--kills`` times: the time from the
  kill to a standby saying ``"role": "leader"`` on ``/healthz`` (the take-over) and to its first
  answered ``POST /v1/flights`` (writes again) is recorded; the killed process is started again
  (a standby) and the next kill waits until it is loaded. ``--world`` options choose the
  airspace (a million flights over 30 days need more than the 77 stations:
  ``--world='--scenario singapore-all'``).

- ``archive``: a week of traffic (``--per-day`` requests a day, Singapore uniform pairs,
  departures within the day) on a SQLite folder and on a PostgreSQL store, each day a service
  started with its clock at 06:00 that day and ``--archive-after-days 1``: the store's bytes at
  each start (once the pass has run) and the archive files' bytes per day.

Loopback only; every process it starts is stopped by its own id. The PostgreSQL server is
given by ``--pg URL`` (a role that may create databases): each run uses a fresh database.

  scripts/measure-failover.py load --muse target/release/muse --pg postgres://muse@127.0.0.1:55432/muse --out out/failover
  scripts/measure-failover.py takeover --muse target/release/muse --pg postgres://muse@127.0.0.1:55432/muse --out out/failover
"""

import argparse
import json
import os
import pathlib
import shlex
import signal
import statistics
import subprocess
import tempfile
import time
import urllib.error
import urllib.request

STARTED = []


def fresh_db(admin, name):
    """A new, empty database `name` on the server of `admin`: its URL."""
    for sql in (f'DROP DATABASE IF EXISTS "{name}"', f'CREATE DATABASE "{name}"'):
        subprocess.run(["psql", "-q", admin, "-c", sql], check=True, capture_output=True)
    return admin.rsplit("/", 1)[0] + "/" + name


def serve(muse, log, *args):
    """Starts `muse serve` on a free loopback port; returns (process, base URL, seconds to
    "listening on")."""
    started = time.monotonic()
    out = open(log, "w")
    p = subprocess.Popen(
        [muse, "serve", "--listen", "127.0.0.1:0", "--rate-limit", "0", *args],
        stdout=subprocess.PIPE, stderr=out, text=True,
    )
    STARTED.append(p)
    for line in p.stdout:
        out.write(line)
        out.flush()
        if line.startswith("listening on "):
            base = line.split()[-1]
            # Keep draining stdout.
            subprocess.Popen(["cat"], stdin=p.stdout, stdout=out)
            return p, base, time.monotonic() - started
    raise SystemExit(f"muse serve ended ({p.wait()}): see {log}")


def kill9(p):
    p.send_signal(signal.SIGKILL)
    p.wait()


def get(base, path, timeout=2.0):
    try:
        with urllib.request.urlopen(base + path, timeout=timeout) as r:
            return r.status, json.load(r)
    except urllib.error.HTTPError as e:
        return e.code, None
    except (urllib.error.URLError, OSError, ValueError):
        return None, None


def post(base, body, timeout=5.0):
    request = urllib.request.Request(
        base + "/v1/flights", data=json.dumps(body).encode(),
        headers={"content-type": "application/json"}, method="POST",
    )
    try:
        with urllib.request.urlopen(request, timeout=timeout) as r:
            return r.status
    except urllib.error.HTTPError as e:
        return e.code
    except (urllib.error.URLError, OSError):
        return None


def rss_mb(p):
    try:
        for line in open(f"/proc/{p.pid}/status"):
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024
    except OSError:
        pass
    return float("nan")


def load(muse, out, base, mode, seconds, label):
    args = ["--clients", "16", "--duration", str(seconds), "--no-verify"]
    if mode == "paced":
        args += ["--rate", "2000"]
    report = out / f"{label}-{mode}.json"
    subprocess.run([muse, "load", "--url", base, *args, "--out", str(report)],
                   check=True, capture_output=True)
    r = json.load(open(report))
    lat = r["latency_ms"]
    return {
        "store": label, "mode": mode,
        "answered_per_s": round(r["throughput"]["answered_per_s"]),
        "errors": r["counts"]["errors"],
        "p50_ms": round(lat["p50_ms"], 3), "p99_ms": round(lat["p99_ms"], 3),
        "p99_9_ms": round(lat["p99_9_ms"], 3), "max_ms": round(lat["max_ms"], 3),
    }


def measure_load(a):
    out = pathlib.Path(a.out)
    rows = []
    for rep in range(a.reps):
        for mode in ("closed", "paced"):
            for label in ("sqlite", "pg-leader", "pg-standby"):
                procs = []
                if label == "sqlite":
                    data = tempfile.mkdtemp(prefix="muse-measure-")
                    p, base, _ = serve(a.muse, out / f"{label}-{mode}-{rep}.log", "--data", data)
                    procs.append(p)
                    target = base
                else:
                    url = fresh_db(a.pg, f"measure_{mode}_{rep}_{label.replace('-', '_')}")
                    p, leader, _ = serve(a.muse, out / f"{label}-{mode}-{rep}-a.log", "--store", url)
                    q, standby, _ = serve(a.muse, out / f"{label}-{mode}-{rep}-b.log", "--store", url)
                    procs += [p, q]
                    target = leader if label == "pg-leader" else standby
                row = load(a.muse, out, target, mode, a.seconds, f"{label}-{rep}")
                row["rep"] = rep
                rows.append(row)
                print(json.dumps(row), flush=True)
                for p in procs:
                    kill9(p)
    json.dump(rows, open(out / "load.json", "w"), indent=1)


def leader_of(bases):
    for i, b in enumerate(bases):
        if b is None:
            continue
        code, h = get(b, "/healthz", timeout=0.5)
        if code == 200 and h and h.get("role") == "leader":
            return i
    return None


def measure_takeover(a):
    out = pathlib.Path(a.out)
    url = fresh_db(a.pg, "measure_takeover")
    common = ["--store", url, "--booking-horizon-days", str(a.horizon_days), *a.world]
    procs = [None, None, None]
    bases = [None, None, None]
    procs[0], bases[0], _ = serve(a.muse, out / "takeover-0.log", *common)
    _, airspace = get(bases[0], "/v1/airspace")
    stations = [f["properties"]["id"] for f in airspace["features"]
                if f["properties"].get("kind") == "station"]
    # Fill: in-range pairs, departures spread over the horizon, until enough flights are held.
    lead = f"1:{min(a.horizon_days * 1440 - 60, 43_200)}"
    filled_at = time.monotonic()
    while True:
        _, h = get(bases[0], "/healthz")
        held = h["flights_held"]
        print(f"fill: {held} flights held, {h['flights']} stored", flush=True)
        if held >= a.flights:
            break
        count = min(200_000, max(10_000, int((a.flights - held) * 1.1)))
        subprocess.run(
            [a.muse, "load", "--url", bases[0], "--clients", "16", "--count", str(count),
             "--od", "in-range", "--lead-min", lead, "--no-verify", "--seed", str(held),
             "--out", str(out / "fill.json")],
            check=True, capture_output=True,
        )
    fill_s = time.monotonic() - filled_at
    for i in (1, 2):
        procs[i], bases[i], loaded = serve(a.muse, out / f"takeover-{i}.log", *common)
        print(f"standby {i} ready in {loaded:.1f} s, {rss_mb(procs[i]):.0f} MB", flush=True)
    takeovers, writes, reloads = [], [], []
    for k in range(a.kills):
        old = leader_of(bases)
        assert old is not None, "a leader"
        _, h = get(bases[old], "/healthz")
        killed = time.monotonic()
        kill9(procs[old])
        bases[old] = None
        new = None
        while new is None:
            new = leader_of(bases)
            if time.monotonic() - killed > 60:
                raise SystemExit("no take-over within 60 s")
        took = time.monotonic() - killed
        body = {"id": f"takeover-probe-{k}", "origin": stations[0], "destination": stations[1],
                "departure": time.strftime("%Y-%m-%dT%H:%M:%S+00:00",
                                           time.gmtime(time.time() + 7200))}
        while post(bases[new], body) not in (200, 201):
            time.sleep(0.002)
        wrote = time.monotonic() - killed
        takeovers.append(took)
        writes.append(wrote)
        _, h2 = get(bases[new], "/healthz")
        print(f"kill {k}: instance {old} killed, instance {new} leads after {took * 1e3:.0f} ms, "
              f"answers a write after {wrote * 1e3:.0f} ms; {h2['flights_held']} flights held, "
              f"{rss_mb(procs[new]):.0f} MB", flush=True)
        procs[old], bases[old], loaded = serve(a.muse, out / f"takeover-{old}-{k}.log", *common)
        reloads.append(loaded)
    result = {
        "flights_held": h2["flights_held"], "fill_s": round(fill_s, 1), "kills": a.kills,
        "takeover_ms": {"p50": round(statistics.median(takeovers) * 1e3, 1),
                        "max": round(max(takeovers) * 1e3, 1),
                        "all": [round(t * 1e3, 1) for t in takeovers]},
        "first_write_ms": {"p50": round(statistics.median(writes) * 1e3, 1),
                           "max": round(max(writes) * 1e3, 1)},
        "standby_start_s": {"p50": round(statistics.median(reloads), 1),
                            "max": round(max(reloads), 1)},
    }
    print(json.dumps(result, indent=1))
    json.dump(result, open(out / "takeover.json", "w"), indent=1)


def store_bytes(store):
    """The bytes a store takes: the SQLite database and its WAL, or PostgreSQL's tables with
    their indexes."""
    kind, where = store
    if kind == "sqlite":
        return sum(os.path.getsize(os.path.join(where, f))
                   for f in ("muse.db", "muse.db-wal") if os.path.exists(os.path.join(where, f)))
    sql = ("SELECT sum(pg_total_relation_size(c)) FROM unnest(ARRAY['flights','events','zones',"
           "'meta','lease','archived','archived_events']::regclass[]) c")
    out = subprocess.run(["psql", "-qAt", where, "-c", sql], check=True, capture_output=True,
                         text=True)
    return int(out.stdout.strip())


def measure_archive(a):
    out = pathlib.Path(a.out)
    rows = []
    for kind in ("sqlite", "postgres"):
        archive = tempfile.mkdtemp(prefix="muse-archive-")
        if kind == "sqlite":
            where = tempfile.mkdtemp(prefix="muse-measure-")
            args = ["--data", where]
        else:
            where = fresh_db(a.pg, "measure_archive")
            args = ["--store", where]
        for day in range(a.days + 1):
            clock = time.strftime("%Y-%m-%dT06:00:00+08:00",
                                  time.gmtime(time.mktime((2026, 3, 2 + day, 0, 0, 0, 0, 0, 0))))
            p, base, _ = serve(a.muse, out / f"archive-{kind}-{day}.log", *args, "--clock", clock,
                               "--archive-after-days", "1", "--archive-dir", archive)
            # The start's pass (a day of flights: well under a second here).
            time.sleep(2)
            files = {f: os.path.getsize(os.path.join(archive, f)) for f in os.listdir(archive)}
            _, health = get(base, "/healthz")
            row = {"store": kind, "day": day, "store_bytes": store_bytes((kind, where)),
                   "flights_stored": health["flights"],
                   "archive_bytes": sum(files.values()), "archive_files": len(files)}
            if day < a.days:
                subprocess.run(
                    [a.muse, "load", "--url", base, "--clients", "16", "--count",
                     str(a.per_day), "--lead-min", "1:600", "--no-verify", "--seed", str(day),
                     "--id-prefix", f"d{day}-", "--out", str(out / "archive-load.json")],
                    check=True, capture_output=True)
                row["store_bytes_after_load"] = store_bytes((kind, where))
            print(json.dumps(row), flush=True)
            rows.append(row)
            p.send_signal(signal.SIGTERM)
            p.wait()
        per_day = sorted({(f, os.path.getsize(os.path.join(archive, f))) for f in os.listdir(archive)})
        print(json.dumps({"store": kind, "files": per_day}), flush=True)
        rows.append({"store": kind, "files": per_day})
    json.dump(rows, open(out / "archive.json", "w"), indent=1)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("what", choices=["load", "takeover", "archive"])
    parser.add_argument("--muse", required=True)
    parser.add_argument("--pg", required=True, help="a PostgreSQL URL whose role may create databases")
    parser.add_argument("--out", required=True)
    parser.add_argument("--reps", type=int, default=2)
    parser.add_argument("--seconds", type=int, default=20)
    parser.add_argument("--flights", type=int, default=1_000_000)
    parser.add_argument("--horizon-days", type=int, default=30)
    parser.add_argument("--world", default="",
                        help="options of the world served, e.g. --world='--scenario singapore-all'")
    parser.add_argument("--kills", type=int, default=20)
    parser.add_argument("--days", type=int, default=7)
    parser.add_argument("--per-day", type=int, default=10_000)
    a = parser.parse_args()
    a.world = shlex.split(a.world)
    os.makedirs(a.out, exist_ok=True)
    try:
        {"load": measure_load, "takeover": measure_takeover, "archive": measure_archive}[a.what](a)
    finally:
        for p in STARTED:
            if p.poll() is None:
                kill9(p)


if __name__ == "__main__":
    main()
