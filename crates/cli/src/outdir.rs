//! Output folders a run owns.
//!
//! Before any computation, [`OutDir::prepare`] checks that the folder can be
//! written (it creates it, and a probe file in it) and that it is tecon's:
//! a folder that holds files but no `tecon-manifest.json` was not written by
//! tecon and is refused unless `--force`. After a successful run,
//! [`OutDir::finish`] removes the files of the previous run that this run did
//! not write again (no stale `vessel_005.vtu` beside a shorter series) and
//! writes the manifest: the command and every file of this run.
//!
//! The previous run's files are moved aside into `.tecon-previous/` when the
//! folder is claimed: whatever is in the folder after a successful run was
//! written by it (or is a foreign file kept with `--force`), and the aside
//! copy is deleted. After a failed run [`OutDir::abandon`] moves the previous
//! results back, so a failure never leaves a half-replaced folder.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

/// Name of the manifest in every output folder.
pub const MANIFEST: &str = "tecon-manifest.json";

/// Where the previous run's files wait while a run is under way.
pub const ASIDE: &str = ".tecon-previous";

/// Errors of the output-folder manager.
#[derive(Debug, thiserror::Error)]
pub enum OutDirError {
    /// The path exists and is not a folder.
    #[error("output folder {0}: exists and is not a folder")]
    NotAFolder(String),
    /// The folder cannot be created or written.
    #[error("output folder {path}: cannot write there ({message})")]
    NotWritable {
        /// the folder
        path: String,
        /// the system's message
        message: String,
    },
    /// The folder holds files tecon did not write.
    #[error(
        "output folder {path}: holds files tecon did not write ({examples}); choose another --out, or pass --force to write beside them"
    )]
    Foreign {
        /// the folder
        path: String,
        /// a few of its entries
        examples: String,
    },
    /// Listing, removing or writing failed after the run.
    #[error("output folder {path}: {message}")]
    Io {
        /// the file or folder
        path: String,
        /// the system's message
        message: String,
    },
}

/// The manifest: which command wrote the folder, and its files.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Manifest {
    /// always "tecon"
    pub written_by: String,
    /// tecon's version
    pub version: String,
    /// the command line that wrote the folder (without the program name)
    pub command: String,
    /// files written, relative to the folder, sorted
    pub files: Vec<String>,
}

/// An output folder prepared for a run.
#[derive(Debug)]
pub struct OutDir {
    path: PathBuf,
    command: String,
    previous: Option<Manifest>,
    /// entries present before the run that tecon did not write (kept with `--force`)
    foreign: BTreeSet<String>,
    created: bool,
    /// previous files moved aside (relative paths)
    aside: Vec<String>,
}

fn io(path: &Path, e: impl std::fmt::Display) -> OutDirError {
    OutDirError::Io {
        path: path.display().to_string(),
        message: e.to_string(),
    }
}

/// Every file below `dir`, relative to it, with `/` separators.
fn list_files(dir: &Path) -> Result<BTreeSet<String>, OutDirError> {
    let mut out = BTreeSet::new();
    let mut stack = vec![PathBuf::new()];
    while let Some(rel) = stack.pop() {
        let abs = dir.join(&rel);
        for e in std::fs::read_dir(&abs).map_err(|e| io(&abs, e))? {
            let e = e.map_err(|e| io(&abs, e))?;
            let r = rel.join(e.file_name());
            if rel.as_os_str().is_empty() && e.file_name() == ASIDE {
                continue;
            }
            let ft = e.file_type().map_err(|e| io(&e_path(&abs, &r), e))?;
            if ft.is_dir() {
                stack.push(r);
            } else {
                out.insert(r.to_string_lossy().replace('\\', "/"));
            }
        }
    }
    Ok(out)
}

fn e_path(abs: &Path, rel: &Path) -> PathBuf {
    abs.join(rel)
}

