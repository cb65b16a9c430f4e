//! Comparing the CSV files of sweeps, timing columns aside.

use std::path::Path;

/// The CSV at `path` without its timing columns (`planner_ms…`, which no two runs share), as
/// rows of cells.
pub fn untimed_csv(path: &Path) -> Vec<Vec<String>> {
    let text =
        std::fs::read_to_string(path).unwrap_or_else(|e| panic!("reading {}: {e}", path.display()));
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().expect("a header").split(',').collect();
    let keep: Vec<usize> = (0..header.len())
        .filter(|&i| !header[i].starts_with("planner_ms"))
        .collect();
    assert!(
        keep.len() < header.len(),
        "{} has timing columns",
        path.display()
    );
    std::iter::once(header.join(","))
        .chain(lines.map(str::to_owned))
        .map(|l| {
            let cells: Vec<&str> = l.split(',').collect();
            keep.iter().map(|&i| cells[i].to_owned()).collect()
        })
        .collect()
}

/// Asserts that the CSV `file` in the folders `a` and `b` are the same but for their timing
/// columns, and that it has runs.
pub fn same_untimed(a: &Path, b: &Path, file: &str) {
    let (x, y) = (untimed_csv(&a.join(file)), untimed_csv(&b.join(file)));
    assert!(x.len() > 1, "{}/{file} has rows", a.display());
    assert_eq!(x.len(), y.len(), "{file}: rows");
    assert_eq!(x, y, "{file}: {} differs from {}", b.display(), a.display());
}
