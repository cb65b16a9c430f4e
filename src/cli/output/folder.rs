//! Output folders written whole: a run writes into a temporary folder beside its output
//! folder and puts it in place when everything is written.

use std::ffi::OsString;
use std::path::{Path, PathBuf};

use anyhow::{Context as _, bail};

use super::{
    Inputs, OLD, PARTIAL, STDOUT, clean_stale, interrupt, is_run_file, kind, split, temp_of,
};

/// An output folder being written: files go into [`OutFolder::path`], a temporary folder
/// `.NAME.partial-PID` beside it; [`OutFolder::commit`] puts it in place. Dropped without a
/// commit (an error), the temporary folder is removed; a run killed before its commit leaves
/// it, under that name, for a later run into the same place to remove.
#[derive(Debug)]
pub struct OutFolder {
    option: String,
    /// The output folder, as given.
    target: PathBuf,
    /// Where it is written meanwhile.
    staging: PathBuf,
    committed: bool,
}

/// The output folder `option` names, `path`, checked before the run does any work, and its
/// temporary folder made. Refused: `-`; a path with no name of its own (`.`); a path that
/// exists and is not a folder (a symbolic link is not followed); a folder holding anything
/// but files muse runs write and folders (an earlier run's folder is replaced whole, its
/// folders kept: not a user's folder); a folder holding one of the run's `inputs`, which the
/// replacement would remove.
pub fn folder(option: &str, path: &Path, inputs: &Inputs) -> anyhow::Result<OutFolder> {
    let shown = path.display();
    if path.as_os_str() == STDOUT {
        bail!(
            "{option} -: this command writes a folder of files, and standard output takes a single file; give a folder path"
        );
    }
    let Some((parent, name)) = split(path) else {
        bail!(
            "{option} {shown}: give the output folder a name of its own (e.g. {option} run1): muse replaces it as a whole"
        );
    };
    if parent.is_dir() {
        clean_stale(&parent, &name, path);
    }
    if path.symlink_metadata().is_ok_and(|m| m.is_dir()) {
        let folder = std::fs::canonicalize(path)
            .with_context(|| format!("{option} {shown}: reading its path"))?;
        for (input, at) in inputs.iter() {
            let Ok(file) = std::fs::canonicalize(at) else {
                continue;
            };
            if file == folder || file.parent() == Some(folder.as_path()) {
                bail!(
                    "{option} {shown} holds the input {input} {}: muse replaces its output folder as a whole, which would remove it; give another {option}",
                    at.display()
                );
            }
        }
    }
    survey(option, path)?;
    std::fs::create_dir_all(&parent)
        .with_context(|| format!("{option} {shown}: creating {}", parent.display()))?;
    let staging = parent.join(super::temp_name(&name, PARTIAL));
    if staging.symlink_metadata().is_ok() {
        std::fs::remove_dir_all(&staging)
            .with_context(|| format!("removing the stale {}", staging.display()))?;
    }
    interrupt::guard(&staging);
    if let Err(e) = std::fs::create_dir(&staging) {
        interrupt::release(&staging);
        return Err(e).with_context(|| format!("creating {}", staging.display()));
    }
    Ok(OutFolder {
        option: option.to_owned(),
        target: path.to_owned(),
        staging,
        committed: false,
    })
}

impl OutFolder {
    /// Where the run writes its files until [`OutFolder::commit`].
    pub fn path(&self) -> &Path {
        &self.staging
    }

