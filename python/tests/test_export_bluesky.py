"""`muse export bluesky` flown in BlueSky: every flight reaches its destination, near MUSE's landing.

The test simulates a small day with `muse simulate` (a 4 x 4 grid of corridors 300 m long, 30
requests in three minutes: the planner makes some drones hover and some fly waiting loops with
U-turns), exports it with `muse export bluesky`, and flies the scenario headless in BlueSky
(`python/tools/bluesky_run.py`, in a subprocess: BlueSky keeps global state). It checks that
every flight is deleted within 5 m of its destination (the scenario deletes a flight as it
passes its destination; BlueSky moves a drone about 0.4 m a step) and that its arrival drifts
from MUSE's landing by no more than the bounds below, and prints the drift and BlueSky's count
of losses of separation at a protected radius of 41.7 m (5 s at 30 km/h).

The muse binary is `$MUSE_BIN`, else `target/debug/muse` of this repository (build it first:
`cargo build --bin muse`). Without BlueSky (`pip install bluesky-simulator`) the test is
skipped. BlueSky's working folder (settings and its navigation cache) is
`$MUSE_BLUESKY_WORKDIR`, else `~/.cache/muse-bluesky`: the first run also builds the cache (20 to
60 s more); the test takes 16 to 50 s on two shared cores, by their load.

Run: `python -m pytest -s python/tests/test_export_bluesky.py`.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

pytest.importorskip(
    "bluesky",
    reason="BlueSky is not installed (pip install bluesky-simulator): nothing to fly the scenario",
)

from conftest import REPO, muse_bin

RUNNER = REPO / "python" / "tools" / "bluesky_run.py"

#: Where a flight may be deleted, at most, from its destination (metres).
MAX_DISTANCE_M = 5.0
#: Bounds of the arrival drift, BlueSky's arrival minus MUSE's landing (seconds). The
#: scenario's required times of arrival at every waypoint keep the planned times: measured on
#: this day -0.00 to +0.04 s, median +0.02 s (flown open loop, `--open-loop`, as exported
#: before: -1.35 to +11.17 s, median +1.47 s, the fly-over U-turns of waiting loops costing the
#: most).
MIN_DRIFT_S = -0.5
MAX_DRIFT_S = 0.5
MAX_MEDIAN_ABS_DRIFT_S = 0.1


def muse(*args: str, cwd: Path) -> str:
    """Runs muse; fails the test with its output if it fails."""
    done = subprocess.run(
        [str(muse_bin()), *args], cwd=cwd, capture_output=True, text=True, check=False
    )
    if done.returncode != 0:
        pytest.fail(f"muse {' '.join(args)} failed:\n{done.stdout}{done.stderr}", pytrace=False)
    return done.stdout + done.stderr


def test_every_flight_reaches_its_destination_near_its_landing(tmp_path: Path) -> None:
    muse(
        "simulate",
        "--synthetic", "grid", "--nodes", "16", "--spacing-m", "300",
        "--station-share", "0.5",
        "--count", "30", "--from", "08:00", "--to", "08:03",
        "--out", "day",
        cwd=tmp_path,
    )  # fmt: skip
    said = muse("export", "bluesky", "--plans", "day/plans.jsonl", "--out", "day.scn", cwd=tmp_path)
    print(said.strip())
    planned = [
        json.loads(line)
        for line in (tmp_path / "day" / "plans.jsonl").read_text(encoding="utf-8").splitlines()
    ]
    flying = [p["request"] for p in planned if p["status"] == "planned"]
    assert flying, "the day has no planned flight"

    figures = tmp_path / "figures.json"
    done = subprocess.run(
        [
            sys.executable, str(RUNNER), str(tmp_path / "day.scn"),
            "--radius-m", f"{5 * 30 / 3.6:.4f}", "--half-height-ft", "15",
            "--json", str(figures),
        ],
        capture_output=True, text=True, check=False, timeout=300,
    )  # fmt: skip
    assert done.returncode == 0, done.stdout + done.stderr
    print(done.stdout.strip())
    result = json.loads(figures.read_text(encoding="utf-8"))

    assert result["flights"] == len(flying)
    assert result["not_arrived"] == []
    arrivals = result["arrivals"]
    assert sorted(a["request"] for a in arrivals) == sorted(flying)
    far = [a for a in arrivals if a["distance_m"] > MAX_DISTANCE_M]
    assert far == [], f"deleted more than {MAX_DISTANCE_M} m from the destination: {far}"
    drift = result["drift_s"]
    print(
        f"arrival drift (s): min {drift['min']:+.2f}, median {drift['median']:+.2f}, "
        f"max {drift['max']:+.2f}; losses of separation: {result['los_events']} events, "
        f"{result['los_pairs']} pairs"
    )
    off = [a for a in arrivals if not MIN_DRIFT_S <= a["drift_s"] <= MAX_DRIFT_S]
    assert off == [], f"arrivals outside [{MIN_DRIFT_S}, {MAX_DRIFT_S}] s: {off}"
    median_abs = sorted(abs(a["drift_s"]) for a in arrivals)[len(arrivals) // 2]
    assert median_abs <= MAX_MEDIAN_ABS_DRIFT_S
