//! `--vary separation`: metric separation (docs/reference.md#metric-separation: at every
//! instant two flights are both airborne, at least `D` apart horizontally or `V` vertically),
//! one variant per `--separations-m` value; 0 is the time rules alone.

use muse_model::{FlightParams, Metres, Separation};

use super::lever::{Base, Lever, LeverError, Setting, list, with_params};
use crate::experiment::sweep::variant::Variant;

/// The widest separation `--separations-m` compares: a kilometre, as `--separation-m`.
const MAX_SEPARATION_M: f64 = 1_000.0;

/// Metric separation `D` at each `--separations-m` value, the vertical separation as given.
pub struct Separations;

impl Lever for Separations {
    fn name(&self) -> &'static str {
        "separation"
    }

    fn help(&self) -> &'static str {
        "Metric separation `D` at each `--separations-m` value (docs/reference.md#metric-separation)"
    }

    fn setting(&self) -> Option<Setting> {
        Some(Setting {
            name: "separations-m",
            value_name: "M,...",
            help: "`--vary separation`: the metric separations `D` to compare, metres, \
                   comma-separated, each from 0 (off) to 1000, at most 100 \
                   [default: 0,10,20,30,50]",
            default: "0,10,20,30,50",
        })
    }

    fn apply(
        &self,
        _: &Base<'_>,
        current: &Variant,
        value: &str,
    ) -> Result<Vec<(String, Variant)>, LeverError> {
        let distances = list(
            "--separations-m",
            value,
            &format!("metres, each from 0 to {MAX_SEPARATION_M}"),
            |x| {
                let d: f64 = x.parse().ok()?;
                if !(0.0..=MAX_SEPARATION_M).contains(&d) {
                    return None;
                }
                Metres::from_m(d).ok()
            },
        )?;
        Ok(distances
            .into_iter()
            .map(|d| {
                let params = FlightParams {
                    separation: Separation {
                        horizontal: d,
                        ..current.params.separation
                    },
                    ..current.params
                };
                (format!("D {d} m"), with_params(current, params))
            })
            .collect())
    }
}

#[cfg(test)]
mod tests {
    use muse_model::{FlightParams, Metres};

    use crate::experiment::sweep::levers::{Base, variants};

    #[test]
    fn separations_name_their_variants_and_refuse_what_is_out_of_range() {
        let base = Base {
            params: FlightParams::default(),
            zones: &[],
            zone_label: "no zone",
        };
        let v = variants(&base, &["separation"], &[("separations-m", "0,30,12.5")]).unwrap();
        let names: Vec<&str> = v.iter().map(|v| v.name.as_str()).collect();
        assert_eq!(names, ["D 0 m", "D 30 m", "D 12.5 m"]);
        assert!(!v[0].params.separation.is_on());
        assert_eq!(v[1].params.separation.horizontal, Metres::from_mm(30_000));
        let e = variants(&base, &["separation"], &[("separations-m", "30,1001")]).unwrap_err();
        assert_eq!(
            e.to_string(),
            "--separations-m `30,1001`: expected at most 100 comma-separated metres, each from 0 to 1000"
        );
    }
}
