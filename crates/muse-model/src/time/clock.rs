//! Local clock times of day (`HH:MM[:SS[.mmm]]`), as zone windows and options give them.

use super::{Millis, TimeError};

/// Parses a local clock time `HH:MM`, `HH:MM:SS` or `HH:MM:SS.mmm` into a time of day.
/// `24:00[:00]` is accepted as the end of the day; a leap second `:60` is refused
/// ([`TimeError::LeapSecond`]).
///
/// ```
/// use muse_model::time::parse_clock;
/// assert_eq!(parse_clock("08:15").unwrap().0, (8 * 3600 + 15 * 60) * 1000);
/// assert_eq!(parse_clock("10:00:01.5").unwrap().0, 36_001_500);
/// assert!(parse_clock("25:00").is_err());
/// assert!(parse_clock("23:59:60").is_err());
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
        if s == 60 {
            return Err(TimeError::LeapSecond(text.to_owned()));
        }
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
