//! The files one run writes, all or nothing (DESIGN §9 "nothing is
//! half-written").
//!
//! 1. [`Outputs::preflight`], before the (possibly long) run: every output
//!    path names a file (not a folder) in an existing folder where a file
//!    can be created, and no two flags name the same file. A run that could
//!    not save its results does not start.
//! 2. [`Outputs::stage`], after the run: each output is written in full to a
//!    temporary file beside its destination (`.NAME.tmpPID`) and synced.
//! 3. [`Outputs::commit`]: once every output is staged, each temporary is
//!    renamed onto its destination (a rename is atomic on one file system).
//!
//! If anything fails before the commit — an error, a full disk, a panic —
//! dropping the [`Outputs`] removes every temporary and no destination is
//! touched. The commit's renames are the only step that can leave some
//! outputs new and others old: it takes no writing, only renames in folders
//! already proved writable.

use anyhow::{Context, Result, bail};
use std::collections::HashSet;
use std::path::{Path, PathBuf};

/// Outputs staged in temporary files, renamed into place by [`Outputs::commit`].
#[derive(Debug, Default)]
pub struct Outputs {
    staged: Vec<(PathBuf, PathBuf)>,
}

/// The temporary file that stands for `path` until the commit.
fn temporary(path: &Path) -> PathBuf {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    path.with_file_name(format!(".{name}.tmp{}", std::process::id()))
}

impl Outputs {
    /// Checks every `(flag, path)` before the run (see the module
    /// documentation). Creates nothing that stays.
    ///
    /// # Errors
    /// One line naming the flag and the path: a folder given as a file, a
    /// missing folder, a folder where no file can be created, or a path
    /// named twice.
    pub fn preflight(outputs: &[(&str, &Path)]) -> Result<()> {
        let mut seen = HashSet::new();
        for &(flag, path) in outputs {
            let shown = path.display();
            if path.file_name().is_none() || path.is_dir() {
                bail!("{flag} {shown}: is a folder; give a file name");
            }
            if !seen.insert(path) {
                bail!("{flag} {shown}: another output has the same path");
            }
            let folder = match path.parent() {
                Some(p) if !p.as_os_str().is_empty() => p,
                _ => Path::new("."),
            };
            if !folder.is_dir() {
                bail!(
                    "{flag} {shown}: the folder {} does not exist",
                    folder.display()
                );
            }
            let probe = temporary(path);
            std::fs::File::create(&probe)
                .with_context(|| format!("{flag} {shown}: cannot create a file there"))?;
            let _ = std::fs::remove_file(&probe);
        }
        Ok(())
    }

    /// Writes `bytes` in full to the temporary file of `path`.
    ///
    /// # Errors
    /// Naming `path`; the temporaries staged so far are removed when `self`
    /// is dropped.
    pub fn stage(&mut self, path: &Path, bytes: &[u8]) -> Result<()> {
        use std::io::Write;
        let tmp = temporary(path);
        // Recorded first, so that a partial temporary is removed too.
        self.staged.push((tmp.clone(), path.to_path_buf()));
        let write = || -> std::io::Result<()> {
            let mut f = std::fs::File::create(&tmp)?;
            f.write_all(bytes)?;
            f.sync_all()
        };
        write().with_context(|| format!("{}: cannot write", path.display()))
    }

    /// Renames every staged temporary onto its destination, in staging order.
    ///
    /// # Errors
    /// Naming the destination that could not be replaced; temporaries not
    /// yet renamed are removed.
    pub fn commit(mut self) -> Result<()> {
        while !self.staged.is_empty() {
            let (tmp, path) = self.staged.remove(0);
            if let Err(e) = std::fs::rename(&tmp, &path) {
                let _ = std::fs::remove_file(&tmp);
                return Err(e).with_context(|| format!("{}: cannot write", path.display()));
            }
        }
        Ok(())
    }
}

impl Drop for Outputs {
    fn drop(&mut self) {
        for (tmp, _) in &self.staged {
            let _ = std::fs::remove_file(tmp);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dir(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("trample-out-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    fn names(d: &Path) -> Vec<String> {
        let mut v: Vec<String> = std::fs::read_dir(d)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    }

    #[test]
    fn staged_outputs_appear_only_at_commit_and_vanish_on_drop() {
        let d = dir("stage");
        let (a, b) = (d.join("a.npy"), d.join("b.json"));
        let mut out = Outputs::default();
        out.stage(&a, b"aaa").unwrap();
        out.stage(&b, b"bbb").unwrap();
        assert!(!a.exists() && !b.exists(), "nothing before the commit");
        out.commit().unwrap();
        assert_eq!(names(&d), ["a.npy", "b.json"]);

        let mut out = Outputs::default();
        out.stage(&a, b"new").unwrap();
        let err = out.stage(&d.join("missing/c.npy"), b"c").unwrap_err();
        assert!(err.to_string().contains("missing/c.npy: cannot write"));
        drop(out);
        assert_eq!(names(&d), ["a.npy", "b.json"], "no temporary is left");
        assert_eq!(std::fs::read(&a).unwrap(), b"aaa", "a.npy untouched");
        std::fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn preflight_names_the_flag_and_what_is_wrong() {
        let d = dir("preflight");
        let ok = d.join("x.npy");
        Outputs::preflight(&[("--dump-blades", &ok)]).unwrap();
        assert!(names(&d).is_empty(), "the probe file is removed");
        let msg = |outputs: &[(&str, &Path)]| {
            Outputs::preflight(outputs)
                .unwrap_err()
                .to_string()
                .replace(&d.display().to_string(), "<d>")
        };
        assert_eq!(
            msg(&[("--dump-blades", &d)]),
            "--dump-blades <d>: is a folder; give a file name"
        );
        assert_eq!(
            msg(&[("--dump-classes", &d.join("no/c.npy"))]),
            "--dump-classes <d>/no/c.npy: the folder <d>/no does not exist"
        );
        assert_eq!(
            msg(&[("--dump-blades", &ok), ("--dump-classes", &ok)]),
            "--dump-classes <d>/x.npy: another output has the same path"
        );
        std::fs::remove_dir_all(&d).unwrap();
    }
}
