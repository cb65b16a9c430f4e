//! Integer-millisecond time.
//!
//! The planner never does floating-point time arithmetic (docs/reference.md#time): an [`Instant`]
//! is a count of milliseconds since the Unix epoch and a [`Millis`] is a signed duration in
//! milliseconds. Conversion to and from RFC 3339 text happens only at the I/O edge
//! ([`Instant::parse_rfc3339`], [`Instant::to_rfc3339`], [`parse_clock`]), in exact integer
//! arithmetic on the proleptic Gregorian calendar.
//!
//! Every RFC 3339 timestamp is read exactly, years 0000 to 9999 with any offset up to
//! ±23:59, so `9999-12-31T23:59:59.999-23:59` is as good an instant as any other. Beyond
//! them, the year is written (and read) as an ISO 8601 expanded year, a sign and six digits
//! (`+010000-01-01T07:59:59.000+08:00`, as RFC 9557 and `jiff` write it). MUSE reads instants
//! from `-999999-01-01T00:00:00Z` to `+999999-12-31T23:59:59.999Z` ([`Instant::TEXT_MIN`],
//! [`Instant::TEXT_MAX`]): far beyond any flight, and far enough inside `i64` that no
//! arithmetic on them overflows; each of them is written back, in any offset, as text that
//! reads back exactly. A time beyond them is refused as out of range, saying so.
//!
//! A leap second (`23:59:60`) is refused everywhere: MUSE time, like Unix time, has 60 seconds
//! in every minute, and rounding a leap second to `:59` (as `jiff` does) would silently change
//! the value given.

use std::fmt;
use std::ops::{Add, AddAssign, Sub, SubAssign};

use jiff::civil::Date;

mod calendar;
mod clock;

use calendar::{civil_from_days, days_from_civil, days_in_month};
pub use clock::parse_clock;

/// Milliseconds in a day.
const DAY_MS: i64 = 86_400_000;

/// The years an RFC 3339 timestamp can write (four digits); others take an expanded year.
const YEARS: std::ops::RangeInclusive<i64> = 0..=9_999;

/// The largest year (either side of year 0) a timestamp's text may give: one more than
/// [`Instant::TEXT_MIN`] and [`Instant::TEXT_MAX`] hold, so that each of them reads back in
/// any offset.
const MAX_ABS_YEAR: i64 = 1_000_000;

/// Errors from parsing or formatting times.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum TimeError {
    /// The text is not an RFC 3339 timestamp with an explicit offset.
    #[error(
        "`{text}` is not an RFC 3339 timestamp with an offset (e.g. 2026-01-05T08:15:03.250+08:00): {reason}"
    )]
    Rfc3339 {
        /// The offending text.
        text: String,
        /// What the parser said.
        reason: String,
    },
    /// The timestamp has a fraction finer than a millisecond.
    #[error("`{0}` has sub-millisecond precision; MUSE times are whole milliseconds")]
    SubMillisecond(String),
    /// The text is not a local clock time `HH:MM[:SS[.mmm]]`.
    #[error("`{0}` is not a local clock time HH:MM[:SS[.mmm]]")]
    ClockTime(String),
    /// The text is not a UTC offset such as `+08:00` or `Z`.
    #[error("`{0}` is not a UTC offset such as +08:00 or Z")]
    Offset(String),
    /// A duration in seconds is negative, not finite or not a whole number of milliseconds.
    #[error("{0} s is not a valid duration (finite, non-negative, millisecond precision)")]
    Seconds(f64),
    /// The timestamp is well formed but outside the instants MUSE reads,
    /// [`Instant::TEXT_MIN`] to [`Instant::TEXT_MAX`].
    #[error(
        "`{0}` is out of the range MUSE represents: -999999-01-01T00:00:00Z to \
         +999999-12-31T23:59:59.999Z"
    )]
    OutOfRange(String),
    /// The time is a leap second, `:60`.
    #[error(
        "`{0}` is a leap second (second 60): leap seconds are not accepted, since MUSE time \
         (like Unix time) has 60 seconds in every minute; give :59 or the next minute's :00"
    )]
    LeapSecond(String),
}

/// A point in time: milliseconds since 1970-01-01T00:00:00Z.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Default)]
#[repr(transparent)]
pub struct Instant(pub i64);

