//! What a step wrote: the blades whose vertices and the cells whose state
//! (level of detail, billboard slope) a step set, so that a host (or a
//! renderer) uploads only those (issue 14, item 2).
//!
//! The writes record themselves: [`super::Blades::store`] marks its blade,
//! [`super::Cells::set_slope`] and the level-of-detail classification mark
//! their cell. A step clears the sets when it begins and sorts them when it
//! ends; between steps they read in ascending order, each index once.

use std::ops::Range;

/// Indices (of blades or of cells) written since the set was last cleared:
/// one bit per index, and the list of the 64-index words that have a bit
/// set. Costs about 0.19 bytes an index however many are written (the
/// list holds at most one entry per 64 indices), and clearing or sorting it
/// costs what was written, not the length.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct ChangeSet {
    /// Bit i: index i was written.
    bits: Vec<u64>,
    /// Words of `bits` that are not zero, in the order first written until
    /// [`ChangeSet::sort`], ascending after it.
    words: Vec<u32>,
}

impl ChangeSet {
    /// An empty set over indices `0..len`.
    #[must_use]
    pub fn new(len: usize) -> Self {
        Self {
            bits: vec![0; len.div_ceil(64)],
            words: Vec::new(),
        }
    }

    /// Records index `i` as written (once, however often it is written).
    /// Indices past the length given to [`ChangeSet::new`] grow the set.
    pub fn mark(&mut self, i: usize) {
        self.mark_word(i / 64, 1u64 << (i % 64));
    }

    /// Records every index of `indices` as [`ChangeSet::mark`] does, a
    /// word at a time while they fall in one 64-index word (ascending runs,
    /// as the level-of-detail classification lists its changes): the same
    /// set, for any order.
    pub fn mark_all(&mut self, indices: impl IntoIterator<Item = usize>) {
        let mut word = usize::MAX;
        let mut bits = 0u64;
        for i in indices {
            if i / 64 != word {
                self.mark_word(word, bits);
                word = i / 64;
                bits = 0;
            }
            bits |= 1u64 << (i % 64);
        }
        self.mark_word(word, bits);
    }

    /// Sets `bits` in word `word` (none when `bits` is 0).
    fn mark_word(&mut self, word: usize, bits: u64) {
        if bits == 0 {
            return;
        }
        if word >= self.bits.len() {
            self.bits.resize(word + 1, 0);
        }
        if self.bits[word] == 0 {
            self.words.push(word as u32);
        }
        self.bits[word] |= bits;
    }

    /// Forgets every index (costs what was written, not the length).
    pub fn clear(&mut self) {
        for &w in &self.words {
            self.bits[w as usize] = 0;
        }
        self.words.clear();
    }

    /// Puts the set in ascending order for [`ChangeSet::iter`] (a step does
    /// it when it ends).
    pub fn sort(&mut self) {
        self.words.sort_unstable();
    }

    /// The indices written, ascending after [`ChangeSet::sort`] (which
    /// every step does at its end), each once.
    pub fn iter(&self) -> impl Iterator<Item = u32> + '_ {
        self.words.iter().flat_map(move |&w| {
            let mut rest = self.bits[w as usize];
            std::iter::from_fn(move || {
                (rest != 0).then(|| {
                    let bit = rest.trailing_zeros();
                    rest &= rest - 1;
                    w * 64 + bit
                })
            })
        })
    }

    /// How many indices were written.
    #[must_use]
    pub fn len(&self) -> usize {
        self.words
            .iter()
            .map(|&w| self.bits[w as usize].count_ones() as usize)
            .sum()
    }

    /// True when nothing was written.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.words.is_empty()
    }

    /// Whether index `i` was written.
    #[must_use]
    pub fn contains(&self, i: usize) -> bool {
        self.bits
            .get(i / 64)
            .is_some_and(|w| w & (1u64 << (i % 64)) != 0)
    }

    /// The indices as runs of consecutive indices, in order (for uploads
    /// of contiguous spans); the set must be sorted.
    pub fn ranges(&self) -> impl Iterator<Item = Range<u32>> + '_ {
        let mut all = self.iter().peekable();
        std::iter::from_fn(move || {
            let start = all.next()?;
            let mut end = start + 1;
            while all.next_if_eq(&end).is_some() {
                end += 1;
            }
            Some(start..end)
        })
    }
}

#[cfg(test)]
mod tests {
    use super::ChangeSet;

    #[test]
    fn marks_once_sorts_clears_and_groups_ranges() {
        let mut s = ChangeSet::new(1000);
        for i in [700, 2, 3, 700, 9, 2, 4, 63, 64, 130] {
            s.mark(i);
        }
        s.sort();
        assert_eq!(
            s.iter().collect::<Vec<_>>(),
            vec![2, 3, 4, 9, 63, 64, 130, 700]
        );
        assert_eq!(s.len(), 8);
        assert!(s.contains(3) && !s.contains(5));
        assert_eq!(
            s.ranges().collect::<Vec<_>>(),
            vec![2..5, 9..10, 63..65, 130..131, 700..701]
        );
        s.clear();
        assert!(s.is_empty() && s.iter().next().is_none());
        assert!(!s.contains(3));
        s.mark(1130);
        assert_eq!(s.iter().collect::<Vec<_>>(), vec![1130]);
        assert!(s.contains(1130) && !s.contains(66));
    }

    /// Marking a list at once gives the set, and the order of its words
    /// before sorting, that marking its indices one by one gives: ascending
    /// runs (as the level-of-detail changes come), words revisited out of
    /// order, index 0, and indices past the set's length (which grow it).
    #[test]
    fn marking_a_list_at_once_is_marking_it_index_by_index() {
        let mut lists: Vec<Vec<usize>> = vec![
            vec![],
            vec![0],
            (0..200).collect(),
            (60..70).chain(5..9).chain(66..130).collect(),
            vec![700, 2, 3, 700, 9, 2, 4, 63, 64, 130, 5000, 64, 0],
        ];
        // A deterministic scramble of indices (an LCG), some past the length.
        let mut x = 12345u64;
        lists.push(
            (0..500)
                .map(|_| {
                    x = x
                        .wrapping_mul(6364136223846793005)
                        .wrapping_add(1442695040888963407);
                    (x >> 33) as usize % 1500
                })
                .collect(),
        );
        for list in lists {
            let mut one = ChangeSet::new(1000);
            for &i in &list {
                one.mark(i);
            }
            let mut all = ChangeSet::new(1000);
            all.mark_all(list.iter().copied());
            assert_eq!(one, all, "{list:?}");
        }
    }
}
