//! Opening a data folder: its lock, the store's file and settings, a new store's tables, and
//! the check that a store was written for the world this service plans with.

use std::fs::{File, OpenOptions};
use std::path::{Path, PathBuf};

use muse_model::Airspace;
use rusqlite::{Connection, OpenFlags, params};

use super::acked::{self, Acked};
use super::{
    DB_FILE, ImportReport, LOCK_FILE, SqliteStore, StoreError, WorldMeta, checkpoint, file, io,
    legacy, schema, sql,
};

/// A data folder opened and locked, its store checked, not yet loaded.
#[derive(Debug)]
pub struct Opening {
    dir: PathBuf,
    lock: File,
    /// A log of an earlier version to convert first.
    import: Option<PathBuf>,
    /// How many of the last flights and events the start checks whole.
    recent: u64,
}

impl Opening {
    /// Locks `dir` (creating it if missing) and checks what it holds against `world`: a store
    /// written for the same world, a log of an earlier version written for it (to convert
    /// with [`Opening::finish`]), or nothing yet. Quick: reads no flight.
    pub fn open(dir: &Path, world: &WorldMeta, legacy_world: &str) -> Result<Opening, StoreError> {
        std::fs::create_dir_all(dir).map_err(io(format!("creating {}", dir.display())))?;
        let lock_path = dir.join(LOCK_FILE);
        let lock = OpenOptions::new()
            .create(true)
            .truncate(false)
            .write(true)
            .open(&lock_path)
            .map_err(io(format!("opening {}", lock_path.display())))?;
        match lock.try_lock() {
            Ok(()) => {}
            Err(std::fs::TryLockError::WouldBlock) => {
                return Err(StoreError::Locked(dir.to_path_buf()));
            }
            Err(std::fs::TryLockError::Error(e)) => {
                return Err(io(format!("locking {}", lock_path.display()))(e));
            }
        }
        let db = dir.join(DB_FILE);
        let log = dir.join(legacy::LOG_FILE);
        let import = if db.exists() {
            file::check(&db)?;
            let label = db.display().to_string();
            let conn = connect(&db, false).map_err(|e| e.in_store(&label))?;
            check_meta(&conn, &db, world).map_err(|e| e.in_store(&label))?;
            acked::check(&conn, &db).map_err(|e| e.in_store(&label))?;
            if log.exists() {
                // Converted, and the process stopped before the log was renamed.
                legacy::retire(&log)?;
            }
            None
        } else {
            if let Some(acked) = acked::read_file(dir)?.filter(|a| a.n > 0) {
                return Err(StoreError::Damaged {
                    path: db.display().to_string(),
                    what: format!(
                        "it is missing, but {} records {} acknowledged transaction(s) of a \
                         store in this folder",
                        dir.join(acked::ACKED_FILE).display(),
                        acked.n
                    ),
                });
            }
            if log.exists() {
                legacy::check_header(&log, legacy_world)?;
                Some(log)
            } else {
                None
            }
        };
        Ok(Opening {
            dir: dir.to_path_buf(),
            lock,
            import,
            recent: super::RECENT,
        })
    }

    /// Has the start check the last `n` flights and events whole (default [`super::RECENT`]).
    #[must_use]
    pub fn checking_recent(mut self, n: u64) -> Opening {
        self.recent = n;
        self
    }

    /// The store's database file in words.
    pub fn label(&self) -> String {
        self.dir.join(DB_FILE).display().to_string()
    }

    /// The handlers' reads of this folder's store (archived flights read from `archive`).
    pub(crate) fn reader(&self, archive: Option<PathBuf>) -> super::Reader {
        super::Reader::new(self.dir.join(DB_FILE), archive)
    }

    /// Whether a log of an earlier version will be converted.
    pub fn imports(&self) -> Option<&Path> {
        self.import.as_deref()
    }

    /// Converts a log of an earlier version if there is one (calling `progress` with the
    /// records read so far), creates the store if there is none, and opens it for writing.
    pub fn finish(
        self,
        airspace: &Airspace,
        world: &WorldMeta,
        progress: &mut dyn FnMut(u64),
    ) -> Result<(SqliteStore, Option<ImportReport>), StoreError> {
        let db = self.dir.join(DB_FILE);
        let report = if let Some(log) = &self.import {
            Some(legacy::import(log, &db, airspace, world, progress)?)
        } else {
            if !db.exists() {
                create(&db, world)?;
            }
            None
        };
        let conn = connect(&db, true)?;
        conn.execute_batch(super::archive::CREATE)
            .map_err(sql("adding the archive's tables"))?;
        let (count, acked) = counted(&conn, &self.dir)?;
        let checkpoints = checkpoint::Checkpointer::start(&db)?;
        Ok((
            SqliteStore {
                path: db,
                conn,
                count,
                acked,
                recent: self.recent,
                _lock: self.lock,
                in_transaction: false,
                written: 0,
                last_wal_restart: std::time::Instant::now(),
                _checkpoints: checkpoints,
            },
            report,
        ))
    }
}

