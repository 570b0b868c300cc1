//! The backstop for vertices an approximate solve leaves unreached inside
//! the area it reached (see [`fill_gaps`]).

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use geodesics_mesh::Mesh;
use geodesics_window::{DistanceField, NO_SOURCE, corner_neighbours};

/// Gives each vertex that the windows left unreached, although a
/// neighbour was reached, its shortest distance along mesh edges from the
/// reached vertices (Dijkstra through the unreached vertices only; no
/// reached distance changes), if that is within `max_distance`. Returns
/// how many vertices it filled.
///
/// Why: a reset restarts the wavefront from point sources whose distances
/// tie, to the last digits, those of the windows kept beyond the guard
/// band. In rare configurations the pruning among such near-ties, next to
/// a nearly flat saddle that emits only into its thin shadow, leaves a
/// narrow sector that no window covers, and a vertex inside it is never
/// reached (on `skull.glb` at λ = 32 from one face point, one vertex of
/// 50K; none in 7,680 other solves over 17 meshes, at λ from 2 to 128). Emitting into
/// whole corners closes such sectors but cost 28–65 % more time on the
/// Loop×4 bunny; this backstop costs one scan of the distances when every
/// vertex was reached, and one scan of the smaller side's edges when
/// some are beyond the limit or in another component. Its distance is the length of a real path (to a
/// reached vertex, then along edges), so it is never below exact either.
pub(crate) fn fill_gaps(mesh: &Mesh, field: &mut DistanceField, max_distance: Option<f64>) -> u64 {
    let unreached = field.distance.iter().filter(|d| !d.is_finite()).count();
    if unreached == 0 {
        return 0;
    }
    let limit = max_distance.unwrap_or(f64::INFINITY);
    let input = |v: u32| mesh.pinch_origin(v) as usize;
    // The edge paths from reached vertices to unreached neighbours within
    // the limit, found from the smaller of the two sets (a limited solve
    // reaches few, a full one misses few). Usually there are none (other
    // components, or past the limit), and nothing more is allocated.
    let from_reached = field.distance.len() - unreached < unreached;
    let mut first = Vec::new();
    for v in 0..mesh.vertex_count() as u32 {
        if field.distance[input(v)].is_finite() != from_reached {
            continue;
        }
        for (u, l) in neighbours(mesh, v) {
            if field.distance[input(u)].is_finite() == from_reached {
                continue;
            }
            let (to, from) = if from_reached { (u, v) } else { (v, u) };
            let i = input(from);
            let d = field.distance[i] + l;
            if d <= limit {
                first.push((to, d, field.nearest_source[i]));
            }
        }
    }
    if first.is_empty() {
        return 0;
    }
    let mut gaps = Gaps {
        limit,
        best: vec![(f64::INFINITY, NO_SOURCE); mesh.vertex_count()],
        queue: BinaryHeap::new(),
    };
    for (v, d, source) in first {
        gaps.offer(v, d, source);
    }
    let mut filled = 0;
    while let Some(Reverse((key, v))) = gaps.queue.pop() {
        let (d, source) = gaps.best[v as usize];
        let i = input(v);
        if key != d.to_bits() || field.distance[i].is_finite() {
            continue; // stale, or a pinch copy of a vertex just filled
        }
        field.distance[i] = d;
        field.nearest_source[i] = source;
        filled += 1;
        for (u, l) in neighbours(mesh, v) {
            if !field.distance[input(u)].is_finite() {
                gaps.offer(u, d + l, source);
            }
        }
    }
    filled
}

/// Each neighbour of `v` with the length of the edge to it: the two other
/// corners of every face around it (`corner_neighbours`, which also finds
/// the last neighbour of a boundary vertex; inner ones come twice).
fn neighbours(mesh: &Mesh, v: u32) -> impl Iterator<Item = (u32, f64)> + '_ {
    mesh.fan(v)
        .iter()
        .flat_map(move |&h| corner_neighbours(mesh, h).map(|(u, l, _)| (u, l)))
}

