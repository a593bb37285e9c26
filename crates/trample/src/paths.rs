//! Files a scene names — meshes, height maps, a glTF file's buffers — are
//! read only from inside the folder that holds what names them (ours; DESIGN
//! §9 asks for clear errors on bad paths, this goes further).
//!
//! Why: a scene folder is a unit that is shared and downloaded. Refusing
//! `../` and absolute paths means a scene cannot make the tool read
//! `/etc/...`, a device such as `/dev/zero` (which never ends) or another
//! user's files, and that a scene folder that works on one machine works on
//! another. The repository's scenes keep their meshes in `scenes/meshes/`.
//!
//! The policy, in [`resolve_inside`]: the path must be relative; `..` may
//! not climb above the folder (`meshes/../car.obj` is fine); and when the
//! file exists, its real location (symbolic links followed) must be inside
//! the folder's real location too. [`read_regular_file`] then refuses
//! anything that is not a regular file (a folder, a FIFO, a device) and
//! files larger than a stated limit, before reading a byte.

use std::path::{Component, Path, PathBuf};

/// Why a path named by a scene was refused by [`resolve_inside`].
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum PathEscape {
    /// An absolute path (or, on Windows, one with a drive prefix).
    #[error("is absolute; it must be a path relative to {folder}, inside it")]
    Absolute {
        /// The folder it must stay in.
        folder: String,
    },
    /// A relative path whose `..` components climb above the folder.
    #[error("climbs above {folder} with `..`; it must stay inside that folder")]
    AboveFolder {
        /// The folder it must stay in.
        folder: String,
    },
    /// A path that stays inside lexically but whose real location (after
    /// symbolic links) is elsewhere.
    #[error(
        "leads (through a symbolic link) to {target}, outside {folder}; it must stay inside that folder"
    )]
    ThroughLink {
        /// The folder it must stay in.
        folder: String,
        /// Where the path really leads.
        target: String,
    },
}

/// `folder.join(relative)`, provided `relative` stays inside `folder` (see
/// the module documentation for the rules). A file that does not exist is
/// not an error here (its reader reports it, naming the file).
///
/// # Errors
/// [`PathEscape`] saying how the path leaves the folder.
pub fn resolve_inside(folder: &Path, relative: &Path) -> Result<PathBuf, PathEscape> {
    let shown = || folder.display().to_string();
    let mut depth: usize = 0;
    for component in relative.components() {
        match component {
            Component::Prefix(_) | Component::RootDir => {
                return Err(PathEscape::Absolute { folder: shown() });
            }
            Component::CurDir => {}
            Component::ParentDir => {
                depth = depth
                    .checked_sub(1)
                    .ok_or_else(|| PathEscape::AboveFolder { folder: shown() })?;
            }
            Component::Normal(_) => depth += 1,
        }
    }
    let full = folder.join(relative);
    if let (Ok(real_folder), Ok(real_file)) = (folder.canonicalize(), full.canonicalize())
        && !real_file.starts_with(&real_folder)
    {
        return Err(PathEscape::ThroughLink {
            folder: shown(),
            target: real_file.display().to_string(),
        });
    }
    Ok(full)
}

/// Why [`read_regular_file`] read nothing.
#[derive(Debug, thiserror::Error)]
pub enum ReadError {
    /// The operating system refused (missing file, no permission, ...).
    #[error("{0}")]
    Io(#[from] std::io::Error),
    /// A folder, FIFO, socket or device.
    #[error("not a regular file ({0}); allowed: a regular file")]
    NotRegular(&'static str),
    /// Larger than the caller's limit.
    #[error("the file is {bytes} bytes; at most {limit} bytes are allowed")]
    TooLarge {
        /// The file's size.
        bytes: u64,
        /// The limit.
        limit: u64,
    },
}

/// Reads the whole of `path` if it is a regular file (symbolic links
/// followed) of at most `limit` bytes.
///
/// # Errors
/// [`ReadError`]: the OS error, not a regular file, or too large.
pub fn read_regular_file(path: &Path, limit: u64) -> Result<Vec<u8>, ReadError> {
    let meta = std::fs::metadata(path)?;
    if !meta.is_file() {
        return Err(ReadError::NotRegular(if meta.is_dir() {
            "a folder"
        } else {
            "a device, FIFO or socket"
        }));
    }
    if meta.len() > limit {
        return Err(ReadError::TooLarge {
            bytes: meta.len(),
            limit,
        });
    }
    Ok(std::fs::read(path)?)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn check(relative: &str) -> Result<PathBuf, PathEscape> {
        resolve_inside(Path::new("/nonexistent/scene"), Path::new(relative))
    }

    #[test]
    fn relative_paths_inside_the_folder_pass() {
        assert_eq!(
            check("meshes/car.obj"),
            Ok(PathBuf::from("/nonexistent/scene/meshes/car.obj"))
        );
        assert!(check("./meshes/../car.obj").is_ok());
        assert!(check("a/b/../../c.obj").is_ok());
    }

    #[test]
    fn absolute_and_climbing_paths_are_refused() {
        assert_eq!(
            check("/etc/passwd").unwrap_err().to_string(),
            "is absolute; it must be a path relative to /nonexistent/scene, inside it"
        );
        assert_eq!(
            check("../x.obj").unwrap_err().to_string(),
            "climbs above /nonexistent/scene with `..`; it must stay inside that folder"
        );
        assert!(matches!(
            check("meshes/../../x.obj"),
            Err(PathEscape::AboveFolder { .. })
        ));
    }

    #[test]
    fn a_symbolic_link_out_of_the_folder_is_refused() {
        let dir = std::env::temp_dir().join(format!("trample-paths-{}", std::process::id()));
        let (inside, outside) = (dir.join("scene"), dir.join("elsewhere"));
        std::fs::create_dir_all(&inside).unwrap();
        std::fs::create_dir_all(&outside).unwrap();
        std::fs::write(outside.join("x.obj"), "v 0 0 0\n").unwrap();
        std::fs::write(inside.join("y.obj"), "v 0 0 0\n").unwrap();
        let link = inside.join("link.obj");
        let _ = std::fs::remove_file(&link);
        std::os::unix::fs::symlink(outside.join("x.obj"), &link).unwrap();
        let got = resolve_inside(&inside, Path::new("link.obj"));
        assert!(
            matches!(got, Err(PathEscape::ThroughLink { .. })),
            "{got:?}"
        );
        assert!(resolve_inside(&inside, Path::new("y.obj")).is_ok());
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn only_regular_files_within_the_limit_are_read() {
        assert!(matches!(
            read_regular_file(Path::new("/dev/zero"), 1 << 20),
            Err(ReadError::NotRegular(_))
        ));
        assert!(matches!(
            read_regular_file(Path::new("/"), 1 << 20),
            Err(ReadError::NotRegular("a folder"))
        ));
        let p = std::env::temp_dir().join(format!("trample-read-{}", std::process::id()));
        std::fs::write(&p, [0u8; 100]).unwrap();
        assert_eq!(read_regular_file(&p, 100).unwrap().len(), 100);
        assert_eq!(
            read_regular_file(&p, 99).unwrap_err().to_string(),
            "the file is 100 bytes; at most 99 bytes are allowed"
        );
        std::fs::remove_file(&p).unwrap();
    }
}