/// A signed duration in milliseconds.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Default)]
#[repr(transparent)]
pub struct Millis(pub i64);

/// A fixed UTC offset, in seconds east of UTC (Singapore: `+08:00` = 28 800 s).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub struct UtcOffset(pub i32);

impl Millis {
    /// Zero duration.
    pub const ZERO: Millis = Millis(0);

    /// A duration of whole seconds.
    ///
    /// ```
    /// assert_eq!(muse_model::Millis::from_secs(5).0, 5_000);
    /// ```
    pub const fn from_secs(s: i64) -> Self {
        Millis(s * 1_000)
    }

    /// A duration of whole minutes.
    ///
    /// ```
    /// assert_eq!(muse_model::Millis::from_mins(20).0, 1_200_000);
    /// ```
    pub const fn from_mins(m: i64) -> Self {
        Millis(m * 60_000)
    }

    /// Seconds as given in files (a JSON number with millisecond precision), rounded to the
    /// nearest millisecond. Negative, non-finite or absurdly large values are errors.
    ///
    /// ```
    /// assert_eq!(muse_model::Millis::from_secs_f64(17.28).unwrap().0, 17_280);
    /// assert!(muse_model::Millis::from_secs_f64(-1.0).is_err());
    /// ```
    pub fn from_secs_f64(s: f64) -> Result<Self, TimeError> {
        if !s.is_finite() || !(0.0..=1e12).contains(&s) {
            return Err(TimeError::Seconds(s));
        }
        Ok(Millis((s * 1_000.0).round() as i64))
    }

    /// The duration in seconds, for output (`17_280` ms → `17.28`).
    ///
    /// ```
    /// assert_eq!(muse_model::Millis(17_280).as_secs_f64(), 17.28);
    /// ```
    pub fn as_secs_f64(self) -> f64 {
        self.0 as f64 / 1_000.0
    }
}

impl UtcOffset {
    /// Singapore's offset, `+08:00`.
    pub const SINGAPORE: UtcOffset = UtcOffset(8 * 3_600);

    /// Parses `Z`, `+08:00`, `-05:30` or `+0800`.
    ///
    /// ```
    /// use muse_model::UtcOffset;
    /// assert_eq!(UtcOffset::parse("+08:00").unwrap(), UtcOffset::SINGAPORE);
    /// assert_eq!(UtcOffset::parse("Z").unwrap(), UtcOffset(0));
    /// assert!(UtcOffset::parse("08:00").is_err());
    /// ```
    pub fn parse(text: &str) -> Result<Self, TimeError> {
        let err = || TimeError::Offset(text.to_owned());
        if text == "Z" || text == "z" {
            return Ok(UtcOffset(0));
        }
        let (sign, rest) = match text.as_bytes().first() {
            Some(b'+') => (1, &text[1..]),
            Some(b'-') => (-1, &text[1..]),
            _ => return Err(err()),
        };
        let digits: String = rest.chars().filter(|c| *c != ':').collect();
        if digits.len() != 4 || !digits.bytes().all(|b| b.is_ascii_digit()) || rest.len() > 5 {
            return Err(err());
        }
        let h: i32 = digits[..2].parse().map_err(|_| err())?;
        let m: i32 = digits[2..].parse().map_err(|_| err())?;
        if h > 18 || m > 59 {
            return Err(err());
        }
        Ok(UtcOffset(sign * (h * 3_600 + m * 60)))
    }
}

impl fmt::Display for UtcOffset {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let sign = if self.0 < 0 { '-' } else { '+' };
        let abs = self.0.unsigned_abs();
        write!(f, "{sign}{:02}:{:02}", abs / 3_600, (abs % 3_600) / 60)
    }
}

impl Instant {
    /// The earliest instant [`Instant::parse_rfc3339`] reads: `-999999-01-01T00:00:00Z`.
    pub const TEXT_MIN: Instant = Instant(days_from_civil(-999_999, 1, 1) * DAY_MS);

    /// The latest instant [`Instant::parse_rfc3339`] reads: `+999999-12-31T23:59:59.999Z`.
    pub const TEXT_MAX: Instant = Instant(days_from_civil(1_000_000, 1, 1) * DAY_MS - 1);

