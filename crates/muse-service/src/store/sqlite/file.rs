//! A structural check of the database file before SQLite opens it: a file cut short (by a
//! failing disk, a bad copy, a full volume) is refused, never read as a smaller database.
//!
//! The SQLite header (the first 100 bytes) records the page size and, when valid, how many
//! pages the database has. Every page the header counts must be in the file, or in the WAL
//! beside it (a crash during a checkpoint can leave the file shorter than its new header; the
//! WAL still holds those pages then).
//!
//! The WAL is checked too. SQLite reads it frame by frame, each frame's checksum chained to
//! the one before, and stops at the first frame that fails: what follows is taken for a write
//! torn by a crash and ignored. A crash can tear only the last transaction (every earlier one
//! was synced before its commit returned), so a failing frame followed by the commit frames of
//! two or more transactions is damage, not a torn write: ignoring it would drop committed
//! transactions, or bring back older copies of pages they changed. It is refused. Damage in
//! the last transactions looks like a torn write from the WAL alone: `acked` tells them apart,
//! and [`wal_damage`] names the frame.

use std::collections::HashSet;
use std::io::Read as _;
use std::path::Path;

use super::StoreError;

/// The first bytes of every SQLite database.
const MAGIC: &[u8; 16] = b"SQLite format 3\0";

/// Checks that the database at `path` holds every page its header counts.
pub(super) fn check(path: &Path) -> Result<(), StoreError> {
    let label = path.display().to_string();
    let damaged = |what: String| StoreError::Damaged {
        path: label.clone(),
        what,
    };
    let mut header = [0u8; 100];
    let len = std::fs::metadata(path)
        .map_err(|error| StoreError::Io {
            what: format!("reading {label}"),
            error,
        })?
        .len();
    if len == 0 {
        return Err(damaged("the file is empty".into()));
    }
    let mut f = std::fs::File::open(path).map_err(|error| StoreError::Io {
        what: format!("opening {label}"),
        error,
    })?;
    if len < 100 || f.read_exact(&mut header).is_err() {
        return Err(damaged(format!(
            "the file is {len} bytes, shorter than an SQLite header"
        )));
    }
    if &header[..16] != MAGIC {
        return Err(StoreError::NotAStore {
            path: path.display().to_string(),
            why: "it is not an SQLite database (bad header)".into(),
        });
    }
    let page_size = match u16::from_be_bytes([header[16], header[17]]) {
        1 => 65_536,
        n => u64::from(n),
    };
    if !page_size.is_power_of_two() || !(512..=65_536).contains(&page_size) {
        return Err(damaged(format!(
            "its header gives a page size of {page_size}"
        )));
    }
    check_wal(&path.with_extension("db-wal"))?;
    let be32 = |at: usize| u32::from_be_bytes(header[at..at + 4].try_into().expect("4 bytes"));
    let (counter, pages, valid_for) = (be32(24), u64::from(be32(28)), be32(92));
    if counter != valid_for || pages == 0 {
        // The header's page count is not maintained: SQLite goes by the file's length.
        return Ok(());
    }
    let in_file = len / page_size;
    if in_file >= pages {
        return Ok(());
    }
    let in_wal = wal_pages(&path.with_extension("db-wal"), page_size);
    let missing: Vec<u64> = (in_file + 1..=pages)
        .filter(|p| !in_wal.contains(p))
        .collect();
    if missing.is_empty() {
        return Ok(());
    }
    Err(damaged(format!(
        "the file is {len} bytes but its header counts {pages} pages of {page_size} bytes \
         ({} bytes): it was cut short, and {} of the missing pages are in no WAL either",
        pages * page_size,
        missing.len()
    )))
}

/// The chained checksum of SQLite's WAL over `data` (a multiple of 8 bytes), from `s`.
fn wal_sum(data: &[u8], big_endian: bool, mut s: (u32, u32)) -> (u32, u32) {
    let word = |b: &[u8]| {
        let b: [u8; 4] = b.try_into().expect("4 bytes");
        if big_endian {
            u32::from_be_bytes(b)
        } else {
            u32::from_le_bytes(b)
        }
    };
    for pair in data.chunks_exact(8) {
        s.0 = s.0.wrapping_add(word(&pair[..4])).wrapping_add(s.1);
        s.1 = s.1.wrapping_add(word(&pair[4..])).wrapping_add(s.0);
    }
    s
}