/// The store's count of transactions (the `commits` table, added to a store written before it)
/// and its record file, holding that count (created if missing: a folder of an earlier
/// version, or a database restored from a copy of `muse.db` alone).
fn counted(conn: &Connection, dir: &Path) -> Result<(acked::Count, Acked), StoreError> {
    let label = dir.join(DB_FILE).display().to_string();
    let count = if let Some(c) = acked::read_row(conn, &label)? {
        c
    } else {
        conn.execute_batch("BEGIN IMMEDIATE")
            .map_err(sql("adding the commits table"))?;
        let c = acked::create_table(conn)?;
        conn.execute_batch("COMMIT")
            .map_err(sql("adding the commits table"))?;
        c
    };
    let file = match acked::read_file(dir)? {
        Some(a) if a.store == count.store => Acked::open(&dir.join(acked::ACKED_FILE))?,
        _ => Acked::create(dir, count)?,
    };
    // The database may hold one transaction more than was acknowledged (committed, never
    // answered): from now on it counts as acknowledged.
    file.record(count)?;
    Ok((count, file))
}

/// Opens a connection to the database at `path` with the store's settings (`write`: the
/// planner task's, which syncs every commit; else a read-only one).
pub(crate) fn connect(path: &Path, write: bool) -> Result<Connection, StoreError> {
    let flags = if write {
        OpenFlags::SQLITE_OPEN_READ_WRITE | OpenFlags::SQLITE_OPEN_NO_MUTEX
    } else {
        OpenFlags::SQLITE_OPEN_READ_ONLY | OpenFlags::SQLITE_OPEN_NO_MUTEX
    };
    let conn = Connection::open_with_flags(path, flags).map_err(|error| StoreError::Sql {
        what: format!("opening {}", path.display()),
        error,
    })?;
    // The writer's page cache: 8 MiB. The end of a write transaction can scan the whole
    // hash table of the page cache (`pcache1TruncateUnsafe`: 3–4 % of the service's time
    // under closed-loop load with 64 MiB, profiled), so a larger cache costs every commit
    // time in proportion; the pages a commit needs (the ends of the tables, the interior
    // index pages) fit, and the rest is in the operating system's cache.
    let settings = if write {
        "PRAGMA journal_mode = WAL; PRAGMA synchronous = FULL; PRAGMA wal_autocheckpoint = 0; \
         PRAGMA journal_size_limit = 67108864; PRAGMA cache_size = -8192; \
         PRAGMA busy_timeout = 10000;"
    } else {
        "PRAGMA busy_timeout = 10000; PRAGMA query_only = 1;"
    };
    conn.execute_batch(settings)
        .map_err(|error| StoreError::Sql {
            what: format!("setting up {}", path.display()),
            error,
        })?;
    Ok(conn)
}

/// Creates a new store at `path` for `world`, atomically: written beside it, then renamed.
fn create(path: &Path, world: &WorldMeta) -> Result<(), StoreError> {
    let tmp = path.with_extension("db.creating");
    let _ = std::fs::remove_file(&tmp);
    {
        let conn = Connection::open(&tmp).map_err(|error| StoreError::Sql {
            what: format!("creating {}", tmp.display()),
            error,
        })?;
        write_schema(&conn, world)?;
        conn.execute_batch("PRAGMA journal_mode = WAL;")
            .map_err(sql("setting WAL mode"))?;
        conn.close().map_err(|(_, e)| StoreError::Sql {
            what: format!("closing {}", tmp.display()),
            error: e,
        })?;
    }
    File::open(&tmp)
        .and_then(|f| f.sync_all())
        .map_err(io(format!("syncing {}", tmp.display())))?;
    std::fs::rename(&tmp, path).map_err(io(format!("renaming {}", tmp.display())))?;
    sync_dir(path.parent().unwrap_or(Path::new(".")))
}

/// Creates the tables of a new store in `conn` and records `world` in `meta`.
pub(crate) fn write_schema(conn: &Connection, world: &WorldMeta) -> Result<(), StoreError> {
    conn.execute_batch(&format!(
        "PRAGMA page_size = {}; BEGIN; {}",
        schema::PAGE_SIZE,
        schema::CREATE
    ))
    .map_err(sql("creating the tables"))?;
    for (key, value, crc) in super::meta::rows(world) {
        conn.execute(
            "INSERT INTO meta (key, value, crc) VALUES (?1, ?2, ?3)",
            params![key, value, crc],
        )
        .map_err(sql("writing the meta table"))?;
    }
    acked::create_table(conn)?;
    conn.execute_batch("COMMIT")
        .map_err(sql("creating the tables"))
}

/// Checks the `meta` rows of an existing store: its format, then the world it was written for.
fn check_meta(conn: &Connection, path: &Path, world: &WorldMeta) -> Result<(), StoreError> {
    let not = |why: String| StoreError::NotAStore {
        path: path.display().to_string(),
        why,
    };
    let mut stmt = conn
        .prepare("SELECT key, value, crc FROM meta")
        .map_err(|error| {
            let found = StoreError::Sql {
                what: "reading the meta table".into(),
                error,
            }
            .in_store(&path.display().to_string());
            match found {
                StoreError::Sql { error, .. } => {
                    not(format!("it has no readable meta table ({error})"))
                }
                damage => damage,
            }
        })?;
    let read = stmt
        .query_map([], |r| {
            Ok((
                r.get::<_, String>(0)?,
                r.get::<_, String>(1)?,
                r.get::<_, i64>(2)?,
            ))
        })
        .map_err(|e| not(format!("its meta table cannot be read ({e})")))?
        .collect::<Result<Vec<_>, _>>()
        .map_err(sql("reading the meta table"))?;
    super::meta::check(&path.display().to_string(), read, world)
}

/// Makes a new file's directory entry durable.
pub(crate) fn sync_dir(dir: &Path) -> Result<(), StoreError> {
    File::open(dir)
        .and_then(|d| d.sync_all())
        .map_err(io(format!("syncing the folder {}", dir.display())))
}