    /// Parses an RFC 3339 timestamp with an explicit offset, e.g.
    /// `2026-01-05T08:15:03.250+08:00`: `YYYY-MM-DD`, `T` (or `t`, or a space), `hh:mm:ss`, an
    /// optional fraction, then `Z` (or `z`) or `±hh:mm`. Every such timestamp of the years
    /// 0000 to 9999 is read exactly, whatever its offset; beyond them the year is written
    /// expanded, a sign and six digits, as [`Instant::to_rfc3339`] does (`+010000`,
    /// `-000001`). Precision finer than a millisecond is an error
    /// ([`TimeError::SubMillisecond`]), so is a leap second `:60` ([`TimeError::LeapSecond`])
    /// and an instant outside [`Instant::TEXT_MIN`] to [`Instant::TEXT_MAX`]
    /// ([`TimeError::OutOfRange`]).
    ///
    /// ```
    /// use muse_model::Instant;
    /// let t = Instant::parse_rfc3339("1970-01-01T08:00:01.500+08:00").unwrap();
    /// assert_eq!(t, Instant(1_500));
    /// assert_eq!(
    ///     Instant::parse_rfc3339("9999-12-31T23:59:59Z").unwrap(),
    ///     Instant(253_402_300_799_000)
    /// );
    /// assert!(Instant::parse_rfc3339("2026-01-05T08:15:03").is_err());
    /// assert!(Instant::parse_rfc3339("2026-06-30T23:59:60Z").is_err());
    /// assert!(Instant::parse_rfc3339("+999999999-01-01T00:00:00Z").is_err());
    /// ```
    pub fn parse_rfc3339(text: &str) -> Result<Self, TimeError> {
        let trimmed = text.trim();
        let bad = |reason: String| TimeError::Rfc3339 {
            text: text.to_owned(),
            reason,
        };
        let out_of_range = || TimeError::OutOfRange(text.to_owned());
        let (year, rest) = split_year(trimmed).map_err(|e| match e {
            YearError::Syntax(reason) => bad(reason),
            YearError::OutOfRange => out_of_range(),
        })?;
        let mut c = Cursor {
            text: rest,
            at: trimmed.len() - rest.len(),
        };
        let month = c
            .expect(b"-", "`-` after the year")
            .and_then(|()| c.number(2, "month"));
        let fields = month.and_then(|month| {
            c.expect(b"-", "`-` after the month")?;
            let day = c.number(2, "day")?;
            c.expect(b"Tt ", "`T` between the date and the time")?;
            let hour = c.number(2, "hour")?;
            c.expect(b":", "`:` after the hour")?;
            let minute = c.number(2, "minute")?;
            c.expect(b":", "`:` and the seconds after the minutes")?;
            let second = c.number(2, "second")?;
            let fraction = c.fraction()?;
            let offset = c.offset()?;
            if !c.text.is_empty() {
                return Err(format!(
                    "unexpected `{}` after the offset, at byte {}",
                    c.text, c.at
                ));
            }
            Ok((month, day, hour, minute, second, fraction, offset))
        });
        let (month, day, hour, minute, second, (ms, sub_ms), offset_s) = fields.map_err(bad)?;
        if !(1..=12).contains(&month) {
            return Err(bad(format!("month {month:02} is not 01 to 12")));
        }
        if day < 1 || day > days_in_month(year, month) {
            return Err(bad(format!(
                "day {day:02} does not exist in {year:04}-{month:02}"
            )));
        }
        if hour > 23 || minute > 59 {
            return Err(bad(format!(
                "{hour:02}:{minute:02} is not a time of day (00:00 to 23:59)"
            )));
        }
        if second == 60 {
            return Err(TimeError::LeapSecond(text.to_owned()));
        }
        if second > 59 {
            return Err(bad(format!("second {second:02} is not 00 to 59")));
        }
        if sub_ms {
            return Err(TimeError::SubMillisecond(text.to_owned()));
        }
        let days = i128::from(days_from_civil(year, month, day));
        let local =
            ((days * 24 + i128::from(hour)) * 60 + i128::from(minute)) * 60 + i128::from(second);
        let utc_ms = (local - i128::from(offset_s)) * 1_000 + i128::from(ms);
        i64::try_from(utc_ms)
            .ok()
            .map(Instant)
            .filter(|t| (Instant::TEXT_MIN..=Instant::TEXT_MAX).contains(t))
            .ok_or_else(out_of_range)
    }

