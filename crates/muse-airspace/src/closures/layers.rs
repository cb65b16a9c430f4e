//! What a zone closes on a layered airspace (docs/reference.md#layered-airspace), from what it
//! closes on the flat one.
//!
//! The zone's area and listed ids are tested once, on the flat airspace
//! ([`Airspace::flat`]); its vertical band then chooses the copies:
//!
//! - node `n` at layer `k` is closed when flat node `n` is and the band contains the layer's
//!   altitude `h_k` ([`VerticalLimits::contains`]);
//! - corridor `e` at layer `k` (where the heading rule keeps it) likewise, with flat corridor
//!   `e`;
//! - the vertical link at node `n` between layers `k` and `k + 1` when flat node `n` is closed
//!   and the band meets the span `[h_k, h_{k+1}]` ([`VerticalLimits::meets`]).
//!
//! A zone without limits (the whole sky) so closes every copy of what it covers and every
//! vertical link at its nodes.

use muse_model::{Airspace, EdgeId, Layers, NodeId, VerticalLimits};

/// The elements of the layered `airspace` (laid out by `layers`) that a zone of band `band`
/// closes, given the flat elements it closes (`flat_nodes`, `flat_edges`, indices of
/// [`Airspace::flat`]). Each list is sorted by index, without repeats.
pub(super) fn copies_in_band(
    airspace: &Airspace,
    layers: &Layers,
    band: &VerticalLimits,
    flat_nodes: &[NodeId],
    flat_edges: &[EdgeId],
) -> (Vec<NodeId>, Vec<EdgeId>) {
    let flat = airspace.flat();
    let mut nodes = Vec::new();
    let mut edges = Vec::new();
    for k in 1..=layers.count {
        if !band.contains(layers.altitude(k)) {
            continue;
        }
        nodes.extend(flat_nodes.iter().filter_map(|&n| airspace.at_layer(n, k)));
        for &e in flat_edges {
            let corridor = flat.edge(e);
            let ends = airspace
                .at_layer(corridor.from, k)
                .zip(airspace.at_layer(corridor.to, k));
            // Absent at this layer under the heading rule, or one-way (either direction).
            if let Some((a, b)) = ends
                && let Some(copy) = airspace
                    .edge_between(a, b)
                    .or_else(|| airspace.edge_between(b, a))
            {
                edges.push(copy);
            }
        }
    }
    for k in 1..layers.count {
        if !band.meets(layers.altitude(k), layers.altitude(k + 1)) {
            continue;
        }
        for &n in flat_nodes {
            let link = airspace
                .at_layer(n, k)
                .zip(airspace.at_layer(n, k + 1))
                .and_then(|(low, high)| airspace.edge_between(low, high));
            edges.extend(link);
        }
    }
    nodes.sort_unstable();
    nodes.dedup();
    edges.sort_unstable();
    edges.dedup();
    (nodes, edges)
}

#[cfg(test)]
mod tests {
    use muse_model::{HeadingRule, Metres, Period, Zone};

    use crate::announced::KnownZones;
    use crate::closures::fixtures::{airspace, names, square, square_airspace, t, zone};
    use crate::closures::{ClosureError, closed_elements, resolve};

    use super::*;

    /// Three layers: 60 m, 69.144 m and 78.288 m.
    fn three() -> Layers {
        Layers {
            count: 3,
            ..Layers::default()
        }
    }

    fn band(lower_mm: Option<i64>, upper_mm: Option<i64>) -> VerticalLimits {
        VerticalLimits::agl(lower_mm.map(Metres::from_mm), upper_mm.map(Metres::from_mm))
    }

    /// The square zone with the given band (it closes EDGE, CORNER and IN, OUT-EDGE and S-N
    /// on the flat airspace).
    fn square_in(vertical: VerticalLimits) -> Zone {
        let mut z = zone("Z", Some(square()), vec![]);
        z.vertical = vertical;
        z
    }

