//! AVTP's wavefront reset (Du et al. 2021, Algorithm 3, lines 6–14), the
//! bookkeeping shared by the sequential and the parallel solver.

use geodesics_mesh::Mesh;

use crate::prune::apex_paths;
use crate::{EndedWindow, Triangle, Window, WindowReset};

/// The best path to the apex of half-edge `h`'s face through `list` (Rule
/// 1's, as crossing the face would give it): its length, the window giving
/// it and where its ray crosses `h` (the bend). `None` when no window of
/// the list lights the apex. For lighting the apex before a reset deletes
/// the list ([`WindowReset::light_apices`]); `paths` is scratch.
pub fn path_to_apex(
    mesh: &Mesh,
    h: u32,
    list: &[EndedWindow],
    paths: &mut Vec<(f64, f64, f64)>,
) -> Option<(f64, Window, f64)> {
    let p = Mesh::prev(h);
    let tri = Triangle::with_lengths(
        mesh.length(h),
        mesh.apex(h),
        mesh.length(p),
        mesh.length(Mesh::next(h)),
    );
    let (best, k) = apex_paths(list, &tri, paths);
    best.is_finite().then(|| (best, list[k].window, paths[k].1))
}

/// Which vertices a window reset makes pseudo-sources and which lists it
/// empties, found in time proportional to what changed since the last
/// reset.
///
/// Each time the wavefront passes a multiple of `λ·h`, every wavefront
/// vertex (reached, not yet popped) within the guard band `λ_g·h` beyond
/// that radius becomes a pseudo-source, and the windows waiting on the
/// edges between two such vertices are deleted. A vertex reset once stays
/// among them until it is popped: its distance only falls and the band
/// only moves out. So a reset needs to look only at
///
/// - the reached vertices not yet reset (a new one joins when it enters
///   the band), and
/// - the edges around the vertices that join, plus the lists between two
///   reset vertices that grew since the last reset (every other list
///   between two reset vertices was emptied then and has stayed empty).
///
/// Rescanning the whole wavefront at every reset instead made small λ
/// quadratic: with `λ·h` below the edge lengths every pop resets, and the
/// subdivided bunny of 557K vertices took 5.4 s at λ = 0.01, as long as
/// exact VTP; now 0.46 s.
///
/// # Example
///
/// ```
/// use geodesics_mesh::{BuildOptions, Mesh};
/// use geodesics_window::{ResetFront, WindowReset};
///
/// let mesh = Mesh::build(geodesics_shapes::flat_grid(4, 4, 1.0), &BuildOptions::default())?;
/// let mut front = ResetFront::new(WindowReset::every(2.0), 1.0, mesh.vertex_count());
/// for v in [0, 1, 5] {
///     front.reached(v); // given a distance while outside
/// }
/// assert!(!front.is_due(1.5) && front.is_due(2.5));
/// let distance = |v: u32| v as f64 * 0.1;
/// let joined = front.advance(2.5, |_| false, distance);
/// assert_eq!(joined, [0, 1, 5]);
/// // The edge 0–1 lies between two reset vertices: its lists go.
/// let edges = front.lists_to_empty(&mesh, |_| false);
/// assert!(edges.iter().any(|&h| {
///     let ends = [mesh.tail(h), mesh.head(h)];
///     ends == [0, 1] || ends == [1, 0]
/// }));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Debug)]
pub struct ResetFront {
    step: f64,
    guard_band: f64,
    next: f64,
    /// Per vertex: made a pseudo-source by a reset.
    is_reset: Vec<bool>,
    /// Reached vertices not reset yet (some popped since: dropped lazily).
    waiting: Vec<u32>,
    /// The vertices the last [`ResetFront::advance`] reset.
    joined: Vec<u32>,
    /// Half-edges between two reset vertices whose lists received windows
    /// since the last reset (repeats allowed).
    grown: Vec<u32>,
    /// The half-edges whose lists the current reset empties.
    to_empty: Vec<u32>,
    resets: u64,
    light_apices: bool,
}

impl ResetFront {
    /// Bookkeeping for resets `reset` on a mesh of `vertices` vertices and
    /// mean edge length `mean_edge`.
    pub fn new(reset: WindowReset, mean_edge: f64, vertices: usize) -> ResetFront {
        let step = reset.lambda * mean_edge;
        ResetFront {
            step,
            guard_band: reset.lambda_g * mean_edge,
            next: step,
            is_reset: vec![false; vertices],
            waiting: Vec::new(),
            joined: Vec::new(),
            grown: Vec::new(),
            to_empty: Vec::new(),
            resets: 0,
            light_apices: reset.light_apices,
        }
    }

