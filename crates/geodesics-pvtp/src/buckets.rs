//! The vertex buckets of PVTP (Section 4.2 of Du et al. 2021, after FWP).
//!
//! Bucket `i` holds the vertices whose distance lies in `[i·w, (i+1)·w)`,
//! `w = h/τ` (`h` the mean edge length, `τ` the rounded mean anisotropy).
//! Pushing beyond the current bucket is O(1); entries are `(distance bits,
//! vertex)` with lazy deletion (an entry is stale when the vertex's distance
//! changed since). Unlike the authors' unordered bins, the current bucket is
//! a binary heap, and an entry pushed below it joins it: pops therefore come
//! out in exact `(distance, vertex)` order, which keeps the wavefront as
//! tight as VTP's (fewer redundant windows) and makes the order independent
//! of how entries were pushed. The heap holds one bucket, not the whole
//! wavefront, so its operations stay cheap.
use std::cmp::Reverse;
use std::collections::BinaryHeap;

/// A bucket queue of vertices keyed by distance.
pub(crate) struct Buckets {
    inv_width: f64,
    /// Largest bucket index (farther entries share it).
    cap: usize,
    /// Buckets beyond the current one, unordered.
    bins: Vec<Vec<(u64, u32)>>,
    /// Index of the current bucket; its entries (and any pushed below it)
    /// live in `heap`.
    cur: usize,
    heap: BinaryHeap<Reverse<(u64, u32)>>,
}

impl Buckets {
    /// Buckets of width `width` (a non-positive or non-finite width falls
    /// back to one bucket per unit), at most `cap + 1` of them.
    pub(crate) fn new(width: f64, cap: usize) -> Buckets {
        let inv_width = if width.is_finite() && width > 0.0 {
            1.0 / width
        } else {
            1.0
        };
        Buckets {
            inv_width,
            cap,
            bins: Vec::new(),
            cur: 0,
            heap: BinaryHeap::new(),
        }
    }

    /// Queues vertex `v` at distance `d` (non-negative).
    #[inline]
    pub(crate) fn push(&mut self, d: f64, v: u32) {
        let x = d * self.inv_width;
        // `as` saturates (and sends NaN to 0); clamp to the last bucket.
        let b = (x as usize).min(self.cap);
        let key = (d.to_bits(), v);
        if b <= self.cur {
            self.heap.push(Reverse(key));
        } else {
            if b >= self.bins.len() {
                self.bins.resize_with(b + 1, Vec::new);
            }
            self.bins[b].push(key);
        }
    }

    /// The smallest live entry `(distance, vertex)`, dropping stale entries
    /// (whose distance bits differ from `current(vertex)`) on the way.
    pub(crate) fn peek(&mut self, current: impl Fn(u32) -> u64) -> Option<(f64, u32)> {
        loop {
            while self.heap.is_empty() {
                // Move on to the next non-empty bucket.
                let next = (self.cur + 1..self.bins.len()).find(|&b| !self.bins[b].is_empty())?;
                self.cur = next;
                let bin = std::mem::take(&mut self.bins[next]);
                self.heap.extend(bin.into_iter().map(Reverse));
            }
            let &Reverse((bits, v)) = self.heap.peek()?;
            if current(v) == bits {
                return Some((f64::from_bits(bits), v));
            }
            self.heap.pop();
        }
    }

    /// Up to `n` vertices of the current bucket that come out soon (the
    /// heap's first entries: the next one is among them), for prefetching;
    /// may include stale entries.
    #[inline]
    pub(crate) fn upcoming(&self, n: usize) -> impl Iterator<Item = u32> + '_ {
        self.heap
            .as_slice()
            .iter()
            .take(n)
            .map(|&Reverse((_, v))| v)
    }

    /// Removes the entry [`Buckets::peek`] returned.
    pub(crate) fn pop(&mut self) {
        self.heap.pop();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pops_in_distance_then_vertex_order_and_skips_stale() {
        let mut dist = [3.0, 0.5, 0.5, 10.0, 2.0];
        let mut b = Buckets::new(1.0, 100);
        for (v, &d) in dist.iter().enumerate() {
            b.push(d, v as u32);
        }
        // Vertex 4 improves: its old entry goes stale.
        dist[4] = 0.7;
        b.push(0.7, 4);
        let mut order = Vec::new();
        while let Some((d, v)) = b.peek(|v| dist[v as usize].to_bits()) {
            b.pop();
            order.push((d, v));
            // A vertex lowered below the current bucket still comes out.
            if v == 4 {
                dist[0] = 0.1;
                b.push(0.1, 0);
            }
        }
        assert_eq!(
            order,
            vec![(0.5, 1), (0.5, 2), (0.7, 4), (0.1, 0), (10.0, 3)]
        );
    }

    #[test]
    fn upcoming_starts_with_the_next_vertex_of_the_current_bucket() {
        let dist = [0.3, 0.1, 0.7, 0.2, 5.0];
        let mut b = Buckets::new(1.0, 100);
        for (v, &d) in dist.iter().enumerate() {
            b.push(d, v as u32);
        }
        let current = |v: u32| dist[v as usize].to_bits();
        for next in [1, 3, 0, 2] {
            assert_eq!(b.peek(current), Some((dist[next as usize], next)));
            let soon: Vec<u32> = b.upcoming(3).collect();
            assert_eq!(soon[0], next, "{soon:?}");
            assert!(soon.len() <= 3);
            b.pop();
        }
        // The current bucket is empty: nothing to announce until the next
        // one is moved in by `peek`.
        assert_eq!(b.upcoming(3).count(), 0);
        assert_eq!(b.peek(current), Some((5.0, 4)));
        assert_eq!(b.upcoming(3).collect::<Vec<_>>(), vec![4]);
    }

    #[test]
    fn far_entries_share_the_last_bucket() {
        let dist = [1e300, 5.0, f64::MAX];
        let mut b = Buckets::new(1.0, 4);
        for (v, &d) in dist.iter().enumerate() {
            b.push(d, v as u32);
        }
        let mut order = Vec::new();
        while let Some((_, v)) = b.peek(|v| dist[v as usize].to_bits()) {
            b.pop();
            order.push(v);
        }
        assert_eq!(order, vec![1, 0, 2]);
        assert!(b.bins.len() <= 5);
    }
}
