//! Writing run folders safely when runs are interrupted, repeated, or made by several
//! processes into one folder at once (GNU parallel, job arrays on a shared disk).
//!
//! - A run is made under a lock, `OUT/.<run>.lock` (an advisory file lock, released
//!   by the system when the process ends, however it ends): a second process that
//!   wants the same run refuses at once instead of racing the first.
//! - The folder is written into a hidden temporary `OUT/.<run>-XXXXXX/` and renamed
//!   into place when whole. An interrupted run leaves only that temporary, which
//!   `plot` never reads and the next `learn` of the same run removes.

use std::fs::{File, OpenOptions, TryLockError};
use std::path::{Path, PathBuf};

use anyhow::{Context as _, bail};
use sim_host::learn::{self, RunOutcome};

use crate::cli::output;

/// Random characters in a temporary folder's name.
const RANDOM: usize = 6;

/// The right to make one run, held until dropped (the lock file is then removed).
pub struct Claim {
    file: File,
    path: PathBuf,
}

impl Drop for Claim {
    fn drop(&mut self) {
        // Remove the name first, then unlock: a process that opens the name after
        // this makes a new file, and one that opened the old file before finds it
        // unlinked when it checks (see `claim`).
        let _ = std::fs::remove_file(&self.path);
        let _ = self.file.unlock();
    }
}

/// Takes the lock of run `name` in `out`.
///
/// # Errors
/// Another process holds it, or the lock file cannot be made.
pub fn claim(out: &Path, name: &str) -> anyhow::Result<Claim> {
    let path = out.join(format!(".{name}.lock"));
    loop {
        let file = OpenOptions::new()
            .create(true)
            .truncate(false)
            .write(true)
            .open(&path)
            .with_context(|| format!("cannot write into {}", out.display()))?;
        match file.try_lock() {
            Ok(()) => {}
            Err(TryLockError::WouldBlock) => bail!(
                "{}: another `sim-host learn` is making this run now (it holds {}); wait for it to \
                 finish, or write to another --out",
                out.join(name).display(),
                path.display()
            ),
            Err(TryLockError::Error(e)) => {
                return Err(e).with_context(|| format!("cannot lock {}", path.display()));
            }
        }
        // The holder before us may have removed the name after we opened it: then our
        // lock is on a file nobody else will find. Try again on the current name.
        if same_file(&file, &path) {
            return Ok(Claim { file, path });
        }
    }
}

#[cfg(unix)]
fn same_file(file: &File, path: &Path) -> bool {
    use std::os::unix::fs::MetadataExt as _;
    match (file.metadata(), std::fs::metadata(path)) {
        (Ok(a), Ok(b)) => a.dev() == b.dev() && a.ino() == b.ino(),
        _ => false,
    }
}

#[cfg(not(unix))]
fn same_file(_: &File, path: &Path) -> bool {
    path.exists()
}

/// Whether `entry` (a file name in the output folder) is a temporary folder of run
/// `name`: `.<name>-` and six random characters.
pub fn is_temporary_of(entry: &str, name: &str) -> bool {
    entry
        .strip_prefix('.')
        .and_then(|e| e.strip_prefix(name))
        .and_then(|e| e.strip_prefix('-'))
        .is_some_and(|r| r.len() == RANDOM && r.chars().all(|c| c.is_ascii_alphanumeric()))
}

/// Removes the temporaries interrupted makings of run `name` left in `out` (call with
/// the run's [`Claim`] held: nobody else is writing them). Returns how many.
///
/// # Errors
/// A temporary that cannot be removed.
pub fn remove_temporaries(out: &Path, name: &str, _claim: &Claim) -> anyhow::Result<usize> {
    let mut removed = 0;
    let entries = std::fs::read_dir(out).with_context(|| format!("cannot read {}", out.display()))?;
    for entry in entries.flatten() {
        let file_name = entry.file_name();
        let Some(n) = file_name.to_str() else { continue };
        if is_temporary_of(n, name) && entry.file_type().is_ok_and(|t| t.is_dir()) {
            std::fs::remove_dir_all(entry.path())
                .with_context(|| format!("cannot remove {}, left by an interrupted run", entry.path().display()))?;
            removed += 1;
        }
    }
    Ok(removed)
}

/// Writes a run's folder whole: into a temporary folder beside it, then renamed.
///
/// # Errors
/// The folder exists and `force` is not given; any write error.
pub fn write_folder(out: &Path, run: &RunOutcome, force: bool, _claim: &Claim) -> anyhow::Result<PathBuf> {
    let name = run.spec.folder();
    let folder = out.join(&name);
    let files = learn::folder_files(run)?;
    let tmp = tempfile::Builder::new()
        .prefix(&format!(".{name}-"))
        .rand_bytes(RANDOM)
        .tempdir_in(out)
        .with_context(|| format!("cannot write into {}", out.display()))?;
    for (file, bytes) in files {
        output::write_whole(&tmp.path().join(file), &bytes)?;
    }
    if folder.exists() {
        if !force {
            bail!("{} exists; pass --force to replace it", folder.display());
        }
        std::fs::remove_dir_all(&folder).with_context(|| format!("cannot replace {}", folder.display()))?;
    }
    let tmp = tmp.keep();
    std::fs::rename(&tmp, &folder).with_context(|| format!("cannot write {}", folder.display()))?;
    Ok(folder)
}
