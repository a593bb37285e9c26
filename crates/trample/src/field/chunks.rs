//! Chunks of patches: a field's blade vertices cut into runs of whole
//! patches, each run's vertices (16 bytes each, the core's layout over the
//! run's blades: vertex k of its blade l at `k * blades + l`) within one
//! storage binding of a device. The GPU path steps a large field chunk by
//! chunk (trample-gpu's `chunk` module); a renderer on the CPU path
//! uploads and draws it chunk by chunk ([`drawn_ranges`] splits its list
//! of drawn cells between them). A field within one binding is one chunk.

use std::ops::Range;

/// Bytes of one blade vertex on a device: `vec4<f32>` (the core's
/// [`super::BladeVertex`], `[x, y, z, 0]`).
pub const VERTEX_BYTES: u64 = 16;

/// Why a field cannot be cut into chunks.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum ChunkError {
    /// The blade count is not a whole number of units (patches).
    #[error("{count} blades are not whole chunk units of {unit} blades")]
    Layout {
        /// Blades of the field.
        count: u32,
        /// Blades of one unit (0 is refused too).
        unit: u32,
    },
    /// One unit alone is over the binding.
    #[error(
        "the blade positions of one patch (the smallest chunk) take {bytes} bytes, \
         over the {limit} bytes of one binding"
    )]
    UnitTooLarge {
        /// Bytes of one unit's vertices.
        bytes: u64,
        /// The binding's bytes.
        limit: u64,
    },
}

/// The blade ranges of the chunks of a field of `count` blades of `verts`
/// vertices, cut at multiples of `unit` blades (a patch; `count` is a
/// multiple of it), each chunk's vertices ([`VERTEX_BYTES`] each) within
/// `max_bytes`. As few chunks as fit, all but the last of equal size.
///
/// # Errors
/// [`ChunkError::UnitTooLarge`] when one unit alone is over `max_bytes`;
/// [`ChunkError::Layout`] when `unit` is 0 or does not divide `count`.
pub fn plan_chunks(
    count: u32,
    verts: u32,
    unit: u32,
    max_bytes: u64,
) -> Result<Vec<Range<u32>>, ChunkError> {
    if unit == 0 || !count.is_multiple_of(unit) {
        return Err(ChunkError::Layout { count, unit });
    }
    let unit_bytes = u64::from(unit) * u64::from(verts) * VERTEX_BYTES;
    if unit_bytes > max_bytes {
        return Err(ChunkError::UnitTooLarge {
            bytes: unit_bytes,
            limit: max_bytes,
        });
    }
    let units_per_chunk = (max_bytes / unit_bytes).min(u64::from(u32::MAX)) as u32;
    let per_chunk = units_per_chunk.saturating_mul(unit);
    let mut out = Vec::new();
    let mut start = 0u32;
    while start < count {
        let end = start.saturating_add(per_chunk).min(count);
        out.push(start..end);
        start = end;
    }
    Ok(out)
}

/// For a list of drawn cells in ascending order (as
/// [`super::drawn_blade_cells`] gives them) and the chunks' blade ranges
/// (whole cells of `blades_per_cell` blades, ascending, as
/// [`plan_chunks`] gives them): the range of `cells` that lies in each
/// chunk, one a chunk. A cell past the last chunk is in none.
#[must_use]
pub fn drawn_ranges(
    cells: &[u32],
    chunks: &[Range<u32>],
    blades_per_cell: u32,
) -> Vec<Range<usize>> {
    let per_cell = u64::from(blades_per_cell.max(1));
    split_at_chunks(cells, |&c| u64::from(c) * per_cell, chunks)
}

/// For a list of drawn things ascending by their first blade (`blade`
/// gives it: a cell's, or a blade's own index) and the chunks' blade
/// ranges (ascending): the range of `list` that lies in each chunk, one a
/// chunk. A thing past the last chunk is in none.
#[must_use]
pub fn split_at_chunks<T>(
    list: &[T],
    blade: impl Fn(&T) -> u64,
    chunks: &[Range<u32>],
) -> Vec<Range<usize>> {
    let mut at = 0usize;
    chunks
        .iter()
        .map(|chunk| {
            let start = at + list[at..].partition_point(|t| blade(t) < u64::from(chunk.start));
            let end = start + list[start..].partition_point(|t| blade(t) < u64::from(chunk.end));
            at = end;
            start..end
        })
        .collect()
}

