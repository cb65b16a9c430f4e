//! Integer-millisecond time.
//!
//! The planner never does floating-point time arithmetic (SPEC §1): an [`Instant`] is a count
//! of milliseconds since the Unix epoch and a [`Millis`] is a signed duration in milliseconds.
//! Conversion to and from RFC 3339 text happens only at the I/O edge, through `jiff`.

use std::fmt;
use std::ops::{Add, AddAssign, Sub, SubAssign};

use jiff::Timestamp;
use jiff::civil::Date;
use jiff::tz::{Offset, TimeZone};

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
    /// The instant is outside the range `jiff` can represent.
    #[error("instant {0} ms is out of range")]
    OutOfRange(i64),
}

/// A point in time: milliseconds since 1970-01-01T00:00:00Z.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Default)]
pub struct Instant(pub i64);

/// A signed duration in milliseconds.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Default)]
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

    fn to_jiff(self) -> Offset {
        Offset::from_seconds(self.0).unwrap_or(Offset::UTC)
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
    /// Parses an RFC 3339 timestamp with an explicit offset, e.g.
    /// `2026-01-05T08:15:03.250+08:00`. Precision finer than a millisecond is an error.
    ///
    /// ```
    /// use muse_model::Instant;
    /// let t = Instant::parse_rfc3339("1970-01-01T08:00:01.500+08:00").unwrap();
    /// assert_eq!(t, Instant(1_500));
    /// assert!(Instant::parse_rfc3339("2026-01-05T08:15:03").is_err());
    /// ```
    pub fn parse_rfc3339(text: &str) -> Result<Self, TimeError> {
        let ts: Timestamp = text
            .trim()
            .parse()
            .map_err(|e: jiff::Error| TimeError::Rfc3339 {
                text: text.to_owned(),
                reason: e.to_string(),
            })?;
        if ts.subsec_nanosecond() % 1_000_000 != 0 {
            return Err(TimeError::SubMillisecond(text.to_owned()));
        }
        Ok(Instant(ts.as_millisecond()))
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
        let days = i64::from(
            date.since(jiff::civil::date(1970, 1, 1))
                .map_or(0, |s| s.get_days()),
        );
        Instant(days * 86_400_000 + time_of_day.0 - i64::from(offset.0) * 1_000)
    }

    /// The local calendar date of this instant in a zone with `offset`.
    ///
    /// ```
    /// use muse_model::{Instant, UtcOffset};
    /// assert_eq!(Instant(0).local_date(UtcOffset::SINGAPORE), jiff::civil::date(1970, 1, 1));
    /// ```
    pub fn local_date(self, offset: UtcOffset) -> Date {
        let local_ms = self.0 + i64::from(offset.0) * 1_000;
        let days = local_ms.div_euclid(86_400_000);
        jiff::civil::date(1970, 1, 1)
            .checked_add(jiff::Span::new().days(days))
            .unwrap_or(jiff::civil::date(1970, 1, 1))
    }

    /// Formats as RFC 3339 with millisecond precision in the given offset, e.g.
    /// `2026-01-05T08:15:03.250+08:00`.
    ///
    /// ```
    /// use muse_model::{Instant, UtcOffset};
    /// assert_eq!(Instant(1_500).to_rfc3339(UtcOffset::SINGAPORE), "1970-01-01T08:00:01.500+08:00");
    /// ```
    pub fn to_rfc3339(self, offset: UtcOffset) -> String {
        let Ok(ts) = Timestamp::from_millisecond(self.0) else {
            return format!("<out of range: {} ms>", self.0);
        };
        let zoned = ts.to_zoned(TimeZone::fixed(offset.to_jiff()));
        format!("{}{}", zoned.strftime("%Y-%m-%dT%H:%M:%S%.3f"), offset)
    }
}

/// Parses a local clock time `HH:MM`, `HH:MM:SS` or `HH:MM:SS.mmm` into a time of day.
/// `24:00[:00]` is accepted as the end of the day.
///
/// ```
/// use muse_model::time::parse_clock;
/// assert_eq!(parse_clock("08:15").unwrap().0, (8 * 3600 + 15 * 60) * 1000);
/// assert_eq!(parse_clock("10:00:01.5").unwrap().0, 36_001_500);
/// assert!(parse_clock("25:00").is_err());
/// ```
pub fn parse_clock(text: &str) -> Result<Millis, TimeError> {
    let err = || TimeError::ClockTime(text.to_owned());
    let parts: Vec<&str> = text.trim().split(':').collect();
    if !(2..=3).contains(&parts.len()) || parts[..2].iter().any(|p| p.len() != 2) {
        return Err(err());
    }
    let num = |p: &str| -> Result<i64, TimeError> {
        if p.bytes().all(|b| b.is_ascii_digit()) && !p.is_empty() {
            p.parse().map_err(|_| err())
        } else {
            Err(err())
        }
    };
    let h = num(parts[0])?;
    let m = num(parts[1])?;
    let mut ms = 0;
    if let Some(sec) = parts.get(2) {
        let (whole, frac) = sec.split_once('.').unwrap_or((sec, ""));
        if whole.len() != 2 || frac.len() > 3 || (sec.contains('.') && frac.is_empty()) {
            return Err(err());
        }
        let s = num(whole)?;
        if s > 59 {
            return Err(err());
        }
        ms = s * 1_000;
        if !frac.is_empty() {
            ms += num(frac)? * 10_i64.pow(3 - frac.len() as u32);
        }
    }
    if m > 59 || h > 24 || (h == 24 && (m > 0 || ms > 0)) {
        return Err(err());
    }
    Ok(Millis((h * 3_600 + m * 60) * 1_000 + ms))
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
