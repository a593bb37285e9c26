//! A grey-scale image stretched over the whole field, read as a grid of
//! values in [0, 1] (black 0, white 1) and sampled bilinearly: the height
//! map of the terrain and the grass maps (density, height, tint) share it.
//!
//! The image is found like every file a scene names: inside the scene's
//! folder ([`crate::paths::resolve_inside`]), a regular file only.

use super::terrain::HeightGrid;
use std::path::{Path, PathBuf};

/// Why a grid image could not be read. The callers add the scene key.
#[derive(Debug, thiserror::Error)]
pub enum GridImageError {
    /// The path leaves the scene's folder.
    #[error("{path:?}: {reason}")]
    Outside {
        /// The path as written.
        path: PathBuf,
        /// How it leaves the folder.
        reason: crate::paths::PathEscape,
    },
    /// The file is not a regular file or not an image that decodes.
    #[error("{path}: {reason}")]
    Unreadable {
        /// The image file.
        path: String,
        /// What went wrong.
        reason: String,
    },
    /// Fewer than 2×2 pixels: nothing to interpolate between.
    #[error("{path}: {w}x{h} pixels; at least 2x2 are needed")]
    TooSmall {
        /// The image file.
        path: String,
        /// Width in pixels.
        w: u32,
        /// Height in pixels.
        h: u32,
    },
}

/// Reads the grey image `path` (relative to `base_dir`, inside it) as a
/// grid of values in [0, 1] covering a field of `extent` (x, z) metres
/// centred on the origin: pixel column i, row j sits at
/// `x = -extent.x/2 + i/(w−1)·extent.x`, `z = -extent.z/2 + j/(h−1)·extent.z`
/// (image rows run along +z). Colour images are read as their luminance;
/// 16-bit images keep their precision.
///
/// # Errors
/// [`GridImageError`] when the path leaves the folder, the file is not a
/// regular file or does not decode, or it has fewer than 2×2 pixels.
pub fn load_grid_image(
    base_dir: &Path,
    path: &Path,
    extent: [f32; 2],
) -> Result<HeightGrid, GridImageError> {
    let full =
        crate::paths::resolve_inside(base_dir, path).map_err(|reason| GridImageError::Outside {
            path: path.to_path_buf(),
            reason,
        })?;
    let shown = full.display().to_string();
    // A FIFO or a device would block or never end: regular files only.
    match std::fs::metadata(&full) {
        Ok(m) if !m.is_file() => {
            return Err(GridImageError::Unreadable {
                path: shown,
                reason: "not a regular file; allowed: a PNG image file".into(),
            });
        }
        _ => {}
    }
    let img = image::open(&full)
        .map_err(|e| GridImageError::Unreadable {
            path: shown.clone(),
            reason: match (&e, image::image_dimensions(&full)) {
                // `image::open` decodes under the default limits.
                (image::ImageError::Limits(_), Ok((w, h))) => format!(
                    "{w}x{h} pixels, too large to decode ({e}: the image decoder allows \
                     {} MiB); allowed: a smaller image (a map is sampled once per cell: \
                     more pixels than the field has cells add nothing)",
                    image::Limits::default().max_alloc.unwrap_or(u64::MAX) >> 20
                ),
                _ => e.to_string(),
            },
        })?
        .into_luma16();
    let (w, h) = img.dimensions();
    if w < 2 || h < 2 {
        return Err(GridImageError::TooSmall { path: shown, w, h });
    }
    Ok(HeightGrid {
        dims: [w as usize, h as usize],
        heights: img.pixels().map(|p| f32::from(p.0[0]) / 65535.0).collect(),
        origin: [-extent[0] * 0.5, -extent[1] * 0.5],
        size: extent,
    })
}
