//! The keys of a table's last rows, read in order (the start's check of what was written
//! last, in both stores): they run without a gap from the first of the window to the largest
//! stored, but for keys archived (see [`super::archive`]), which count as present.

use super::StoreError;

/// A window of a table's last keys, walked in order.
pub(super) struct Keys<'a> {
    path: &'a str,
    table: &'static str,
    key: &'static str,
    /// The first key of the window.
    pub first: u64,
    /// The key the next row must have.
    want: u64,
    last: u64,
    /// Keys of the window found archived.
    archived: u64,
}

impl<'a> Keys<'a> {
    /// The last `window` keys of `table` (column `key`) of the store `path`, `last` the
    /// largest stored.
    pub fn window(
        path: &'a str,
        table: &'static str,
        key: &'static str,
        last: u64,
        window: u64,
    ) -> Keys<'a> {
        let first = last.saturating_sub(window) + 1;
        Keys {
            path,
            table,
            key,
            first,
            want: first,
            last,
            archived: 0,
        }
    }

    /// The next row read has key `got`: the one expected, or the next after keys archived
    /// (`archived(table, key, from, to)` counts the keys of `[from, to)` that the archive's
    /// table `table` holds by its column `key`), or damage.
    pub fn next(
        &mut self,
        got: i64,
        archived: impl FnOnce(&'static str, &'static str, u64, u64) -> Result<u64, StoreError>,
    ) -> Result<(), StoreError> {
        if got > self.want as i64 {
            let (table, key) = if self.table == "flights" {
                ("archived", "seq")
            } else {
                ("archived_events", "id")
            };
            let gap = got as u64 - self.want;
            if archived(table, key, self.want, got as u64)? == gap {
                self.archived += gap;
                self.want = got as u64;
            }
        }
        if got != self.want as i64 {
            return Err(self.damaged(format!(
                "{} row {} {} is missing (the rows go on with {} {got})",
                self.table, self.key, self.want, self.key
            )));
        }
        self.want += 1;
        Ok(())
    }

    /// Every key up to the largest was read; returns how many rows were.
    pub fn finish(self) -> Result<u64, StoreError> {
        if self.last > 0 && self.want != self.last + 1 {
            return Err(self.damaged(format!(
                "{} rows {} {} to {} are missing",
                self.table, self.key, self.want, self.last
            )));
        }
        Ok(self.want - self.first - self.archived)
    }

    fn damaged(&self, what: String) -> StoreError {
        StoreError::Damaged {
            path: self.path.to_owned(),
            what,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_gap_is_damage_unless_its_keys_were_archived() {
        let none = |_: &str, _: &str, _: u64, _: u64| Ok::<u64, StoreError>(0);
        let mut keys = Keys::window("db", "flights", "seq", 10, 5);
        assert_eq!(keys.first, 6);
        keys.next(6, none).unwrap();
        let e = keys.next(8, none).unwrap_err().to_string();
        assert!(e.contains("flights row seq 7 is missing"), "{e}");
        let mut keys = Keys::window("db", "flights", "seq", 10, 5);
        keys.next(6, none).unwrap();
        keys.next(9, |t, k, from, to| {
            assert_eq!((t, k, from, to), ("archived", "seq", 7, 9));
            Ok(2)
        })
        .unwrap();
        keys.next(10, none).unwrap();
        assert_eq!(keys.finish().unwrap(), 3);
        let mut keys = Keys::window("db", "events", "id", 10, 5);
        keys.next(6, none).unwrap();
        let e = keys.finish().unwrap_err().to_string();
        assert!(e.contains("events rows id 7 to 10 are missing"), "{e}");
    }
}
