//! The day an airspace is planned on: a calendar date and a UTC offset, which give meaning to
//! bare local clock times (a requests file's `08:15`, the demand window `08:00–20:00`) and in
//! which every output writes its times.
//!
//! A built-in scenario has its own (Singapore's: Monday 2026-01-05, `+08:00`). An airspace
//! file may carry one as members of its FeatureCollection (written by `muse airspace build
//! --pads … --time-zone NAME`):
//!
//! ```json
//! {"type": "FeatureCollection", "date": "2026-01-05", "utc_offset": "+01:00",
//!  "time_zone": "Europe/Vienna", "features": [...]}
//! ```
//!
//! `date` and `utc_offset` come together; `time_zone`, an IANA name, is optional and, when
//! given, must give `utc_offset` at noon of `date` (one offset serves the whole day, as in a
//! file's timestamps). A file without them is planned on the default day.

use std::fmt::Write as _;

use jiff::civil::Date;
use muse_model::UtcOffset;
use serde_json::Value;

use crate::error::{InputError, Location};

/// The date and offset that give meaning to bare local clock times.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LocalDay {
    /// The scenario date.
    pub date: Date,
    /// The scenario's UTC offset.
    pub offset: UtcOffset,
}

/// The years a day may fall in: every instant of the day, and of the days around it that a
/// zone's daily schedule reaches, is then within what zones are resolved over.
pub const YEARS: std::ops::RangeInclusive<i16> = 1001..=8999;

/// An airspace file's day, and the time zone it was taken from, if the file names one.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FileDay {
    /// The date and offset.
    pub day: LocalDay,
    /// The IANA time zone the offset is that of (at noon of the date), e.g. `Europe/Vienna`.
    pub time_zone: Option<String>,
}

/// Why a day cannot be made of what was given: the option or member at fault, and why.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{field}: {message}")]
pub struct DayError {
    /// The member of the file (`date`, `utc_offset`, `time_zone`) or the option.
    pub field: &'static str,
    /// What is wrong.
    pub message: String,
}

impl DayError {
    fn new(field: &'static str, message: impl Into<String>) -> Self {
        DayError {
            field,
            message: message.into(),
        }
    }
}

impl FileDay {
    /// The day of `date` in the IANA time zone `name`, at the zone's offset at noon.
    ///
    /// ```
    /// use muse_formats::day::FileDay;
    /// let winter = FileDay::in_zone("2026-01-05", "Europe/Vienna").unwrap();
    /// assert_eq!(winter.day.offset.to_string(), "+01:00");
    /// let summer = FileDay::in_zone("2026-07-06", "Europe/Vienna").unwrap();
    /// assert_eq!(summer.day.offset.to_string(), "+02:00");
    /// assert!(FileDay::in_zone("2026-01-05", "Europe/Atlantis").is_err());
    /// ```
    pub fn in_zone(date: &str, name: &str) -> Result<Self, DayError> {
        let date = parse_date(date)?;
        let offset = offset_at_noon(date, name)?;
        Ok(FileDay {
            day: LocalDay { date, offset },
            time_zone: Some(name.to_owned()),
        })
    }

    /// The day of `date` at the fixed offset `offset` (`+01:00`, `-05:30`, `Z`).
    ///
    /// ```
    /// let d = muse_formats::day::FileDay::at_offset("2026-01-05", "-05:00").unwrap();
    /// assert_eq!(d.day.offset.0, -5 * 3600);
    /// assert!(muse_formats::day::FileDay::at_offset("2026-01-05", "5").is_err());
    /// ```
    pub fn at_offset(date: &str, offset: &str) -> Result<Self, DayError> {
        let date = parse_date(date)?;
        let offset =
            UtcOffset::parse(offset).map_err(|e| DayError::new("utc_offset", e.to_string()))?;
        Ok(FileDay {
            day: LocalDay { date, offset },
            time_zone: None,
        })
    }