impl OutDir {
    /// Checks and claims `path` for a run of `command`, before anything is
    /// computed: creates it, writes and removes a probe file, and refuses a
    /// non-empty folder without a manifest unless `force`.
    pub fn prepare(path: &Path, command: &str, force: bool) -> Result<OutDir, OutDirError> {
        let shown = path.display().to_string();
        if path.exists() && !path.is_dir() {
            return Err(OutDirError::NotAFolder(shown));
        }
        let created = !path.exists();
        std::fs::create_dir_all(path).map_err(|e| OutDirError::NotWritable {
            path: shown.clone(),
            message: e.to_string(),
        })?;
        let probe = path.join(format!(".tecon-write-test-{}", std::process::id()));
        let written = std::fs::write(&probe, b"tecon").and_then(|_| std::fs::remove_file(&probe));
        if let Err(e) = written {
            let _ = std::fs::remove_file(&probe);
            if created {
                let _ = std::fs::remove_dir(path);
            }
            return Err(OutDirError::NotWritable {
                path: shown,
                message: e.to_string(),
            });
        }
        let manifest_path = path.join(MANIFEST);
        let previous: Option<Manifest> = std::fs::read_to_string(&manifest_path)
            .ok()
            .and_then(|t| serde_json::from_str(&t).ok())
            .filter(|m: &Manifest| m.written_by == "tecon");
        let existing = list_files(path)?;
        let mut foreign: BTreeSet<String> = existing.clone();
        if let Some(m) = &previous {
            for f in &m.files {
                foreign.remove(f);
            }
            foreign.remove(MANIFEST);
        }
        if !foreign.is_empty() && !force {
            let examples: Vec<&str> = foreign.iter().take(3).map(String::as_str).collect();
            let more = if foreign.len() > 3 {
                format!(", … {} entries", foreign.len())
            } else {
                String::new()
            };
            return Err(OutDirError::Foreign {
                path: shown,
                examples: format!("{}{more}", examples.join(", ")),
            });
        }
        // a leftover of an interrupted run
        let aside_dir = path.join(ASIDE);
        if aside_dir.exists() {
            std::fs::remove_dir_all(&aside_dir).map_err(|e| io(&aside_dir, e))?;
        }
        let mut aside = Vec::new();
        for f in existing.iter().filter(|f| !foreign.contains(*f)) {
            let from = path.join(f);
            let to = aside_dir.join(f);
            if let Some(parent) = to.parent() {
                std::fs::create_dir_all(parent).map_err(|e| io(parent, e))?;
            }
            std::fs::rename(&from, &to).map_err(|e| io(&from, e))?;
            aside.push(f.clone());
        }
        remove_empty_dirs(path);
        Ok(OutDir {
            path: path.to_path_buf(),
            command: command.to_string(),
            previous,
            foreign,
            created,
            aside,
        })
    }

    /// The folder.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The command of the run that wrote the folder before, if tecon did.
    pub fn previous_command(&self) -> Option<&str> {
        self.previous.as_ref().map(|m| m.command.as_str())
    }

    /// After a successful run: removes the previous run's files that this
    /// run did not write, writes the manifest and returns it.
    pub fn finish(self) -> Result<Manifest, OutDirError> {
        let aside_dir = self.path.join(ASIDE);
        if aside_dir.exists() {
            std::fs::remove_dir_all(&aside_dir).map_err(|e| io(&aside_dir, e))?;
        }
        let files: Vec<String> = list_files(&self.path)?
            .into_iter()
            .filter(|f| f != MANIFEST && !self.foreign.contains(f))
            .collect();
        let m = Manifest {
            written_by: "tecon".into(),
            version: env!("CARGO_PKG_VERSION").into(),
            command: self.command.clone(),
            files,
        };
        let p = self.path.join(MANIFEST);
        let text = serde_json::to_string_pretty(&m).map_err(|e| io(&p, e))?;
        std::fs::write(&p, text + "\n").map_err(|e| io(&p, e))?;
        Ok(m)
    }

    /// After a failed run: moves the previous results back (where this run
    /// did not write a file of the same name) and removes the folder again
    /// if this run created it and left it empty.
    pub fn abandon(self) {
        let aside_dir = self.path.join(ASIDE);
        for f in &self.aside {
            let to = self.path.join(f);
            if !to.exists() {
                if let Some(parent) = to.parent() {
                    let _ = std::fs::create_dir_all(parent);
                }
                let _ = std::fs::rename(aside_dir.join(f), &to);
            }
        }
        let _ = std::fs::remove_dir_all(&aside_dir);
        if self.created {
            let _ = std::fs::remove_dir(&self.path);
        }
    }
}

