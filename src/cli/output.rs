//! Where a run's outputs go and how they are written: every command that writes files goes
//! through here (docs/reference.md#outputs).
//!
//! - An output path that exists must be what the command writes: a regular file for a file
//!   output, a folder for a folder output. A symbolic link (never followed), a device, a FIFO
//!   or a socket is refused before anything is computed.
//! - An output that would replace an input of the same run is refused, and so are two outputs
//!   of one run naming the same file.
//! - `-` is standard output where a command writes one file; a folder output cannot be `-`.
//! - A file is written to `.NAME.partial-PID` beside it and renamed over `NAME` when complete.
//! - A folder is written whole ([`OutFolder`]): into `.NAME.partial-PID` beside it, then put
//!   in place of `NAME`, replacing an earlier run's folder as a whole.
//!
//! The temporary names carry the process id of the run: a later run into the same place
//! removes those of runs no longer running ([`clean_stale`]), and never takes one for output.
//! A run interrupted by SIGINT or SIGTERM removes its own before it ends (`interrupt`).

mod folder;
mod interrupt;
#[cfg(test)]
mod tests;

use std::ffi::{OsStr, OsString};
use std::fmt;
use std::io::Write as _;
use std::path::{Path, PathBuf};

use anyhow::{Context as _, bail};

pub use folder::{OutFolder, folder};
pub use interrupt::hold_if_interrupted;

use super::common::WorldArgs;

/// The output path that means standard output.
pub const STDOUT: &str = "-";

/// Every file a muse command writes into an output folder. A folder holding only these (and
/// folders) is one muse may replace: an earlier run's. Add a file here when a command starts
/// writing one into its folder (committing a folder with any other file is an error).
pub const RUN_FILES: &[&str] = &[
    // simulate, plan
    "requests.csv",
    "plans.jsonl",
    "summary.json",
    "flights.geojson",
    "flights.csv",
    "stays.csv",
    "map.svg",
    "view.html",
    // sweep (and sweep merge)
    "sweep.csv",
    "sweep_summary.csv",
    "sweep_runtime.svg",
    "sweep_success.svg",
    "sweep_air_delay.svg",
    // sweep --vary announce-lead
    "announce_lead.csv",
    "announce_lead_summary.csv",
    "announce_lead_success.svg",
    "announce_lead_outcomes.svg",
    "announce_lead_extra_delay.svg",
    // sweep --shard
    "shard.json",
    // bench
    "bench.csv",
    "bench_time_per_request.svg",
    "bench_expanded.svg",
    "bench_peak_memory.svg",
    // siting
    "siting.csv",
    "curve.csv",
    "curve.svg",
    "airspace.geojson",
];

/// Whether `name` is a file a muse run writes into its folder, or the temporary name an
/// earlier version of muse wrote it under (`plans.partial` for `plans.jsonl`).
pub(crate) fn is_run_file(name: &OsStr) -> bool {
    let Some(name) = name.to_str() else {
        return false;
    };
    RUN_FILES.iter().any(|f| {
        *f == name
            || name
                .strip_suffix(".partial")
                .is_some_and(|stem| Path::new(f).file_stem() == Some(OsStr::new(stem)))
    })
}

/// The inputs of a run, by the option that names each: no output may replace one.
#[derive(Debug, Default)]
pub struct Inputs(Vec<(String, PathBuf)>);

impl Inputs {
    /// No inputs yet.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds the file `path` given by `option`.
    #[must_use]
    pub fn add(mut self, option: &str, path: &Path) -> Self {
        self.0.push((option.to_owned(), path.to_owned()));
        self
    }

    /// Adds every file of `paths`, given by `option`.
    #[must_use]
    pub fn add_all(self, option: &str, paths: &[PathBuf]) -> Self {
        paths.iter().fold(self, |inputs, p| inputs.add(option, p))
    }

