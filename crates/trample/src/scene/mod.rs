//! Scene files (lead).