    /// The instant at local clock time `time_of_day` on `date` in a zone with `offset`.
    ///
    /// ```
    /// use muse_model::{Instant, Millis, UtcOffset};
    /// let d = jiff::civil::date(1970, 1, 1);
    /// let t = Instant::at_local(d, Millis::from_secs(8 * 3600), UtcOffset::SINGAPORE);
    /// assert_eq!(t, Instant(0));
    /// ```
    pub fn at_local(date: Date, time_of_day: Millis, offset: UtcOffset) -> Self {
        let days = days_from_civil(
            i64::from(date.year()),
            i64::from(date.month()),
            i64::from(date.day()),
        );
        Instant(days * DAY_MS + time_of_day.0 - i64::from(offset.0) * 1_000)
    }

    /// The local calendar date of this instant in a zone with `offset`.
    ///
    /// ```
    /// use muse_model::{Instant, UtcOffset};
    /// assert_eq!(Instant(0).local_date(UtcOffset::SINGAPORE), jiff::civil::date(1970, 1, 1));
    /// ```
    pub fn local_date(self, offset: UtcOffset) -> Date {
        let local_ms = self.0 + i64::from(offset.0) * 1_000;
        let days = local_ms.div_euclid(DAY_MS);
        jiff::civil::date(1970, 1, 1)
            .checked_add(jiff::Span::new().days(days))
            .unwrap_or(jiff::civil::date(1970, 1, 1))
    }

    /// Formats as RFC 3339 with millisecond precision in the given offset, e.g.
    /// `2026-01-05T08:15:03.250+08:00`: exactly the text [`Instant::parse_rfc3339`] reads
    /// back as this instant. A local date outside the years 0000–9999, which RFC 3339 cannot
    /// write, is given with an ISO 8601 expanded year (`+010000-01-01T…`, six digits, more
    /// beyond [`Instant::TEXT_MIN`] and [`Instant::TEXT_MAX`], which are not read back).
    ///
    /// ```
    /// use muse_model::{Instant, UtcOffset};
    /// assert_eq!(Instant(1_500).to_rfc3339(UtcOffset::SINGAPORE), "1970-01-01T08:00:01.500+08:00");
    /// assert_eq!(
    ///     Instant(253_402_300_799_000).to_rfc3339(UtcOffset::SINGAPORE),
    ///     "+010000-01-01T07:59:59.000+08:00"
    /// );
    /// ```
    pub fn to_rfc3339(self, offset: UtcOffset) -> String {
        let local = i128::from(self.0) + i128::from(offset.0) * 1_000;
        let day_ms = i128::from(DAY_MS);
        // |local| < 2^64, so the day count fits an i64 and the rest is below a day.
        let days = local.div_euclid(day_ms) as i64;
        let ms = local.rem_euclid(day_ms) as i64;
        let (year, month, day) = civil_from_days(days);
        let (h, m, s, milli) = (
            ms / 3_600_000,
            ms / 60_000 % 60,
            ms / 1_000 % 60,
            ms % 1_000,
        );
        let year = if YEARS.contains(&year) {
            format!("{year:04}")
        } else {
            let sign = if year < 0 { '-' } else { '+' };
            format!("{sign}{:06}", year.unsigned_abs())
        };
        format!("{year}-{month:02}-{day:02}T{h:02}:{m:02}:{s:02}.{milli:03}{offset}")
    }
}

/// Why the year of a timestamp could not be read.
enum YearError {
    /// Not a year as RFC 3339 (or an expanded year) is written.
    Syntax(String),
    /// A well-formed year far beyond what an [`Instant`] holds.
    OutOfRange,
}

/// Splits the year off the start of `text`: four digits, or (ISO 8601 expanded years, for the
/// years RFC 3339 cannot write) a sign and six or more digits; then `-`. A year beyond
/// [`MAX_ABS_YEAR`] is out of range.
fn split_year(text: &str) -> Result<(i64, &str), YearError> {
    let (sign, body) = match text.as_bytes().first() {
        Some(b'+') => (Some(1), &text[1..]),
        Some(b'-') => (Some(-1), &text[1..]),
        _ => (None, text),
    };
    let digits = body.bytes().take_while(u8::is_ascii_digit).count();
    let well_formed = match sign {
        None => digits == 4,
        Some(_) => digits >= 6,
    };
    if !well_formed || !body[digits..].starts_with('-') {
        return Err(YearError::Syntax(
            "expected a four-digit year, then `-` (beyond 0000-9999: a sign and six or more \
             digits, e.g. +010000)"
                .into(),
        ));
    }
    let year = body[..digits]
        .parse::<i64>()
        .ok()
        .filter(|y| *y <= MAX_ABS_YEAR)
        .ok_or(YearError::OutOfRange)?;
    Ok((sign.unwrap_or(1) * year, &body[digits..]))
}