/// A WAL file, read whole (see the module docs).
struct Wal {
    bytes: Vec<u8>,
    /// How its checksums read words: `None` if it does not start with the WAL's magic.
    big_endian: Option<bool>,
}

/// One whole frame of a WAL file.
#[derive(Clone, Copy, Debug)]
struct Frame {
    /// Its number, from 1.
    n: usize,
    /// Where it begins in the file.
    at: usize,
    /// The database page it holds.
    page: u32,
    /// Whether it ends a transaction.
    commit: bool,
    /// Whether it carries the header's salts (it is of the WAL's current generation).
    current: bool,
}

/// Why SQLite stops reading a WAL at a frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Break {
    /// The frame carries other salts than the header.
    Salts,
    /// The frame fails its chained checksum.
    Checksum,
}

impl Wal {
    /// The WAL at `path`; `None` if there is none (or not even a header's worth of bytes).
    fn read(path: &Path) -> Option<Wal> {
        let bytes = std::fs::read(path).ok()?;
        if bytes.len() < 32 {
            return None;
        }
        let big_endian = match u32::from_be_bytes(bytes[..4].try_into().expect("4 bytes")) {
            0x377f_0683 => Some(true),
            0x377f_0682 => Some(false),
            _ => None,
        };
        Some(Wal { bytes, big_endian })
    }

    fn be32(&self, at: usize) -> u32 {
        u32::from_be_bytes(self.bytes[at..at + 4].try_into().expect("4 bytes"))
    }

    /// The page size its header gives.
    fn page_size(&self) -> usize {
        self.be32(8) as usize
    }

    /// Whether its header is one SQLite reads: the magic, a page size, its checksum. (A
    /// header torn while the WAL was restarted makes SQLite ignore the whole file.)
    fn header_ok(&self) -> bool {
        let size = self.page_size();
        self.big_endian.is_some_and(|big| {
            size.is_power_of_two()
                && (512..=65_536).contains(&size)
                && wal_sum(&self.bytes[..24], big, (0, 0)) == (self.be32(24), self.be32(28))
        })
    }

    /// Every whole frame of the file, taken with pages of `page_size` bytes.
    fn frames(&self, page_size: usize) -> impl Iterator<Item = Frame> + '_ {
        let size = 24 + page_size;
        let salts = &self.bytes[16..24];
        (0..(self.bytes.len() - 32) / size).map(move |k| {
            let at = 32 + k * size;
            Frame {
                n: k + 1,
                at,
                page: self.be32(at),
                commit: self.be32(at + 4) != 0,
                current: &self.bytes[at + 8..at + 16] == salts,
            }
        })
    }

    /// Where and why SQLite stops reading this WAL (its header read): the first frame of other
    /// salts or failing its checksum; `None` if it reads every frame.
    fn first_break(&self) -> Option<(Frame, Break)> {
        let big = self.big_endian?;
        let size = 24 + self.page_size();
        let mut sum = wal_sum(&self.bytes[..24], big, (0, 0));
        for f in self.frames(self.page_size()) {
            if !f.current {
                return Some((f, Break::Salts));
            }
            let next = wal_sum(&self.bytes[f.at..f.at + 8], big, sum);
            let next = wal_sum(&self.bytes[f.at + 24..f.at + size], big, next);
            if next != (self.be32(f.at + 16), self.be32(f.at + 20)) {
                return Some((f, Break::Checksum));
            }
            sum = next;
        }
        None
    }
}

/// Refuses a WAL whose failing frame is followed by two or more committed transactions (see
/// the module docs). No WAL, or a WAL of another generation only, is fine.
fn check_wal(path: &Path) -> Result<(), StoreError> {
    let Some(wal) = Wal::read(path).filter(Wal::header_ok) else {
        return Ok(());
    };
    let Some((bad, Break::Checksum)) = wal.first_break() else {
        return Ok(());
    };
    let commits = wal
        .frames(wal.page_size())
        .skip(bad.n)
        .take_while(|f| f.current)
        .filter(|f| f.commit)
        .count();
    if commits >= 2 {
        return Err(StoreError::Damaged {
            path: path.display().to_string(),
            what: format!(
                "frame {} of the WAL (page {}) fails its checksum and {commits} committed \
                 transactions follow it: not a write torn by a crash",
                bad.n, bad.page
            ),
        });
    }
    Ok(())
}

