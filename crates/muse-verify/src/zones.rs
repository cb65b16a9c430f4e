//! The zone rule (docs/reference.md#no-fly-zones), with zones announced during the day
//! (docs/reference.md#zones-announced-during-the-day).

use muse_airspace::announced::Announced;
use muse_airspace::closures::{Closures, Window};
use muse_model::{Airspace, FlightParams, Instant, UtcOffset};

use crate::{Ending, Flight, Rule, Violation, edge_of, node_name, span, stamp, traversal_time};

/// Whether an occupation `[a, d]` shares an instant with the window `[start, end)`:
/// it is allowed only when `d < start` or `a >= end` (docs/reference.md#no-fly-zones).
fn shares_instant(w: Window, a: Instant, d: Instant) -> bool {
    !(d < w.start || a >= w.end)
}

/// Zone rule for every stay and traversal of one flight (of every leg: on the ground between
/// two legs the drone is outside the airspace).
pub(crate) fn zone_rule(
    airspace: &Airspace,
    closures: &Closures,
    announced: &[Announced],
    params: &FlightParams,
    flight: &Flight<'_>,
    out: &mut Vec<Violation>,
    offset: UtcOffset,
) {
    let mut push = |element: String, what: &str, a: Instant, d: Instant, w: Window, by: &str| {
        out.push(Violation {
            rule: Rule::Zone,
            flights: vec![flight.id.to_string()],
            element,
            detail: format!(
                "{what} {} shares an instant with the closure [{}, {}){by}",
                span(a, d, offset),
                stamp(w.start, offset),
                stamp(w.end, offset)
            ),
        });
    };
    // The zones that bind an occupation beginning at `t`: those known from the start, and
    // the announced ones announced by then (docs/reference.md#zones-announced-during-the-day).
    let binding = |t: Instant| {
        std::iter::once((closures, String::new())).chain(
            announced.iter().filter(move |a| a.binds(t)).map(|a| {
                (
                    &a.closures,
                    format!(" of zone `{}` announced at {}", a.zone, stamp(a.at, offset)),
                )
            }),
        )
    };
    if flight.ending == Ending::Committed {
        return; // a contingency: see the crate docs
    }
    let path = &flight.plan.path;
    for stay in path {
        if stay.node.index() >= airspace.node_count() {
            continue;
        }
        for (layer, by) in binding(stay.arrive) {
            for &w in layer.node(stay.node) {
                if shares_instant(w, stay.arrive, stay.depart) {
                    push(
                        node_name(airspace, stay.node),
                        "stay",
                        stay.arrive,
                        stay.depart,
                        w,
                        &by,
                    );
                }
            }
        }
    }
    for (x, y) in flight.plan.hops() {
        let Some(e) = edge_of(airspace, x.node, y.node) else {
            continue;
        };
        let s = x.depart;
        let f = s + traversal_time(airspace, params, e);
        for (layer, by) in binding(s) {
            for &w in layer.edge(e) {
                if shares_instant(w, s, f) {
                    push(crate::edge_name(airspace, e), "traversal", s, f, w, &by);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use muse_airspace::announced::KnownZones;
    use muse_model::{Layers, Metres, Period, Plan, Stay, VerticalLimits, Zone};

    use crate::tests::{airspace, params, request, rules};
    use crate::{Flight, Rule, Violation, edge_of, traversal_time, verify_known};

    use super::*;

    /// [`airspace`] at two layers, 60 m and 69.144 m.
    fn two_layers() -> Airspace {
        let layers = Layers {
            count: 2,
            ..Layers::default()
        };
        airspace().layered(&layers).unwrap()
    }

    /// A zone over the listed nodes and corridors from 0 to 1,000 s, in `lower`–`upper` mm.
    fn zone(nodes: &[&str], edges: &[&str], lower: Option<i64>, upper: Option<i64>) -> Zone {
        Zone {
            id: "Z".into(),
            name: String::new(),
            restriction: String::new(),
            area: None,
            node_ids: nodes.iter().map(|s| (*s).to_owned()).collect(),
            edge_ids: edges.iter().map(|s| (*s).to_owned()).collect(),
            announced: None,
            withdrawn: None,
            vertical: VerticalLimits::agl(lower.map(Metres::from_mm), upper.map(Metres::from_mm)),
            periods: vec![Period {
                start: Some(Instant(0)),
                end: Some(Instant(1_000_000)),
                daily: vec![],
            }],
        }
    }

    /// A plan through the nodes `ids` taking off at 10 s, no hover, each hop in its own time
    /// (a corridor 10 s, a vertical link 1.829 s).
    fn through(a: &Airspace, ids: &[&str]) -> Plan {
        let mut now = Instant(10_000);
        let mut path: Vec<Stay> = Vec::new();
        for id in ids {
            let node = a.node_id(id).unwrap();
            if let Some(last) = path.last() {
                let e = edge_of(a, last.node, node).unwrap();
                now += traversal_time(a, &params(), e);
            }
            path.push(Stay {
                node,
                arrive: now,
                depart: now,
            });
        }
        Plan { path }
    }

    fn check(a: &Airspace, zones: &[Zone], plan: &Plan) -> Vec<Violation> {
        let known = KnownZones::resolve(a, zones, Instant(0), Instant(86_400_000)).unwrap();
        let r = request(a, plan, plan.takeoff().0);
        verify_known(a, &known, &params(), &[Flight::new("f", &r, plan)])
    }

    fn elements(v: &[Violation]) -> Vec<&str> {
        v.iter().map(|v| v.element.as_str()).collect()
    }

    #[test]
    fn a_zone_binds_only_the_layers_of_its_band() {
        let a = two_layers();
        let low = through(&a, &["A", "B", "C"]);
        let high = through(&a, &["A", "A@2", "B@2", "C@2", "C"]);
        assert_eq!(check(&a, &[], &high), [], "the plan itself is valid");
        // B and B-C up to 65 m: layer 1 only.
        let z = [zone(&["B"], &["B-C"], Some(0), Some(65_000))];
        let v = check(&a, &z, &low);
        assert_eq!(rules(&v), [Rule::Zone, Rule::Zone]);
        assert_eq!(elements(&v), ["B (layer 1)", "B-C (layer 1)"]);
        assert_eq!(check(&a, &z, &high), [], "layer 2 is above the band");
        // From 65 m up: layer 2 only.
        let z = [zone(&["B"], &["B-C"], Some(65_000), None)];
        assert_eq!(check(&a, &z, &low), []);
        assert_eq!(
            elements(&check(&a, &z, &high)),
            ["B (layer 2)", "B-C (layer 2)"]
        );
        // Without limits: both.
        let z = [zone(&["B"], &[], None, None)];
        assert_eq!(elements(&check(&a, &z, &low)), ["B (layer 1)"]);
        assert_eq!(elements(&check(&a, &z, &high)), ["B (layer 2)"]);
    }

    #[test]
    fn a_zone_binds_the_vertical_links_whose_span_meets_its_band() {
        let a = two_layers();
        let high = through(&a, &["A", "A@2", "B@2", "C@2", "C"]);
        // 66–200 m at A: the climb from 60 m to 69.144 m crosses it, and A@2 lies in it.
        let v = check(&a, &[zone(&["A"], &[], Some(66_000), Some(200_000))], &high);
        assert_eq!(rules(&v), [Rule::Zone, Rule::Zone]);
        assert_eq!(
            elements(&v),
            [
                "A (layer 2)",
                "the vertical link at A between layers 1 and 2"
            ]
        );
        // 61–65 m at A: no layer, but the climb crosses it.
        let v = check(&a, &[zone(&["A"], &[], Some(61_000), Some(65_000))], &high);
        assert_eq!(
            elements(&v),
            ["the vertical link at A between layers 1 and 2"]
        );
        assert!(v[0].detail.starts_with("traversal ["), "{}", v[0]);
        // Above both layers: nothing.
        assert_eq!(
            check(&a, &[zone(&["A"], &[], Some(70_000), None)], &high),
            []
        );
    }
}
