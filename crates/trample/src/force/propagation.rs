//! (filled in by the forces/deformation helper)
