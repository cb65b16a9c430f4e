//! Resident memory of this process, from `/proc/self/status` (Linux).

/// The value of a `Name:  <n> kB` line of `/proc/<pid>/status`, in bytes.
///
/// ```
/// use muse_sim::experiment::bench::status_kib_field;
/// let status = "Name:\tmuse\nVmPeak:\t  20000 kB\nVmHWM:\t    1536 kB\nVmRSS:\t 1024 kB\n";
/// assert_eq!(status_kib_field(status, "VmHWM"), Some(1536 * 1024));
/// assert_eq!(status_kib_field(status, "VmSwap"), None);
/// ```
pub fn status_kib_field(status: &str, name: &str) -> Option<u64> {
    status.lines().find_map(|line| {
        let rest = line.strip_prefix(name)?.strip_prefix(':')?;
        let mut words = rest.split_whitespace();
        let value: u64 = words.next()?.parse().ok()?;
        match words.next() {
            Some("kB") if words.next().is_none() => value.checked_mul(1024),
            _ => None,
        }
    })
}

/// This process's peak resident memory (`VmHWM`), in bytes; `None` where
/// `/proc/self/status` is unavailable (not Linux) or has no such line.
pub fn peak_rss_bytes() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    status_kib_field(&status, "VmHWM")
}

/// This process's current resident memory (`VmRSS`), in bytes, where available.
pub fn current_rss_bytes() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    status_kib_field(&status, "VmRSS")
}

/// Bytes as MiB with one decimal, or `n/a`.
pub fn mib(bytes: Option<u64>) -> String {
    bytes.map_or_else(|| "n/a".to_owned(), |b| format!("{:.1}", b as f64 / MIB))
}

/// Bytes in a mebibyte.
pub const MIB: f64 = 1024.0 * 1024.0;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn vm_hwm_parser() {
        let status = "Name:\tmuse\nUmask:\t0022\nState:\tR (running)\nVmPeak:\t  123456 kB\n\
                      VmSize:\t  120000 kB\nVmHWM:\t   51200 kB\nVmRSS:\t   40960 kB\nThreads:\t1\n";
        assert_eq!(status_kib_field(status, "VmHWM"), Some(51_200 * 1024));
        assert_eq!(status_kib_field(status, "VmRSS"), Some(40_960 * 1024));
        // Whole names only; missing, malformed or unitless lines give nothing.
        assert_eq!(status_kib_field(status, "VmH"), None);
        assert_eq!(status_kib_field(status, "Threads"), None);
        assert_eq!(status_kib_field("VmHWM:\t12 MB\n", "VmHWM"), None);
        assert_eq!(status_kib_field("VmHWM:\tlots kB\n", "VmHWM"), None);
        assert_eq!(status_kib_field("VmHWM:\t12 kB extra\n", "VmHWM"), None);
        assert_eq!(status_kib_field("", "VmHWM"), None);
        assert_eq!(status_kib_field("VmHWM:\t0 kB", "VmHWM"), Some(0));
        assert_eq!(
            status_kib_field(&format!("VmHWM:\t{} kB", u64::MAX), "VmHWM"),
            None
        );
        // On Linux both live values are there. (The peak is not compared with the current
        // size: the kernel folds its per-thread counters into the peak lazily, so a peak read
        // just after growth may lag the current size by a few pages.)
        if cfg!(target_os = "linux") {
            assert!(current_rss_bytes().expect("VmRSS on Linux") > 0);
            assert!(peak_rss_bytes().expect("VmHWM on Linux") > 0);
        }
        assert_eq!(mib(None), "n/a");
        assert_eq!(mib(Some(3 * 1024 * 1024 / 2)), "1.5");
    }
}
