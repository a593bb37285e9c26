//! .npy writer (lead).
