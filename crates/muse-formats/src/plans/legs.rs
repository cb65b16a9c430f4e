//! The legs of a multi-leg plan (docs/reference.md#multi-leg-trips) in a plans file.
//!
//! A plan of two or more legs keeps the fields of the trip as a whole (`takeoff` the first
//! take-off, `landing` the last landing, `path` every stay, the station repeated at each
//! battery swap) and adds `legs`, one object per leg:
//!
//! ```json
//! "legs": [{"takeoff": "...", "landing": "...", "path": [{"node": "A", ...}, {"node": "B", ...}]},
//!          {"takeoff": "...", "landing": "...", "path": [{"node": "B", ...}, {"node": "C", ...}]}]
//! ```
//!
//! The same goes for `original` (the plan first accepted, with its own `legs`) and for a
//! contingency's `committed` stays (`committed_legs`, whose last leg has `landing: null`: the
//! committed part does not land). A single-leg plan has no `legs`.
//!
//! When reading, `legs` is optional (the path alone splits into legs: a leg ends where two
//! consecutive stays are at the same station); when present it must agree exactly with the
//! path, stay by stay, and each leg's `takeoff` and `landing` with the ends of its stays.

use muse_model::{Airspace, Plan, Stay, UtcOffset};
use serde::{Deserialize, Serialize};

use super::line::LineReader;
use super::{StayLine, stay_lines};
use crate::error::InputError;

/// One leg of a multi-leg plan, as written.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LegLine {
    /// The leg's take-off (arrival at its first stay), RFC 3339.
    pub takeoff: String,
    /// The leg's landing (departure from its last stay), RFC 3339; `null` for the last leg of
    /// a contingency's committed part, which does not land.
    pub landing: Option<String>,
    /// The leg's stays.
    pub path: Vec<StayLine>,
}

/// The legs of `plan` as written, or `None` for a plan of fewer than two legs. `lands`:
/// whether the last leg lands (false for a contingency's committed part).
pub(super) fn leg_lines(
    airspace: &Airspace,
    offset: UtcOffset,
    plan: &Plan,
    lands: bool,
) -> Option<Vec<LegLine>> {
    let count = plan.leg_count();
    (count >= 2).then(|| {
        plan.legs()
            .enumerate()
            .map(|(k, stays)| LegLine {
                takeoff: stays[0].arrive.to_rfc3339(offset),
                landing: (lands || k + 1 < count)
                    .then(|| stays[stays.len() - 1].depart.to_rfc3339(offset)),
                path: stay_lines(airspace, offset, stays),
            })
            .collect()
    })
}

/// Where a plan is in a line: the fields of its stays and of its legs.
pub(super) struct PlanFields<'a> {
    /// The stays' field name (`path`, `original.path`, `committed`).
    pub path: &'a str,
    /// The stays.
    pub stays: Option<&'a Vec<StayLine>>,
    /// The legs' field name (`legs`, `original.legs`, `committed_legs`).
    pub legs: &'a str,
    /// The legs, if written.
    pub leg_lines: Option<&'a Vec<LegLine>>,
    /// Whether the last leg lands (false for a contingency's committed part).
    pub lands: bool,
}

