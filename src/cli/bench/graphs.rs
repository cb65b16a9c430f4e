//! The graphs `muse bench` measures: built-in scenarios by name, and synthetic geometric
//! graphs `synthetic-N`.

use std::borrow::Cow;

use anyhow::Context as _;
use muse_model::{Airspace, UtcOffset, Zone};
use muse_sim::experiment::bench::grouped;

/// Synthetic graphs of `--graphs synthetic-N`: geometric layout, this share of stations,
/// this spacing and seed.
const SYNTHETIC_STATION_SHARE: f64 = 0.1;
const SYNTHETIC_SPACING_M: f64 = 1_500.0;
const SYNTHETIC_SEED: u64 = 1;
/// The smallest synthetic graph: 10% of it must give at least two stations.
const SYNTHETIC_MIN_NODES: usize = 20;
/// The largest synthetic graph the generator builds.
const SYNTHETIC_MAX_NODES: usize = muse_scenario::synthetic::MAX_NODES;

/// A graph named on the command line.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum GraphName {
    /// A built-in scenario, e.g. `singapore-77`.
    Scenario(String),
    /// `synthetic-N`.
    Synthetic(usize),
}

impl std::fmt::Display for GraphName {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            GraphName::Scenario(name) => f.write_str(name),
            GraphName::Synthetic(n) => write!(f, "synthetic-{n}"),
        }
    }
}

/// A loaded graph with its zones and the day planned on.
pub struct Graph {
    /// The airspace.
    pub airspace: Cow<'static, Airspace>,
    /// Its zones.
    pub zones: Cow<'static, [Zone]>,
    /// The day planned on.
    pub date: jiff::civil::Date,
    /// Its UTC offset.
    pub offset: UtcOffset,
}

/// Parses one graph name; built-in scenario names are checked when loading.
pub fn parse_graph(name: &str) -> anyhow::Result<GraphName> {
    let name = name.trim();
    if let Some(n) = name.strip_prefix("synthetic-") {
        let n: usize = n.replace('_', "").parse().map_err(|_| {
            anyhow::anyhow!("--graphs: `{name}`: expected synthetic-N with N a number of nodes")
        })?;
        if !(SYNTHETIC_MIN_NODES..=SYNTHETIC_MAX_NODES).contains(&n) {
            anyhow::bail!(
                "--graphs: `{name}`: a synthetic graph has {SYNTHETIC_MIN_NODES} to {} nodes",
                grouped(SYNTHETIC_MAX_NODES)
            );
        }
        return Ok(GraphName::Synthetic(n));
    }
    if name.is_empty() {
        anyhow::bail!("--graphs: empty graph name");
    }
    Ok(GraphName::Scenario(name.to_owned()))
}

/// Parses `--graphs`: names separated by commas, each at most once.
pub fn parse_graphs(text: &str) -> anyhow::Result<Vec<GraphName>> {
    let mut out: Vec<GraphName> = Vec::new();
    for item in text.split(',') {
        let g = parse_graph(item)?;
        if out.contains(&g) {
            anyhow::bail!("--graphs: `{g}` is named twice");
        }
        out.push(g);
    }
    Ok(out)
}

/// Loads a graph: a built-in scenario with its zones, or a synthetic graph without zones
/// (planned on the Singapore default's day).
pub fn load_graph(name: &GraphName) -> anyhow::Result<Graph> {
    match name {
        GraphName::Scenario(s) => {
            let scenario = muse_scenario::by_name(s).with_context(|| format!("--graphs: `{s}`"))?;
            Ok(Graph {
                airspace: Cow::Borrowed(&scenario.airspace),
                zones: Cow::Borrowed(&scenario.zones),
                date: scenario.date,
                offset: scenario.offset,
            })
        }
        GraphName::Synthetic(n) => {
            use muse_scenario::synthetic::{Layout, SyntheticSpec, synthetic};
            let spec = SyntheticSpec {
                layout: Layout::Geometric,
                nodes: *n,
                spacing_m: SYNTHETIC_SPACING_M,
                station_share: SYNTHETIC_STATION_SHARE,
                seed: SYNTHETIC_SEED,
            };
            let airspace = synthetic(&spec).with_context(|| format!("--graphs: `{name}`"))?;
            let day = muse_scenario::by_name(muse_scenario::SINGAPORE_77)?;
            Ok(Graph {
                airspace: Cow::Owned(airspace),
                zones: Cow::Borrowed(&[]),
                date: day.date,
                offset: day.offset,
            })
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn graph_lists() {
        assert_eq!(
            parse_graphs("singapore-77, singapore-all,synthetic-10000").unwrap(),
            vec![
                GraphName::Scenario("singapore-77".into()),
                GraphName::Scenario("singapore-all".into()),
                GraphName::Synthetic(10_000)
            ]
        );
        assert_eq!(GraphName::Synthetic(10_000).to_string(), "synthetic-10000");
        for (bad, message) in [
            ("synthetic-ten", "expected synthetic-N"),
            ("synthetic-", "expected synthetic-N"),
            ("synthetic-5", "a synthetic graph has 20 to 1,000,000 nodes"),
            ("synthetic-2000000", "a synthetic graph has 20"),
            ("singapore-77,,synthetic-100", "empty graph name"),
            ("singapore-77,singapore-77", "`singapore-77` is named twice"),
            (
                "synthetic-100,synthetic-1_00",
                "`synthetic-100` is named twice",
            ),
        ] {
            let err = parse_graphs(bad).unwrap_err().to_string();
            assert!(
                err.contains(message) && err.starts_with("--graphs"),
                "{bad}: {err}"
            );
        }
        // Unknown names are caught when loading, before any case runs.
        let err = load_graph(&parse_graph("atlantis").unwrap()).err().unwrap();
        assert!(format!("{err:#}").contains("`atlantis`"), "{err:#}");
    }
}