    /// The day a user asks for by name: `date` (or `default_date`) in time zone `time_zone`,
    /// or at the fixed offset `utc_offset`; `None` when neither is given. A date without
    /// either is an error (field `date`), and so are both (field `time_zone`). The command
    /// line's `--time-zone`, `--utc-offset` and `--date` and the Python package's keywords
    /// of the same names are read by this one function.
    ///
    /// ```
    /// use muse_formats::day::FileDay;
    /// let d = FileDay::asked(Some("Asia/Tokyo"), None, None, "2026-01-05").unwrap().unwrap();
    /// assert_eq!(d.day.offset.to_string(), "+09:00");
    /// assert_eq!(FileDay::asked(None, None, None, "2026-01-05"), Ok(None));
    /// assert_eq!(FileDay::asked(None, None, Some("2026-02-01"), "2026-01-05").unwrap_err().field, "date");
    /// ```
    pub fn asked(
        time_zone: Option<&str>,
        utc_offset: Option<&str>,
        date: Option<&str>,
        default_date: &str,
    ) -> Result<Option<Self>, DayError> {
        let on = date.unwrap_or(default_date);
        match (time_zone, utc_offset) {
            (Some(_), Some(_)) => Err(DayError::new(
                "time_zone",
                "give a time zone or a UTC offset, not both",
            )),
            (Some(zone), None) => Self::in_zone(on, zone).map(Some),
            (None, Some(offset)) => Self::at_offset(on, offset).map(Some),
            (None, None) if date.is_some() => Err(DayError::new(
                "date",
                "a date needs a time zone or a UTC offset, the offset it is planned at",
            )),
            (None, None) => Ok(None),
        }
    }

    /// The members that carry this day, as the airspace writer puts them after `"type"`:
    /// `"date": …, "utc_offset": …` and, with a zone, `"time_zone": …`, each followed by
    /// `", "`.
    pub(crate) fn members(&self) -> String {
        let mut out = format!(
            "\"date\": \"{}\", \"utc_offset\": \"{}\", ",
            self.day.date, self.day.offset
        );
        if let Some(zone) = &self.time_zone {
            let _ = write!(out, "\"time_zone\": {}, ", Value::from(zone.as_str()));
        }
        out
    }
}

/// The day an airspace file's FeatureCollection `root` carries, if any.
pub(crate) fn read_day(root: &Value, file: &str) -> Result<Option<FileDay>, InputError> {
    let member = |name: &'static str| -> Result<Option<&str>, InputError> {
        match root.get(name) {
            None | Some(Value::Null) => Ok(None),
            Some(Value::String(s)) => Ok(Some(s)),
            Some(_) => Err(member_error(file, name, "must be a string")),
        }
    };
    let (date, offset, zone) = (member("date")?, member("utc_offset")?, member("time_zone")?);
    let checked = |r: Result<FileDay, DayError>| {
        r.map(Some)
            .map_err(|e| member_error(file, e.field, e.message))
    };
    match (date, offset, zone) {
        (None, None, None) => Ok(None),
        (Some(d), Some(o), None) => checked(FileDay::at_offset(d, o)),
        (Some(d), Some(o), Some(z)) => {
            let day = checked(FileDay::at_offset(d, o))?.expect("a day");
            let in_zone = checked(FileDay::in_zone(d, z))?.expect("a day");
            if in_zone.day.offset != day.day.offset {
                return Err(member_error(
                    file,
                    "utc_offset",
                    format!(
                        "{o} is not the offset of time zone `{z}` on {d} ({} at noon)",
                        in_zone.day.offset
                    ),
                ));
            }
            Ok(Some(in_zone))
        }
        (None, _, _) => Err(member_error(
            file,
            "date",
            "missing: a file that gives `utc_offset` or `time_zone` gives the date they apply on",
        )),
        (Some(_), None, _) => Err(member_error(
            file,
            "utc_offset",
            "missing: a file that gives `date` gives its UTC offset (e.g. \"+01:00\")",
        )),
    }
}

fn member_error(file: &str, field: &'static str, message: impl Into<String>) -> InputError {
    InputError::new(file, Location::Whole, Some(field), message.into())
}

