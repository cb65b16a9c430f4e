//! When a zone closes (docs/reference.md#no-fly-zones), space aside: [`zone_windows`].
//!
//! Each period of a zone becomes windows inside `[from, to)`: a period with daily windows
//! gives, for every local date (in the daily window's offset) whose window can touch the
//! range, on the listed weekdays (the weekday of the date the window starts), the window
//! clipped to the period's `[start, end)`; a period without daily windows closes its own
//! `[start, end)` (unbounded sides clipped to `[from, to)`); a permanent zone closes all of
//! `[from, to)`.

use muse_model::{DailyWindow, Instant, Millis, Period, Weekday, Zone};

use super::{ClosureError, Window, merge};

const DAY_MS: i64 = 86_400_000;

/// The instants zones are resolved over: 0000-01-01T00:00:00Z to 9999-01-01T00:00:00Z, so
/// that every local date a daily window is worked out on (a day either side, in any offset)
/// is a calendar date. It holds the years MUSE plans ([`muse_model::request::PLANNED`]) with
/// room for a day and a trip either side.
const RESOLVED: std::ops::Range<Instant> =
    Instant(-62_167_219_200_000)..Instant(253_370_764_800_000);

/// The longest range [`resolve`](super::resolve) expands, in days (about 100 years).
pub const MAX_RANGE_DAYS: i64 = 36_525;

/// The windows during which a zone is closed within `[from, to)`, sorted and merged.
///
/// ```
/// use muse_airspace::closures::zone_windows;
/// use muse_model::{Instant, Period, Zone};
/// let t = |s: &str| Instant::parse_rfc3339(s).unwrap();
/// let zone = Zone {
///     id: "Z".into(), name: String::new(), restriction: String::new(), area: None,
///     node_ids: vec![], edge_ids: vec![], announced: None, withdrawn: None,
///     vertical: muse_model::VerticalLimits::WHOLE_SKY,
///     periods: vec![Period { start: Some(t("2026-01-05T09:00:00Z")), end: None, daily: vec![] }],
/// };
/// let w = zone_windows(&zone, t("2026-01-05T00:00:00Z"), t("2026-01-06T00:00:00Z")).unwrap();
/// assert_eq!((w[0].start, w[0].end), (t("2026-01-05T09:00:00Z"), t("2026-01-06T00:00:00Z")));
/// ```
pub fn zone_windows(zone: &Zone, from: Instant, to: Instant) -> Result<Vec<Window>, ClosureError> {
    check_range(from, to)?;
    let mut out = Vec::new();
    if from == to {
        return Ok(out);
    }
    if zone.is_permanent() {
        out.push(Window::new(from, to));
        return Ok(out);
    }
    for period in &zone.periods {
        period_windows(zone, period, from, to, &mut out)?;
    }
    merge(&mut out);
    Ok(out)
}

pub(super) fn check_range(from: Instant, to: Instant) -> Result<(), ClosureError> {
    let bad = |reason: &str| ClosureError::BadRange {
        from: from.0,
        to: to.0,
        reason: reason.into(),
    };
    if to < from {
        return Err(bad("the end is before the start"));
    }
    if from < RESOLVED.start || to > RESOLVED.end {
        return Err(bad(
            "outside the years 0000 to 9998 (UTC) over which zones are worked out",
        ));
    }
    if (to - from).0 > MAX_RANGE_DAYS * DAY_MS {
        return Err(bad(&format!("longer than {MAX_RANGE_DAYS} days")));
    }
    Ok(())
}

fn period_windows(
    zone: &Zone,
    p: &Period,
    from: Instant,
    to: Instant,
    out: &mut Vec<Window>,
) -> Result<(), ClosureError> {
    let lo = p.start.map_or(from, |s| s.max(from));
    let hi = p.end.map_or(to, |e| e.min(to));
    if lo >= hi {
        return Ok(());
    }
    if p.daily.is_empty() {
        out.push(Window::new(lo, hi));
        return Ok(());
    }
    for dw in &p.daily {
        check_daily(zone, dw)?;
        // A window starting the day before `lo` (local) may run past midnight into the range.
        let mut date = lo
            .local_date(dw.offset)
            .yesterday()
            .unwrap_or(lo.local_date(dw.offset));
        let last = (hi - Millis(1)).local_date(dw.offset);
        while date <= last {
            if dw.days.contains(&Weekday::of(date)) {
                let start = Instant::at_local(date, dw.start, dw.offset);
                let mut end = Instant::at_local(date, dw.end, dw.offset);
                if dw.end <= dw.start {
                    end += Millis(DAY_MS);
                }
                let w = Window::new(start.max(lo), end.min(hi));
                if !w.is_empty() {
                    out.push(w);
                }
            }
            let Ok(next) = date.tomorrow() else { break };
            date = next;
        }
    }
    Ok(())
}

