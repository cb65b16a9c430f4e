//! What the store has acknowledged, recorded apart from the database, so that damage to the
//! last acknowledged transactions is never taken for a write torn by a crash.
//!
//! SQLite reads its WAL frame by frame and stops at the first frame that fails its checksum
//! (or carries other salts): what follows is taken for a write torn by a crash. From the WAL
//! alone a flipped byte in the last committed transaction looks exactly like a torn one, and a
//! flipped byte in an earlier frame drops every transaction after it. So the store keeps its
//! own count:
//!
//! - the `commits` table (one row) holds the store's identity (a random number chosen when it
//!   was created) and `n`, the write transactions committed; every transaction raises `n` by
//!   one, inside itself;
//! - `ACKED`, a file of two 512-byte records beside the database, holds the identity and the
//!   last `n` whose commit returned: written and synced after each commit, before any of its
//!   answers is sent. Record `n` goes into slot `n % 2`, so a record torn by a power cut
//!   leaves the other, one transaction older, intact.
//!
//! At start the database's `n` (as SQLite reads it, WAL included) must be at least `ACKED`'s:
//! one more is a transaction committed but never answered, kept as SQLite keeps it; fewer means
//! acknowledged transactions are missing, and the store is refused, naming the first damaged
//! frame of the WAL when there is one.

use std::fs::{File, OpenOptions};
use std::os::unix::fs::FileExt as _;
use std::path::{Path, PathBuf};

use rusqlite::{Connection, OptionalExtension as _, params};

use super::rows::RowSum;
use super::{StoreError, file, io, sql, sync_dir};

/// The record file's name inside the data folder.
pub(crate) const ACKED_FILE: &str = "ACKED";

/// The first bytes of a record.
const MAGIC: &[u8; 16] = b"MUSE-ACKED 1\0\0\0\0";

/// Bytes per record: a sector, written whole.
const SLOT: usize = 512;

/// Bytes of a record that carry data: the magic, the store, `n` and their CRC-32.
const USED: usize = 16 + 8 + 8 + 4;

/// The count of a store: which store, and how many write transactions.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Count {
    /// The store's identity.
    pub store: i64,
    /// Write transactions committed (in the database) or acknowledged (in `ACKED`).
    pub n: u64,
}

/// The checksum of the `commits` row.
fn row_sum(c: Count) -> i64 {
    RowSum::new("commits").int(c.store).int(c.n as i64).finish()
}

/// Creates the `commits` table and its row in `conn` (inside the caller's transaction, in a
/// store without it), with a new identity and `n` = 0. Returns the row.
pub(crate) fn create_table(conn: &Connection) -> Result<Count, StoreError> {
    conn.execute_batch(super::schema::CREATE_COMMITS)
        .map_err(sql("creating the commits table"))?;
    let store: i64 = conn
        .query_row("SELECT random()", [], |r| r.get(0))
        .map_err(sql("choosing the store's identity"))?;
    let c = Count { store, n: 0 };
    conn.execute(
        "INSERT INTO commits (one, store, n, crc) VALUES (1, ?1, 0, ?2)",
        params![store, row_sum(c)],
    )
    .map_err(sql("writing the commits table"))?;
    Ok(c)
}

/// The `commits` row, checked; `None` in a store written before it existed.
pub(crate) fn read_row(conn: &Connection, label: &str) -> Result<Option<Count>, StoreError> {
    let exists: Option<i64> = conn
        .query_row(
            "SELECT 1 FROM sqlite_schema WHERE type = 'table' AND name = 'commits'",
            [],
            |r| r.get(0),
        )
        .optional()
        .map_err(sql("reading the schema"))?;
    if exists.is_none() {
        return Ok(None);
    }
    let row: Option<(i64, i64, i64)> = conn
        .query_row("SELECT store, n, crc FROM commits WHERE one = 1", [], |r| {
            Ok((r.get(0)?, r.get(1)?, r.get(2)?))
        })
        .optional()
        .map_err(sql("reading the commits table"))?;
    let damaged = |what: &str| StoreError::Damaged {
        path: label.to_owned(),
        what: format!("the commits row: {what}"),
    };
    let Some((store, n, crc)) = row else {
        return Err(damaged("it is missing"));
    };
    let c = Count {
        store,
        n: u64::try_from(n).map_err(|_| damaged("its count is negative"))?,
    };
    if row_sum(c) != crc {
        return Err(damaged(
            "its checksum does not match its content (a byte of it changed on disk)",
        ));
    }
    Ok(Some(c))
}

