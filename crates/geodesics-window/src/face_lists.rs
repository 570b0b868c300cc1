//! Where the sequential solvers (VTP's, and each region's in PVTP's region
//! schedule) keep, per face, the window lists waiting on its half-edges.
//!
//! A face's record is four words: the *list word* of each half-edge
//! `3f + i`, then the pop at which the face joined the traversed area
//! ([`ENTERED`]). They sit together because they are read together:
//! entering a face looks at all four, crossing one reads its list word and
//! the entry pop. A list word is the index of the half-edge's list in the
//! solver's pool ([`NO_LIST`] for none) with bit 31 ([`QUEUED`]) set while
//! the half-edge waits in the solver's FIFO, so queueing touches one word.
//!
//! ```
//! use geodesics_window::face_lists::{FaceLists, NEW_FACE, NO_LIST, list_word, queue_list};
//!
//! let mut faces: Vec<FaceLists> = vec![NEW_FACE; 2];
//! let mut fifo = Vec::new();
//! queue_list(list_word(&mut faces, 4), 4, &mut fifo); // no list yet: not queued
//! assert!(fifo.is_empty());
//! *list_word(&mut faces, 4) = 7; // half-edge 4 (face 1, edge 1) has list 7
//! queue_list(list_word(&mut faces, 4), 4, &mut fifo);
//! queue_list(list_word(&mut faces, 4), 4, &mut fifo); // already waiting
//! assert_eq!(fifo, [4]);
//! assert_eq!(faces[1][1] & !geodesics_window::face_lists::QUEUED, 7);
//! assert_eq!(faces[0], NEW_FACE);
//! # let _ = NO_LIST;
//! ```

/// Bit 31 of a list word: the half-edge waits in the FIFO.
pub const QUEUED: u32 = 1 << 31;

/// The list index of a half-edge with no list.
pub const NO_LIST: u32 = QUEUED - 1;

/// A face's three list words and its entry pop.
pub type FaceLists = [u32; 4];

/// Where the entry pop sits in a [`FaceLists`].
pub const ENTERED: usize = 3;

/// The entry pop of a face not entered yet.
pub const NOT_ENTERED: u32 = u32::MAX;

/// A face with no lists, not entered.
pub const NEW_FACE: FaceLists = [NO_LIST, NO_LIST, NO_LIST, NOT_ENTERED];

/// Where the list word of half-edge `h` sits in the flattened face
/// records: word `h % 3` of face `h / 3`, so `4·(h / 3) + h % 3`.
#[inline]
pub fn list_word_index(h: u32) -> usize {
    (h + h / 3) as usize
}

/// The list word of half-edge `h` in the face records (a free function,
/// so a caller may hold it while it pushes to its FIFO).
#[inline]
pub fn list_word(faces: &mut [FaceLists], h: u32) -> &mut u32 {
    &mut faces.as_flattened_mut()[list_word_index(h)]
}

/// Queues half-edge `h`, whose list word is `word`, unless it has no list
/// or waits in `fifo` already.
#[inline(always)]
pub fn queue_list(word: &mut u32, h: u32, fifo: &mut Vec<u32>) {
    if *word & QUEUED == 0 && *word != NO_LIST {
        *word |= QUEUED;
        fifo.push(h);
    }
}
