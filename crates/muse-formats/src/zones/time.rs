//! Time in zone files: periods (`limitedApplicability` / `applicability`), RFC 3339
//! date-times, daily schedule windows and clock times with a UTC offset.

use muse_model::time::parse_clock;
use muse_model::{DailyWindow, Instant, Millis, Period, UtcOffset, Weekday};
use serde_json::{Map, Value};

use super::{Ctx, expect_object, join, list_of, member, one_of, show};
use crate::InputError;

const DAY_MS: i64 = 86_400_000;

/// Whether a period has no bounds and no schedule: it always applies (the zone is permanent).
pub(super) fn is_always(p: &Period) -> bool {
    p.start.is_none() && p.end.is_none() && p.daily.is_empty()
}

/// `limitedApplicability` (ED-318) or `applicability` (ED-269).
pub(super) fn parse_periods(
    ctx: &Ctx<'_>,
    obj: &Map<String, Value>,
) -> Result<Vec<Period>, InputError> {
    let Some((key, v)) = one_of(ctx, obj, &["limitedApplicability", "applicability"], "")? else {
        return Ok(Vec::new());
    };
    let mut periods = Vec::new();
    for (i, item) in list_of(v).iter().enumerate() {
        let field = format!("{key}[{i}]");
        periods.push(parse_period(ctx, item, &field)?);
    }
    if periods.iter().any(is_always) {
        periods.clear();
    }
    Ok(periods)
}

fn parse_period(ctx: &Ctx<'_>, v: &Value, field: &str) -> Result<Period, InputError> {
    let obj = expect_object(ctx, v, field, "a time period")?;
    if let Some(p) = member(obj, "permanent") {
        let ok = match p {
            Value::Bool(_) => true,
            Value::String(s) => s.eq_ignore_ascii_case("YES") || s.eq_ignore_ascii_case("NO"),
            _ => false,
        };
        if !ok {
            return Err(ctx.err(
                &join(field, "permanent"),
                format!("expected \"YES\" or \"NO\", got {}", show(p)),
            ));
        }
    }
    let start = parse_date_time(ctx, obj, "startDateTime", field)?;
    let end = parse_date_time(ctx, obj, "endDateTime", field)?;
    if let (Some(s), Some(e)) = (start, end)
        && e <= s
    {
        return Err(ctx.err(
            &join(field, "endDateTime"),
            "endDateTime must be after startDateTime",
        ));
    }
    let mut daily = Vec::new();
    if let Some((key, v)) = one_of(ctx, obj, &["schedule", "dailyPeriod"], field)? {
        let items = list_of(v);
        if items.is_empty() {
            return Err(ctx.err(
                &join(field, key),
                "an empty schedule never applies; omit it instead",
            ));
        }
        for (j, item) in items.iter().enumerate() {
            daily.push(parse_daily(
                ctx,
                item,
                &format!("{}[{j}]", join(field, key)),
            )?);
        }
    }
    Ok(Period { start, end, daily })
}

pub(super) fn parse_date_time(
    ctx: &Ctx<'_>,
    obj: &Map<String, Value>,
    key: &str,
    prefix: &str,
) -> Result<Option<Instant>, InputError> {
    let Some(v) = member(obj, key) else {
        return Ok(None);
    };
    let field = join(prefix, key);
    let s = v.as_str().ok_or_else(|| {
        ctx.err(
            &field,
            format!("expected an RFC 3339 date-time string, got {}", show(v)),
        )
    })?;
    Instant::parse_rfc3339(s)
        .map(Some)
        .map_err(|e| ctx.err(&field, e.to_string()))
}

fn parse_daily(ctx: &Ctx<'_>, v: &Value, field: &str) -> Result<DailyWindow, InputError> {
    let obj = expect_object(ctx, v, field, "a schedule entry")?;
    for key in ["startEvent", "endEvent"] {
        if member(obj, key).is_some() {
            return Err(ctx.err(
                &join(field, key),
                "daylight events (SR, SS, BMCT, EECT) are not supported; give startTime and \
                 endTime with a UTC offset",
            ));
        }
    }
    let Some((day_key, days_v)) = one_of(ctx, obj, &["day", "days"], field)? else {
        return Err(ctx.err(
            &join(field, "day"),
            "missing: list the days, e.g. [\"ANY\"]",
        ));
    };
    let day_field = join(field, day_key);
    let day_items = list_of(days_v);
    if day_items.is_empty() {
        return Err(ctx.err(&day_field, "no days given; use [\"ANY\"] for every day"));
    }
    let mut days = Vec::new();
    for (k, d) in day_items.iter().enumerate() {
        let name = d.as_str().unwrap_or_default();
        if name.trim().eq_ignore_ascii_case("ANY") {
            days.extend(Weekday::ALL);
        } else if let Some(day) = Weekday::ALL
            .into_iter()
            .find(|w| w.as_str().eq_ignore_ascii_case(name.trim()))
        {
            days.push(day);
        } else {
            return Err(ctx.err(
                &format!("{day_field}[{k}]"),
                format!(
                    "unknown day {}: expected ANY, MON, TUE, WED, THU, FRI, SAT or SUN",
                    show(d)
                ),
            ));
        }
    }
    days.sort_unstable();
    days.dedup();
    let (start, offset) = parse_clock_with_offset(ctx, obj, "startTime", field)?;
    let (end, end_offset) = parse_clock_with_offset(ctx, obj, "endTime", field)?;
    if start.0 >= DAY_MS {
        return Err(ctx.err(
            &join(field, "startTime"),
            "a schedule cannot start at 24:00; use 00:00",
        ));
    }
    let end = if end_offset == offset {
        end
    } else {
        // Same instant of day, stated in the start time's offset.
        let shifted = (end.0 + i64::from(offset.0 - end_offset.0) * 1_000).rem_euclid(DAY_MS);
        Millis(if shifted == 0 { DAY_MS } else { shifted })
    };
    check_overnight(ctx, obj, field, start, end)?;
    Ok(DailyWindow {
        days,
        start,
        end,
        offset,
    })
}