/// Raises the `commits` row to `c` (inside the transaction being committed).
pub(crate) fn write_row(conn: &Connection, c: Count) -> Result<(), StoreError> {
    conn.prepare_cached("UPDATE commits SET n = ?1, crc = ?2 WHERE one = 1")
        .and_then(|mut s| s.execute(params![c.n as i64, row_sum(c)]))
        .map_err(sql("counting the transaction"))?;
    Ok(())
}

/// One record's bytes.
fn encode(c: Count) -> [u8; SLOT] {
    let mut b = [0u8; SLOT];
    b[..16].copy_from_slice(MAGIC);
    b[16..24].copy_from_slice(&c.store.to_le_bytes());
    b[24..32].copy_from_slice(&c.n.to_le_bytes());
    let crc = crc32fast::hash(&b[..32]);
    b[32..USED].copy_from_slice(&crc.to_le_bytes());
    b
}

/// The count a record holds, if it passes its checks.
fn decode(b: &[u8]) -> Option<Count> {
    if b.len() < USED || &b[..16] != MAGIC {
        return None;
    }
    let crc = u32::from_le_bytes(b[32..USED].try_into().ok()?);
    if crc32fast::hash(&b[..32]) != crc {
        return None;
    }
    Some(Count {
        store: i64::from_le_bytes(b[16..24].try_into().ok()?),
        n: u64::from_le_bytes(b[24..32].try_into().ok()?),
    })
}

/// The record file, open for writing.
#[derive(Debug)]
pub(crate) struct Acked {
    file: File,
    path: PathBuf,
}

impl Acked {
    /// Creates the record file in `dir` holding `c` (both slots), atomically: written beside
    /// it, synced, renamed, the folder synced.
    pub(crate) fn create(dir: &Path, c: Count) -> Result<Acked, StoreError> {
        let path = dir.join(ACKED_FILE);
        let tmp = dir.join(format!("{ACKED_FILE}.creating"));
        {
            let f = File::create(&tmp).map_err(io(format!("creating {}", tmp.display())))?;
            let mut both = encode(c).to_vec();
            both.extend_from_slice(&encode(c));
            f.write_all_at(&both, 0)
                .and_then(|()| f.sync_all())
                .map_err(io(format!("writing {}", tmp.display())))?;
        }
        std::fs::rename(&tmp, &path).map_err(io(format!("renaming {}", tmp.display())))?;
        sync_dir(dir)?;
        Acked::open(&path)
    }

    /// Opens the record file at `path` for writing.
    pub(crate) fn open(path: &Path) -> Result<Acked, StoreError> {
        let file = OpenOptions::new()
            .write(true)
            .open(path)
            .map_err(io(format!("opening {}", path.display())))?;
        Ok(Acked {
            file,
            path: path.to_path_buf(),
        })
    }

    /// Records that the transaction `c.n` is committed, durably: call it after the commit
    /// returned and before any of its answers is sent.
    pub(crate) fn record(&self, c: Count) -> Result<(), StoreError> {
        let at = (c.n % 2) * SLOT as u64;
        self.file
            .write_all_at(&encode(c), at)
            .and_then(|()| self.file.sync_data())
            .map_err(io(format!("writing {}", self.path.display())))
    }
}

