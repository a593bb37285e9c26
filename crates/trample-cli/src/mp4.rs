//! `trample run --mp4`: frames piped as raw RGBA into `ffmpeg` (H.264,
//! yuv420p, for any player), written under a temporary name and renamed when
//! ffmpeg has finished.

use anyhow::{Context, Result, bail};
use std::io::{Read, Write};
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdin, Command, Stdio};

/// The `ffmpeg` on the PATH, or a one-line error that says what to do.
///
/// # Errors
/// When no executable `ffmpeg` is on the PATH.
pub fn find_ffmpeg() -> Result<PathBuf> {
    let path = std::env::var_os("PATH").unwrap_or_default();
    for dir in std::env::split_paths(&path) {
        let candidate = dir.join("ffmpeg");
        if candidate.is_file() {
            return Ok(candidate);
        }
    }
    bail!(
        "--mp4: ffmpeg is not on the PATH; install it (Debian: apt-get install ffmpeg) or use --gif"
    )
}

/// An ffmpeg process encoding the frames it is given.
pub struct Mp4Out {
    child: Child,
    stdin: Option<ChildStdin>,
    stderr: Option<std::thread::JoinHandle<String>>,
    tmp: PathBuf,
    path: PathBuf,
    size: (u32, u32),
}

impl Mp4Out {
    /// Starts `ffmpeg` for frames of `size` pixels at `fps` frames per second.
    ///
    /// # Errors
    /// No ffmpeg on the PATH, or it cannot be started.
    pub fn new(path: &Path, size: (u32, u32), fps: f64) -> Result<Self> {
        let ffmpeg = find_ffmpeg()?;
        let name = path
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        let tmp = path.with_file_name(format!(".{name}.tmp{}", std::process::id()));
        let mut child = Command::new(&ffmpeg)
            .args(["-hide_banner", "-loglevel", "error", "-y"])
            .args(["-f", "rawvideo", "-pix_fmt", "rgba"])
            .args(["-s", &format!("{}x{}", size.0, size.1)])
            .args(["-framerate", &format!("{fps:.3}")])
            .args(["-i", "-", "-an"])
            // yuv420p (what players expect) needs even sides.
            .args(["-vf", "scale=trunc(iw/2)*2:trunc(ih/2)*2"])
            .args(["-c:v", "libx264", "-pix_fmt", "yuv420p"])
            .args(["-movflags", "+faststart", "-f", "mp4"])
            .arg(&tmp)
            .stdin(Stdio::piped())
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .with_context(|| format!("--mp4: cannot start {}", ffmpeg.display()))?;
        let stdin = child.stdin.take();
        let mut err = child.stderr.take();
        let stderr = std::thread::spawn(move || {
            let mut s = String::new();
            if let Some(e) = err.as_mut() {
                let _ = e.read_to_string(&mut s);
            }
            s
        });
        Ok(Self {
            child,
            stdin,
            stderr: Some(stderr),
            tmp,
            path: path.to_path_buf(),
            size,
        })
    }

    /// Sends one frame (its size must be the one given to [`Mp4Out::new`]).
    ///
    /// # Errors
    /// A frame of another size, or ffmpeg stopped reading.
    pub fn push(&mut self, img: &image::RgbaImage) -> Result<()> {
        if img.dimensions() != self.size {
            bail!(
                "--mp4: frame of {:?}, expected {:?}",
                img.dimensions(),
                self.size
            );
        }
        let stdin = self.stdin.as_mut().context("--mp4: ffmpeg input closed")?;
        stdin
            .write_all(img.as_raw())
            .context("--mp4: ffmpeg stopped reading frames")
    }

    /// Closes the input, waits for ffmpeg and renames the video into place.
    ///
    /// # Errors
    /// ffmpeg failed (its last message is quoted), or the rename failed.
    pub fn finish(mut self) -> Result<()> {
        drop(self.stdin.take());
        let status = self.child.wait().context("--mp4: ffmpeg did not finish")?;
        let log = self
            .stderr
            .take()
            .and_then(|h| h.join().ok())
            .unwrap_or_default();
        if !status.success() {
            let _ = std::fs::remove_file(&self.tmp);
            let last = log.lines().last().unwrap_or("no message");
            bail!("--mp4: ffmpeg failed ({status}): {last}");
        }
        std::fs::rename(&self.tmp, &self.path)
            .with_context(|| format!("{}: cannot write", self.path.display()))
    }
}

impl Drop for Mp4Out {
    fn drop(&mut self) {
        // Unfinished (an error before `finish`): stop ffmpeg, keep nothing.
        if self.stdin.is_some() {
            drop(self.stdin.take());
            let _ = self.child.kill();
            let _ = self.child.wait();
            let _ = std::fs::remove_file(&self.tmp);
        }
    }
}