    /// Adds the file `--customers` names, if it names one (not the embedded customers,
    /// [`SINGAPORE_HDB`](super::common::SINGAPORE_HDB)).
    #[must_use]
    pub fn customers(self, arg: Option<&Path>) -> Self {
        match arg.and_then(super::common::customers_file) {
            Some(path) => self.add("--customers", path),
            None => self,
        }
    }

    /// Adds the files a world is read from: `--airspace` and `--zones` (not `none`).
    #[must_use]
    pub fn world(self, world: &WorldArgs) -> Self {
        let zones: Vec<PathBuf> = world
            .zones
            .iter()
            .filter(|z| z.as_os_str() != "none")
            .cloned()
            .collect();
        let inputs = match &world.airspace {
            Some(a) => self.add("--airspace", a),
            None => self,
        };
        inputs.add_all("--zones", &zones)
    }

    /// The inputs, as `(option, path)`.
    pub(crate) fn iter(&self) -> impl Iterator<Item = (&str, &Path)> {
        self.0.iter().map(|(o, p)| (o.as_str(), p.as_path()))
    }
}

/// One file a run writes: a path, or standard output.
#[derive(Debug)]
pub struct FileOut {
    option: String,
    /// `None`: standard output.
    path: Option<PathBuf>,
}

impl FileOut {
    /// Whether it is standard output (the run's messages then go to stderr).
    pub fn is_stdout(&self) -> bool {
        self.path.is_none()
    }

    /// Writes `text` whole: to standard output, or atomically to the file.
    pub fn write(&self, text: &str) -> anyhow::Result<()> {
        if let Some(path) = &self.path {
            return write_atomically(path, text);
        }
        let mut out = std::io::stdout().lock();
        out.write_all(text.as_bytes())
            .and_then(|()| out.flush())
            .context("writing to standard output")
    }
}

impl fmt::Display for FileOut {
    /// The path, or `standard output`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.path {
            Some(p) => write!(f, "{}", p.display()),
            None => f.write_str("standard output"),
        }
    }
}

/// The file output `option` names, `path` (`-`: standard output), checked before the run
/// does any work: it is refused if it is a folder's path (ending in `/`), if it exists and is
/// not a regular file, if its folder does not exist, or if it is one of the run's `inputs`.
pub fn file(option: &str, path: &Path, inputs: &Inputs) -> anyhow::Result<FileOut> {
    if path.as_os_str() == STDOUT {
        return Ok(FileOut {
            option: option.to_owned(),
            path: None,
        });
    }
    let shown = path.display();
    let (parent, name) = split(path)
        .with_context(|| format!("{option} {shown}: give a file path, or - for standard output"))?;
    if path.to_string_lossy().ends_with(std::path::is_separator) {
        bail!(
            "{option} {shown} ends with {}, a folder's path: give the path of the file to write \
             (or - for standard output)",
            std::path::MAIN_SEPARATOR
        );
    }
    match std::fs::metadata(&parent) {
        Ok(m) if m.is_dir() => {}
        Ok(_) => bail!("{option} {shown}: {} is not a folder", parent.display()),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => bail!(
            "{option} {shown}: its folder {} does not exist: make it first, or give another path",
            parent.display()
        ),
        Err(e) => bail!("{option} {shown}: its folder {}: {e}", parent.display()),
    }
    clean_stale(&parent, &name, path);
    if let Some(kind) = not_regular(path)? {
        bail!("{option} {shown} is {kind}; give a regular file path (or - for standard output)");
    }
    for (input, at) in inputs.iter() {
        if same_file(path, at) {
            bail!(
                "{option} {shown} is the input {input} {}: writing it would replace that input; give another {option}",
                at.display()
            );
        }
    }
    Ok(FileOut {
        option: option.to_owned(),
        path: Some(path.to_owned()),
    })
}

