//! What happened to each blade over a whole run (DBG, PBG or untouched):
//! the `--dump-classes` values and the renderer's debug colours.

/// What happened to a blade over the whole run (the `--dump-classes` values,
/// stored one byte per blade: `repr(u8)` with the values below, which are
/// also what the GPU path keeps per blade).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[repr(u8)]
pub enum BladeClass {
    /// Never touched.
    #[default]
    Untouched = 0,
    /// Hit directly by an object (DBG, paper Definition 1) in some frame.
    Direct = 1,
    /// Reached only by propagation (PBG, paper Definition 2).
    Propagated = 2,
}

impl BladeClass {
    /// The class stored as `value` (0, 1, 2); larger values (which the GPU
    /// path never writes) count as [`BladeClass::Propagated`].
    #[must_use]
    pub fn from_u32(value: u32) -> Self {
        match value {
            0 => BladeClass::Untouched,
            1 => BladeClass::Direct,
            _ => BladeClass::Propagated,
        }
    }

    /// The class's value as stored and dumped (0, 1, 2).
    #[must_use]
    pub fn as_u8(self) -> u8 {
        self as u8
    }
}

impl From<BladeClass> for u8 {
    fn from(c: BladeClass) -> u8 {
        c as u8
    }
}

impl From<BladeClass> for u32 {
    fn from(c: BladeClass) -> u32 {
        u32::from(c as u8)
    }
}

#[cfg(test)]
mod tests {
    use super::BladeClass;

    #[test]
    fn values_round_trip() {
        for c in [
            BladeClass::Untouched,
            BladeClass::Direct,
            BladeClass::Propagated,
        ] {
            assert_eq!(BladeClass::from_u32(u32::from(c.as_u8())), c);
        }
        assert_eq!(BladeClass::from_u32(7), BladeClass::Propagated);
    }
}
