//! Zones by when they became known (docs/reference.md#zones-announced-during-the-day).
//!
//! A zone without an announcement instant is known from the start: it binds every flight.
//! A zone announced at `n` binds every stay and traversal that *begins* at or after `n` (and,
//! if it is withdrawn at `m`, before `m`); one that begins earlier is exempt from it.
//! [`KnownZones`] keeps the first kind merged into one [`Closures`] and the second kind one
//! [`Announced`] layer per zone, in announcement order, which is what the simulator replays
//! and the verifier checks.

use muse_model::{Airspace, Instant, Zone};

use crate::closures::{ClosureError, Closures, resolve};

/// One zone announced during the day, with its closures.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Announced {
    /// The zone's id.
    pub zone: String,
    /// When it became known.
    pub at: Instant,
    /// When it was withdrawn, if it was.
    pub withdrawn: Option<Instant>,
    /// What it closes, and when.
    pub closures: Closures,
}

impl Announced {
    /// Whether a stay or traversal beginning at `t` is bound by the zone: `at <= t`, and
    /// `t < withdrawn` if it was withdrawn.
    ///
    /// ```
    /// use muse_airspace::announced::Announced;
    /// use muse_airspace::closures::Closures;
    /// use muse_model::Instant;
    /// let z = Announced { zone: "Z".into(), at: Instant(100), withdrawn: Some(Instant(200)),
    ///                     closures: Closures::default() };
    /// assert!(!z.binds(Instant(99)) && z.binds(Instant(100)) && !z.binds(Instant(200)));
    /// ```
    pub fn binds(&self, t: Instant) -> bool {
        t >= self.at && self.withdrawn.is_none_or(|w| t < w)
    }
}

/// The zones of a run: those known from the start, merged, and those announced during it.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct KnownZones {
    /// Closures of the zones known from the start.
    pub base: Closures,
    /// Zones announced later, in order of announcement (then id).
    pub announced: Vec<Announced>,
}

impl KnownZones {
    /// Resolves `zones` over `[from, to)` (as [`resolve`]): zones without
    /// [`Zone::announced`] into the base, each announced zone into its own layer, with its
    /// [withdrawal](Zone::withdrawn) if it was withdrawn (a zone withdrawn but never announced,
    /// which no file reader gives, is a layer known from the earliest instant).
    ///
    /// ```
    /// use muse_airspace::announced::KnownZones;
    /// use muse_model::{Airspace, Instant, LonLat, Node, NodeId, NodeKind, Period, Zone};
    /// let airspace = Airspace::new(
    ///     vec![Node { id: "S1".into(), kind: NodeKind::Station, name: String::new(),
    ///                 pos: LonLat::new(103.85, 1.29) }],
    ///     vec![],
    /// ).unwrap();
    /// let zone = |id: &str, announced| Zone {
    ///     id: id.into(), name: String::new(), restriction: String::new(), area: None,
    ///     node_ids: vec!["S1".into()], edge_ids: vec![], announced, withdrawn: None,
    ///     vertical: muse_model::VerticalLimits::WHOLE_SKY,
    ///     periods: vec![Period { start: Some(Instant(1_000)), end: Some(Instant(2_000)), daily: vec![] }],
    /// };
    /// let known = KnownZones::resolve(&airspace, &[zone("A", None), zone("B", Some(Instant(500)))],
    ///                                 Instant(0), Instant(10_000)).unwrap();
    /// assert_eq!(known.base.node(NodeId(0)).len(), 1);
    /// assert_eq!((known.announced[0].zone.as_str(), known.announced[0].at), ("B", Instant(500)));
    /// ```
    pub fn resolve(
        airspace: &Airspace,
        zones: &[Zone],
        from: Instant,
        to: Instant,
    ) -> Result<Self, ClosureError> {
        let (later, start): (Vec<&Zone>, Vec<&Zone>) = zones
            .iter()
            .partition(|z| z.announced.is_some() || z.withdrawn.is_some());
        let start: Vec<Zone> = start.into_iter().cloned().collect();
        let base = resolve(airspace, &start, from, to)?;
        let mut announced = later
            .into_iter()
            .map(|z| {
                Ok(Announced {
                    zone: z.id.clone(),
                    at: z.announced.unwrap_or(Instant::TEXT_MIN),
                    withdrawn: z.withdrawn,
                    closures: resolve(airspace, std::slice::from_ref(z), from, to)?,
                })
            })
            .collect::<Result<Vec<_>, ClosureError>>()?;
        announced.sort_by(|a, b| a.at.cmp(&b.at).then_with(|| a.zone.cmp(&b.zone)));
        Ok(KnownZones { base, announced })
    }
}
