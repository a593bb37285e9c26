//! Forces on geometric blades (paper §5): EqF for blades hit directly (DBG,
//! Eq. 2) and propagation to neighbouring blades (PBG, Eq. 4).

pub mod eqf;
pub mod propagation;