    /// Vertex `v` got its first finite distance while outside the
    /// traversed area: it is on the wavefront.
    #[inline]
    pub fn reached(&mut self, v: u32) {
        self.waiting.push(v);
    }

    /// The list of half-edge `h`, whose ends were both reset (see
    /// [`ResetFront::is_reset`]), received windows. Lists with an end not
    /// reset need not be reported: if that end is reset later, the reset
    /// looks at its edges anyway.
    #[inline]
    pub fn grown(&mut self, h: u32) {
        self.grown.push(h);
    }

    /// Whether popping a vertex at distance `d` passes the next reset
    /// radius.
    #[inline]
    pub fn is_due(&self, d: f64) -> bool {
        d > self.next
    }

    /// Whether the apex beyond a list is lit before the list is deleted
    /// (see [`WindowReset::light_apices`]).
    pub fn lights_apices(&self) -> bool {
        self.light_apices
    }

    /// How many resets happened.
    pub fn resets(&self) -> u64 {
        self.resets
    }

    /// Whether `v` was made a pseudo-source by a reset.
    #[inline]
    pub fn is_reset(&self, v: u32) -> bool {
        self.is_reset[v as usize]
    }

    /// Resets at `d`, the distance of the vertex being popped (still on
    /// the wavefront): moves the radius to the last multiple of the step
    /// below `d` (the wavefront may jump several at once) and returns the
    /// wavefront vertices that now join the reset ones, to be made
    /// pseudo-sources. `inside` tells a popped vertex, `distance` gives a
    /// vertex's current distance.
    pub fn advance(
        &mut self,
        d: f64,
        inside: impl Fn(u32) -> bool,
        distance: impl Fn(u32) -> f64,
    ) -> &[u32] {
        let steps = (d / self.step).floor();
        self.next = (steps + 1.0) * self.step;
        let guard = steps * self.step + self.guard_band;
        self.resets += 1;
        self.joined.clear();
        let (joined, is_reset) = (&mut self.joined, &mut self.is_reset);
        self.waiting.retain(|&v| {
            if inside(v) {
                return false;
            }
            if distance(v) <= guard {
                is_reset[v as usize] = true;
                joined.push(v);
                return false;
            }
            true
        });
        &self.joined
    }

    /// What the last [`ResetFront::lists_to_empty`] returned (kept until the
    /// next reset), for a caller that must hand the front back before it
    /// walks them.
    pub fn emptied(&self) -> &[u32] {
        &self.to_empty
    }