/// The Dijkstra of [`fill_gaps`] over the unreached vertices.
struct Gaps {
    limit: f64,
    /// Per mesh vertex: the shortest edge path found so far, its source.
    best: Vec<(f64, u32)>,
    queue: BinaryHeap<Reverse<(u64, u32)>>,
}

impl Gaps {
    /// A path of length `d` from `source` to unreached vertex `v`.
    fn offer(&mut self, v: u32, d: f64, source: u32) {
        if d <= self.limit && d < self.best[v as usize].0 {
            self.best[v as usize] = (d, source);
            self.queue.push(Reverse((d.to_bits(), v)));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tests::grid;

    /// The vertex at `(x, y)` (grid coordinates are whole numbers, exactly).
    fn at(mesh: &Mesh, x: f64, y: f64) -> usize {
        (0..mesh.vertex_count())
            .find(|&v| {
                let p = mesh.position(v as u32);
                p.x == x && p.y == y
            })
            .expect("a grid vertex there")
    }

    /// The Euclidean distances from vertex 0 (the origin), source 0.
    fn euclidean(mesh: &Mesh) -> DistanceField {
        let o = mesh.position(0);
        let distance: Vec<f64> = (0..mesh.vertex_count() as u32)
            .map(|v| mesh.position(v).distance(o))
            .collect();
        let nearest_source = vec![0; distance.len()];
        DistanceField {
            distance,
            nearest_source,
        }
    }

    #[test]
    fn a_complete_field_is_left_alone() {
        let mesh = grid(5);
        let mut field = euclidean(&mesh);
        let before = field.clone();
        assert_eq!(fill_gaps(&mesh, &mut field, None), 0);
        assert_eq!(field, before);
    }

    #[test]
    fn a_hole_takes_the_shortest_edge_path_from_its_reached_neighbours() {
        let mesh = grid(5);
        let mut field = euclidean(&mesh);
        let exact = field.clone();
        let hole = [at(&mesh, 2.0, 2.0), at(&mesh, 3.0, 2.0)];
        for v in hole {
            field.distance[v] = f64::INFINITY;
            field.nearest_source[v] = NO_SOURCE;
        }
        assert_eq!(fill_gaps(&mesh, &mut field, None), 2);
        for v in hole {
            // One edge from the best reached neighbour, in the edge lengths
            // the fill adds: the filled distance is at most this, bit for
            // bit (a path through the other hole vertex is only longer).
            let via: f64 = neighbours(&mesh, v as u32)
                .filter(|&(u, _)| !hole.contains(&(u as usize)))
                .map(|(u, l)| exact.distance[u as usize] + l)
                .fold(f64::INFINITY, f64::min);
            assert!(via.is_finite(), "vertex {v} has reached neighbours");
            assert!(
                field.distance[v] >= exact.distance[v],
                "vertex {v} below exact"
            );
            assert!(
                field.distance[v] <= via,
                "vertex {v}: {} > {via}",
                field.distance[v]
            );
            assert_eq!(field.nearest_source[v], 0);
        }
        // Every other vertex kept its distance.
        for v in (0..exact.distance.len()).filter(|v| !hole.contains(v)) {
            assert_eq!(field.distance[v].to_bits(), exact.distance[v].to_bits());
        }
    }

    #[test]
    fn nothing_is_filled_beyond_the_limit_or_in_an_unreached_component() {
        let mesh = grid(5);
        let mut field = euclidean(&mesh);
        let v = at(&mesh, 2.0, 2.0);
        field.distance[v] = f64::INFINITY;
        // Every path to (2, 2) is at least its Euclidean distance, 2.83.
        assert_eq!(fill_gaps(&mesh, &mut field, Some(2.5)), 0);
        assert!(field.distance[v].is_infinite());
        // Nothing reached at all: nothing to fill from.
        let mut none = DistanceField {
            distance: vec![f64::INFINITY; mesh.vertex_count()],
            nearest_source: vec![NO_SOURCE; mesh.vertex_count()],
        };
        assert_eq!(fill_gaps(&mesh, &mut none, None), 0);
    }
}