    fn closes(a: &Airspace, z: &Zone) -> (Vec<String>, Vec<String>) {
        let (n, e) = closed_elements(a, z).unwrap();
        names(a, &n, &e)
    }

    #[test]
    fn a_low_zone_closes_layer_one_and_the_links_whose_span_meets_it() {
        let a = square_airspace().layered(&three()).unwrap();
        let (n, e) = closes(&a, &square_in(band(Some(0), Some(65_000))));
        assert_eq!(n, ["EDGE", "CORNER", "IN"], "layer 1 only");
        // [60, 69.144] meets 0–65 m; [69.144, 78.288] does not.
        assert_eq!(e, ["OUT-EDGE", "S-N", "EDGE@1^2", "CORNER@1^2", "IN@1^2"]);
        // A band touching layer 2's altitude from below closes it too, ends included.
        let (n, e) = closes(&a, &square_in(band(Some(61_000), Some(69_144))));
        assert_eq!(n, ["EDGE@2", "CORNER@2", "IN@2"]);
        assert_eq!(
            e,
            [
                "OUT-EDGE@2",
                "S-N@2",
                "EDGE@1^2",
                "CORNER@1^2",
                "IN@1^2",
                "EDGE@2^3",
                "CORNER@2^3",
                "IN@2^3"
            ]
        );
    }

    #[test]
    fn a_band_between_two_layers_closes_only_the_links_across_it() {
        let a = square_airspace().layered(&three()).unwrap();
        let (n, e) = closes(&a, &square_in(band(Some(70_000), Some(75_000))));
        assert!(n.is_empty(), "{n:?}");
        assert_eq!(e, ["EDGE@2^3", "CORNER@2^3", "IN@2^3"]);
        // Above every layer: nothing at all.
        let (n, e) = closes(&a, &square_in(band(Some(80_000), None)));
        assert!(n.is_empty() && e.is_empty(), "{n:?} {e:?}");
    }

    #[test]
    fn a_zone_without_limits_closes_every_layer_and_every_link_at_its_nodes() {
        let a = square_airspace().layered(&three()).unwrap();
        let (n, e) = closes(&a, &square_in(VerticalLimits::WHOLE_SKY));
        let at = |ids: &[&str], k: u32| -> Vec<String> {
            ids.iter()
                .map(|id| {
                    if k == 1 {
                        (*id).to_owned()
                    } else {
                        format!("{id}@{k}")
                    }
                })
                .collect()
        };
        let nodes = ["EDGE", "CORNER", "IN"];
        let want: Vec<String> = (1..=3).flat_map(|k| at(&nodes, k)).collect();
        assert_eq!(n, want);
        let mut want: Vec<String> = (1..=3).flat_map(|k| at(&["OUT-EDGE", "S-N"], k)).collect();
        for k in 1..=2 {
            want.extend(nodes.iter().map(|id| format!("{id}@{k}^{}", k + 1)));
        }
        assert_eq!(e, want);
        // An open floor or ceiling is the same when every layer is on its side.
        assert_eq!(
            closes(&a, &square_in(band(Some(0), None))),
            (n.clone(), e.clone())
        );
        assert_eq!(closes(&a, &square_in(band(None, Some(100_000)))), (n, e));
    }

    #[test]
    fn listed_ids_close_their_copies_in_the_band() {
        let a = square_airspace().layered(&three()).unwrap();
        let mut z = zone("LISTED", None, vec![]);
        z.node_ids = vec!["E".into()];
        z.edge_ids = vec!["S-N".into(), "W1-OUT".into()];
        z.vertical = band(Some(65_000), None);
        let (n, e) = closes(&a, &z);
        assert_eq!(n, ["E@2", "E@3"]);
        assert_eq!(
            e,
            ["S-N@2", "OUT-W1@2", "S-N@3", "OUT-W1@3", "E@1^2", "E@2^3"],
            "listed corridors close no vertical link; listed nodes close theirs"
        );
        // A zone names the flat airspace's ids: a copy's id is not one of them.
        z.node_ids = vec!["E@2".into()];
        assert_eq!(
            closed_elements(&a, &z).unwrap_err(),
            ClosureError::UnknownNode {
                zone: "LISTED".into(),
                id: "E@2".into()
            }
        );
    }

