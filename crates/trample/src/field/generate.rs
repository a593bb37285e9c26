//! Field generation (lead).