fn check_daily(zone: &Zone, dw: &DailyWindow) -> Result<(), ClosureError> {
    let bad = |reason: String| ClosureError::BadSchedule {
        zone: zone.id.clone(),
        reason,
    };
    if !(0..DAY_MS).contains(&dw.start.0) {
        return Err(bad(format!(
            "start {} ms is not a time of day in [00:00, 24:00)",
            dw.start.0
        )));
    }
    if !(0..=DAY_MS).contains(&dw.end.0) {
        return Err(bad(format!(
            "end {} ms is not a time of day in [00:00, 24:00]",
            dw.end.0
        )));
    }
    if dw.offset.0.abs() > 18 * 3_600 {
        return Err(bad(format!("offset {} s is beyond ±18 h", dw.offset.0)));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::closures::fixtures::{daily, t, w, zone};

    #[test]
    fn daily_expansion_with_weekday_filter() {
        // 2026-01-05 is a Monday.
        let z = zone(
            "Z",
            None,
            vec![daily(
                &[Weekday::Mon, Weekday::Wed],
                "10:00",
                "12:00",
                "+08:00",
            )],
        );
        let got = zone_windows(
            &z,
            t("2026-01-05T00:00:00+08:00"),
            t("2026-01-12T00:00:00+08:00"),
        )
        .unwrap();
        assert_eq!(
            got,
            [
                w("2026-01-05T10:00:00+08:00", "2026-01-05T12:00:00+08:00"),
                w("2026-01-07T10:00:00+08:00", "2026-01-07T12:00:00+08:00"),
            ]
        );
        // Clipped at both ends of the range.
        let got = zone_windows(
            &z,
            t("2026-01-05T11:00:00+08:00"),
            t("2026-01-07T11:30:00+08:00"),
        )
        .unwrap();
        assert_eq!(
            got,
            [
                w("2026-01-05T11:00:00+08:00", "2026-01-05T12:00:00+08:00"),
                w("2026-01-07T10:00:00+08:00", "2026-01-07T11:30:00+08:00"),
            ]
        );
    }

    #[test]
    fn window_across_midnight() {
        // 2026-01-10 is a Saturday.
        let z = zone(
            "Z",
            None,
            vec![daily(&[Weekday::Sat], "22:00", "02:00", "+08:00")],
        );
        let got = zone_windows(
            &z,
            t("2026-01-10T00:00:00+08:00"),
            t("2026-01-12T00:00:00+08:00"),
        )
        .unwrap();
        assert_eq!(
            got,
            [w("2026-01-10T22:00:00+08:00", "2026-01-11T02:00:00+08:00")]
        );
        // A range starting on Sunday still sees the tail of Saturday's window.
        let got = zone_windows(
            &z,
            t("2026-01-11T00:00:00+08:00"),
            t("2026-01-12T00:00:00+08:00"),
        )
        .unwrap();
        assert_eq!(
            got,
            [w("2026-01-11T00:00:00+08:00", "2026-01-11T02:00:00+08:00")]
        );
        // end == start: a full day; end 24:00: until midnight.
        let z = zone(
            "Z",
            None,
            vec![
                daily(&[Weekday::Sat], "06:00", "06:00", "Z"),
                daily(&[Weekday::Mon], "20:00", "24:00", "Z"),
            ],
        );
        let got = zone_windows(&z, t("2026-01-10T00:00:00Z"), t("2026-01-13T00:00:00Z")).unwrap();
        assert_eq!(
            got,
            [
                w("2026-01-10T06:00:00Z", "2026-01-11T06:00:00Z"),
                w("2026-01-12T20:00:00Z", "2026-01-13T00:00:00Z"),
            ]
        );
    }

    #[test]
    fn offsets_give_the_right_utc_instants() {
        let range = (t("2026-01-05T00:00:00Z"), t("2026-01-06T00:00:00Z"));
        let sg = zone(
            "SG",
            None,
            vec![daily(&Weekday::ALL, "10:00", "12:00", "+08:00")],
        );
        let utc = zone(
            "UTC",
            None,
            vec![daily(&Weekday::ALL, "02:00", "04:00", "Z")],
        );
        let a = zone_windows(&sg, range.0, range.1).unwrap();
        let b = zone_windows(&utc, range.0, range.1).unwrap();
        assert_eq!(a, b);
        assert_eq!(a, [w("2026-01-05T02:00:00Z", "2026-01-05T04:00:00Z")]);
        // The weekday is the local one: Monday 01:00 +08:00 is Sunday 17:00 UTC.
        let mon = zone(
            "M",
            None,
            vec![daily(&[Weekday::Mon], "01:00", "02:00", "+08:00")],
        );
        let got = zone_windows(&mon, t("2026-01-04T00:00:00Z"), t("2026-01-06T00:00:00Z")).unwrap();
        assert_eq!(got, [w("2026-01-04T17:00:00Z", "2026-01-04T18:00:00Z")]);
        let neg = zone(
            "N",
            None,
            vec![daily(&[Weekday::Sun], "20:00", "21:00", "-05:30")],
        );
        let got = zone_windows(&neg, t("2026-01-04T00:00:00Z"), t("2026-01-06T00:00:00Z")).unwrap();
        assert_eq!(got, [w("2026-01-05T01:30:00Z", "2026-01-05T02:30:00Z")]);
    }

    #[test]
    fn periods_clip_daily_windows_and_stand_alone() {
        let mut p = daily(&Weekday::ALL, "10:00", "12:00", "Z");
        p.start = Some(t("2026-01-05T11:00:00Z"));
        p.end = Some(t("2026-01-06T11:30:00Z"));
        let whole = Period {
            start: Some(t("2026-01-07T08:00:00Z")),
            end: Some(t("2026-01-07T09:00:00Z")),
            daily: vec![],
        };
        let open = Period {
            start: Some(t("2026-01-08T23:00:00Z")),
            end: None,
            daily: vec![],
        };
        let z = zone("Z", None, vec![p, whole, open]);
        let got = zone_windows(&z, t("2026-01-05T00:00:00Z"), t("2026-01-09T00:00:00Z")).unwrap();
        assert_eq!(
            got,
            [
                w("2026-01-05T11:00:00Z", "2026-01-05T12:00:00Z"),
                w("2026-01-06T10:00:00Z", "2026-01-06T11:30:00Z"),
                w("2026-01-07T08:00:00Z", "2026-01-07T09:00:00Z"),
                w("2026-01-08T23:00:00Z", "2026-01-09T00:00:00Z"),
            ]
        );
    }

    #[test]
    fn bad_ranges_and_schedules() {
        let z = zone("Z", None, vec![]);
        assert!(matches!(
            zone_windows(&z, Instant(10), Instant(5)),
            Err(ClosureError::BadRange { .. })
        ));
        assert!(matches!(
            zone_windows(&z, Instant(0), Instant(MAX_RANGE_DAYS * DAY_MS + 1)),
            Err(ClosureError::BadRange { .. })
        ));
        assert!(matches!(
            zone_windows(&z, Instant(i64::MIN), Instant(0)),
            Err(ClosureError::BadRange { .. })
        ));
        assert!(zone_windows(&z, Instant(5), Instant(5)).unwrap().is_empty());
        // The years zones are resolved over hold those MUSE plans, a day and a trip either side.
        assert_eq!(
            RESOLVED,
            t("0000-01-01T00:00:00Z")..t("9999-01-01T00:00:00Z")
        );
        let planned = muse_model::request::PLANNED;
        let week = Millis(7 * DAY_MS);
        let edges = [planned.start - week, planned.end + week];
        for at in edges {
            assert!(zone_windows(&z, at, at + Millis(DAY_MS)).is_ok());
        }
        let year_10000 = Instant(253_402_300_800_000);
        let e = zone_windows(&z, t("9998-01-01T00:00:00Z"), year_10000).unwrap_err();
        assert_eq!(
            e.to_string(),
            "cannot resolve zones over [9998-01-01T00:00:00.000+00:00, \
             +010000-01-01T00:00:00.000+00:00): outside the years 0000 to 9998 (UTC) over \
             which zones are worked out"
        );
        let mut p = daily(&Weekday::ALL, "10:00", "12:00", "Z");
        p.daily[0].end = Millis(DAY_MS + 1);
        let bad = zone("B", None, vec![p]);
        let err = zone_windows(&bad, Instant(0), Instant(DAY_MS)).unwrap_err();
        assert!(
            err.to_string()
                .contains("zone `B` has an invalid daily schedule"),
            "{err}"
        );
    }
}