/// A daily window whose end is at or before its start runs past midnight into the next day:
/// that must be said with `"overnight": true` (a MUSE extension), since an end before the
/// start is more often a mistake (10:00 to 09:00 would close the zone 23 hours a day). An end
/// equal to the start (empty, or a whole day?) is refused: a whole day is 00:00 to 24:00.
fn check_overnight(
    ctx: &Ctx<'_>,
    obj: &Map<String, Value>,
    field: &str,
    start: Millis,
    end: Millis,
) -> Result<(), InputError> {
    let overnight_field = join(field, "overnight");
    let overnight = match member(obj, "overnight") {
        None => false,
        Some(Value::Bool(b)) => *b,
        Some(v) => {
            return Err(ctx.err(
                &overnight_field,
                format!("expected true or false, got {}", show(v)),
            ));
        }
    };
    let (from, to) = (hh_mm(start), hh_mm(end));
    if end == start {
        return Err(ctx.err(
            &join(field, "endTime"),
            format!(
                "the window ends ({to}) when it starts: give a later endTime (for a whole day, \
                 startTime 00:00 and endTime 24:00)"
            ),
        ));
    }
    match (end < start, overnight) {
        (true, false) => Err(ctx.err(
            &join(field, "endTime"),
            format!(
                "the window ends ({to}) before it starts ({from}), times in the startTime's \
                 offset: it would run past midnight and close {} a day. If it is meant to end \
                 the next day, add \"overnight\": true to this schedule entry; otherwise \
                 give an endTime after the startTime, up to 24:00",
                duration(Millis(end.0 + DAY_MS - start.0))
            ),
        )),
        (false, true) => Err(ctx.err(
            &overnight_field,
            format!(
                "the window {from}–{to} ends the day it starts; `overnight: true` is for a \
                 window whose endTime is before its startTime (it ends the next day)"
            ),
        )),
        _ => Ok(()),
    }
}

/// `HH:MM`, or `HH:MM:SS[.mmm]` when it has seconds.
fn hh_mm(t: Millis) -> String {
    let (h, m, s, ms) = (
        t.0 / 3_600_000,
        t.0 / 60_000 % 60,
        t.0 / 1_000 % 60,
        t.0 % 1_000,
    );
    match (s, ms) {
        (0, 0) => format!("{h:02}:{m:02}"),
        (_, 0) => format!("{h:02}:{m:02}:{s:02}"),
        _ => format!("{h:02}:{m:02}:{s:02}.{ms:03}"),
    }
}

/// `23 h`, `1 h 30 min`, `45 min`, or `30 s` for what is shorter.
fn duration(d: Millis) -> String {
    let minutes = d.0 / 60_000;
    match (minutes / 60, minutes % 60) {
        (0, 0) => format!("{} s", d.0 as f64 / 1_000.0),
        (0, m) => format!("{m} min"),
        (h, 0) => format!("{h} h"),
        (h, m) => format!("{h} h {m} min"),
    }
}

fn parse_clock_with_offset(
    ctx: &Ctx<'_>,
    obj: &Map<String, Value>,
    key: &str,
    prefix: &str,
) -> Result<(Millis, UtcOffset), InputError> {
    let field = join(prefix, key);
    let Some(v) = member(obj, key) else {
        return Err(ctx.err(
            &field,
            format!("missing: a schedule entry needs `{key}`, e.g. \"10:00:00+08:00\""),
        ));
    };
    let text = v
        .as_str()
        .ok_or_else(|| {
            ctx.err(
                &field,
                format!(
                    "expected a time such as \"10:00:00+08:00\", got {}",
                    show(v)
                ),
            )
        })?
        .trim();
    let Some(split) = text.find(['+', '-', 'Z', 'z']) else {
        return Err(ctx.err(
            &field,
            format!(
                "`{text}` has no UTC offset: daily schedule times must state one, e.g. \
                 \"{text}+08:00\" or \"{text}Z\""
            ),
        ));
    };
    let clock = parse_clock(&text[..split]).map_err(|e| ctx.err(&field, e.to_string()))?;
    let offset = UtcOffset::parse(&text[split..]).map_err(|e| ctx.err(&field, e.to_string()))?;
    Ok((clock, offset))
}
