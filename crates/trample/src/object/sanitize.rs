//! (filled in by the object helper)
