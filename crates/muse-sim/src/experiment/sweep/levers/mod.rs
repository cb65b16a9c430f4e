//! The levers of the paper's sweep (`muse sweep --vary NAME`), one file each, and the variants
//! they make together: the cartesian product of their settings, on the same seeds.
//!
//! Adding a lever is one file implementing [`Lever`] and one line in the list below.

mod lever;

pub use lever::{Base, Lever, LeverError, MAX_LIST, Setting, durations, list, with_params};

use crate::day::Planning;
use crate::experiment::sweep::variant::Variant;

/// Declares the lever files and lists their levers in [`LEVERS`], in `--help` order.
macro_rules! levers {
    ($($file:ident :: $lever:ident),* $(,)?) => {
        $(mod $file;)*

        /// Every lever, in `--help` order.
        pub static LEVERS: &[&dyn Lever] = &[$(&$file::$lever),*];
    };
}

levers! {
    zones::Zones,
    edge_rule::EdgeRules,
    ground_delay::GroundDelay,
    battery_swap::BatterySwaps,
    tau::Tau,
    separation::Separations,
    planner::Planners,
    layers::LayerCounts,
    heading::HeadingRules,
}

/// The lever whose `--vary` value is `name`.
pub fn lever(name: &str) -> Option<&'static dyn Lever> {
    LEVERS.iter().copied().find(|l| l.name() == name)
}

/// The variants of a sweep varying `vary` (levers' names, in order; none: the base alone):
/// the cartesian product of their settings applied to `base`, named `label / label / …`
/// (the base alone is named after its zones). `given` holds the lever options given, by
/// name; a lever whose option is not among them uses its default.
///
/// ```
/// use muse_model::FlightParams;
/// use muse_sim::experiment::sweep::levers::{Base, variants};
/// let base = Base { params: FlightParams::default(), zones: &[], zone_label: "no zone" };
/// let names = |vary: &[&str]| -> Vec<String> {
///     variants(&base, vary, &[("swap-min", "5")]).unwrap().into_iter().map(|v| v.name).collect()
/// };
/// assert_eq!(names(&[]), ["no zone"]);
/// assert_eq!(names(&["ground-delay", "battery-swap"]), [
///     "G_max 0 / no swaps", "G_max 0 / swaps 5 min",
///     "G_max 10 min / no swaps", "G_max 10 min / swaps 5 min",
/// ]);
/// assert!(variants(&base, &["zones"], &[]).is_err()); // no zones to compare
/// ```
pub fn variants(
    base: &Base<'_>,
    vary: &[&str],
    given: &[(&str, &str)],
) -> Result<Vec<Variant>, LeverError> {
    let mut out = vec![Variant {
        name: String::new(),
        zones: base.zones.to_vec(),
        params: base.params,
        planning: Planning::FirstComeFirstServed,
        layers: muse_model::Layers::default(),
    }];
    for &name in vary {
        let lever =
            lever(name).ok_or_else(|| LeverError(format!("--vary `{name}`: no such lever")))?;
        let value = lever.setting().map_or("", |s| {
            given
                .iter()
                .find(|(n, _)| *n == s.name)
                .map_or(s.default, |(_, v)| v)
        });
        let mut next = Vec::new();
        for current in &out {
            for (label, mut variant) in lever.apply(base, current, value)? {
                variant.name = if current.name.is_empty() {
                    label
                } else {
                    format!("{} / {label}", current.name)
                };
                next.push(variant);
            }
        }
        out = next;
    }
    if out.len() == 1 && out[0].name.is_empty() {
        base.zone_label.clone_into(&mut out[0].name);
    }
    Ok(out)
}
