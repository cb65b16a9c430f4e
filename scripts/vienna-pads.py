#!/usr/bin/env python3
"""Derives examples/vienna-pads.csv from data/vienna/wienerlinien-ogd-haltestellen.csv.

The rule, so that the pads spread over the city as Singapore's 77 stations do: the public
transport stops of the file in the municipality of Vienna (`Municipality` is `Wien`) are put in
the cells of a grid of 0.04 degrees of longitude by 0.025 of latitude (about 3 km by 2.8 km at
48.2 degrees north) anchored at 16.0 E, 48.0 N; in each cell the stop nearest the cell's centre
(in degrees, ties to the smaller DIVA number) is a pad, named after the stop. Ids are `W` and
the stop's DIVA number. Run from the repository root: python3 scripts/vienna-pads.py
"""

import csv
import math

SOURCE = "data/vienna/wienerlinien-ogd-haltestellen.csv"
OUT = "examples/vienna-pads.csv"
CELL = (0.04, 0.025)
ANCHOR = (16.0, 48.0)


def main() -> None:
    best = {}
    with open(SOURCE, encoding="utf-8", newline="") as f:
        for row in csv.DictReader(f, delimiter=";"):
            if row["Municipality"] != "Wien":
                continue
            lon, lat = float(row["Longitude"]), float(row["Latitude"])
            cell = (
                math.floor((lon - ANCHOR[0]) / CELL[0]),
                math.floor((lat - ANCHOR[1]) / CELL[1]),
            )
            centre = (
                ANCHOR[0] + (cell[0] + 0.5) * CELL[0],
                ANCHOR[1] + (cell[1] + 0.5) * CELL[1],
            )
            key = (math.hypot(lon - centre[0], lat - centre[1]), int(row["DIVA"]))
            if cell not in best or key < best[cell][0]:
                best[cell] = (key, row)
    rows = sorted((r for _, r in best.values()), key=lambda r: int(r["DIVA"]))
    with open(OUT, "w", encoding="utf-8", newline="") as f:
        out = csv.writer(f, lineterminator="\n")
        out.writerow(["id", "lon", "lat", "name"])
        for r in rows:
            out.writerow([f"W{r['DIVA']}", r["Longitude"], r["Latitude"], r["PlatformText"]])
    print(f"wrote {OUT}: {len(rows)} pads")


if __name__ == "__main__":
    main()
