//! Deformation (paper §6): blade bending with length preservation (Eq. 5–7,
//! Fig. 7), billboard slopes (Eq. 8) and transitions between the levels of
//! detail (Eq. 9–13).

pub mod bend;
pub mod billboard;
pub mod transition;
