//! Colours and fonts shared by the renderers (number formats are in `ticks`).

use plotters::style::text_anchor::{HPos, Pos, VPos};
use plotters::style::{Color, FontDesc, FontFamily, FontStyle, RGBColor, TextStyle};

/// Sea / background inside the map frame.
pub(crate) const SEA: RGBColor = RGBColor(0xC4, 0xDA, 0xEA);
/// Land fill.
pub(crate) const LAND: RGBColor = RGBColor(0xF6, 0xF3, 0xE6);
/// Coastline stroke.
pub(crate) const COAST: RGBColor = RGBColor(0x7E, 0x98, 0xAD);
/// Ordinary corridors.
pub(crate) const EDGE: RGBColor = RGBColor(0x4F, 0x6D, 0x8F);
/// Stations and most text.
pub(crate) const INK: RGBColor = RGBColor(0x1B, 0x2A, 0x41);
/// Waypoints.
pub(crate) const WAYPOINT: RGBColor = RGBColor(0x6E, 0x7B, 0x88);
/// Zones and closed elements.
pub(crate) const ZONE: RGBColor = RGBColor(0xD6, 0x27, 0x28);
/// Marked stations (e.g. pads a siting added): orange.
pub(crate) const MARKED: RGBColor = RGBColor(0xE8, 0x7A, 0x00);
/// Secondary text (ticks, attribution).
pub(crate) const MUTED: RGBColor = RGBColor(0x55, 0x5F, 0x6B);
/// Paper.
pub(crate) const PAPER: RGBColor = RGBColor(0xFF, 0xFF, 0xFF);

/// Line colours for plot series, in order of use: the Okabe–Ito colour-blind-safe palette
/// without its yellow (too pale on white), with the palette's black swapped for [`INK`].
pub(crate) const SERIES: [RGBColor; 7] = [
    RGBColor(0x00, 0x72, 0xB2), // blue
    RGBColor(0xD5, 0x5E, 0x00), // vermillion
    RGBColor(0x00, 0x9E, 0x73), // bluish green
    RGBColor(0xCC, 0x79, 0xA7), // reddish purple
    RGBColor(0xE6, 0x9F, 0x00), // orange
    RGBColor(0x56, 0xB4, 0xE9), // sky blue
    INK,
];

/// Anchors of the load ramp, light to dark (a yellow-green-blue sequential ramp without its
/// palest end, so that quiet corridors still show on the land colour).
const RAMP: [RGBColor; 5] = [
    RGBColor(0xB4, 0xE0, 0xA8),
    RGBColor(0x6C, 0xC5, 0xBD),
    RGBColor(0x2C, 0x8F, 0xC0),
    RGBColor(0x25, 0x44, 0x9A),
    RGBColor(0x0B, 0x1D, 0x5A),
];

/// The load ramp at `t` ∈ [0, 1] (clamped), interpolated linearly between anchors.
pub(crate) fn ramp(t: f64) -> RGBColor {
    let t = if t.is_finite() {
        t.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let pos = t * (RAMP.len() - 1) as f64;
    let seg = (pos.floor() as usize).min(RAMP.len() - 2);
    let frac = pos - seg as f64;
    let (lo, hi) = (RAMP[seg], RAMP[seg + 1]);
    let mix = |from: u8, to: u8| {
        (f64::from(from) + (f64::from(to) - f64::from(from)) * frac).round() as u8
    };
    RGBColor(mix(lo.0, hi.0), mix(lo.1, hi.1), mix(lo.2, hi.2))
}

/// A sans-serif text style whose SVG `font-size` is `px` (plotters divides the size it is
/// given by 1.24 when writing SVG text). No font file is involved: the viewer lays it out.
pub(crate) fn text(px: f64, bold: bool, colour: RGBColor, h: HPos, v: VPos) -> TextStyle<'static> {
    let style = if bold {
        FontStyle::Bold
    } else {
        FontStyle::Normal
    };
    TextStyle {
        font: FontDesc::new(FontFamily::SansSerif, plotters_size(px), style),
        color: colour.to_backend_color(),
        pos: Pos::new(h, v),
    }
}

/// The size to give plotters so that the SVG says `font-size="px"` exactly: plotters writes
/// `size / 1.24`, and `px * 1.24 / 1.24` can come out as `13.000000000000002`. A neighbouring
/// float that divides back exactly is used when there is one.
fn plotters_size(px: f64) -> f64 {
    let guess = px * 1.24;
    (-4_i64..=4)
        .map(|k| f64::from_bits(guess.to_bits().wrapping_add_signed(k)))
        .find(|v| (v / 1.24).to_bits() == px.to_bits())
        .unwrap_or(guess)
}

/// The size nearest to `px`, in quarter pixels (larger first on a tie), that the SVG can say
/// exactly: for some sizes, such as 13, no float divides by 1.24 to give them.
pub(crate) fn exact_px(px: f64) -> f64 {
    let base = (px * 4.0).round() / 4.0;
    (0..=16)
        .flat_map(|k| [k, -k])
        .map(|k| base + f64::from(k) * 0.25)
        .find(|&c| c > 0.0 && (plotters_size(c) / 1.24).to_bits() == c.to_bits())
        .unwrap_or(base)
}

/// Estimated width in pixels of `s` set at `px` (sans-serif; digits and capitals are about
/// 0.62 em, bold a little wider). Only used to keep labels apart.
pub(crate) fn text_width(s: &str, px: f64, bold: bool) -> f64 {
    let em = if bold { 0.66 } else { 0.6 };
    s.chars().count() as f64 * px * em
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ramp_ends_and_clamps() {
        assert_eq!(ramp(0.0), RAMP[0]);
        assert_eq!(ramp(1.0), RAMP[4]);
        assert_eq!(ramp(7.0), RAMP[4]);
        assert_eq!(ramp(f64::NAN), RAMP[0]);
        assert_eq!(ramp(0.25), RAMP[1]);
    }

    #[test]
    #[allow(clippy::float_cmp)]
    fn font_sizes_are_exact() {
        for px in [11.0, 12.0, 14.0, 16.0, 17.0, 18.0, 28.0, 12.5] {
            assert_eq!(plotters_size(px) / 1.24, px);
        }
        for px in [13.0, 15.0, 26.0, 52.0, 61.75] {
            let exact = exact_px(px);
            assert!((exact - px).abs() <= 0.5, "{px} -> {exact}");
            assert_eq!(plotters_size(exact) / 1.24, exact);
        }
        assert_eq!(exact_px(14.0), 14.0);
    }
}
