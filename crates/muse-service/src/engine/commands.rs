//! What handlers ask of the planner task, what it answers, and an answer waiting for its
//! group to be durable.

use std::sync::Arc;

use muse_model::Request;
use tokio::sync::oneshot;

use crate::auth::Caller;
use crate::flights::FlightEntry;
use crate::store::ImportReport;
use crate::zones::book::NewZone;
use crate::zones::decide::{AnnounceReply, WithdrawReply};

/// A change asked of the planner task.
#[derive(Debug)]
pub enum Command {
    /// Plan a new flight (or answer a retry of one).
    Plan {
        /// Who asks.
        caller: Caller,
        /// The request, validated.
        request: Request,
        /// Where to send the answer.
        reply: oneshot::Sender<PlanReply>,
    },
    /// Cancel a flight.
    Cancel {
        /// Who asks.
        caller: Caller,
        /// The flight's id.
        id: String,
        /// Where to send the answer.
        reply: oneshot::Sender<CancelReply>,
    },
    /// Announce a zone now (docs/reference.md#zones-announced-during-the-day); the caller is the
    /// authority.
    Announce {
        /// The zone, read and checked.
        zone: NewZone,
        /// Where to send the answer.
        reply: oneshot::Sender<AnnounceReply>,
    },
    /// Withdraw an announced zone; the caller is the authority.
    Withdraw {
        /// The zone's id.
        id: String,
        /// Where to send the answer.
        reply: oneshot::Sender<WithdrawReply>,
    },
}

impl Command {
    /// Answers that the service failed, without deciding anything.
    pub(super) fn refuse(self, message: &str) {
        let m = message.to_owned();
        match self {
            Command::Plan { reply, .. } => drop(reply.send(PlanReply::Failed(m))),
            Command::Cancel { reply, .. } => drop(reply.send(CancelReply::Failed(m))),
            Command::Announce { reply, .. } => drop(reply.send(AnnounceReply::Failed(m))),
            Command::Withdraw { reply, .. } => drop(reply.send(WithdrawReply::Failed(m))),
        }
    }
}

/// The answer to [`Command::Plan`].
#[derive(Debug)]
pub enum PlanReply {
    /// A new request, answered (planned or rejected) and stored.
    New(Arc<FlightEntry>),
    /// A retry with the same id and content: the flight as it stands.
    Repeat(Arc<FlightEntry>),
    /// The id names another request (or another operator's).
    Conflict,
    /// The service could not answer (nothing was booked).
    Failed(String),
}

/// The answer to [`Command::Cancel`].
#[derive(Debug)]
pub enum CancelReply {
    /// Cancelled now, durably.
    Done(Arc<FlightEntry>),
    /// Already cancelled earlier.
    Already(Arc<FlightEntry>),
    /// No such flight for this caller.
    NotFound,
    /// It has taken off: committed.
    TookOff(Arc<FlightEntry>),
    /// It was rejected: there is nothing to cancel.
    NotPlanned,
    /// The service could not answer.
    Failed(String),
}

/// What the start found in the store, for the start-up message.
#[derive(Clone, Debug, Default)]
pub struct Restored {
    /// Flights stored (every status, for the life of the store).
    pub flights: u64,
    /// Of those, the flights still ahead or in the air, put back into the schedule.
    pub held: usize,
    /// Zones announced (their outcomes are in the flights).
    pub zones: usize,
    /// Of those, zones withdrawn since.
    pub withdrawn: usize,
    /// Events stored (the id of the last one).
    pub events: u64,
    /// The last flights and events written, checked whole at the start.
    pub checked: crate::store::Recent,
    /// What the conversion of an earlier version's log did, if there was one.
    pub import: Option<ImportReport>,
}

/// An answer waiting for its group to be durable.
pub(super) enum Pending {
    Plan(oneshot::Sender<PlanReply>, PlanReply),
    Cancel(oneshot::Sender<CancelReply>, CancelReply),
    Announce(oneshot::Sender<AnnounceReply>, AnnounceReply),
    Withdraw(oneshot::Sender<WithdrawReply>, WithdrawReply),
}

impl Pending {
    /// Answers that the store failed.
    pub(super) fn fail(self, message: &str) {
        let m = message.to_owned();
        match self {
            Pending::Plan(tx, _) => drop(tx.send(PlanReply::Failed(m))),
            Pending::Cancel(tx, _) => drop(tx.send(CancelReply::Failed(m))),
            Pending::Announce(tx, _) => drop(tx.send(AnnounceReply::Failed(m))),
            Pending::Withdraw(tx, _) => drop(tx.send(WithdrawReply::Failed(m))),
        }
    }

    /// Sends the answer (a client that went away no longer waits for it; its work is done).
    pub(super) fn send(self) {
        match self {
            Pending::Plan(tx, answer) => drop(tx.send(answer)),
            Pending::Cancel(tx, answer) => drop(tx.send(answer)),
            Pending::Announce(tx, answer) => drop(tx.send(answer)),
            Pending::Withdraw(tx, answer) => drop(tx.send(answer)),
        }
    }
}