    #[test]
    fn corridors_the_heading_rule_removes_are_not_closed_and_one_way_ones_are() {
        // A — B south-east (about 135°): under quadrantal sectors, flown from A at layer 2
        // (90°–180°) and back at layer 4 (270°–360°), absent at layers 1 and 3.
        let flat = airspace(&[("A", 103.80, 1.30), ("B", 103.81, 1.29)], &["A-B"]);
        let layers = Layers {
            count: 4,
            heading_rule: HeadingRule::Sectors,
            ..Layers::default()
        };
        let a = flat.layered(&layers).unwrap();
        let mut z = zone("Z", None, vec![]);
        z.edge_ids = vec!["A-B".into()];
        let (n, e) = closes(&a, &z);
        assert!(n.is_empty());
        assert_eq!(e, ["A-B@2", "A-B@4"]);
        z.vertical = band(None, Some(70_000));
        assert_eq!(closes(&a, &z).1, ["A-B@2"]);
    }

    #[test]
    fn on_a_flat_airspace_the_band_is_not_used() {
        let a = square_airspace();
        let high = square_in(band(Some(100_000), Some(200_000)));
        assert_eq!(
            closes(&a, &high),
            closes(&a, &square_in(VerticalLimits::WHOLE_SKY))
        );
        // So is one layer, whatever its altitude.
        let one = Layers {
            base: Metres::from_mm(500_000),
            ..Layers::default()
        };
        let a = a.layered(&one).unwrap();
        assert_eq!(closes(&a, &high).0, ["EDGE", "CORNER", "IN"]);
    }

    #[test]
    fn resolve_and_announced_zones_close_by_layer() {
        let a = square_airspace().layered(&three()).unwrap();
        let node = |id: &str| a.node_id(id).unwrap();
        let (from, to) = (t("2026-01-05T00:00:00Z"), t("2026-01-06T00:00:00Z"));
        let low = square_in(band(Some(0), Some(65_000)));
        let mut high = zone(
            "HIGH",
            None,
            vec![Period {
                start: Some(t("2026-01-05T10:00:00Z")),
                end: Some(t("2026-01-05T12:00:00Z")),
                daily: vec![],
            }],
        );
        high.node_ids = vec!["OUT".into()];
        high.vertical = band(Some(75_000), None);
        high.announced = Some(t("2026-01-05T08:00:00Z"));

        let c = resolve(&a, std::slice::from_ref(&low), from, to).unwrap();
        let (n, e) = closed_elements(&a, &low).unwrap();
        assert_eq!(c.closed_nodes().map(|(n, _)| n).collect::<Vec<_>>(), n);
        assert_eq!(c.closed_edges().map(|(e, _)| e).collect::<Vec<_>>(), e);

        let known = KnownZones::resolve(&a, &[low, high], from, to).unwrap();
        assert!(!known.base.node(node("IN")).is_empty());
        assert!(known.base.node(node("IN@2")).is_empty());
        let [announced] = known.announced.as_slice() else {
            panic!("one announced zone: {:?}", known.announced);
        };
        assert_eq!(announced.at, t("2026-01-05T08:00:00Z"));
        let c = &announced.closures;
        let closed: Vec<&str> = c
            .closed_nodes()
            .map(|(n, _)| a.node(n).id.as_str())
            .collect();
        assert_eq!(closed, ["OUT@3"], "78.288 m only");
        let links: Vec<&str> = c
            .closed_edges()
            .map(|(e, _)| a.edge(e).id.as_str())
            .collect();
        assert_eq!(links, ["OUT@2^3"]);
        assert_eq!(
            c.node(node("OUT@3")),
            [crate::closures::Window::new(
                t("2026-01-05T10:00:00Z"),
                t("2026-01-05T12:00:00Z")
            )]
        );
    }
}
