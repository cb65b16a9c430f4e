//! The `meta` table, the same in both stores: what a store was written for, as `(key, value)`
//! rows in words, each with its checksum, and the check that a store opened is of this
//! version's format and was written for the world this service plans with.

use std::collections::BTreeMap;

use super::rows::RowSum;
use super::{StoreError, WorldMeta};

/// The value of the `format` meta entry this version writes and reads.
pub(super) const FORMAT: &str = "muse-store 1";

/// The checksum of a `meta` row.
pub(super) fn sum(key: &str, value: &str) -> i64 {
    RowSum::new("meta").text(key).text(value).finish()
}

/// The rows a new store written for `world` holds, each with its checksum: the format first.
pub(super) fn rows(world: &WorldMeta) -> Vec<(String, String, i64)> {
    std::iter::once(("format".to_owned(), FORMAT.to_owned()))
        .chain(world.iter().cloned())
        .map(|(k, v)| {
            let crc = sum(&k, &v);
            (k, v, crc)
        })
        .collect()
}

/// Checks the `meta` rows read from the store `label` (key, value, checksum): each row's
/// checksum, the format, then the world it was written for against `world`.
pub(super) fn check(
    label: &str,
    read: Vec<(String, String, i64)>,
    world: &WorldMeta,
) -> Result<(), StoreError> {
    let not = |why: String| StoreError::NotAStore {
        path: label.to_owned(),
        why,
    };
    let mut stored = BTreeMap::new();
    for (key, value, crc) in read {
        if sum(&key, &value) != crc {
            return Err(StoreError::Damaged {
                path: label.to_owned(),
                what: format!(
                    "meta row {key:?}: its checksum does not match its content (a byte of it \
                     changed on disk)"
                ),
            });
        }
        stored.insert(key, value);
    }
    match stored.remove("format") {
        Some(f) if f == FORMAT => {}
        Some(f) => {
            return Err(not(format!(
                "it is of format {f:?}, this version reads {FORMAT:?}"
            )));
        }
        None => return Err(not("it has no format entry".into())),
    }
    let (mut was, mut now) = (Vec::new(), Vec::new());
    for (key, value) in world {
        let old = stored.remove(key);
        if old.as_deref() != Some(value.as_str()) {
            was.push(format!(
                "{key} {}",
                old.as_deref().unwrap_or("(not recorded)")
            ));
            now.push(format!("{key} {value}"));
        }
    }
    for (key, value) in stored {
        was.push(format!("{key} {value}"));
        now.push(format!("{key} (none)"));
    }
    if was.is_empty() {
        Ok(())
    } else {
        Err(StoreError::Mismatch {
            path: label.to_owned(),
            stored: was.join(", "),
            wanted: now.join(", "),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn world() -> WorldMeta {
        vec![
            ("speed".into(), "30 km/h".into()),
            ("airspace".into(), "77 nodes".into()),
        ]
    }

    #[test]
    fn a_store_of_the_same_world_passes_and_any_difference_is_named() {
        assert!(check("db", rows(&world()), &world()).is_ok());
        let mut other = world();
        other[0].1 = "40 km/h".into();
        let e = check("db", rows(&other), &world()).unwrap_err().to_string();
        assert!(
            e.contains("speed 40 km/h") && e.contains("this service plans with speed 30 km/h"),
            "{e}"
        );
        let mut flipped = rows(&world());
        flipped[1].1 = "31 km/h".into();
        let e = check("db", flipped, &world()).unwrap_err().to_string();
        assert!(
            e.contains("meta row \"speed\"") && e.contains("damaged"),
            "{e}"
        );
        let e = check("db", rows(&world())[1..].to_vec(), &world())
            .unwrap_err()
            .to_string();
        assert!(e.contains("no format entry"), "{e}");
    }
}
