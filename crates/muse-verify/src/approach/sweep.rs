//! Which pieces of different flights can come within a distance of each other: a sweep over
//! time in windows, each piece's stretch in a window boxed and put in the cells of a grid it
//! touches, so that only pieces sharing a cell in a window are compared exactly.
//!
//! Two pieces closer than `r` at an instant of a window have boxes, grown by `r/2` on every
//! side, that overlap; each such pair is compared once per window, in the cell holding the
//! lower-left corner of the overlap of their boxes. The work grows with the pieces and the
//! pairs of pieces near each other, not with the square of the flights.

use super::pair::closest;
use super::track::Piece;

/// Seconds per window of the sweep.
const WINDOW_S: f64 = 10.0;

/// Calls `found(a, b, distance, instant)` for every pair of pieces of different flights whose
/// closest approach within some window is under `reach` metres (with vertical separation
/// `vertical`),
/// once per window; `pieces` sorted by start.
pub fn near_pairs(
    pieces: &[Piece],
    reach: f64,
    vertical: f64,
    mut found: impl FnMut(usize, usize, f64, f64),
) {
    let Some(first) = pieces.first() else { return };
    let cell = reach.max(25.0);
    let grow = reach / 2.0;
    let mut start = (first.t0 / WINDOW_S).floor() * WINDOW_S;
    let mut next = 0usize;
    let mut active: Vec<usize> = Vec::new();
    // The grown box of each piece in the window, and the cells each touches.
    let mut boxes: Vec<(usize, [f64; 4])> = Vec::new();
    let mut cells: Vec<u128> = Vec::new();
    while next < pieces.len() || !active.is_empty() {
        let end = start + WINDOW_S;
        while next < pieces.len() && pieces[next].t0 < end {
            active.push(next);
            next += 1;
        }
        active.retain(|&i| pieces[i].t1 >= start);
        if active.is_empty() {
            if next < pieces.len() {
                start = (pieces[next].t0 / WINDOW_S).floor() * WINDOW_S;
            }
            continue;
        }
        boxes.clear();
        cells.clear();
        for &i in &active {
            let piece = &pieces[i];
            let (lo, hi) = (piece.t0.max(start), piece.t1.min(end));
            if lo > hi {
                continue;
            }
            let (first, last) = (piece.at(lo), piece.at(hi));
            let bbox = [
                first[0].min(last[0]) - grow,
                first[1].min(last[1]) - grow,
                first[0].max(last[0]) + grow,
                first[1].max(last[1]) + grow,
            ];
            let k = boxes.len() as u32;
            boxes.push((i, bbox));
            for cx in cell_of(bbox[0], cell)..=cell_of(bbox[2], cell) {
                for cy in cell_of(bbox[1], cell)..=cell_of(bbox[3], cell) {
                    cells.push(packed(cx, cy, k));
                }
            }
        }
        cells.sort_unstable();
        for run in cells.chunk_by(|a, b| a >> 32 == b >> 32) {
            let (cx, cy, _) = unpacked(run[0]);
            for (m, &a) in run.iter().enumerate() {
                let (i, bi) = boxes[unpacked(a).2 as usize];
                for &b in &run[m + 1..] {
                    let (j, bj) = boxes[unpacked(b).2 as usize];
                    if pieces[i].flight == pieces[j].flight {
                        continue;
                    }
                    let (x0, y0) = (bi[0].max(bj[0]), bi[1].max(bj[1]));
                    if x0 > bi[2].min(bj[2]) || y0 > bi[3].min(bj[3]) {
                        continue;
                    }
                    if (cell_of(x0, cell), cell_of(y0, cell)) != (cx, cy) {
                        continue;
                    }
                    if let Some((d, t)) = closest(&pieces[i], &pieces[j], start, end, vertical)
                        && d < reach
                    {
                        found(i, j, d, t);
                    }
                }
            }
        }
        start = end;
    }
}

/// A cell and a box number in one sortable number: cells in order, then boxes.
fn packed(cx: i64, cy: i64, k: u32) -> u128 {
    let bias = |c: i64| u128::from((c as i32 as u32) ^ 0x8000_0000);
    (bias(cx) << 64) | (bias(cy) << 32) | u128::from(k)
}

/// The cell and box number of [`packed`].
fn unpacked(v: u128) -> (i64, i64, u32) {
    let unbias = |b: u128| i64::from(((b as u32) ^ 0x8000_0000) as i32);
    (unbias(v >> 64), unbias(v >> 32), v as u32)
}

/// The grid cell of a coordinate.
fn cell_of(x: f64, cell: f64) -> i64 {
    (x / cell).floor() as i64
}