/// The last count `ACKED` in `dir` records: `None` if there is no such file; an error if it
/// exists but neither record passes its checks.
pub(crate) fn read_file(dir: &Path) -> Result<Option<Count>, StoreError> {
    let path = dir.join(ACKED_FILE);
    let bytes = match std::fs::read(&path) {
        Ok(b) => b,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
        Err(e) => return Err(io(format!("reading {}", path.display()))(e)),
    };
    let slots: Vec<Count> = bytes.chunks(SLOT).take(2).filter_map(decode).collect();
    match slots.as_slice() {
        [] => Err(StoreError::Damaged {
            path: path.display().to_string(),
            what: format!(
                "neither of its two records passes its checks ({} bytes)",
                bytes.len()
            ),
        }),
        [one] => Ok(Some(*one)),
        [a, b] if a.store != b.store => Err(StoreError::Damaged {
            path: path.display().to_string(),
            what: "its two records name different stores".into(),
        }),
        [a, b] => Ok(Some(if a.n >= b.n { *a } else { *b })),
        _ => unreachable!("at most two records are read"),
    }
}

/// Checks at start that the database `db` (read through `conn`) holds every transaction the
/// record file beside it says was acknowledged (see the module docs).
pub(crate) fn check(conn: &Connection, db: &Path) -> Result<(), StoreError> {
    let label = db.display().to_string();
    let dir = db.parent().unwrap_or(Path::new("."));
    let in_db = read_row(conn, &label)?;
    let acked = read_file(dir)?;
    let record = dir.join(ACKED_FILE);
    match (in_db, acked) {
        (_, None) | (None, Some(Count { n: 0, .. })) => Ok(()),
        (None, Some(a)) => Err(StoreError::Damaged {
            path: label,
            what: format!(
                "it has no commits table, but {} says {} transactions were acknowledged",
                record.display(),
                a.n
            ),
        }),
        (Some(d), Some(a)) if d.store != a.store => Err(StoreError::Damaged {
            path: label,
            what: format!(
                "{} is the record of another store (it was copied from another folder, or \
                 the database was replaced): move it away only if this database is the one \
                 to keep",
                record.display()
            ),
        }),
        (Some(d), Some(a)) if d.n < a.n => {
            let wal = db.with_extension("db-wal");
            let why = file::wal_damage(&wal).map_or_else(
                || "no damaged frame is found in the WAL: the database or its WAL was replaced by an older copy, or a damaged page dropped them".to_owned(),
                |w| format!("{w}; SQLite stops reading the WAL there"),
            );
            Err(StoreError::Damaged {
                path: label,
                what: format!(
                    "{} transactions were acknowledged ({}) but the database holds {}: the \
                     last {} acknowledged transaction(s) are missing ({why})",
                    a.n,
                    record.display(),
                    d.n,
                    a.n - d.n
                ),
            })
        }
        (Some(_), Some(_)) => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_record_reads_back_and_a_damaged_one_does_not() {
        let c = Count {
            store: -42,
            n: 1_234_567,
        };
        let b = encode(c);
        assert_eq!(decode(&b), Some(c));
        for at in 0..USED {
            let mut d = b;
            d[at] ^= 0x5a;
            assert_eq!(decode(&d), None, "byte {at}");
        }
    }

    #[test]
    fn the_newest_intact_record_is_taken() {
        let dir = std::env::temp_dir().join(format!("muse-acked-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        assert_eq!(read_file(&dir).unwrap(), None);
        let c = |n| Count { store: 7, n };
        let a = Acked::create(&dir, c(0)).unwrap();
        for n in 1..=5 {
            a.record(c(n)).unwrap();
        }
        assert_eq!(read_file(&dir).unwrap(), Some(c(5)));
        // Slot 1 (record 5) torn: record 4 stands.
        let path = dir.join(ACKED_FILE);
        let mut bytes = std::fs::read(&path).unwrap();
        bytes[SLOT + 20] ^= 1;
        std::fs::write(&path, &bytes).unwrap();
        assert_eq!(read_file(&dir).unwrap(), Some(c(4)));
        // Both damaged: refused, named.
        bytes[20] ^= 1;
        std::fs::write(&path, &bytes).unwrap();
        let e = read_file(&dir).unwrap_err().to_string();
        assert!(
            e.contains("ACKED is damaged") && e.contains("neither"),
            "{e}"
        );
        let _ = std::fs::remove_dir_all(&dir);
    }
}
