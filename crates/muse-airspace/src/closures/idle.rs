//! Zones that do nothing ([`idle`]): legal, but closing nothing on an airspace, ever. Such a
//! zone is more likely a mistake (the wrong file, a typo in a date or a coordinate) than a
//! wish, so the command line warns of it.

use muse_model::{Airspace, Instant, Zone};

use super::{ClosureError, closed_elements, zone_windows};

/// How far back [`idle`] looks for the end of the last window of a zone announced after it.
const LOOK_BACK_MS: i64 = 400 * 86_400_000;

/// Why a zone does nothing.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Idle {
    /// Its area covers no node and no corridor of the airspace, and it names none.
    ClosesNothing,
    /// It covers nodes or corridors of the flat airspace, but its heights hold no layer of
    /// the layered one, nor the span of a vertical link.
    ClosesNothingAtItsHeights,
    /// It is announced after its last window ended: it binds only what begins from its
    /// announcement on, and nothing is closed then.
    AnnouncedAfterItsWindows {
        /// When it is announced.
        announced: Instant,
        /// When its last window ended.
        ended: Instant,
    },
}

/// Whether `zone` does nothing on `airspace` (flat or layered), and why; `None` when it closes
/// something at some time.
///
/// # Errors
/// The zone names a node or corridor the airspace does not have, or its area is invalid
/// ([`closed_elements`]).
///
/// ```
/// use muse_airspace::closures::idle::{Idle, idle};
/// use muse_model::testing::{joined, station};
/// use muse_model::{Instant, Period, VerticalLimits, Zone};
/// let airspace = joined(vec![station("A", 103.8, 1.3), station("B", 103.81, 1.3)],
///                       &[("A", "B", 1_000.0)]);
/// let t = |s: &str| Instant::parse_rfc3339(s).unwrap();
/// let mut zone = Zone {
///     id: "Z".into(), name: String::new(), restriction: "PROHIBITED".into(), area: None,
///     node_ids: vec![], edge_ids: vec![], announced: None, withdrawn: None,
///     vertical: VerticalLimits::WHOLE_SKY, periods: vec![],
/// };
/// assert_eq!(idle(&airspace, &zone).unwrap(), Some(Idle::ClosesNothing));
/// zone.node_ids = vec!["A".into()];
/// assert_eq!(idle(&airspace, &zone).unwrap(), None);
/// zone.periods = vec![Period { start: Some(t("2026-01-05T10:00:00Z")),
///                              end: Some(t("2026-01-05T12:00:00Z")), daily: vec![] }];
/// zone.announced = Some(t("2026-01-05T13:00:00Z"));
/// assert_eq!(
///     idle(&airspace, &zone).unwrap(),
///     Some(Idle::AnnouncedAfterItsWindows {
///         announced: t("2026-01-05T13:00:00Z"), ended: t("2026-01-05T12:00:00Z") })
/// );
/// ```
pub fn idle(airspace: &Airspace, zone: &Zone) -> Result<Option<Idle>, ClosureError> {
    let (nodes, edges) = closed_elements(airspace, zone)?;
    if nodes.is_empty() && edges.is_empty() {
        if airspace.layers().is_none() {
            return Ok(Some(Idle::ClosesNothing));
        }
        let (nodes, edges) = closed_elements(airspace.flat(), zone)?;
        return Ok(Some(if nodes.is_empty() && edges.is_empty() {
            Idle::ClosesNothing
        } else {
            Idle::ClosesNothingAtItsHeights
        }));
    }
    Ok(announced_after_its_windows(zone))
}

/// [`Idle::AnnouncedAfterItsWindows`] when `zone` is announced and every one of its periods
/// ends, and no window of it is open at or after the announcement.
fn announced_after_its_windows(zone: &Zone) -> Option<Idle> {
    let announced = zone.announced?;
    let last_end = zone
        .periods
        .iter()
        .map(|p| p.end)
        .collect::<Option<Vec<Instant>>>()?
        .into_iter()
        .max()?;
    // A range MUSE cannot resolve (beyond the supported years) is left to the resolution's
    // own error.
    if last_end > announced && !zone_windows(zone, announced, last_end).ok()?.is_empty() {
        return None;
    }
    // The end of the last window before the announcement (the period's end if none is found
    // in the last 400 days).
    let from = Instant(announced.0.saturating_sub(LOOK_BACK_MS));
    let ended = zone_windows(zone, from, announced)
        .ok()
        .and_then(|w| w.last().map(|w| w.end))
        .unwrap_or(last_end.min(announced));
    Some(Idle::AnnouncedAfterItsWindows { announced, ended })
}