/// Refuses two outputs of one run that name the same file (or both standard output).
pub fn distinct(outputs: &[&FileOut]) -> anyhow::Result<()> {
    for (i, a) in outputs.iter().enumerate() {
        for b in &outputs[i + 1..] {
            let same = match (&a.path, &b.path) {
                (None, None) => true,
                (Some(p), Some(q)) => same_file(p, q) || absolute(p) == absolute(q),
                _ => false,
            };
            if same {
                bail!(
                    "{} and {} both name {a}: one would replace the other; give each its own file",
                    a.option,
                    b.option
                );
            }
        }
    }
    Ok(())
}

/// Prints a line about the run: on stdout, or on stderr when stdout carries an output.
pub fn say(stdout_taken: bool, line: impl fmt::Display) {
    if stdout_taken {
        eprintln!("{line}");
    } else {
        println!("{line}");
    }
}

/// Writes `text` to `path` atomically: into `.NAME.partial-PID` beside it, flushed to disk,
/// then renamed over `NAME`, so that a failed or killed run never leaves a file that looks
/// whole; the temporary file is removed on an error. Refuses to replace anything but a
/// regular file (a link, a device, a FIFO, a socket, a folder).
pub fn write_atomically(path: &Path, text: &str) -> anyhow::Result<()> {
    let (parent, name) = split(path).with_context(|| format!("writing {}", path.display()))?;
    if let Some(kind) = not_regular(path)? {
        bail!(
            "{} is {kind}; muse replaces only regular files",
            path.display()
        );
    }
    let tmp = parent.join(temp_name(&name, PARTIAL));
    interrupt::guard(&tmp);
    let written = create_new(&tmp)
        .and_then(|mut f| {
            f.write_all(text.as_bytes())?;
            f.sync_all()
        })
        .with_context(|| format!("writing {}", tmp.display()))
        .and_then(|()| {
            std::fs::rename(&tmp, path).with_context(|| format!("renaming to {}", path.display()))
        });
    if written.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    interrupt::release(&tmp);
    written
}

/// Creates `path` for writing, as a new file (a stale one of this process id is replaced).
fn create_new(path: &Path) -> std::io::Result<std::fs::File> {
    let open = || {
        std::fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(path)
    };
    match open() {
        Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {
            std::fs::remove_file(path)?;
            open()
        }
        other => other,
    }
}

/// The temporary-name tag of output still being written.
const PARTIAL: &str = "partial";
/// The temporary-name tag of an earlier run's folder being replaced.
const OLD: &str = "old";

/// `.NAME.TAG-PID`: a temporary name beside `NAME` of this process.
fn temp_name(name: &OsStr, tag: &str) -> OsString {
    let mut s = OsString::from(".");
    s.push(name);
    s.push(format!(".{tag}-{}", std::process::id()));
    s
}

/// The name, tag and process id of `entry` if it is a temporary name `.NAME.TAG-PID`.
fn temp_of(entry: &OsStr) -> Option<(&str, &str, u32)> {
    let (head, pid) = entry.to_str()?.strip_prefix('.')?.rsplit_once('-')?;
    if pid.is_empty() || !pid.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    let (name, tag) = head.rsplit_once('.')?;
    if name.is_empty() || (tag != PARTIAL && tag != OLD) {
        return None;
    }
    Some((name, tag, pid.parse().ok()?))
}

/// The tag and process id of `entry` if it is a temporary name beside `name`.
fn parse_temp<'a>(entry: &'a OsStr, name: &OsStr) -> Option<(&'a str, u32)> {
    let (of, tag, pid) = temp_of(entry)?;
    (OsStr::new(of) == name).then_some((tag, pid))
}

/// Whether process `pid` is running: `None` where this cannot be told (no `/proc`).
fn running(pid: u32) -> Option<bool> {
    if pid == std::process::id() {
        return Some(true);
    }
    let proc = Path::new("/proc");
    proc.join("self")
        .exists()
        .then(|| proc.join(pid.to_string()).exists())
}

