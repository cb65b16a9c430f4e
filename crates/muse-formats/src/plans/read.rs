//! Reading plans files: each line checked against the airspace, errors naming the line and
//! the field.

use std::collections::HashMap;
use std::path::Path;

use muse_model::plan::{CANCELLED_BY_OPERATOR, Change, Fate, FateKind, ZONE_ANNOUNCED};
use muse_model::{Airspace, Instant, Millis, NodeId, Plan, RejectReason, Stay};

use super::legs::PlanFields;
use super::line::LineReader;
use super::{OperatorCancellation, PlanEntry, PlanItem, PlanLine, PlanRecord, StayLine};
use crate::error::{InputError, Location};

/// Reads the records of a plans JSON Lines file's text: every line that holds a request's
/// answer (planned, rejected, or changed by zone announcements). A line of a flight its
/// operator cancelled (a service listing) is read and checked like any other but, holding no
/// answer that flies, is left out; [`read_plan_entries`] gives every line. Node ids are
/// resolved against `airspace` (in a layered one, each stay's flat id at its `layer`); every
/// error names the file, line and field. A request id on two lines is an error (a plans file
/// holds one line per request); [`read_listed_plans`] reads a listing that may repeat one.
pub fn read_plans(
    text: &str,
    file: &str,
    airspace: &Airspace,
) -> Result<Vec<PlanRecord>, InputError> {
    Ok(records(read_entries(text, file, airspace, Ids::Unique)?))
}

/// Reads the records of flights a service listed page after page, as [`read_plans`] reads a
/// plans file's, except that a flight listed twice (a page boundary gone wrong) is read
/// twice: the caller counts such repeats, and a listing may be empty. `source` names the
/// listing in errors.
pub fn read_listed_plans(
    text: &str,
    source: &str,
    airspace: &Airspace,
) -> Result<Vec<PlanRecord>, InputError> {
    Ok(records(read_entries(
        text,
        source,
        airspace,
        Ids::MayRepeat,
    )?))
}

/// The lines of `entries` that hold a request's answer.
fn records(entries: Vec<PlanEntry>) -> Vec<PlanRecord> {
    entries
        .into_iter()
        .filter_map(|e| match e.item {
            PlanItem::Record(r) => Some(r),
            PlanItem::CancelledByOperator(_) => None,
        })
        .collect()
}

/// Reads every line of a plans JSON Lines file's text (blank lines aside): the lines `muse
/// plan` and `muse simulate` write, and those of a service listing saved one flight a line
/// (`operator`, `cancelled_at` and flights cancelled by their operator included). Node ids
/// are resolved against `airspace`; every error names the file, line and field. A request id
/// is given on one line only: a second line with it is an error naming both lines (a flight
/// zone announcements changed keeps its first plan on its own line, in `original`). A file
/// with no line (blank lines aside) is an error too.
///
/// ```
/// use muse_formats::plans::{PlanItem, read_plan_entries};
/// let air = muse_model::Airspace::line(&[1_000.0]); // stations A and B, 1 km apart
/// let line = r#"{"request": "f1", "status": "cancelled", "reason": "cancelled_by_operator",
///   "origin": "A", "destination": "B", "requested_departure": "2026-01-05T09:00:00.000+08:00",
///   "takeoff": null, "landing": null, "airborne_s": null, "free_flow_s": 120.0,
///   "air_delay_s": null, "ground_delay_s": null, "distance_m": null, "expanded": 1,
///   "operator": "alpha", "cancelled_at": "2026-01-05T08:30:00.000+08:00"}"#;
/// let line = line.replace('\n', "");
/// let entries = read_plan_entries(&line, "p.jsonl", &air).unwrap();
/// assert_eq!(entries[0].status(), "cancelled");
/// assert_eq!(entries[0].operator.as_deref(), Some("alpha"));
/// assert!(matches!(entries[0].item, PlanItem::CancelledByOperator(_)));
/// let twice = format!("{line}\n{line}\n");
/// let e = read_plan_entries(&twice, "p.jsonl", &air).unwrap_err();
/// assert_eq!(
///     e.to_string(),
///     "p.jsonl: line 2: field `request`: duplicate request id `f1` (first on line 1): a plans \
///      file holds one line per request"
/// );
/// ```
pub fn read_plan_entries(
    text: &str,
    file: &str,
    airspace: &Airspace,
) -> Result<Vec<PlanEntry>, InputError> {
    read_entries(text, file, airspace, Ids::Unique)
}

/// Whether a request id may be given on more than one line.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Ids {
    /// A plans file: one line per request.
    Unique,
    /// A service's listing read page after page, whose repeats the caller counts.
    MayRepeat,
}