    /// Puts the written folder in place of the output folder. An earlier run's folder there
    /// is moved aside (`.NAME.old-PID`), the new one renamed in, the earlier one's folders
    /// moved into the new one, and the rest of it removed: at no moment does the output path
    /// hold files of two runs. Refuses a folder that became something else meanwhile.
    pub fn commit(mut self) -> anyhow::Result<()> {
        let shown = self.target.display();
        for entry in read_names(&self.staging)? {
            if !is_run_file(&entry) {
                bail!(
                    "internal error: {} is not among the files muse runs write (output::RUN_FILES)",
                    entry.to_string_lossy()
                );
            }
        }
        let exists = survey(&self.option, &self.target)?;
        let staging = self.staging.clone();
        // An interruption waits until the folder is in place (or the commit failed).
        interrupt::finish(&staging, || {
            if exists {
                let (parent, name) = split(&self.target).context("the output folder has a name")?;
                let old = parent.join(super::temp_name(&name, OLD));
                std::fs::rename(&self.target, &old)
                    .with_context(|| format!("moving the earlier {shown} aside"))?;
                if let Err(e) = std::fs::rename(&self.staging, &self.target) {
                    let _ = std::fs::rename(&old, &self.target);
                    return Err(e).with_context(|| format!("putting {shown} in place"));
                }
                self.committed = true;
                carry_folders(&old, &self.target);
            } else {
                std::fs::rename(&self.staging, &self.target)
                    .with_context(|| format!("putting {shown} in place"))?;
                self.committed = true;
            }
            Ok(())
        })
    }
}

impl Drop for OutFolder {
    /// An output folder never committed (the run failed) leaves nothing behind.
    fn drop(&mut self) {
        if !self.committed {
            let _ = std::fs::remove_dir_all(&self.staging);
            interrupt::release(&self.staging);
        }
    }
}

/// Whether the output folder `path` exists; an error if it exists and is not a folder muse
/// may replace: not a folder, or holding an entry that is neither a file muse runs write, nor
/// a temporary entry of muse, nor a folder.
fn survey(option: &str, path: &Path) -> anyhow::Result<bool> {
    let shown = path.display();
    let meta = match std::fs::symlink_metadata(path) {
        Ok(m) => m,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(false),
        Err(e) => return Err(e).with_context(|| format!("{option} {shown}: reading it")),
    };
    if !meta.is_dir() {
        bail!(
            "{option} {shown} is {}; give a folder path",
            kind(meta.file_type())
        );
    }
    let mut foreign = Vec::new();
    for entry in std::fs::read_dir(path).with_context(|| format!("{option} {shown}: reading it"))? {
        let entry = entry.with_context(|| format!("{option} {shown}: reading it"))?;
        let name = entry.file_name();
        let t = entry
            .file_type()
            .with_context(|| format!("{option} {shown}: reading it"))?;
        let muse_temp = temp_of(&name).is_some();
        if !(t.is_dir() || (t.is_file() && (is_run_file(&name) || muse_temp))) {
            foreign.push(format!("{} ({})", name.to_string_lossy(), kind(t)));
        }
    }
    if !foreign.is_empty() {
        foreign.sort();
        let more = foreign.len().saturating_sub(3);
        foreign.truncate(3);
        bail!(
            "{option} {shown} holds {}{}, which no muse run writes: muse replaces its output folder as a whole, and replaces only a folder of an earlier run; give a new folder (or move those away)",
            foreign.join(", "),
            if more > 0 {
                format!(" and {more} more")
            } else {
                String::new()
            }
        );
    }
    Ok(true)
}

/// The names in folder `path`.
fn read_names(path: &Path) -> anyhow::Result<Vec<OsString>> {
    std::fs::read_dir(path)
        .and_then(|d| d.map(|e| e.map(|e| e.file_name())).collect())
        .with_context(|| format!("reading {}", path.display()))
}

/// Moves the folders of the earlier output folder `old` into the new one `into` (nested
/// output folders, such as `out/sweep` beside a run in `out`, outlive the run around them),
/// then removes `old`; if a folder cannot be moved, `old` is kept and a warning printed.
pub(crate) fn carry_folders(old: &Path, into: &Path) {
    let mut kept = Vec::new();
    for entry in std::fs::read_dir(old).into_iter().flatten().flatten() {
        if !entry.file_type().is_ok_and(|t| t.is_dir()) {
            continue;
        }
        let to = into.join(entry.file_name());
        if to.symlink_metadata().is_ok() || std::fs::rename(entry.path(), &to).is_err() {
            kept.push(entry.file_name().to_string_lossy().into_owned());
        }
    }
    if kept.is_empty() {
        let _ = std::fs::remove_dir_all(old);
    } else {
        eprintln!(
            "warning: kept {}: its folders {} could not be moved into {}",
            old.display(),
            kept.join(", "),
            into.display()
        );
    }
}
