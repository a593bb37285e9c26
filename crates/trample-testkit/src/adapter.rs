//! `TRAMPLE_TEST_ADAPTER`: comma-separated words the GPU adapter's name
//! must contain (e.g. `llvmpipe,Vulkan`). CI sets it so that a GPU test run
//! meant for one driver cannot pass on another; unset, any adapter does.

/// The environment variable read by [`check_adapter_name`].
pub const TRAMPLE_TEST_ADAPTER: &str = "TRAMPLE_TEST_ADAPTER";

/// Checks `name` (an adapter's name as `"name (backend, device type)"`,
/// e.g. `llvmpipe (LLVM 15.0.6, 256 bits) (Vulkan, Cpu)`) against
/// [`TRAMPLE_TEST_ADAPTER`].
///
/// # Panics
/// When a word the variable lists is not in `name`: the test runs on
/// another adapter than the one asked for.
pub fn check_adapter_name(name: &str) {
    if let Ok(wanted) = std::env::var(TRAMPLE_TEST_ADAPTER)
        && let Some(word) = missing_word(name, &wanted)
    {
        panic!(
            "adapter {name} is not the one {TRAMPLE_TEST_ADAPTER}={wanted} asks for (no {word:?} in its name)"
        );
    }
}

/// The first word of `wanted` (comma-separated, blanks trimmed, empty words
/// skipped) that `name` does not contain.
fn missing_word<'a>(name: &str, wanted: &'a str) -> Option<&'a str> {
    wanted
        .split(',')
        .map(str::trim)
        .filter(|w| !w.is_empty())
        .find(|w| !name.contains(w))
}

#[cfg(test)]
mod tests {
    use super::missing_word;

    #[test]
    fn every_listed_word_must_be_in_the_name() {
        let name = "llvmpipe (LLVM 15.0.6, 256 bits) (Vulkan, Cpu)";
        assert_eq!(missing_word(name, "llvmpipe,Vulkan"), None);
        assert_eq!(missing_word(name, " llvmpipe , , Vulkan "), None);
        assert_eq!(missing_word(name, ""), None);
        assert_eq!(missing_word(name, "llvmpipe,Gl"), Some("Gl"));
        assert_eq!(missing_word(name, "NVIDIA"), Some("NVIDIA"));
    }
}
