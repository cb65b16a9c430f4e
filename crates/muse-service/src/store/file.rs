//! A structural check of the database file before SQLite opens it: a file cut short (by a
//! failing disk, a bad copy, a full volume) is refused, never read as a smaller database.
//!
//! The SQLite header (the first 100 bytes) records the page size and, when valid, how many
//! pages the database has. Every page the header counts must be in the file, or in the WAL
//! beside it (a crash during a checkpoint can leave the file shorter than its new header; the
//! WAL still holds those pages then).

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
        .map_err(|source| StoreError::Io {
            what: format!("reading {label}"),
            source,
        })?
        .len();
    if len == 0 {
        return Err(damaged("the file is empty".into()));
    }
    let mut f = std::fs::File::open(path).map_err(|source| StoreError::Io {
        what: format!("opening {label}"),
        source,
    })?;
    if len < 100 || f.read_exact(&mut header).is_err() {
        return Err(damaged(format!(
            "the file is {len} bytes, shorter than an SQLite header"
        )));
    }
    if &header[..16] != MAGIC {
        return Err(StoreError::NotAStore {
            path: path.to_path_buf(),
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

/// The page numbers of the WAL's frames of its current generation (those whose salts match
/// the WAL header's); empty if there is no WAL.
fn wal_pages(path: &Path, page_size: u64) -> HashSet<u64> {
    let mut out = HashSet::new();
    let Ok(bytes) = std::fs::read(path) else {
        return out;
    };
    if bytes.len() < 32 {
        return out;
    }
    let salts = &bytes[16..24];
    let frame = 24 + page_size as usize;
    let mut at = 32;
    while at + frame <= bytes.len() {
        if &bytes[at + 8..at + 16] != salts {
            break;
        }
        let page = u32::from_be_bytes(bytes[at..at + 4].try_into().expect("4 bytes"));
        out.insert(u64::from(page));
        at += frame;
    }
    out
}
