//! Camera path (lead).
