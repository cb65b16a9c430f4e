//! Opening a PostgreSQL store: the connection and its settings, a new store's tables, and the
//! check that a store was written for the world this service plans with.

use postgres::Client;
use std::collections::HashMap;

use super::connect::connect;
use super::reader::Reader;
use super::{PostgresStore, pg, schema};
use crate::store::{StoreError, WorldMeta, meta};

/// The key of the transaction-level advisory lock under which a store's tables are made and
/// checked, so that services starting together on an empty database make them once.
const SCHEMA_LOCK: i64 = 0x4d55_5345_0001;

/// A PostgreSQL store opened and checked, not yet loaded.
pub struct Opening {
    url: String,
    label: String,
    client: Client,
    /// How many of the last flights and events the start checks whole.
    recent: u64,
}

impl std::fmt::Debug for Opening {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Opening")
            .field("label", &self.label)
            .field("recent", &self.recent)
            .finish_non_exhaustive()
    }
}

impl Opening {
    /// Connects to `url`, checks that the server makes commits durable, makes the store's
    /// tables if the database has none, and checks that a store it holds was written for
    /// `world`. Quick: reads no flight.
    pub fn open(url: &str, world: &WorldMeta) -> Result<Opening, StoreError> {
        let label = super::without_password(url);
        let mut client = connect(url, &label)?;
        durable(&mut client, &label)?;
        let mut tx = client.transaction().map_err(pg("starting a transaction"))?;
        tx.execute("SELECT pg_advisory_xact_lock($1)", &[&SCHEMA_LOCK])
            .map_err(pg("locking the store's tables"))?;
        let exists: bool = tx
            .query_one("SELECT to_regclass('meta') IS NOT NULL", &[])
            .and_then(|r| r.try_get(0))
            .map_err(pg("looking for the store's tables"))?;
        if exists {
            let read = tx
                .query("SELECT key, value, crc FROM meta", &[])
                .map_err(|e| StoreError::NotAStore {
                    path: label.clone(),
                    why: format!(
                        "it has a table `meta` this version cannot read ({})",
                        super::describe(&e)
                    ),
                })?
                .iter()
                .map(|r| Ok((r.try_get(0)?, r.try_get(1)?, r.try_get(2)?)))
                .collect::<Result<Vec<(String, String, i64)>, postgres::Error>>()
                .map_err(pg("reading the meta table"))?;
            meta::check(&label, read, world)?;
            tx.batch_execute(schema::CREATE_LEASE)
                .and_then(|()| tx.batch_execute(super::archive::CREATE))
                .map_err(pg("creating the lease and archive tables"))?;
        } else {
            tx.batch_execute(schema::CREATE)
                .and_then(|()| tx.batch_execute(schema::CREATE_LEASE))
                .and_then(|()| tx.batch_execute(super::archive::CREATE))
                .map_err(pg("creating the tables"))?;
            for (key, value, crc) in meta::rows(world) {
                tx.execute(
                    "INSERT INTO meta (key, value, crc) VALUES ($1, $2, $3)",
                    &[&key, &value, &crc],
                )
                .map_err(pg("writing the meta table"))?;
            }
        }
        tx.commit().map_err(pg("creating the tables"))?;
        Ok(Opening {
            url: url.to_owned(),
            label,
            client,
            recent: crate::store::RECENT,
        })
    }

    /// Has the start check the last `n` flights and events whole.
    #[must_use]
    pub fn checking_recent(mut self, n: u64) -> Opening {
        self.recent = n;
        self
    }

    /// The database's URL without its password.
    pub fn label(&self) -> String {
        self.label.clone()
    }

    /// The handlers' reads of this database (archived flights read from `archive`).
    pub(crate) fn reader(&self, archive: Option<std::path::PathBuf>) -> Reader {
        Reader::new(self.url.clone(), self.label.clone(), archive)
    }

    /// The store, open for writing.
    pub(crate) fn finish(self) -> PostgresStore {
        PostgresStore {
            url: self.url,
            label: self.label,
            client: self.client,
            prepared: HashMap::new(),
            in_transaction: false,
            recent: self.recent,
            written: 0,
            term: None,
            listening: false,
        }
    }
}

/// Refuses a server that acknowledges commits it has not made durable (`fsync` off), and turns
/// `synchronous_commit` on for this connection when the server has it off (any other value
/// flushes the commit before it returns, locally or on the standbys as configured).
fn durable(client: &mut Client, label: &str) -> Result<(), StoreError> {
    let show = |client: &mut Client, name: &str| -> Result<String, StoreError> {
        client
            .query_one(&format!("SHOW {name}"), &[])
            .and_then(|r| r.try_get(0))
            .map_err(pg("reading the server's settings"))
    };
    if show(client, "fsync")? == "off" {
        return Err(StoreError::Unsafe {
            path: label.to_owned(),
            why: "the server runs with fsync = off, so a commit it acknowledges can be lost in \
                  a crash; MUSE answers only what is durable (set fsync = on)"
                .into(),
        });
    }
    if show(client, "synchronous_commit")? == "off" {
        client
            .batch_execute("SET synchronous_commit = on")
            .map_err(pg("turning synchronous_commit on"))?;
    }
    Ok(())
}