/// Removes the temporary entries beside `path` (named `name`, in `parent`) left by runs that
/// are no longer running, killed before they finished: a file or folder being written is
/// removed; an earlier folder moved aside while being replaced is put back if `path` is
/// gone, else its folders are moved into `path` (see [`OutFolder::commit`]) and the rest
/// removed. Entries of running runs, and where that cannot be told, are left alone.
pub(crate) fn clean_stale(parent: &Path, name: &OsStr, path: &Path) {
    let Ok(entries) = std::fs::read_dir(parent) else {
        return;
    };
    let mut stale: Vec<(String, PathBuf)> = entries
        .filter_map(Result::ok)
        .filter_map(|e| {
            let file_name = e.file_name();
            let (tag, pid) = parse_temp(&file_name, name)?;
            (running(pid) == Some(false)).then(|| (tag.to_owned(), e.path()))
        })
        .collect();
    // An earlier folder is put back before the folders being written are removed.
    stale.sort_by_key(|(tag, _)| tag != OLD);
    for (tag, entry) in stale {
        let is_dir = entry.symlink_metadata().is_ok_and(|m| m.is_dir());
        if tag == OLD && is_dir {
            if std::fs::symlink_metadata(path).is_err() {
                let _ = std::fs::rename(&entry, path);
            } else {
                folder::carry_folders(&entry, path);
            }
        } else if is_dir {
            let _ = std::fs::remove_dir_all(&entry);
        } else {
            let _ = std::fs::remove_file(&entry);
        }
    }
}

/// The folder `path` is in and its name; `None` for a path with no name of its own (`/`,
/// `.`, `..`).
fn split(path: &Path) -> Option<(PathBuf, OsString)> {
    let name = path.file_name()?.to_owned();
    let parent = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_owned(),
        _ => PathBuf::from("."),
    };
    Some((parent, name))
}

/// What `path` is if it exists and is not a regular file (`None` if it is one or does not
/// exist), without following a symbolic link.
fn not_regular(path: &Path) -> anyhow::Result<Option<&'static str>> {
    match std::fs::symlink_metadata(path) {
        Ok(m) if m.is_file() => Ok(None),
        Ok(m) => Ok(Some(kind(m.file_type()))),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(None),
        Err(e) => Err(e).with_context(|| format!("reading what {} is", path.display())),
    }
}

/// What a file type is, for messages: `a symbolic link`, `a folder`, `a FIFO (named pipe)` …
pub(crate) fn kind(t: std::fs::FileType) -> &'static str {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt as _;
        if t.is_fifo() {
            return "a FIFO (named pipe)";
        }
        if t.is_socket() {
            return "a socket";
        }
        if t.is_char_device() {
            return "a character device";
        }
        if t.is_block_device() {
            return "a block device";
        }
    }
    if t.is_symlink() {
        "a symbolic link"
    } else if t.is_dir() {
        "a folder"
    } else if t.is_file() {
        "a regular file"
    } else {
        "not a regular file"
    }
}

/// Whether `a` and `b` both exist and are the same file (the same device and inode; `a` is
/// not followed if it is a link, `b` is).
fn same_file(a: &Path, b: &Path) -> bool {
    let (Ok(ma), Ok(mb)) = (std::fs::symlink_metadata(a), std::fs::metadata(b)) else {
        return false;
    };
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt as _;
        ma.dev() == mb.dev() && ma.ino() == mb.ino()
    }
    #[cfg(not(unix))]
    {
        let _ = (ma, mb);
        std::fs::canonicalize(a).ok() == std::fs::canonicalize(b).ok()
    }
}

/// `path` with its folder made absolute and free of links (the name itself kept), to compare
/// outputs that do not exist yet.
fn absolute(path: &Path) -> Option<PathBuf> {
    let (parent, name) = split(path)?;
    Some(std::fs::canonicalize(parent).ok()?.join(name))
}
