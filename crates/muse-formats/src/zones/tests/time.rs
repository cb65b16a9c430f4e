//! Time in zone files: permanence and periods, clock offsets, midnight, leap seconds and
//! the last representable year.

use super::*;

#[test]
fn permanence_and_periods() {
    let read = |la: Value| {
        read_zones(
            &ed318_with(|p, _| {
                p.insert("limitedApplicability".into(), la);
            }),
            "z",
        )
        .unwrap()
        .remove(0)
    };
    assert!(read(json!([])).is_permanent());
    assert!(read(Value::Null).is_permanent());
    assert!(read(json!([{"permanent": "YES"}])).is_permanent());
    assert!(read(json!([{"startDateTime": "2026-01-05T00:00:00Z"}, {}])).is_permanent());
    let z = read(
        json!({"startDateTime": "2026-01-05T10:00:00+08:00", "endDateTime": "2026-01-05T12:00:00.500Z"}),
    );
    assert_eq!(z.periods.len(), 1);
    assert_eq!(z.periods[0].start, Some(Instant(1_767_578_400_000)));
    assert_eq!(z.periods[0].end, Some(Instant(1_767_614_400_500)));
    let e = err_of(&ed318_with(|p, _| {
        p.insert(
            "limitedApplicability".into(),
            json!([{"permanent": "MAYBE"}]),
        );
    }));
    assert_err(
        &e,
        "limitedApplicability[0].permanent",
        "expected \"YES\" or \"NO\"",
    );
}

#[test]
fn clock_offsets_and_midnight() {
    let read = |sched: Value| {
        let mut z = read_zones(
            &ed318_with(|p, _| {
                p.insert(
                    "limitedApplicability".into(),
                    json!([{"schedule": [sched]}]),
                );
            }),
            "z",
        )
        .unwrap();
        z.remove(0).periods.remove(0).daily.remove(0)
    };
    let d = read(json!({"day": "sat", "startTime": "22:00Z", "endTime": "24:00Z"}));
    assert_eq!(
        (d.days, d.start, d.end, d.offset),
        (
            vec![Weekday::Sat],
            Millis(79_200_000),
            Millis(86_400_000),
            UtcOffset(0)
        )
    );
    // End stated in another offset: converted to the start's (14:00Z = 22:00+08:00).
    let d = read(
        json!({"day": ["SUN", "MON", "MON"], "startTime": "20:00:00+08:00", "endTime": "14:00:00Z"}),
    );
    assert_eq!(
        (d.days, d.start, d.end),
        (
            vec![Weekday::Mon, Weekday::Sun],
            Millis(72_000_000),
            Millis(79_200_000)
        )
    );
    let e = err_of(&ed318_with(|p, _| {
        p.insert(
            "limitedApplicability".into(),
            json!([{"schedule": [
            {"day": ["ANY"], "startTime": "25:00+08:00", "endTime": "12:00+08:00"}]}]),
        );
    }));
    assert_err(
        &e,
        "limitedApplicability[0].schedule[0].startTime",
        "not a local clock time",
    );
}

#[test]
fn leap_seconds_are_refused_in_schedules_and_date_times() {
    let e = err_of(&ed318_with(|p, _| {
        p.insert(
            "limitedApplicability".into(),
            json!([{"schedule": [
            {"day": ["ANY"], "startTime": "10:00:00+08:00", "endTime": "23:59:60+08:00"}]}]),
        );
    }));
    assert_err(
        &e,
        "limitedApplicability[0].schedule[0].endTime",
        "`23:59:60` is a leap second (second 60): leap seconds are not accepted",
    );
    let e = err_of(&ed318_with(|p, _| {
        p.insert(
            "limitedApplicability".into(),
            json!([{"startDateTime": "2026-06-30T23:59:60Z"}]),
        );
    }));
    assert_err(
        &e,
        "limitedApplicability[0].startDateTime",
        "leap seconds are not accepted",
    );
    let e = err_of(&ed318_with(|p, _| {
        p.insert("announced".into(), json!("2026-06-30T23:59:60+00:00"));
    }));
    assert_err(&e, "announced", "leap seconds are not accepted");
}

#[test]
fn date_times_of_year_9999_are_read_exactly() {
    let text = ed318_with(|p, _| {
        p.insert(
            "limitedApplicability".into(),
            json!([{"startDateTime": "2026-01-05T10:00:00+08:00", "endDateTime": "9999-12-31T23:59:59+08:00"}]),
        );
    });
    let zones = read_zones(&text, "z.json").unwrap();
    assert_eq!(
        zones[0].periods[0].end,
        Some(Instant::parse_rfc3339("9999-12-31T15:59:59Z").unwrap())
    );
    let e = err_of(&ed318_with(|p, _| {
        p.insert(
            "limitedApplicability".into(),
            json!([{"endDateTime": "+999999999-01-01T00:00:00Z"}]),
        );
    }));
    assert_err(
        &e,
        "limitedApplicability[0].endDateTime",
        "`+999999999-01-01T00:00:00Z` is out of the range MUSE represents",
    );
}
