//! The zones the service knows: those known from the start and those announced so far (for
//! `GET /v1/zones`, for refusing an id twice, and for withdrawals), and a stored zone read
//! back. How a `POST /v1/zones` body becomes a [`NewZone`] is in the sibling `body`.

use std::collections::HashSet;

use muse_formats::zones::{read_zones, write_ed318};
use muse_model::{Instant, Zone};

/// A zone to announce, read from a request body.
#[derive(Clone, Debug, PartialEq)]
pub struct NewZone {
    /// Its id.
    pub id: String,
    /// The ED-318 feature as received, as compact JSON (what the store keeps).
    pub feature: String,
    /// The zones it reads as (one, or one per area: see [`crate::zones`]), without
    /// announcement instant.
    pub zones: Vec<Zone>,
}

/// The zones a stored feature reads as, announced at `announced`.
pub fn read_stored(feature: &str, announced: Instant) -> Result<Vec<Zone>, String> {
    let mut zones = read_zones(feature, "the stored zone").map_err(|e| e.to_string())?;
    for z in &mut zones {
        z.announced = Some(announced);
    }
    Ok(zones)
}

/// A zone announced during the day.
#[derive(Clone, Debug, PartialEq)]
pub struct AnnouncedZone {
    /// Its id.
    pub id: String,
    /// The zones it reads as, with their announcement instant.
    pub zones: Vec<Zone>,
    /// When it was announced.
    pub announced: Instant,
    /// When it was withdrawn, if it was.
    pub withdrawn: Option<Instant>,
    /// How many flights it changed.
    pub affected: usize,
}

/// What the service knows of zones: those known from the start and those announced since.
#[derive(Debug)]
pub struct ZoneBook {
    base: Vec<Zone>,
    /// Every id in use: the base zones' (and, for `ID#k`, `ID`), the announced ones'.
    taken: HashSet<String>,
    base_ids: HashSet<String>,
    announced: Vec<AnnouncedZone>,
    geojson: String,
}

/// `ID` for `ID#k`.
fn stem(id: &str) -> &str {
    id.rsplit_once('#').map_or(id, |(stem, _)| stem)
}

impl ZoneBook {
    /// The zones known from the start, none announced yet.
    pub fn new(base: &[Zone]) -> Self {
        let base_ids: HashSet<String> = base
            .iter()
            .flat_map(|z| [z.id.clone(), stem(&z.id).to_owned()])
            .collect();
        ZoneBook {
            base: base.to_vec(),
            taken: base_ids.clone(),
            base_ids,
            announced: Vec::new(),
            geojson: write_ed318(base),
        }
    }

    /// Whether `id` names a zone known from the start.
    pub fn is_base(&self, id: &str) -> bool {
        self.base_ids.contains(id)
    }

    /// Whether the id of `zone` (or of one of its parts) is in use.
    pub fn taken(&self, zone: &NewZone) -> bool {
        self.taken.contains(&zone.id) || zone.zones.iter().any(|z| self.taken.contains(&z.id))
    }

    /// The announced zone `id`.
    pub fn get(&self, id: &str) -> Option<&AnnouncedZone> {
        self.announced.iter().find(|z| z.id == id)
    }

    /// Every zone as `GET /v1/zones` lists it: those known from the start, then the parts of
    /// the announced ones (withdrawn ones included), in announcement order.
    pub fn all(&self) -> impl Iterator<Item = &Zone> {
        self.base
            .iter()
            .chain(self.announced.iter().flat_map(|a| a.zones.iter()))
    }

    /// Records an announcement (its id must not be [taken](ZoneBook::taken)).
    pub fn announce(&mut self, zone: AnnouncedZone) {
        self.taken.insert(zone.id.clone());
        self.taken.extend(zone.zones.iter().map(|z| z.id.clone()));
        self.announced.push(zone);
        self.render();
    }

    /// Records a withdrawal of the announced zone `id` at `at`; `false` if there is none.
    pub fn withdraw(&mut self, id: &str, at: Instant) -> bool {
        let Some(zone) = self.announced.iter_mut().find(|z| z.id == id) else {
            return false;
        };
        zone.withdrawn = Some(at);
        self.render();
        true
    }

    /// Every zone as ED-318 `GeoJSON`: those known from the start, then the announced ones
    /// in announcement order with their `announced` instant and, once withdrawn, a
    /// `withdrawn` property (a MUSE extension, RFC 3339 in the offset `announced` is in).
    pub fn geojson(&self) -> &str {
        &self.geojson
    }

    fn render(&mut self) {
        let mut all = self.base.clone();
        for a in &self.announced {
            all.extend(a.zones.iter().map(|z| Zone {
                withdrawn: a.withdrawn,
                ..z.clone()
            }));
        }
        self.geojson = write_ed318(&all);
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// One ED-318 feature of two circles, `EVT` (read as `EVT#1` and `EVT#2`), the first up
    /// to 120 m.
    pub(crate) const ZONE: &str = r#"{"type": "FeatureCollection", "features": [{"type": "Feature",
        "properties": {"identifier": "EVT", "name": "Event"},
        "geometry": {"type": "GeometryCollection", "geometries": [
            {"type": "Point", "coordinates": [103.80, 1.30], "extent": {"subType": "Circle", "radius": 100},
             "layer": {"upper": 120, "upperReference": "AGL", "uom": "m"}},
            {"type": "Point", "coordinates": [103.82, 1.30], "extent": {"subType": "Circle", "radius": 100}}]}}]}"#;

    fn new_zone(text: &str) -> NewZone {
        let zones = read_zones(text, "test").unwrap();
        let id = zones[0]
            .id
            .rsplit_once('#')
            .map_or(zones[0].id.clone(), |(s, _)| s.to_owned());
        NewZone {
            id,
            feature: text.to_owned(),
            zones,
        }
    }

    #[test]
    fn ids_are_never_reused_and_withdrawals_are_listed() {
        let base = new_zone(
            r#"{"type": "Feature", "properties": {"identifier": "BASE", "nodes": ["A"]}}"#,
        );
        let mut book = ZoneBook::new(&base.zones);
        assert!(book.is_base("BASE") && book.taken(&base));
        let evt = new_zone(ZONE);
        assert!(!book.taken(&evt));
        let at = Instant::parse_rfc3339("2026-01-05T14:00:00+08:00").unwrap();
        book.announce(AnnouncedZone {
            id: evt.id.clone(),
            zones: read_stored(&evt.feature, at).unwrap(),
            announced: at,
            withdrawn: None,
            affected: 0,
        });
        assert!(book.taken(&evt) && !book.is_base("EVT"));
        assert!(book.withdraw("EVT", at + muse_model::Millis(1_000)));
        assert!(!book.withdraw("NONE", at));
        let listed = read_zones(book.geojson(), "GET /v1/zones").unwrap();
        let ids: Vec<&str> = listed.iter().map(|z| z.id.as_str()).collect();
        assert_eq!(ids, ["BASE", "EVT#1", "EVT#2"]);
        assert_eq!(listed[1].announced, Some(at));
        // The zones' heights are listed as they were announced.
        assert_eq!(listed[1].vertical.to_string(), "up to 120 m AGL");
        assert!(listed[2].vertical.is_whole_sky());
        assert_eq!(
            book.geojson()
                .matches("\"announced\": \"2026-01-05T06:00:00.000+00:00\",\n        \"withdrawn\": \"2026-01-05T06:00:01.000+00:00\"")
                .count(),
            2,
            "{}",
            book.geojson()
        );
    }
}
