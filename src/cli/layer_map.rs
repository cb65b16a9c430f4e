//! `map.svg` of a layered day (docs/reference.md#layered-airspace): the corridor load at each
//! layer, one panel per layer on one load scale (small multiples). Each panel draws the corridors
//! flown at its layer (under the `sectors` heading rule, only those open in its directions) over
//! the flat stations and waypoints; the vertical links between layers are not corridors and are not
//! drawn.

use anyhow::Context as _;
use muse_model::{Airspace, Edge, EdgeId, EdgeKind};
use muse_render::{MapInput, MapOptions, MapPanel, ZoneLayer, render_map_panels};
use muse_verify::Flight;

use super::common::{MAX_LABELLED_STATIONS, World, world_attribution, world_land};

/// Width of the page, pixels.
const WIDTH_PX: u32 = 1_800;
/// Most panels in a row: 450 px each at [`WIDTH_PX`].
const MAX_COLUMNS: usize = 4;

/// One layer of a layered airspace as a flat airspace of its own: the flat nodes, and the
/// corridors of layer `k` under their flat ids. Also, for each edge of the layered airspace,
/// its index here (`None`: another layer's, or a vertical link).
fn layer_airspace(a: &Airspace, k: u32) -> anyhow::Result<(Airspace, Vec<Option<usize>>)> {
    let flat = a.flat();
    let mut edges = Vec::new();
    let mut index = vec![None; a.edge_count()];
    for (i, e) in a.edges().iter().enumerate() {
        let id = EdgeId(u32::try_from(i).context("edge index")?);
        let (EdgeKind::Corridor { layer, .. }, Some(base)) = (a.edge_kind(id), a.flat_edge(id))
        else {
            continue;
        };
        if layer != k {
            continue;
        }
        index[i] = Some(edges.len());
        edges.push(Edge {
            id: flat.edge(base).id.clone(),
            from: a.flat_node(e.from),
            to: a.flat_node(e.to),
            length_m: e.length_m,
        });
    }
    let own = Airspace::new(flat.nodes().to_vec(), edges)
        .with_context(|| format!("the corridors of layer {k}"))?;
    Ok((own, index))
}

/// The map of a layered day: flights per corridor at each layer, every panel on the scale of
/// the busiest corridor of any layer. `None` when the world is flat.
///
/// # Errors
/// A zone whose closures cannot be resolved, or a drawing failure.
pub fn render_layer_map(world: &World, flights: &[Flight<'_>]) -> anyhow::Result<Option<String>> {
    let a = &world.airspace;
    let Some(layers) = a.layers() else {
        return Ok(None);
    };
    let count = layers.count as usize;
    let columns = (1..=MAX_COLUMNS)
        .find(|c| c * c >= count)
        .unwrap_or(MAX_COLUMNS);
    let land = world_land(world);
    let mut closures = Vec::with_capacity(world.zones.len());
    for zone in &world.zones {
        closures.push(
            muse_airspace::closures::closed_elements(a, zone)
                .with_context(|| format!("zone `{}`", zone.id))?,
        );
    }
    let mut owns = Vec::with_capacity(count);
    for k in 1..=layers.count {
        let (own, index) = layer_airspace(a, k)?;
        let mut load = vec![0.0; own.edge_count()];
        for f in flights {
            for (from, to) in f.plan.hops() {
                if let Some(i) = a
                    .edge_between(from.node, to.node)
                    .and_then(|e| index[e.index()])
                {
                    load[i] += 1.0;
                }
            }
        }
        let zones: Vec<ZoneLayer> = world
            .zones
            .iter()
            .zip(&closures)
            .map(|(zone, (nodes, edges))| ZoneLayer {
                label: zone.name.clone(),
                polygons: zone.polygons(),
                closed_nodes: nodes
                    .iter()
                    .filter(|&&n| a.node_layer(n) == k)
                    .map(|&n| a.flat_node(n))
                    .collect(),
                closed_edges: edges
                    .iter()
                    .filter_map(|e| index[e.index()])
                    .map(|i| EdgeId(u32::try_from(i).unwrap_or(u32::MAX)))
                    .collect(),
            })
            .collect();
        owns.push((own, load, zones, k));
    }
    let panels: Vec<MapPanel<'_>> = owns
        .iter()
        .map(|(own, load, zones, k)| {
            let mut input = MapInput::new(own);
            input.land = &land;
            input.zones.clone_from(zones);
            input.edge_load = Some(load.clone());
            MapPanel {
                input,
                title: format!("Layer {k} · {} m", layers.altitude(*k).m()),
            }
        })
        .collect();
    let rule = match layers.heading_rule {
        muse_model::HeadingRule::None => String::new(),
        muse_model::HeadingRule::Sectors => ", heading sectors".to_owned(),
    };
    let opts = MapOptions {
        width_px: WIDTH_PX,
        title: format!(
            "{} — flights per corridor at each of {} layers (one scale{rule})",
            world.title, layers.count
        ),
        attribution: world_attribution(world),
        label_stations: columns <= 2 && a.stations().count() <= MAX_LABELLED_STATIONS,
        load_label: "Flights per corridor".to_owned(),
        ..MapOptions::default()
    };
    Ok(Some(render_map_panels(&panels, columns, &opts)?))
}

#[cfg(test)]
mod tests {
    use muse_model::{HeadingRule, Layers, NodeId};

    use super::*;

    #[test]
    fn a_layer_is_its_corridors_over_the_flat_nodes() {
        // A — B eastward: under the semicircular rule, layer 1 eastward, layer 2 westward.
        let layers = Layers {
            count: 2,
            heading_rule: HeadingRule::Sectors,
            ..Layers::default()
        };
        let air = Airspace::line(&[1_000.0, 2_000.0])
            .layered(&layers)
            .unwrap();
        for k in 1..=2 {
            let (own, index) = layer_airspace(&air, k).unwrap();
            assert_eq!(own.node_count(), 3);
            assert_eq!(own.edge_count(), 2, "layer {k}");
            let ids: Vec<&str> = own.edges().iter().map(|e| e.id.as_str()).collect();
            assert_eq!(ids, ["A-B", "B-C"]);
            let first = own.edge(EdgeId(0));
            let expected = if k == 1 {
                (NodeId(0), NodeId(1))
            } else {
                (NodeId(1), NodeId(0))
            };
            assert_eq!((first.from, first.to), expected, "flown one way");
            // Two corridors of this layer are mapped; the other layer's and the vertical
            // links are not.
            assert_eq!(index.iter().flatten().count(), 2);
            assert_eq!(index.len(), air.edge_count());
        }
    }
}