/// The first damage in the WAL at `path`, in words, if there is any to see: its header failing
/// its checksum, a frame failing its checksum, or a frame carrying other salts than the header
/// with frames of the header's salts after it (a salt flipped, not a frame left over from an
/// earlier generation of the WAL). A torn last frame is reported too: the caller knows
/// whether it was acknowledged.
pub(super) fn wal_damage(path: &Path) -> Option<String> {
    let wal = Wal::read(path)?;
    if wal.big_endian.is_none() {
        return Some("the WAL's header does not start with its magic number".into());
    }
    if !wal.header_ok() {
        return Some("the WAL's header fails its checksum, so SQLite ignores the whole WAL".into());
    }
    match wal.first_break()? {
        (bad, Break::Salts) => {
            let later = wal
                .frames(wal.page_size())
                .skip(bad.n)
                .find(|f| f.current)?;
            Some(format!(
                "frame {} of the WAL (page {}) carries other salts than the WAL's header, and \
                 frame {} after it carries the header's",
                bad.n, bad.page, later.n
            ))
        }
        (bad, Break::Checksum) => Some(format!(
            "frame {} of the WAL (page {}) fails its checksum",
            bad.n, bad.page
        )),
    }
}

/// The page numbers of the WAL's frames of its current generation (those whose salts match
/// the WAL header's), taken with pages of `page_size` bytes; empty if there is no WAL.
fn wal_pages(path: &Path, page_size: u64) -> HashSet<u64> {
    Wal::read(path).map_or_else(HashSet::new, |wal| {
        wal.frames(page_size as usize)
            .take_while(|f| f.current)
            .map(|f| u64::from(f.page))
            .collect()
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A store with a WAL of `n` transactions, copied while open (so the WAL is kept).
    fn wal_of(name: &str, n: usize) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("muse-wal-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(dir.join("copy")).unwrap();
        let db = dir.join("muse.db");
        let conn = rusqlite::Connection::open(&db).unwrap();
        conn.execute_batch(
            "PRAGMA journal_mode = WAL; PRAGMA wal_autocheckpoint = 0; \
             CREATE TABLE t (k INTEGER PRIMARY KEY, v TEXT);",
        )
        .unwrap();
        for k in 0..n {
            conn.execute(
                "INSERT INTO t (k, v) VALUES (?1, ?2)",
                rusqlite::params![k as i64, "x".repeat(3_000)],
            )
            .unwrap();
        }
        for f in ["muse.db", "muse.db-wal"] {
            std::fs::copy(dir.join(f), dir.join("copy").join(f)).unwrap();
        }
        drop(conn);
        dir.join("copy").join("muse.db")
    }

    fn flip(path: &Path, at: usize) {
        let mut bytes = std::fs::read(path).unwrap();
        bytes[at] ^= 0x5a;
        std::fs::write(path, bytes).unwrap();
    }

    #[test]
    fn damage_inside_the_wal_is_refused_and_a_torn_tail_is_not() {
        let db = wal_of("mid", 12);
        let wal = db.with_extension("db-wal");
        assert!(check(&db).is_ok());
        let len = std::fs::metadata(&wal).unwrap().len() as usize;
        // A torn last frame: what a crash leaves.
        let torn = std::fs::read(&wal).unwrap();
        std::fs::write(&wal, &torn[..len - 1_000]).unwrap();
        assert!(check(&db).is_ok());
        std::fs::write(&wal, &torn).unwrap();
        // The last frame damaged: indistinguishable from a torn write.
        flip(&wal, len - 10);
        assert!(check(&db).is_ok());
        std::fs::write(&wal, &torn).unwrap();
        // The second frame's page damaged, with ten committed transactions after it.
        let page = 4_096;
        flip(&wal, 32 + (24 + page) + 24 + 100);
        let e = check(&db).unwrap_err().to_string();
        assert!(
            e.contains("frame 2 of the WAL") && e.contains("committed transactions follow"),
            "{e}"
        );
        let _ = std::fs::remove_dir_all(db.parent().unwrap().parent().unwrap());
    }
}