/// Removes the empty sub-folders of `dir` (one level deep is all tecon writes).
fn remove_empty_dirs(dir: &Path) {
    if let Ok(rd) = std::fs::read_dir(dir) {
        for e in rd.flatten() {
            if e.file_type().is_ok_and(|t| t.is_dir()) && e.file_name() != ASIDE {
                remove_empty_dirs(&e.path());
                let _ = std::fs::remove_dir(e.path());
            }
        }
    }
}

#[cfg(test)]
mod tests {
    //! Goal: a run owns its folder — stale files go, foreign folders are refused.
    use super::*;

    #[test]
    fn a_rerun_removes_the_files_it_did_not_write_again() {
        let d = tempfile::tempdir().unwrap();
        let out = d.path().join("res");
        let o = OutDir::prepare(&out, "vessel", false).unwrap();
        for f in ["a.vtu", "b.vtu", "summary.json"] {
            std::fs::write(out.join(f), f).unwrap();
        }
        let m = o.finish().unwrap();
        assert_eq!(m.files, vec!["a.vtu", "b.vtu", "summary.json"]);
        let o = OutDir::prepare(&out, "vessel --times 1", false).unwrap();
        assert_eq!(o.previous_command(), Some("vessel"));
        std::fs::write(out.join("a.vtu"), "again").unwrap();
        std::fs::write(out.join("summary.json"), "again").unwrap();
        let m = o.finish().unwrap();
        assert_eq!(m.files, vec!["a.vtu", "summary.json"]);
        assert!(!out.join("b.vtu").exists(), "stale file removed");
        let text = std::fs::read_to_string(out.join(MANIFEST)).unwrap();
        assert!(text.contains("vessel --times 1"));
    }

    #[test]
    fn a_folder_tecon_did_not_write_is_refused_unless_forced() {
        let d = tempfile::tempdir().unwrap();
        std::fs::write(d.path().join("thesis.tex"), "mine").unwrap();
        let e = OutDir::prepare(d.path(), "vessel", false).unwrap_err();
        let msg = e.to_string();
        assert!(
            msg.contains("thesis.tex") && msg.contains("--force"),
            "{msg}"
        );
        let o = OutDir::prepare(d.path(), "vessel", true).unwrap();
        std::fs::write(d.path().join("summary.json"), "{}").unwrap();
        let m = o.finish().unwrap();
        assert_eq!(m.files, vec!["summary.json"]);
        assert!(
            d.path().join("thesis.tex").exists(),
            "foreign files are kept"
        );
    }

    #[test]
    fn a_file_in_the_way_or_an_unwritable_folder_is_an_error_naming_it() {
        let d = tempfile::tempdir().unwrap();
        let f = d.path().join("plain");
        std::fs::write(&f, "x").unwrap();
        let e = OutDir::prepare(&f, "vessel", false).unwrap_err();
        assert!(matches!(e, OutDirError::NotAFolder(_)), "{e}");
        let e = OutDir::prepare(&f.join("below"), "vessel", false).unwrap_err();
        assert!(e.to_string().contains("plain/below"), "{e}");
    }

    #[test]
    fn a_failed_run_leaves_no_new_folder_and_the_previous_results_in_place() {
        let d = tempfile::tempdir().unwrap();
        let out = d.path().join("new");
        OutDir::prepare(&out, "run", false).unwrap().abandon();
        assert!(!out.exists());
        let o = OutDir::prepare(&out, "run", false).unwrap();
        std::fs::write(out.join("summary.json"), "first").unwrap();
        o.finish().unwrap();
        let o = OutDir::prepare(&out, "run", false).unwrap();
        assert!(
            !out.join("summary.json").exists(),
            "moved aside while running"
        );
        o.abandon();
        assert_eq!(
            std::fs::read_to_string(out.join("summary.json")).unwrap(),
            "first"
        );
        assert!(!out.join(ASIDE).exists());
    }
}
