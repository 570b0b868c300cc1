//! The vertex queue of the sequential solvers (VTP's, and each region's
//! in PVTP's region schedule): a 4-ary min-heap of `(distance bits, vertex)` that
//! holds each vertex at most once, lowering its key in place.
//!
//! Four children per node, not two: half as many levels to sift through
//! per pop, and a node's children sit side by side in memory (on
//! armadillo.obj 0.4 % fewer instructions per solve, on the 557K-vertex
//! subdivided bunny under AVTP 0.8 %; the same pops in the same order).
//!
//! A heap with lazy deletion pushes a new entry every time a distance goes
//! down and skips the stale ones when they surface: on armadillo.obj that
//! was 76K pushes and as many pops for 43K vertices. Here a vertex's entry
//! moves up instead, so the heap pops each queued vertex once. The pop
//! order is the same (the smallest key, ties by vertex number), so a solve
//! gives the same bits either way.

const ABSENT: u32 = u32::MAX;

/// Children per heap node (a pop sifts through `log4` levels).
pub const ARITY: usize = 4;

/// A min-queue of vertices keyed by `(distance bits, vertex)`, each vertex
/// at most once (see the module docs).
#[derive(Debug, Default)]
pub struct VertexQueue {
    heap: Vec<(u64, u32)>,
    /// Per vertex: its index in `heap`, `ABSENT` if not queued.
    at: Vec<u32>,
}

impl VertexQueue {
    /// An empty queue for vertices `0..vertices`.
    pub fn new(vertices: usize) -> VertexQueue {
        VertexQueue {
            heap: Vec::new(),
            at: vec![ABSENT; vertices],
        }
    }

    /// Queues `v` with `key`, or lowers its key to `key` if it is queued
    /// with a larger one.
    #[inline]
    pub fn push_or_lower(&mut self, key: u64, v: u32) {
        let i = match self.at[v as usize] {
            ABSENT => {
                self.heap.push((key, v));
                self.heap.len() - 1
            }
            i => {
                let i = i as usize;
                if (key, v) >= self.heap[i] {
                    return;
                }
                self.heap[i].0 = key;
                i
            }
        };
        self.sift_up(i);
    }

    /// Removes and returns the smallest entry.
    #[inline]
    pub fn pop(&mut self) -> Option<(u64, u32)> {
        let last = self.heap.pop()?;
        let top = if self.heap.is_empty() {
            last
        } else {
            let top = std::mem::replace(&mut self.heap[0], last);
            self.sift_down(0);
            top
        };
        self.at[top.1 as usize] = ABSENT;
        Some(top)
    }

    /// The smallest entry.
    #[inline]
    pub fn peek(&self) -> Option<(u64, u32)> {
        self.heap.first().copied()
    }

    /// The first entries in heap order (the smallest, then its children,
    /// one of which is popped next): the vertices popped soon, worth
    /// loading ahead of time.
    #[inline]
    pub fn upcoming(&self, n: usize) -> impl Iterator<Item = u32> + '_ {
        self.heap.iter().take(n).map(|&(_, v)| v)
    }

    /// Empties the queue.
    pub fn clear(&mut self) {
        for &(_, v) in &self.heap {
            self.at[v as usize] = ABSENT;
        }
        self.heap.clear();
    }

    #[inline]
    fn sift_up(&mut self, mut i: usize) {
        let item = self.heap[i];
        while i > 0 {
            let parent = (i - 1) / ARITY;
            let p = self.heap[parent];
            if p <= item {
                break;
            }
            self.place(i, p);
            i = parent;
        }
        self.place(i, item);
    }

    #[inline]
    fn sift_down(&mut self, mut i: usize) {
        let item = self.heap[i];
        let n = self.heap.len();
        loop {
            let first = ARITY * i + 1;
            if first >= n {
                break;
            }
            let child = if first + ARITY <= n {
                // All four children: the smallest by arithmetic selects,
                // not branches (which child wins is a coin toss).
                let h = &self.heap[first..first + ARITY];
                let a = usize::from(precedes(h[1], h[0]));
                let b = 2 + usize::from(precedes(h[3], h[2]));
                first + a + usize::from(precedes(h[b], h[a])) * (b - a)
            } else {
                let mut c = first;
                for k in first + 1..n {
                    if precedes(self.heap[k], self.heap[c]) {
                        c = k;
                    }
                }
                c
            };
            let c = self.heap[child];
            if item <= c {
                break;
            }
            self.place(i, c);
            i = child;
        }
        self.place(i, item);
    }

    /// Puts `entry` at heap position `i`, keeping its vertex's index.
    #[inline]
    fn place(&mut self, i: usize, entry: (u64, u32)) {
        self.heap[i] = entry;
        self.at[entry.1 as usize] = i as u32;
    }
}

/// `a < b` for heap entries (distance bits, then vertex), without branches.
#[inline]
fn precedes(a: (u64, u32), b: (u64, u32)) -> bool {
    (a.0 < b.0) | ((a.0 == b.0) & (a.1 < b.1))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pops_by_key_then_vertex_and_lowers_in_place() {
        let mut q = VertexQueue::new(8);
        for (key, v) in [(5, 0), (3, 1), (3, 2), (9, 3), (7, 4), (1, 5)] {
            q.push_or_lower(key, v);
        }
        // Lowered in place, raised never.
        q.push_or_lower(2, 3);
        q.push_or_lower(8, 1);
        q.push_or_lower(3, 0);
        let mut popped = Vec::new();
        while let Some(e) = q.pop() {
            popped.push(e);
        }
        assert_eq!(popped, [(1, 5), (2, 3), (3, 0), (3, 1), (3, 2), (7, 4)]);
        // A popped vertex can be queued again.
        q.push_or_lower(4, 5);
        assert_eq!(q.peek(), Some((4, 5)));
        q.clear();
        assert_eq!(q.pop(), None);
        q.push_or_lower(6, 5);
        assert_eq!(q.pop(), Some((6, 5)));
    }

    #[test]
    fn matches_a_lazy_heap_on_random_updates() {
        use std::cmp::Reverse;
        use std::collections::BinaryHeap;
        let n = 200;
        let mut seed = 0x9e37_79b9_7f4a_7c15_u64;
        let mut next = |m: u64| {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            seed % m
        };
        let mut q = VertexQueue::new(n);
        let mut lazy = BinaryHeap::new();
        let mut key = vec![u64::MAX; n];
        for _ in 0..20_000 {
            if next(3) == 0 {
                let got = q.pop();
                let want = loop {
                    match lazy.pop() {
                        Some(Reverse((k, v))) if key[v as usize] == k => {
                            key[v as usize] = u64::MAX;
                            break Some((k, v));
                        }
                        Some(_) => continue,
                        None => break None,
                    }
                };
                assert_eq!(got, want);
            } else {
                let v = next(n as u64) as u32;
                let k = next(1000);
                if k < key[v as usize] {
                    key[v as usize] = k;
                    lazy.push(Reverse((k, v)));
                }
                q.push_or_lower(k, v);
            }
        }
    }
}