impl LineReader<'_> {
    /// The plan whose stays are `fields.path` of a `status` line, checked against its legs.
    pub(super) fn plan(&self, status: &str, fields: &PlanFields<'_>) -> Result<Plan, InputError> {
        let plan = self.stays(fields.path, status, fields.stays)?;
        if let (Some(lines), Some(stays)) = (fields.leg_lines, fields.stays) {
            self.legs_agree(status, fields, &plan, stays, lines)?;
        }
        Ok(plan)
    }

    fn legs_agree(
        &self,
        status: &str,
        fields: &PlanFields<'_>,
        plan: &Plan,
        stays: &[StayLine],
        lines: &[LegLine],
    ) -> Result<(), InputError> {
        let (path_field, legs_field) = (fields.path, fields.legs);
        let split: Vec<&[Stay]> = plan.legs().collect();
        if lines.len() != split.len() {
            return Err(self.err(
                Some(legs_field),
                format!(
                    "{} legs, but `{path_field}` has {} (a leg ends where two consecutive stays \
                     are at the same station)",
                    lines.len(),
                    split.len()
                ),
            ));
        }
        let mut first = 0;
        for (k, (line, leg)) in lines.iter().zip(&split).enumerate() {
            let at = |name: &str| format!("{legs_field}[{k}].{name}");
            let last = first + leg.len() - 1;
            let own = self.stays(&at("path"), status, Some(&line.path))?;
            if own.path.len() != leg.len() {
                return Err(self.err(
                    Some(&at("path")),
                    format!(
                        "{} stays, but this leg of `{path_field}` has {} (`{path_field}[{first}]` \
                         to `{path_field}[{last}]`)",
                        own.path.len(),
                        leg.len()
                    ),
                ));
            }
            if let Some(j) = (0..leg.len()).find(|&j| own.path[j] != leg[j]) {
                return Err(self.err(
                    Some(&at(&format!("path[{j}]"))),
                    format!("differs from `{path_field}[{}]`", first + j),
                ));
            }
            if self.time(&at("takeoff"), &line.takeoff)? != leg[0].arrive {
                return Err(self.err(
                    Some(&at("takeoff")),
                    format!(
                        "`{}` is not the leg's take-off, the arrival at its first stay \
                         `{path_field}[{first}].arrive` (`{}`)",
                        line.takeoff, stays[first].arrive
                    ),
                ));
            }
            let lands = fields.lands || k + 1 < split.len();
            match (&line.landing, lands) {
                (Some(text), true) => {
                    if self.time(&at("landing"), text)? != leg[leg.len() - 1].depart {
                        return Err(self.err(
                            Some(&at("landing")),
                            format!(
                                "`{text}` is not the leg's landing, the departure from its last \
                                 stay `{path_field}[{last}].depart` (`{}`)",
                                stays[last].depart
                            ),
                        ));
                    }
                }
                (None, true) => {
                    return Err(self.err(Some(&at("landing")), "missing".into()));
                }
                (Some(_), false) => {
                    return Err(self.err(
                        Some(&at("landing")),
                        "must be null: the committed part does not land".into(),
                    ));
                }
                (None, false) => {}
            }
            first = last + 1;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use muse_model::plan::{Change, Fate};
    use muse_model::testing::plan;
    use muse_model::{Instant, Millis};

    use super::super::tests::air;
    use super::super::{PlanLine, PlanRecord, plan_line, read_plans};
    use super::*;

    /// `A -> B`, 5 minutes on the ground at `B`, `B -> A`; hovering 2.5 s at take-off.
    fn there_and_back(t: i64) -> Plan {
        plan(&[
            (0, t, t + 2_500),
            (1, t + 122_500, t + 122_500),
            (1, t + 422_500, t + 422_500),
            (0, t + 542_500, t + 542_500),
        ])
    }

    fn record(fate: Option<Fate>) -> PlanRecord {
        let mut rec = PlanRecord::first(
            "r1".into(),
            "A".into(),
            "A".into(),
            Instant(0),
            Ok(there_and_back(0)),
            Some(Millis(240_000)),
            1,
        );
        if let Some(fate) = fate {
            rec.changes.push(Change {
                zone: "Z".into(),
                announced: Instant(0),
                airborne: false,
                outcome: fate.kind(),
            });
            rec.fate = Some(fate);
        }
        rec
    }

    fn line(rec: &PlanRecord) -> PlanLine {
        plan_line(&air(), UtcOffset::SINGAPORE, rec)
    }

    /// Reads one line back: the record, or the error's text.
    fn read(line: &PlanLine) -> Result<PlanRecord, String> {
        let text = serde_json::to_string(line).unwrap();
        read_plans(&text, "p.jsonl", &air())
            .map(|mut v| v.remove(0))
            .map_err(|e| e.to_string())
    }

    #[test]
    fn legs_are_written_and_read_back() {
        let rec = record(None);
        let l = line(&rec);
        let legs = l.legs.as_ref().unwrap();
        assert_eq!(legs.len(), 2);
        assert_eq!(legs[0].takeoff, "1970-01-01T08:00:00.000+08:00");
        assert_eq!(
            legs[0].landing.as_deref(),
            Some("1970-01-01T08:02:02.500+08:00")
        );
        assert_eq!(legs[1].takeoff, "1970-01-01T08:07:02.500+08:00");
        assert_eq!(l.airborne_s, Some(542.5));
        assert_eq!(l.distance_m, Some(2_000.0));
        assert_eq!(read(&l), Ok(rec.clone()));
        // Without `legs`, the path alone tells the legs.
        let bare = PlanLine { legs: None, ..l };
        assert_eq!(read(&bare), Ok(rec));
    }

    #[test]
    fn legs_must_agree_with_the_path() {
        let l = line(&record(None));
        let with = |edit: &dyn Fn(&mut Vec<LegLine>)| {
            let mut l = l.clone();
            edit(l.legs.as_mut().unwrap());
            read(&l).unwrap_err()
        };
        assert_eq!(
            with(&|legs| legs[1].takeoff = "1970-01-01T08:07:03.000+08:00".into()),
            "p.jsonl: line 1: field `legs[1].takeoff`: `1970-01-01T08:07:03.000+08:00` is not \
             the leg's take-off, the arrival at its first stay `path[2].arrive` \
             (`1970-01-01T08:07:02.500+08:00`)"
        );
        assert_eq!(
            with(&|legs| legs[0].landing = Some("1970-01-01T08:02:00.000+08:00".into())),
            "p.jsonl: line 1: field `legs[0].landing`: `1970-01-01T08:02:00.000+08:00` is not \
             the leg's landing, the departure from its last stay `path[1].depart` \
             (`1970-01-01T08:02:02.500+08:00`)"
        );
        assert_eq!(
            with(&|legs| legs[1].landing = None),
            "p.jsonl: line 1: field `legs[1].landing`: missing"
        );
        assert!(
            with(&|legs| legs[1].takeoff = "noon".into())
                .starts_with("p.jsonl: line 1: field `legs[1].takeoff`: "),
        );
        assert_eq!(
            with(&|legs| {
                legs.pop();
            }),
            "p.jsonl: line 1: field `legs`: 1 legs, but `path` has 2 (a leg ends where two \
             consecutive stays are at the same station)"
        );
        assert_eq!(
            with(&|legs| legs[0].path[0].depart = "1970-01-01T08:00:02.000+08:00".into()),
            "p.jsonl: line 1: field `legs[0].path[0]`: differs from `path[0]`"
        );
        assert_eq!(
            with(&|legs| {
                let stay = legs[1].path.remove(1);
                legs[0].path.push(stay);
            }),
            "p.jsonl: line 1: field `legs[0].path`: 3 stays, but this leg of `path` has 2 \
             (`path[0]` to `path[1]`)"
        );
        assert_eq!(
            with(&|legs| legs[1].path[1].node = "Q".into()),
            "p.jsonl: line 1: field `legs[1].path[1].node`: unknown node id `Q`"
        );
    }

    #[test]
    fn original_and_committed_legs() {
        let replanned = record(Some(Fate::Replanned(there_and_back(60_000))));
        let l = line(&replanned);
        assert!(l.legs.is_some() && l.original.as_ref().unwrap().legs.is_some());
        assert_eq!(read(&l), Ok(replanned));
        let mut bad = l.clone();
        bad.original.as_mut().unwrap().legs.as_mut().unwrap()[0].takeoff =
            "1970-01-01T08:01:00.000+08:00".into();
        assert!(
            read(&bad)
                .unwrap_err()
                .starts_with("p.jsonl: line 1: field `original.legs[0].takeoff`: "),
        );

        // Stranded on arrival at A, in the second leg: the committed part's last leg does not
        // land.
        let stranded = record(Some(Fate::Contingency(there_and_back(0))));
        let l = line(&stranded);
        let legs = l.committed_legs.as_ref().unwrap();
        assert_eq!(legs.len(), 2);
        assert_eq!(legs[1].landing, None);
        assert_eq!(read(&l), Ok(stranded));
        let mut bad = l.clone();
        bad.committed_legs.as_mut().unwrap()[1].landing = Some(legs[1].takeoff.clone());
        assert_eq!(
            read(&bad).unwrap_err(),
            "p.jsonl: line 1: field `committed_legs[1].landing`: must be null: the committed \
             part does not land"
        );
    }

    #[test]
    fn single_leg_lines_have_no_legs() {
        let rec = PlanRecord {
            result: Ok(Plan {
                path: there_and_back(0).path[..2].to_vec(),
            }),
            ..record(None)
        };
        let l = line(&rec);
        assert!(l.legs.is_none());
        let text = serde_json::to_string(&l).unwrap();
        assert!(!text.contains("legs"), "{text}");
        // A `legs` that agrees is accepted even for a single leg.
        let one = leg_lines(&air(), UtcOffset::SINGAPORE, &there_and_back(0), true).unwrap();
        let mut with = l;
        with.legs = Some(one[..1].to_vec());
        assert_eq!(read(&with), Ok(rec));
    }
}
