//! The handlers' connections, in both stores: a few kept idle between reads, a new one made
//! when none is.

use std::sync::Mutex;

use super::StoreError;

/// Most idle connections kept for reuse.
const KEEP: usize = 8;

/// Idle connections of type `C`.
#[derive(Debug)]
pub(super) struct Pool<C> {
    idle: Mutex<Vec<C>>,
}

impl<C> Default for Pool<C> {
    fn default() -> Self {
        Pool {
            idle: Mutex::new(Vec::new()),
        }
    }
}

impl<C> Pool<C> {
    /// Runs `read` on an idle connection that is still `usable`, or on a new one from
    /// `connect`; keeps the connection afterwards if it is usable and fewer than [`KEEP`] are
    /// idle.
    pub fn with<T>(
        &self,
        connect: impl FnOnce() -> Result<C, StoreError>,
        usable: impl Fn(&C) -> bool,
        read: impl FnOnce(&mut C) -> Result<T, StoreError>,
    ) -> Result<T, StoreError> {
        let idle = self
            .idle
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
            .pop();
        let mut conn = match idle {
            Some(c) if usable(&c) => c,
            _ => connect()?,
        };
        let out = read(&mut conn);
        let mut idle = self
            .idle
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        if idle.len() < KEEP && usable(&conn) {
            idle.push(conn);
        }
        out
    }

    /// Every idle connection, taken out.
    pub fn take_all(&mut self) -> Vec<C> {
        std::mem::take(
            self.idle
                .get_mut()
                .unwrap_or_else(std::sync::PoisonError::into_inner),
        )
    }
}