/// A date `YYYY-MM-DD` within [`YEARS`].
fn parse_date(text: &str) -> Result<Date, DayError> {
    let date: Date = text.parse().map_err(|_| {
        DayError::new(
            "date",
            format!("`{text}` is not a date such as 2026-01-05 (YYYY-MM-DD)"),
        )
    })?;
    if !YEARS.contains(&date.year()) {
        return Err(DayError::new(
            "date",
            format!(
                "{date} is outside the years planned on, {} to {}",
                YEARS.start(),
                YEARS.end()
            ),
        ));
    }
    Ok(date)
}

/// The UTC offset of time zone `name` at noon of `date`, from the IANA database MUSE carries.
fn offset_at_noon(date: Date, name: &str) -> Result<UtcOffset, DayError> {
    let tz = jiff::tz::db().get(name).map_err(|_| {
        DayError::new(
            "time_zone",
            format!("`{name}` is not a time zone of the IANA database (e.g. Europe/Vienna)"),
        )
    })?;
    let noon = date
        .at(12, 0, 0, 0)
        .to_zoned(tz.clone())
        .map_err(|e| DayError::new("time_zone", format!("noon of {date} in `{name}`: {e}")))?;
    Ok(UtcOffset(noon.offset().seconds()))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn day_of(text: &str) -> Result<Option<FileDay>, String> {
        let root: Value = serde_json::from_str(text).unwrap();
        read_day(&root, "a.geojson").map_err(|e| e.to_string())
    }

    #[test]
    fn a_file_without_a_day_has_none() {
        assert_eq!(
            day_of(r#"{"type": "FeatureCollection", "features": []}"#),
            Ok(None)
        );
    }

    #[test]
    fn a_day_is_read_with_or_without_its_zone() {
        let d = day_of(r#"{"date": "2026-01-05", "utc_offset": "+01:00"}"#)
            .unwrap()
            .unwrap();
        assert_eq!((d.day.offset.0, d.time_zone), (3_600, None));
        let d = day_of(
            r#"{"date": "2026-07-06", "utc_offset": "+02:00", "time_zone": "Europe/Vienna"}"#,
        )
        .unwrap()
        .unwrap();
        assert_eq!(d.time_zone.as_deref(), Some("Europe/Vienna"));
        assert_eq!(d.day.date, jiff::civil::date(2026, 7, 6));
    }

    #[test]
    fn a_day_that_contradicts_itself_or_is_half_given_is_refused() {
        let e = day_of(
            r#"{"date": "2026-07-06", "utc_offset": "+01:00", "time_zone": "Europe/Vienna"}"#,
        )
        .unwrap_err();
        assert!(
            e.contains("field `utc_offset`") && e.contains("+02:00 at noon"),
            "{e}"
        );
        let e = day_of(r#"{"utc_offset": "+01:00"}"#).unwrap_err();
        assert!(e.contains("field `date`: missing"), "{e}");
        let e = day_of(r#"{"date": "2026-01-05"}"#).unwrap_err();
        assert!(e.contains("field `utc_offset`: missing"), "{e}");
        let e = day_of(r#"{"date": "5.1.2026", "utc_offset": "+01:00"}"#).unwrap_err();
        assert!(e.contains("is not a date such as 2026-01-05"), "{e}");
        let e = day_of(r#"{"date": "9999-01-05", "utc_offset": "+01:00"}"#).unwrap_err();
        assert!(
            e.contains("outside the years planned on, 1001 to 8999"),
            "{e}"
        );
        let e = day_of(r#"{"date": "2026-01-05", "utc_offset": 1}"#).unwrap_err();
        assert!(e.contains("field `utc_offset`: must be a string"), "{e}");
    }

    #[test]
    fn members_are_written_as_they_are_read() {
        let d = FileDay::in_zone("2026-01-05", "America/New_York").unwrap();
        assert_eq!(
            d.members(),
            "\"date\": \"2026-01-05\", \"utc_offset\": \"-05:00\", \
             \"time_zone\": \"America/New_York\", "
        );
        let text = format!(
            "{{\"type\": \"FeatureCollection\", {}\"features\": []}}",
            d.members()
        );
        assert_eq!(day_of(&text), Ok(Some(d)));
    }
}