/// The pieces of a list of `count` items of `item_bytes` each (a
/// renderer's billboards, 48 bytes) that each fit a binding of `limit`
/// bytes: as few as fit, all but the last full; none for an empty list; one
/// item a piece when one item is over the binding.
#[must_use]
pub fn list_pieces(count: usize, item_bytes: u64, limit: u64) -> Vec<Range<usize>> {
    let per = (limit / item_bytes.max(1)).clamp(1, usize::MAX as u64) as usize;
    (0..count.div_ceil(per))
        .map(|k| k * per..((k + 1) * per).min(count))
        .collect()
}

#[cfg(test)]
// One chunk is a list of one blade range here, not a range to collect.
#[allow(clippy::single_range_in_vec_init)]
mod tests {
    use super::*;

    #[test]
    fn chunks_cover_the_field_in_whole_units_within_the_limit() {
        // 10 patches of 64 blades, 5 vertices: 5,120 bytes a patch.
        let plan = plan_chunks(640, 5, 64, 3 * 5_120 + 100).unwrap();
        assert_eq!(plan, vec![0..192, 192..384, 384..576, 576..640]);
        let one = plan_chunks(640, 5, 64, u64::MAX).unwrap();
        assert_eq!(one, vec![0..640]);
        // Exactly one unit a chunk at exactly its bytes.
        assert_eq!(
            plan_chunks(128, 5, 64, 5_120).unwrap(),
            vec![0..64, 64..128]
        );
    }

    #[test]
    fn a_patch_over_the_limit_or_a_broken_layout_is_refused_by_name() {
        let e = plan_chunks(640, 5, 64, 5_000).unwrap_err();
        assert_eq!(
            e,
            ChunkError::UnitTooLarge {
                bytes: 5_120,
                limit: 5_000
            }
        );
        assert!(e.to_string().contains("one patch"), "{e}");
        assert!(matches!(
            plan_chunks(640, 5, 0, 1 << 20),
            Err(ChunkError::Layout { unit: 0, .. })
        ));
        assert!(plan_chunks(650, 5, 64, 1 << 20).is_err());
    }

    #[test]
    fn lists_are_cut_into_pieces_of_one_binding() {
        // 48 bytes an item: a binding of 480 bytes holds 10.
        assert_eq!(list_pieces(25, 48, 480), [0..10, 10..20, 20..25]);
        assert_eq!(list_pieces(20, 48, 480), [0..10, 10..20]);
        assert_eq!(list_pieces(3, 48, 1 << 27).len(), 1);
        assert!(list_pieces(0, 48, 480).is_empty());
        // A binding under one item still takes them, one a piece.
        assert_eq!(list_pieces(2, 48, 10), [0..1, 1..2]);
    }

    #[test]
    fn drawn_cells_are_split_at_the_chunks_borders() {
        // Chunks of 8 and 8 and 4 blades, 2 blades a cell: cells 0..4, 4..8, 8..10.
        let chunks = [0..8, 8..16, 16..20];
        let cells = [0, 3, 4, 5, 7, 9];
        let r = drawn_ranges(&cells, &chunks, 2);
        assert_eq!(r, vec![0..2, 2..5, 5..6]);
        // Every listed cell's blades lie inside its chunk.
        for (chunk, range) in chunks.iter().zip(&r) {
            for &c in &cells[range.clone()] {
                assert!(chunk.contains(&(c * 2)) && chunk.contains(&(c * 2 + 1)));
            }
        }
        // Empty chunks, an empty list, a cell past the end.
        assert_eq!(drawn_ranges(&[4, 5], &chunks, 2), vec![0..0, 0..2, 2..2]);
        assert_eq!(drawn_ranges(&[], &chunks, 2), vec![0..0; 3]);
        assert_eq!(drawn_ranges(&[1, 50], &chunks, 2), vec![0..1, 1..1, 1..1]);
        // One chunk takes the whole list.
        assert_eq!(drawn_ranges(&cells, &[0..20], 2), vec![0..6]);
        // A list of blades (a renderer's instances).
        let blades = [(1u32, 'a'), (7, 'b'), (8, 'c'), (19, 'd')];
        let r = split_at_chunks(&blades, |b| u64::from(b.0), &chunks);
        assert_eq!(r, vec![0..2, 2..3, 3..4]);
    }
}
