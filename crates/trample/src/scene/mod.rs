//! Scene files (TOML, unknown keys are errors): every parameter of a run,
//! with documented units and defaults. The default scene — the paper's field
//! and a sphere rolling across it — is embedded in the library.

mod build;
mod error;
mod file;

pub use error::SceneError;
pub use file::{RunParams, SceneFile};

use std::path::{Path, PathBuf};

/// The default scene's text (also `scenes/default.toml`).
pub const DEFAULT_SCENE_TOML: &str = include_str!("../../../../scenes/default.toml");

/// A parsed scene and where it came from.
#[derive(Clone, Debug)]
pub struct Scene {
    /// Everything the file says (defaults filled in).
    pub file: SceneFile,
    /// The file name used in messages (`<default scene>` for the embedded one).
    pub source: String,
    /// Folder that relative paths in the scene are resolved against.
    pub base_dir: PathBuf,
}

impl Scene {
    /// The embedded default scene.
    pub fn default_scene() -> Result<Scene, SceneError> {
        Scene::parse(DEFAULT_SCENE_TOML, "<default scene>", Path::new("."))
    }

    /// Reads, parses and validates a scene file.
    pub fn load(path: &Path) -> Result<Scene, SceneError> {
        let scene = Scene::read_unvalidated(path)?;
        scene.validate()?;
        Ok(scene)
    }

    /// Reads and parses a scene file without [`Scene::validate`]: for tools
    /// that override some values first (the CLI's `--precision`,
    /// `--memory-limit-gib`, ...) and then validate. [`Scene::build`]
    /// validates again.
    pub fn read_unvalidated(path: &Path) -> Result<Scene, SceneError> {
        let source = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|e| SceneError::Io {
            file: source.clone(),
            reason: e.to_string(),
        })?;
        let base = path.parent().map(Path::to_path_buf).unwrap_or_default();
        Scene::parse_unvalidated(
            &text,
            &source,
            if base.as_os_str().is_empty() {
                Path::new(".")
            } else {
                &base
            },
        )
    }

    /// Parses and validates scene text; `source` names it in messages,
    /// `base_dir` is the folder its files are read from (and must stay in).
    pub fn parse(text: &str, source: &str, base_dir: &Path) -> Result<Scene, SceneError> {
        let scene = Scene::parse_unvalidated(text, source, base_dir)?;
        scene.validate()?;
        Ok(scene)
    }

    /// Parses scene text (TOML syntax, types, unknown keys) without
    /// [`Scene::validate`]; see [`Scene::read_unvalidated`].
    pub fn parse_unvalidated(
        text: &str,
        source: &str,
        base_dir: &Path,
    ) -> Result<Scene, SceneError> {
        let file: SceneFile =
            toml::from_str(text).map_err(|e| SceneError::from_toml(source, text, &e))?;
        Ok(Scene {
            file,
            source: source.to_string(),
            base_dir: base_dir.to_path_buf(),
        })
    }
}
