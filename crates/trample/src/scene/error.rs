//! Scene errors: one line naming the file, the key (or line) and what is allowed.

/// Why a scene could not be used.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SceneError {
    /// The file could not be read.
    #[error("{file}: cannot read scene: {reason}")]
    Io {
        /// The scene file.
        file: String,
        /// OS reason.
        reason: String,
    },
    /// Not valid TOML, a wrong type, or an unknown key.
    #[error("{file}:{line}:{column}: {message}{table}")]
    Syntax {
        /// The scene file.
        file: String,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// What the parser said.
        message: String,
        /// ` (in [table])` when known.
        table: String,
    },
    /// A value is out of range or inconsistent.
    #[error("{file}: {message}")]
    Invalid {
        /// The scene file.
        file: String,
        /// Key, value and what is allowed.
        message: String,
    },
}

impl SceneError {
    /// Turns a TOML error into a one-line message with line, column and table.
    #[must_use]
    pub fn from_toml(file: &str, text: &str, e: &toml::de::Error) -> Self {
        let offset = e.span().map_or(0, |s| s.start).min(text.len());
        let before = &text[..offset];
        let line = before.matches('\n').count() + 1;
        let column = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
        // The table the error is in: the last `[header]` above the error's
        // line, or on it when the error is at its first column (a missing
        // key is reported at the start of its table's header; an error
        // inside a header, such as an unknown table, is not "in" it).
        let line_start = before.rfind('\n').map_or(0, |i| i + 1);
        let search_end = if offset == line_start {
            text[offset..].find('\n').map_or(text.len(), |i| offset + i)
        } else {
            line_start
        };
        let table = text[..search_end]
            .lines()
            .rev()
            .map(str::trim)
            .find(|l| l.starts_with('['))
            .map(|h| format!(" (in {h})"))
            .unwrap_or_default();
        let message = e.message().replace('\n', " ").trim().to_string();
        SceneError::Syntax {
            file: file.to_string(),
            line,
            column,
            message,
            table,
        }
    }

    /// A value error in `file`.
    #[must_use]
    pub fn invalid(file: &str, message: impl std::fmt::Display) -> Self {
        SceneError::Invalid {
            file: file.to_string(),
            message: message.to_string(),
        }
    }
}
