//! Zones announced during the day (docs/reference.md#zones-announced-during-the-day), in one place:
//! the zones the service knows, reading an announcement, and deciding what an announcement or a
//! withdrawal does.
//!
//! An announced zone is one ED-318 feature. The service sets its announcement instant (its
//! clock's now when the planner takes it); a body that gives one is refused. Its id is the
//! feature's identifier (a feature that reads as several zones, `ID#1`, `ID#2`, … — several
//! circles, say — is announced and withdrawn as one, under `ID`). An id is never reused: not
//! that of a zone known from the start, nor that of a zone announced before, withdrawn or not.
//!
//! - [`book`]: the zones known — from the start and announced since — for `GET /v1/zones`,
//!   for refusing an id twice and for withdrawals; a stored zone read back;
//! - [`body`]: a `POST /v1/zones` body read as a zone to announce, or refused naming the
//!   field at fault;
//! - [`decide`]: an announcement or a withdrawal decided against the live schedule (which
//!   flights it replans, diverts, cancels or leaves in contingency), and the planner task's
//!   answers.
//!
//! The rest of the service handles zones as it handles every flight and command, each in its
//! layer: the HTTP routes (`POST /v1/zones`, `DELETE /v1/zones/{id}`, `GET /v1/zones`,
//! `GET /v1/closures`) are in the API with every other route (`api/zones.rs`); the planner
//! task (`engine`) stores a decision with its group and applies it to the schedule, as it
//! does a flight's; the store keeps the zones announced (`store`).

pub(crate) mod body;
pub(crate) mod book;
pub(crate) mod decide;