/// Reads the fixed-width fields of an RFC 3339 timestamp after the year.
struct Cursor<'a> {
    /// What is left to read.
    text: &'a str,
    /// Its byte position in the whole text, for messages.
    at: usize,
}

impl Cursor<'_> {
    fn advance(&mut self, n: usize) {
        self.text = &self.text[n..];
        self.at += n;
    }

    /// One of the bytes in `any`.
    fn expect(&mut self, any: &[u8], what: &str) -> Result<(), String> {
        match self.text.as_bytes().first() {
            Some(b) if any.contains(b) => {
                self.advance(1);
                Ok(())
            }
            _ => Err(format!("expected {what} at byte {}", self.at)),
        }
    }

    /// Exactly `width` decimal digits.
    fn number(&mut self, width: usize, what: &str) -> Result<i64, String> {
        let digits = self.text.as_bytes().get(..width);
        match digits {
            Some(d) if d.iter().all(u8::is_ascii_digit) => {
                let v = d.iter().fold(0, |v, b| v * 10 + i64::from(b - b'0'));
                self.advance(width);
                Ok(v)
            }
            _ => Err(format!(
                "expected the {what} as {width} digits at byte {}",
                self.at
            )),
        }
    }

    /// An optional `.` and digits: the milliseconds, and whether finer digits are not zero.
    fn fraction(&mut self) -> Result<(i64, bool), String> {
        if !self.text.starts_with('.') {
            return Ok((0, false));
        }
        self.advance(1);
        let n = self.text.bytes().take_while(u8::is_ascii_digit).count();
        if n == 0 {
            return Err(format!(
                "expected digits after the decimal point at byte {}",
                self.at
            ));
        }
        let digits = &self.text.as_bytes()[..n];
        let ms = (0..3).fold(0, |v, k| {
            v * 10 + digits.get(k).map_or(0, |b| i64::from(b - b'0'))
        });
        let finer = digits.iter().skip(3).any(|b| *b != b'0');
        self.advance(n);
        Ok((ms, finer))
    }

    /// `Z`, `z` or `±hh:mm`: seconds east of UTC.
    fn offset(&mut self) -> Result<i64, String> {
        let sign = match self.text.as_bytes().first() {
            Some(b'Z' | b'z') => {
                self.advance(1);
                return Ok(0);
            }
            Some(b'+') => 1,
            Some(b'-') => -1,
            _ => {
                return Err(format!(
                    "expected the UTC offset (`Z` or ±hh:mm) at byte {}",
                    self.at
                ));
            }
        };
        self.advance(1);
        let h = self.number(2, "offset's hours")?;
        self.expect(b":", "`:` in the offset (±hh:mm)")?;
        let m = self.number(2, "offset's minutes")?;
        if h > 23 || m > 59 {
            return Err(format!("offset {h:02}:{m:02} is beyond ±23:59"));
        }
        Ok(sign * (h * 3_600 + m * 60))
    }
}

impl Add<Millis> for Instant {
    type Output = Instant;
    #[inline]
    fn add(self, rhs: Millis) -> Instant {
        Instant(self.0 + rhs.0)
    }
}

impl AddAssign<Millis> for Instant {
    #[inline]
    fn add_assign(&mut self, rhs: Millis) {
        self.0 += rhs.0;
    }
}

impl Sub<Millis> for Instant {
    type Output = Instant;
    #[inline]
    fn sub(self, rhs: Millis) -> Instant {
        Instant(self.0 - rhs.0)
    }
}

impl SubAssign<Millis> for Instant {
    #[inline]
    fn sub_assign(&mut self, rhs: Millis) {
        self.0 -= rhs.0;
    }
}

impl Sub for Instant {
    type Output = Millis;
    #[inline]
    fn sub(self, rhs: Instant) -> Millis {
        Millis(self.0 - rhs.0)
    }
}

