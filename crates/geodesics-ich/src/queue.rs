//! The two schedules: ICH's priority queue and FWP's distance buckets.
//!
//! Items (windows and pseudo-source vertices) are stored inline, so popping
//! one reads memory the queue was already touching; each is pushed with its
//! key, the smallest distance it can give to anything.

use std::cmp::Reverse;
use std::collections::{BinaryHeap, VecDeque};

/// At most this many buckets ahead of the current one; farther keys wait in
/// an overflow list, bucketed when the buckets run dry.
const MAX_BUCKETS: u64 = 1 << 16;

pub(crate) enum Queue<T> {
    /// Xin and Wang: a binary heap on the key.
    Heap(Heap<T>),
    /// Xu et al. 2015: buckets of a fixed width, FIFO inside a bucket.
    Buckets(Buckets<T>),
}

/// A binary heap of small `(key bits, slot)` entries (ties popped by slot,
/// so the order is deterministic) over a slab holding the items: sifting
/// moves 16 bytes per level, not the item.
pub(crate) struct Heap<T> {
    heap: BinaryHeap<Reverse<(u64, u32)>>,
    slab: Vec<T>,
    free: Vec<u32>,
}

pub(crate) struct Buckets<T> {
    width: f64,
    /// Bucket number of `buckets[0]`.
    base: u64,
    buckets: VecDeque<Vec<(f64, T)>>,
    /// Next item to pop in `buckets[0]`.
    cursor: usize,
    /// Emptied buckets kept for reuse (no allocation per bucket).
    spare: Vec<Vec<(f64, T)>>,
    /// Items more than `MAX_BUCKETS` buckets ahead.
    overflow: Vec<(f64, T)>,
}

impl<T: Copy> Queue<T> {
    pub(crate) fn heap() -> Queue<T> {
        Queue::Heap(Heap {
            heap: BinaryHeap::new(),
            slab: Vec::new(),
            free: Vec::new(),
        })
    }

    /// Buckets of `width` (a positive, finite length).
    pub(crate) fn buckets(width: f64) -> Queue<T> {
        Queue::Buckets(Buckets {
            width,
            base: 0,
            buckets: VecDeque::new(),
            cursor: 0,
            spare: Vec::new(),
            overflow: Vec::new(),
        })
    }

    /// Whether items come out in non-decreasing key order.
    pub(crate) fn is_sorted(&self) -> bool {
        matches!(self, Queue::Heap(_))
    }

    /// `key` must be a non-negative number (or +inf).
    #[inline]
    pub(crate) fn push(&mut self, key: f64, item: T) {
        // `+ 0.0` turns a -0.0 into +0.0, whose bits order like the value.
        let key = key + 0.0;
        match self {
            Queue::Heap(h) => {
                let slot = match h.free.pop() {
                    Some(s) => {
                        h.slab[s as usize] = item;
                        s
                    }
                    None => {
                        h.slab.push(item);
                        (h.slab.len() - 1) as u32
                    }
                };
                h.heap.push(Reverse((key.to_bits(), slot)));
            }
            Queue::Buckets(b) => b.push(key, item),
        }
    }

    #[inline]
    pub(crate) fn pop(&mut self) -> Option<(f64, T)> {
        match self {
            Queue::Heap(h) => {
                let Reverse((key, slot)) = h.heap.pop()?;
                h.free.push(slot);
                Some((f64::from_bits(key), h.slab[slot as usize]))
            }
            Queue::Buckets(b) => b.pop(),
        }
    }
}

impl<T: Copy> Buckets<T> {
    #[inline]
    fn push(&mut self, key: f64, item: T) {
        // Saturating float-to-int cast: NaN -> 0, +inf -> u64::MAX.
        let n = (key / self.width) as u64;
        // A key below the current bucket (rounding) joins the current one.
        let offset = n.saturating_sub(self.base);
        if offset >= MAX_BUCKETS {
            self.overflow.push((key, item));
            return;
        }
        let offset = offset as usize;
        while self.buckets.len() <= offset {
            let b = self.spare.pop().unwrap_or_default();
            self.buckets.push_back(b);
        }
        self.buckets[offset].push((key, item));
    }

    #[inline]
    fn pop(&mut self) -> Option<(f64, T)> {
        loop {
            if self.buckets.is_empty() {
                self.refill()?;
            }
            let front = self.buckets.front()?;
            if let Some(&x) = front.get(self.cursor) {
                self.cursor += 1;
                return Some(x);
            }
            if let Some(mut b) = self.buckets.pop_front() {
                b.clear();
                self.spare.push(b);
            }
            self.base = self.base.saturating_add(1);
            self.cursor = 0;
        }
    }

    /// Moves the overflow into buckets starting at its smallest key.
    fn refill(&mut self) -> Option<()> {
        let min = self.overflow.iter().map(|x| x.0).reduce(f64::min)?;
        self.base = (min / self.width) as u64;
        self.cursor = 0;
        for (key, item) in std::mem::take(&mut self.overflow) {
            self.push(key, item);
        }
        Some(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_heap_pops_in_key_order() {
        let mut q = Queue::<u64>::heap();
        for (k, i) in [(2.0, 1), (0.5, 7), (2.0, 0), (-0.0, 3), (1.0, 2)] {
            q.push(k, i);
        }
        let order: Vec<u64> = std::iter::from_fn(|| q.pop().map(|x| x.1)).collect();
        assert_eq!(order, vec![3, 7, 2, 1, 0]);
        q.push(1.0, 5);
        q.push(0.0, 6);
        assert_eq!(q.pop(), Some((0.0, 6)));
        assert_eq!(q.pop(), Some((1.0, 5)));
    }

    #[test]
    fn buckets_pop_bucket_by_bucket_fifo_inside() {
        let mut q = Queue::<u64>::buckets(1.0);
        for (k, i) in [(2.5, 1), (0.5, 7), (2.0, 0), (0.1, 3), (1.0, 2)] {
            q.push(k, i);
        }
        assert_eq!(q.pop(), Some((0.5, 7)));
        // Pushed below the current bucket: joins it, at the back.
        q.push(0.0, 9);
        q.push(f64::INFINITY, 10);
        let order: Vec<u64> = std::iter::from_fn(|| q.pop().map(|x| x.1)).collect();
        assert_eq!(order, vec![3, 9, 2, 1, 0, 10]);
        assert_eq!(q.pop(), None);
        // Pushing after draining restarts from the current bucket.
        q.push(0.0, 4);
        assert_eq!(q.pop(), Some((0.0, 4)));
    }
}
