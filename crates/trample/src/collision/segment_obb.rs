//! (filled in by the OBB/collision helper)