impl Add for Millis {
    type Output = Millis;
    #[inline]
    fn add(self, rhs: Millis) -> Millis {
        Millis(self.0 + rhs.0)
    }
}

impl Sub for Millis {
    type Output = Millis;
    #[inline]
    fn sub(self, rhs: Millis) -> Millis {
        Millis(self.0 - rhs.0)
    }
}

impl fmt::Display for Millis {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{:.3} s", self.as_secs_f64())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip_rfc3339() {
        let text = "2026-01-05T08:15:03.250+08:00";
        let t = Instant::parse_rfc3339(text).unwrap();
        assert_eq!(t.to_rfc3339(UtcOffset::SINGAPORE), text);
        assert_eq!(
            Instant::parse_rfc3339("2026-01-05T00:15:03.250Z").unwrap(),
            t,
            "Z and +08:00 name the same instant"
        );
    }

    #[test]
    fn rejects_missing_offset_and_sub_millisecond() {
        assert!(matches!(
            Instant::parse_rfc3339("2026-01-05T08:15:03"),
            Err(TimeError::Rfc3339 { .. })
        ));
        assert!(matches!(
            Instant::parse_rfc3339("2026-01-05T08:15:03.2501+08:00"),
            Err(TimeError::SubMillisecond(_))
        ));
    }

    #[test]
    fn local_dates_and_negative_offsets() {
        let d = jiff::civil::date(2026, 1, 5);
        let t = Instant::at_local(d, Millis::from_secs(3_600), UtcOffset::SINGAPORE);
        assert_eq!(
            t.to_rfc3339(UtcOffset::SINGAPORE),
            "2026-01-05T01:00:00.000+08:00"
        );
        assert_eq!(t.local_date(UtcOffset::SINGAPORE), d);
        assert_eq!(t.local_date(UtcOffset(0)), jiff::civil::date(2026, 1, 4));
        let ny = UtcOffset::parse("-05:30").unwrap();
        assert_eq!(ny.to_string(), "-05:30");
        assert_eq!(t.to_rfc3339(ny), "2026-01-04T11:30:00.000-05:30");
    }

    #[test]
    fn the_last_day_of_year_9999_is_read_exactly() {
        // 9999-12-31T23:59:59Z is 253 402 300 799 s after the epoch.
        let last = Instant(253_402_300_799_000);
        for (text, want) in [
            ("9999-12-31T23:59:59Z", last),
            ("9999-12-31T23:59:59.999Z", last + Millis(999)),
            (
                "9999-12-31T23:59:59+08:00",
                last - Millis::from_secs(8 * 3_600),
            ),
            (
                "9999-12-31T23:59:59.999-23:59",
                last + Millis(999) + Millis::from_mins(23 * 60 + 59),
            ),
            ("0000-01-01T00:00:00Z", Instant(-62_167_219_200_000)),
            (
                "0000-01-01T00:00:00+23:59",
                Instant(-62_167_219_200_000) - Millis::from_mins(23 * 60 + 59),
            ),
        ] {
            assert_eq!(Instant::parse_rfc3339(text), Ok(want), "{text}");
        }
        assert_eq!(
            last.to_rfc3339(UtcOffset(0)),
            "9999-12-31T23:59:59.000+00:00"
        );
        assert_eq!(
            Instant::parse_rfc3339("9999-12-31T23:59:59+08:00")
                .unwrap()
                .to_rfc3339(UtcOffset::SINGAPORE),
            "9999-12-31T23:59:59.000+08:00"
        );
    }

    #[test]
    fn formatting_agrees_with_jiff_and_reads_back() {
        // Instants spread over the whole range jiff can format, in three offsets.
        let lo = jiff::Timestamp::MIN.as_millisecond() + DAY_MS;
        let hi = jiff::Timestamp::MAX.as_millisecond() - DAY_MS;
        let mut x: u64 = 0x9e37_79b9_7f4a_7c15;
        let mut samples = vec![0, -1, 1, lo, hi, 951_782_400_000, 1_767_225_599_999];
        for _ in 0..20_000 {
            x = x.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
            samples.push(lo + (x >> 1) as i64 % (hi - lo));
        }
        for offset in [
            UtcOffset(0),
            UtcOffset::SINGAPORE,
            UtcOffset(-(5 * 3_600 + 1_800)),
        ] {
            let tz = jiff::tz::TimeZone::fixed(jiff::tz::Offset::from_seconds(offset.0).unwrap());
            for &ms in &samples {
                let t = Instant(ms);
                let text = t.to_rfc3339(offset);
                let zoned = jiff::Timestamp::from_millisecond(ms)
                    .unwrap()
                    .to_zoned(tz.clone());
                let year = zoned.year();
                let date_time = zoned.strftime("%m-%dT%H:%M:%S%.3f").to_string();
                let want = if (0..=9_999).contains(&year) {
                    format!("{year:04}-{date_time}{offset}")
                } else {
                    let sign = if year < 0 { '-' } else { '+' };
                    format!("{sign}{:06}-{date_time}{offset}", year.unsigned_abs())
                };
                assert_eq!(text, want, "{ms} ms");
                assert_eq!(Instant::parse_rfc3339(&text), Ok(t), "{text}");
            }
        }
    }

    #[test]
    fn leap_seconds_are_refused_with_a_message_saying_so() {
        for text in [
            "2026-06-30T23:59:60+00:00",
            "2026-06-30T23:59:60Z",
            "2016-12-31T23:59:60.500Z",
            "2027-01-01T07:59:60+08:00",
        ] {
            let e = Instant::parse_rfc3339(text).unwrap_err();
            assert_eq!(e, TimeError::LeapSecond(text.to_owned()));
            assert!(
                e.to_string().contains("leap seconds are not accepted"),
                "{e}"
            );
        }
        for text in ["23:59:60", "08:00:60", "23:59:60.250"] {
            assert_eq!(
                parse_clock(text),
                Err(TimeError::LeapSecond(text.to_owned()))
            );
        }
        assert!(matches!(
            parse_clock("23:59:61"),
            Err(TimeError::ClockTime(_))
        ));
        assert!(matches!(
            Instant::parse_rfc3339("2026-06-30T23:59:61Z"),
            Err(TimeError::Rfc3339 { .. })
        ));
    }

    #[test]
    fn instants_beyond_year_9999_round_trip_and_only_beyond_the_range_are_refused() {
        // Local years RFC 3339 cannot write take an expanded year, and are read back.
        for (text, want) in [
            ("+010000-01-01T00:00:00Z", Instant(253_402_300_800_000)),
            ("-000001-12-31T23:59:59.999Z", Instant(-62_167_219_200_001)),
            ("+010000-01-01T07:59:59+08:00", Instant(253_402_300_799_000)),
        ] {
            assert_eq!(Instant::parse_rfc3339(text), Ok(want), "{text}");
        }
        assert_eq!(
            Instant(253_402_300_799_000).to_rfc3339(UtcOffset::SINGAPORE),
            "+010000-01-01T07:59:59.000+08:00"
        );
        let (lo, hi) = (Instant::TEXT_MIN, Instant::TEXT_MAX);
        assert_eq!(
            lo.to_rfc3339(UtcOffset(0)),
            "-999999-01-01T00:00:00.000+00:00"
        );
        assert_eq!(
            hi.to_rfc3339(UtcOffset(0)),
            "+999999-12-31T23:59:59.999+00:00"
        );
        let max_offset = 23 * 3_600 + 59 * 60;
        for t in [lo, hi, Instant(0), Instant(-1)] {
            for offset in [
                UtcOffset(0),
                UtcOffset::SINGAPORE,
                UtcOffset(-max_offset),
                UtcOffset(max_offset),
            ] {
                let text = t.to_rfc3339(offset);
                assert_eq!(Instant::parse_rfc3339(&text), Ok(t), "{text}");
            }
        }
        assert_eq!(
            hi.to_rfc3339(UtcOffset(max_offset)),
            "+1000000-01-01T23:58:59.999+23:59"
        );
        // Beyond them: out of range, saying so.
        for text in [
            "+1000000-01-01T00:00:00Z",
            "+999999-12-31T23:59:59.999-00:01",
            "-999999-01-01T00:00:00+00:01",
            "-1000000-12-31T23:59:59.999Z",
            "+292278994-08-17T07:12:55.807Z",
            "-99999999999999999999-01-01T00:00:00Z",
        ] {
            let e = Instant::parse_rfc3339(text).unwrap_err();
            assert_eq!(e, TimeError::OutOfRange(text.to_owned()));
            assert!(
                e.to_string()
                    .contains("is out of the range MUSE represents"),
                "{e}"
            );
        }
        // Whatever an i64 holds can be shown.
        assert_eq!(
            Instant(i64::MIN).to_rfc3339(UtcOffset(0)),
            "-292275055-05-16T16:47:04.192+00:00"
        );
        assert_eq!(
            Instant(i64::MAX).to_rfc3339(UtcOffset(max_offset)),
            "+292278994-08-18T07:11:55.807+23:59"
        );
        // Years beyond 9999 are written with a sign and six or more digits.
        for text in [
            "10000-01-01T00:00:00Z",
            "+10000-01-01T00:00:00Z",
            "+2026-01-05T08:15:03Z",
        ] {
            assert!(
                matches!(Instant::parse_rfc3339(text), Err(TimeError::Rfc3339 { .. })),
                "{text}"
            );
        }
    }

    #[test]
    fn only_rfc3339_is_read() {
        for good in [
            "2024-02-29T00:00:00Z",
            "2026-01-05t08:15:03z",
            "2026-01-05 08:15:03+08:00",
            "2026-01-05T08:15:03-00:00",
            "2026-01-05T08:15:03.250000+08:00",
            " 2026-01-05T08:15:03.2+08:00 ",
        ] {
            assert!(Instant::parse_rfc3339(good).is_ok(), "{good}");
        }
        assert_eq!(
            Instant::parse_rfc3339("2026-01-05T08:15:03.2+08:00"),
            Instant::parse_rfc3339("2026-01-05T00:15:03.200Z")
        );
        for (bad, reason) in [
            ("2026-02-29T00:00:00Z", "day 29 does not exist in 2026-02"),
            ("2026-13-05T08:00:00Z", "month 13"),
            ("2026-01-05T24:00:00Z", "24:00 is not a time of day"),
            ("2026-01-05T08:60:00Z", "08:60 is not a time of day"),
            ("2026-01-05T08:15+08:00", "seconds after the minutes"),
            ("2026-01-05T08:15:03+0800", "`:` in the offset"),
            ("2026-01-05T08:15:03+08", "`:` in the offset"),
            ("2026-01-05T08:15:03+24:00", "beyond ±23:59"),
            (
                "2026-01-05T08:15:03.+08:00",
                "digits after the decimal point",
            ),
            ("2026-01-05T08:15:03,25+08:00", "UTC offset"),
            (
                "2026-01-05T08:15:03+08:00[Asia/Singapore]",
                "after the offset",
            ),
            ("20260105T081503+08:00", "four-digit year"),
            ("+2026-01-05T08:15:03Z", "four-digit year"),
            ("26-01-05T08:15:03Z", "four-digit year"),
            ("2026-1-05T08:15:03Z", "month as 2 digits"),
            ("2026-01-05", "`T` between the date and the time"),
            ("", "four-digit year"),
            ("2026-01-05T08:15:03", "UTC offset"),
        ] {
            match Instant::parse_rfc3339(bad) {
                Err(TimeError::Rfc3339 { text, reason: r }) => {
                    assert_eq!(text, bad);
                    assert!(r.contains(reason), "{bad}: {r}");
                }
                other => panic!("{bad}: {other:?}"),
            }
        }
    }

    #[test]
    fn civil_days_round_trip() {
        for days in (-3_000_000..3_000_000).step_by(997) {
            let (y, m, d) = civil_from_days(days);
            assert!((1..=12).contains(&m) && (1..=days_in_month(y, m)).contains(&d));
            assert_eq!(days_from_civil(y, m, d), days);
        }
        assert_eq!(days_from_civil(1970, 1, 1), 0);
        assert_eq!(days_from_civil(2000, 3, 1), 11_017);
        assert_eq!(civil_from_days(-1), (1969, 12, 31));
    }

    #[test]
    fn clock_times() {
        assert_eq!(parse_clock("24:00").unwrap(), Millis::from_secs(86_400));
        for bad in [
            "8:15",
            "08:60",
            "24:01",
            "08:15:3",
            "08:15:03.",
            "ab:cd",
            "08:15:03.1234",
        ] {
            assert!(parse_clock(bad).is_err(), "{bad}");
        }
    }
}