    /// The half-edges whose lists the reset just advanced empties (both
    /// half-edges of every edge between two reset vertices still on the
    /// wavefront, repeats possible); `inside` as for
    /// [`ResetFront::advance`]. Clears the record of grown lists.
    pub fn lists_to_empty(&mut self, mesh: &Mesh, inside: impl Fn(u32) -> bool) -> &[u32] {
        let on_reset_front = |v: u32| self.is_reset[v as usize] && !inside(v);
        self.to_empty.clear();
        for &v in &self.joined {
            for &h in mesh.fan(v) {
                let p = Mesh::prev(h);
                for (e, other) in [(h, mesh.head(h)), (p, mesh.tail(p))] {
                    if on_reset_front(other) {
                        self.to_empty.push(e);
                        self.to_empty.extend(mesh.twin(e));
                    }
                }
            }
        }
        for &h in &self.grown {
            if on_reset_front(mesh.tail(h)) && on_reset_front(mesh.head(h)) {
                self.to_empty.push(h);
            }
        }
        self.grown.clear();
        &self.to_empty
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use geodesics_mesh::BuildOptions;
    use glam::DVec2;

    fn grid() -> Mesh {
        Mesh::build(
            geodesics_shapes::flat_grid(5, 5, 1.0),
            &BuildOptions::default(),
        )
        .expect("a flat grid is a valid mesh")
    }

    /// Every half-edge with both ends in `set`, sorted.
    fn halves_within(mesh: &Mesh, set: &[u32]) -> Vec<u32> {
        (0..mesh.half_edge_count() as u32)
            .filter(|&h| set.contains(&mesh.tail(h)) && set.contains(&mesh.head(h)))
            .collect()
    }

    fn sorted(halves: &[u32]) -> Vec<u32> {
        let mut v = halves.to_vec();
        v.sort_unstable();
        v.dedup();
        v
    }

    #[test]
    fn the_apex_is_lit_by_the_lists_best_window() {
        let mesh = grid();
        // A diagonal: its apex stands over the inside of the edge.
        let h = (0..3)
            .find(|&h| mesh.apex(h).x > 0.0 && mesh.apex(h).x < mesh.length(h))
            .expect("a grid triangle has a diagonal");
        let (l, c) = (mesh.length(h), mesh.apex(h));
        // One pseudo-source straight below the apex, one farther away and
        // beyond the edge's end: the first one's straight path wins.
        let window = |p: DVec2, sigma: f64, source: u32| {
            EndedWindow::new(Window {
                b0: 0.0,
                b1: l,
                p,
                sigma,
                source,
            })
        };
        let near = window(DVec2::new(c.x, -1.0), 0.5, 7);
        let far = window(DVec2::new(3.0 * l, -1.0), 0.5, 8);
        let mut paths = Vec::new();
        let (d, w, bend) = path_to_apex(&mesh, h, &[far, near], &mut paths).unwrap();
        assert!((d - (0.5 + c.y + 1.0)).abs() < 1e-12, "{d}");
        assert_eq!(w.source, 7);
        assert!((bend - c.x).abs() < 1e-12, "{bend}");
        // The far one alone bends at the edge's end nearest the apex.
        let (d, _, bend) = path_to_apex(&mesh, h, &[far], &mut paths).unwrap();
        assert_eq!(bend, l);
        assert!((d - (far.d1 + DVec2::new(l, 0.0).distance(c))).abs() < 1e-12);
        assert!(path_to_apex(&mesh, h, &[], &mut paths).is_none());
    }

    #[test]
    fn vertices_join_once_within_the_band_and_popped_ones_never() {
        let mesh = grid();
        let reset = WindowReset {
            lambda: 1.0,
            lambda_g: 0.5,
            light_apices: false,
        };
        let mut front = ResetFront::new(reset, 1.0, mesh.vertex_count());
        for v in [3, 4, 7, 8] {
            front.reached(v);
        }
        let dist = |v: u32| match v {
            3 | 4 => 1.2,
            7 => 1.6,
            _ => 2.0,
        };
        assert!(!front.is_due(1.0));
        // Radius 1, band to 1.5: 3 and 4 join; 8 is popped already.
        let joined = front.advance(1.1, |v| v == 8, dist).to_vec();
        assert_eq!(joined, [3, 4]);
        assert!(front.is_reset(3) && !front.is_reset(7) && !front.is_reset(8));
        assert!(!front.is_due(2.0) && front.is_due(2.1));
        // Radius 2, band to 2.5: only 7 is left to join.
        assert_eq!(front.advance(2.2, |v| v == 8, dist), [7]);
        assert_eq!(front.advance(3.2, |_| false, dist), [] as [u32; 0]);
        assert_eq!(front.resets(), 3);
    }

    #[test]
    fn a_reset_empties_lists_between_reset_vertices_and_grown_ones_later() {
        let mesh = grid();
        let mut front = ResetFront::new(WindowReset::every(1.0), 1.0, mesh.vertex_count());
        // A vertex in the middle and its neighbours of the next row: every
        // half-edge among them, interior edges both ways.
        let set = [14, 20, 21];
        for v in set {
            front.reached(v);
        }
        front.advance(1.5, |_| false, |_| 1.0);
        let first = sorted(front.lists_to_empty(&mesh, |_| false));
        assert_eq!(first, halves_within(&mesh, &set));
        assert!(first.len() >= 4, "two interior edges at least: {first:?}");
        // Nothing joins at the next reset, but a list between 14 and 20
        // grew: it goes again. One next to 21, popped since, stays.
        let next_to_21: Vec<u32> = first
            .iter()
            .copied()
            .filter(|&h| !halves_within(&mesh, &[14, 20]).contains(&h))
            .collect();
        let again = halves_within(&mesh, &[14, 20])[0];
        front.grown(again);
        front.grown(next_to_21[0]);
        front.advance(2.5, |v| v == 21, |_| 1.0);
        assert_eq!(front.lists_to_empty(&mesh, |v| v == 21), [again]);
        // The record of grown lists was cleared.
        front.advance(3.5, |v| v == 21, |_| 1.0);
        assert!(front.lists_to_empty(&mesh, |v| v == 21).is_empty());
    }
}
