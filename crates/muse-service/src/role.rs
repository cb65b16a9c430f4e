//! Leader or standby: which part a service plays on a shared store (docs/service.md#several-
//! services-on-one-postgresql).
//!
//! Several `muse serve` processes may run on one PostgreSQL store. Exactly one leads: it
//! plans and writes (the lease in the store says which; see `store::pg::lease`). The others
//! are standbys: they follow what the leader commits into a schedule of their own, kept warm,
//! serve reads, forward writes to the leader, and one of them takes over when the leader
//! stops. A service on a data folder always leads.
//!
//! [`Role`] is what the planner task tells the handlers about it: `/healthz` says `leader` or
//! `standby` (and how far behind a standby is), `/metrics` counts take-overs, and the write
//! routes of a standby go to the leader's address.

use std::fmt::Write as _;
use std::sync::RwLock;
use std::sync::atomic::{AtomicBool, AtomicI64, AtomicU64, Ordering};

use serde::Serialize;

/// The part this service plays, as the planner task last set it (see the module docs).
#[derive(Debug, Default)]
pub struct Role {
    standby: AtomicBool,
    /// The leader's address as it advertised it (a standby's, for forwarding writes).
    leader: RwLock<Option<String>>,
    /// The id of the last event a standby applied.
    applied_event: AtomicU64,
    /// The id of the last event the store held when the standby last looked.
    stored_event: AtomicU64,
    /// When the standby last read the store (milliseconds since the epoch; 0: never).
    followed_ms: AtomicI64,
    /// Take-overs: times this service went from standby to leader.
    takeovers: AtomicU64,
}

/// How far a standby is behind the leader, for `/healthz`.
#[derive(Clone, Copy, Debug, Serialize, PartialEq, Eq)]
pub struct Behind {
    /// Events the store held when the standby last looked that it had not applied yet.
    pub events: u64,
    /// Milliseconds since the standby last read the store.
    pub ms: i64,
}

impl Role {
    /// Whether this service is a standby.
    pub fn is_standby(&self) -> bool {
        self.standby.load(Ordering::Acquire)
    }

    /// The leader's address, if known (a standby's).
    pub fn leader(&self) -> Option<String> {
        self.leader
            .read()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
            .clone()
    }

    /// This service stands by; `leader` is the leader's address, if one leads.
    pub(crate) fn stand_by(&self, leader: Option<String>) {
        *self
            .leader
            .write()
            .unwrap_or_else(std::sync::PoisonError::into_inner) = leader;
        self.standby.store(true, Ordering::Release);
    }

    /// A standby has applied every event up to `applied`; the store held up to `stored` (or
    /// more, if an earlier look read more).
    pub(crate) fn followed(&self, applied: u64, stored: u64, at_ms: i64) {
        self.applied_event.store(applied, Ordering::Relaxed);
        self.stored_event.fetch_max(stored, Ordering::Relaxed);
        self.followed_ms.store(at_ms, Ordering::Relaxed);
    }

    /// This service took the lead from being a standby.
    pub(crate) fn took_over(&self) {
        self.takeovers.fetch_add(1, Ordering::Relaxed);
        *self
            .leader
            .write()
            .unwrap_or_else(std::sync::PoisonError::into_inner) = None;
        self.standby.store(false, Ordering::Release);
    }

    /// How far behind a standby is at `now_ms` (`None` for the leader).
    pub fn behind(&self, now_ms: i64) -> Option<Behind> {
        if !self.is_standby() {
            return None;
        }
        let followed = self.followed_ms.load(Ordering::Relaxed);
        Some(Behind {
            events: self
                .stored_event
                .load(Ordering::Relaxed)
                .saturating_sub(self.applied_event.load(Ordering::Relaxed)),
            ms: if followed == 0 { -1 } else { now_ms - followed },
        })
    }

    /// Take-overs so far.
    pub fn takeovers(&self) -> u64 {
        self.takeovers.load(Ordering::Relaxed)
    }

    /// The role's metrics, in the Prometheus text format.
    pub(crate) fn render(&self, out: &mut String, now_ms: i64) {
        let _ = writeln!(
            out,
            "# HELP muse_leader 1 while this service leads its store (plans and writes), 0 while \
             it stands by.\n# TYPE muse_leader gauge\nmuse_leader {}",
            u8::from(!self.is_standby())
        );
        let _ = writeln!(
            out,
            "# HELP muse_takeovers_total Times this service took the lead from being a standby.\n\
             # TYPE muse_takeovers_total counter\nmuse_takeovers_total {}",
            self.takeovers()
        );
        if let Some(b) = self.behind(now_ms) {
            let _ = writeln!(
                out,
                "# HELP muse_standby_behind_events Events committed by the leader that this \
                 standby had not applied when it last looked.\n# TYPE muse_standby_behind_events \
                 gauge\nmuse_standby_behind_events {}",
                b.events
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_standby_says_how_far_behind_it_is_and_a_take_over_is_counted() {
        let role = Role::default();
        assert_eq!(role.behind(1_000), None);
        role.stand_by(Some("http://127.0.0.1:1".into()));
        assert_eq!(role.behind(1_000), Some(Behind { events: 0, ms: -1 }));
        role.followed(7, 10, 900);
        assert_eq!(role.behind(1_000), Some(Behind { events: 3, ms: 100 }));
        assert_eq!(role.leader().as_deref(), Some("http://127.0.0.1:1"));
        role.took_over();
        assert!(!role.is_standby());
        assert_eq!(role.leader(), None);
        let mut out = String::new();
        role.render(&mut out, 1_000);
        assert!(out.contains("muse_leader 1") && out.contains("muse_takeovers_total 1"));
    }
}