/// Reads every line of `text` (see [`read_plan_entries`]), request ids unique or not.
fn read_entries(
    text: &str,
    file: &str,
    airspace: &Airspace,
    ids: Ids,
) -> Result<Vec<PlanEntry>, InputError> {
    let mut out = Vec::new();
    let mut first_line: HashMap<String, usize> = HashMap::new();
    for (i, raw) in text.lines().enumerate() {
        if raw.trim().is_empty() {
            continue;
        }
        let at = LineReader {
            file,
            line_no: i + 1,
            airspace,
        };
        let line = at.parse(raw)?;
        if ids == Ids::Unique
            && let Some(first) = first_line.insert(line.request.clone(), i + 1)
        {
            return Err(at.err(
                Some("request"),
                format!(
                    "duplicate request id `{}` (first on line {first}): a plans file holds one \
                     line per request",
                    line.request
                ),
            ));
        }
        let item = at.item(&line)?;
        out.push(PlanEntry {
            line: i + 1,
            operator: line.operator,
            item,
        });
    }
    if out.is_empty() && ids == Ids::Unique {
        return Err(InputError::new(
            file,
            Location::Whole,
            None,
            "no plans: the file has no line (a plans file has one line per request)",
        ));
    }
    Ok(out)
}

impl LineReader<'_> {
    /// The JSON object of a line; an unknown field, a missing one or a value of the wrong
    /// kind is named. A line that is not JSON is named as a whole; one that ends inside its
    /// object, as cut short. Places are columns of the line (serde's "line 1" dropped: each
    /// line is read alone).
    pub(super) fn parse(&self, raw: &str) -> Result<PlanLine, InputError> {
        let mut de = serde_json::Deserializer::from_str(raw);
        let line: PlanLine = serde_path_to_error::deserialize(&mut de).map_err(|e| {
            let path = e.path().to_string();
            let field = (path != "." && !e.inner().is_syntax() && !e.inner().is_eof())
                .then_some(path.as_str());
            self.json_err(field, e.inner())
        })?;
        de.end().map_err(|e| self.json_err(None, &e))?;
        Ok(line)
    }

    /// The error of a line serde could not read: not JSON, cut short, or a JSON value that is
    /// not a plan record (in `field`, if known).
    fn json_err(&self, field: Option<&str>, e: &serde_json::Error) -> InputError {
        let text = e.to_string();
        let at = format!(" at line {} column {}", e.line(), e.column());
        let what = match text.strip_suffix(&at) {
            Some(what) => format!("{what} at column {} of the line", e.column()),
            None => text,
        };
        let message = if e.is_eof() {
            "the line is cut short: it ends before its JSON object does (not complete JSON; was \
             the file truncated?)"
                .to_owned()
        } else if e.is_syntax() {
            format!("not JSON: {what}")
        } else {
            format!("not a plan record: {what}")
        };
        self.err(field, message)
    }

    pub(super) fn time(&self, field: &str, text: &str) -> Result<Instant, InputError> {
        Instant::parse_rfc3339(text).map_err(|e| self.err(Some(field), e.to_string()))
    }

    /// The plan whose stays are `field` of a `status` line.
    pub(super) fn stays(
        &self,
        field: &str,
        status: &str,
        stays: Option<&Vec<StayLine>>,
    ) -> Result<Plan, InputError> {
        let stays = stays
            .ok_or_else(|| self.err(Some(field), format!("missing for a `{status}` request")))?;
        if stays.is_empty() {
            return Err(self.err(Some(field), "empty".into()));
        }
        let mut path = Vec::with_capacity(stays.len());
        for (k, s) in stays.iter().enumerate() {
            let node = self.stay_node(&format!("{field}[{k}]"), s)?;
            path.push(Stay {
                node,
                arrive: self.time(&format!("{field}[{k}].arrive"), &s.arrive)?,
                depart: self.time(&format!("{field}[{k}].depart"), &s.depart)?,
            });
        }
        Ok(Plan { path })
    }

    /// The node of stay `at` (`path[3]`): its flat id, at its `layer` in a layered airspace
    /// (docs/reference.md#layered-airspace), which every stay of a layered airspace gives and no
    /// stay of a flat one.
    fn stay_node(&self, at: &str, s: &StayLine) -> Result<NodeId, InputError> {
        let a = self.airspace;
        let flat = a.flat().node_id(&s.node).ok_or_else(|| {
            self.err(
                Some(&format!("{at}.node")),
                format!("unknown node id `{}`", s.node),
            )
        })?;
        let field = format!("{at}.layer");
        match (a.layers(), s.layer) {
            (None, None) => Ok(flat),
            (None, Some(k)) => Err(self.err(
                Some(&field),
                format!(
                    "layer {k}, but the airspace is flat (one layer): a stay gives its layer only \
                     in a layered airspace (`--layers` 2 or more)"
                ),
            )),
            (Some(layers), None) => Err(self.err(
                Some(&field),
                format!(
                    "missing: the airspace has {} layers, and every stay gives its layer (1 to {})",
                    layers.count, layers.count
                ),
            )),
            (Some(layers), Some(k)) => a.at_layer(flat, k).ok_or_else(|| {
                self.err(
                    Some(&field),
                    format!("layer {k} is out of range: give 1 to {}", layers.count),
                )
            }),
        }
    }

    pub(super) fn free_flow(&self, line: &PlanLine) -> Result<Option<Millis>, InputError> {
        line.free_flow_s
            .map(|s| {
                Millis::from_secs_f64(s).map_err(|e| self.err(Some("free_flow_s"), e.to_string()))
            })
            .transpose()
    }

    /// What a line holds: a request's answer, or a flight its operator cancelled.
    pub(super) fn item(&self, line: &PlanLine) -> Result<PlanItem, InputError> {
        let unserved = line.reason.as_deref() == Some(RejectReason::Unserved.as_str());
        for (field, id) in [("origin", &line.origin), ("destination", &line.destination)] {
            match id {
                Some(id) if self.airspace.flat().node_id(id).is_none() => {
                    return Err(self.err(Some(field), format!("unknown node id `{id}`")));
                }
                None if !unserved => {
                    return Err(self.err(
                        Some(field),
                        "missing: only an unserved request (reason `unserved`) may lack a pad"
                            .into(),
                    ));
                }
                _ => {}
            }
        }
        let status = line.status.as_str();
        let reason = line.reason.as_deref();
        if status == "cancelled" && reason == Some(CANCELLED_BY_OPERATOR) {
            return Ok(PlanItem::CancelledByOperator(self.cancellation(line)?));
        }
        if status == "cancelled" && reason != Some(ZONE_ANNOUNCED) {
            return Err(self.err(
                Some("reason"),
                format!(
                    "{} is not the reason of a `cancelled` flight: `{ZONE_ANNOUNCED}` (a zone \
                     announcement cancelled it) or `{CANCELLED_BY_OPERATOR}` (its operator did)",
                    reason.map_or_else(|| "null".to_owned(), |r| format!("`{r}`"))
                ),
            ));
        }
        if line.cancelled_at.is_some() {
            return Err(self.err(
                Some("cancelled_at"),
                format!(
                    "only a flight cancelled by its operator (status `cancelled`, reason \
                     `{CANCELLED_BY_OPERATOR}`) has one; this line's status is `{status}`"
                ),
            ));
        }
        self.record(line).map(PlanItem::Record)
    }

    /// A flight its operator cancelled: no plan of its own; its changes and first plan, if it
    /// had any, are checked like those of any other line.
    pub(super) fn cancellation(&self, line: &PlanLine) -> Result<OperatorCancellation, InputError> {
        let flies = [
            ("path", line.path.is_some()),
            ("legs", line.legs.is_some()),
            ("committed", line.committed.is_some()),
            ("committed_legs", line.committed_legs.is_some()),
            ("diverted_to", line.diverted_to.is_some()),
        ];
        if let Some((field, _)) = flies.iter().find(|(_, given)| *given) {
            return Err(self.err(
                Some(field),
                format!(
                    "a flight cancelled by its operator flies nothing: it has no `{field}` \
                     (status `cancelled`, reason `{CANCELLED_BY_OPERATOR}`)"
                ),
            ));
        }
        let changes = self.changes(line)?;
        let original = match (&line.original, changes.is_empty()) {
            (Some(o), _) => Some(self.plan(
                "cancelled",
                &PlanFields {
                    path: "original.path",
                    stays: Some(&o.path),
                    legs: "original.legs",
                    leg_lines: o.legs.as_ref(),
                    lands: true,
                },
            )?),
            (None, false) => {
                return Err(self.err(
                    Some("original.path"),
                    "missing for a flight that zone announcements changed before its operator \
                     cancelled it"
                        .into(),
                ));
            }
            (None, true) => None,
        };
        Ok(OperatorCancellation {
            request: line.request.clone(),
            origin: line.origin.clone().unwrap_or_default(),
            destination: line.destination.clone().unwrap_or_default(),
            requested_departure: self.time("requested_departure", &line.requested_departure)?,
            free_flow: self.free_flow(line)?,
            original,
            changes,
            cancelled_at: line
                .cancelled_at
                .as_deref()
                .map(|t| self.time("cancelled_at", t))
                .transpose()?,
        })
    }

    pub(super) fn record(&self, line: &PlanLine) -> Result<PlanRecord, InputError> {
        let mut record = PlanRecord::first(
            line.request.clone(),
            line.origin.clone().unwrap_or_default(),
            line.destination.clone().unwrap_or_default(),
            self.time("requested_departure", &line.requested_departure)?,
            Err(RejectReason::NoFeasiblePlan),
            self.free_flow(line)?,
            line.expanded,
        );
        let status = line.status.as_str();
        match status {
            "planned" => record.result = Ok(self.plan(status, &final_plan(line))?),
            "rejected" => {
                let reason = line.reason.as_deref().unwrap_or("");
                record.result = Err(RejectReason::parse(reason).ok_or_else(|| {
                    self.err(
                        Some("reason"),
                        format!("`{reason}` is not a rejection reason"),
                    )
                })?);
            }
            _ => self.changed(line, &mut record)?,
        }
        Ok(record)
    }

    /// The zone announcements a line lists (`changes`), in order; none if it lists none.
    pub(super) fn changes(&self, line: &PlanLine) -> Result<Vec<Change>, InputError> {
        let mut notes = Vec::new();
        for (k, c) in line.changes.iter().flatten().enumerate() {
            let outcome = FateKind::parse(&c.outcome).ok_or_else(|| {
                self.err(
                    Some(&format!("changes[{k}].outcome")),
                    format!("`{}` is not an outcome", c.outcome),
                )
            })?;
            notes.push(Change {
                zone: c.zone.clone(),
                announced: self.time(&format!("changes[{k}].announced"), &c.announced)?,
                airborne: c.airborne,
                outcome,
            });
        }
        Ok(notes)
    }

    /// The first plan, changes and fate of a flight zone announcements changed.
    pub(super) fn changed(
        &self,
        line: &PlanLine,
        record: &mut PlanRecord,
    ) -> Result<(), InputError> {
        let status = line.status.as_str();
        let kind = FateKind::parse(status).ok_or_else(|| {
            self.err(
                Some("status"),
                format!(
                    "`{status}` is not `planned`, `rejected`, `replanned`, `diverted`, \
                     `cancelled` or `contingency`"
                ),
            )
        })?;
        let original = line.original.as_ref();
        record.result = Ok(self.plan(
            status,
            &PlanFields {
                path: "original.path",
                stays: original.map(|o| &o.path),
                legs: "original.legs",
                leg_lines: original.and_then(|o| o.legs.as_ref()),
                lands: true,
            },
        )?);
        record.changes = self.changes(line)?;
        if record.changes.is_empty() {
            return Err(self.err(Some("changes"), format!("missing for a `{status}` request")));
        }
        if record.changes.last().map(|c| c.outcome) != Some(kind) {
            return Err(self.err(
                Some("status"),
                format!("`{status}` is not the outcome of the last change"),
            ));
        }
        let path = || self.plan(status, &final_plan(line));
        let committed = PlanFields {
            path: "committed",
            stays: line.committed.as_ref(),
            legs: "committed_legs",
            leg_lines: line.committed_legs.as_ref(),
            lands: false,
        };
        record.fate = Some(match kind {
            FateKind::Replanned => Fate::Replanned(path()?),
            FateKind::Diverted => Fate::Diverted(path()?),
            FateKind::Cancelled => Fate::Cancelled,
            FateKind::Contingency => Fate::Contingency(self.plan(status, &committed)?),
        });
        Ok(())
    }
}

/// Where a line's final plan is: `path` and `legs`.
fn final_plan(line: &PlanLine) -> PlanFields<'_> {
    PlanFields {
        path: "path",
        stays: line.path.as_ref(),
        legs: "legs",
        leg_lines: line.legs.as_ref(),
        lands: true,
    }
}

/// Reads the records of a plans JSON Lines file (see [`read_plans`]).
pub fn read_plans_file(path: &Path, airspace: &Airspace) -> Result<Vec<PlanRecord>, InputError> {
    read_plans(
        &crate::read_to_string(path)?,
        &path.display().to_string(),
        airspace,
    )
}

/// Reads every line of a plans JSON Lines file (see [`read_plan_entries`]).
pub fn read_plan_entries_file(
    path: &Path,
    airspace: &Airspace,
) -> Result<Vec<PlanEntry>, InputError> {
    read_plan_entries(
        &crate::read_to_string(path)?,
        &path.display().to_string(),
        airspace,
    )
}
