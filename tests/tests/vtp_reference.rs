//! VTP against the exact reference distances (gdist / MMP) on every real and
//! synthetic mesh, from every listed source and from all of them at once.
//!
//! Pass: within `1e-12 ×` the largest finite reference distance at every
//! vertex; infinite exactly where the reference is, except the manifest's
//! `oracle_misses` (gdist wrongly left them infinite; ours must be finite)
//! and meshes with a pinch vertex (cow.obj: gdist does not pass through it,
//! so ours may be shorter there; every such vertex is checked to be reached
//! through the pinch vertex by a second, independent solve from it).
//! Shorter than gdist elsewhere only with a walked proof (`Proof`: a real
//! surface path of that length); longer only where gdist is proven too
//! short by an independent computation (`ORACLE_SHORT`).

use std::time::Instant;

use geodesics_mesh::Mesh;
use geodesics_tests::{EXACT, reference_mesh};
use geodesics_vtp::{Provenance, VtpOptions, solve, solve_with_provenance};
use geodesics_window::Source;
use glam::DVec3;

/// A vertex where gdist is proven too SHORT by an independent exact
/// computation (so ours, longer there, is right).
struct OracleShort {
    /// Reference file.
    file: &'static str,
    /// The vertex.
    vertex: usize,
    /// gdist's value (as in the file).
    gdist: f64,
    /// The true distance, from the independent computation.
    truth: f64,
}

/// gdist's known under-estimates. Proof method, for each: both solvers
/// agree (to 4e-17) at the pseudo-source the path leaves from, and gdist's
/// value at the vertex is that pseudo-source's plus its own distance over a
/// small patch (all faces within 3e-3 of the pseudo-source, cut out of the
/// mesh as stored), so the error is local to the patch. On that patch, an
/// exhaustive search written apart from this project (Python: unpruned
/// window propagation through every edge sequence, every vertex of angle
/// sum ≥ 2π − 1e-5 as a pseudo-source, pruned only by the sound bound
/// σ + |p x| + |x target|₃D > L) finds no path shorter than ours: the
/// shortest crosses 5 faces and passes 7.8e-11 from vertex 154928
/// (9.815275768687746e-4 from the pseudo-source; ours 9.815275768688115e-4;
/// next: through vertex 154928, +1.9e-14); gdist says 9.815275764829634e-4,
/// 3.858e-13 below any path. gdist gives the same value on the patch
/// refined by exact midpoint subdivision (1 and 2 levels), ours too.
///
/// Vertices whose gdist value is carried from such a vertex inherit the
/// error: where gdist's value is its value there plus the distance from
/// there, and ours is no longer than the true value there plus that
/// distance, ours may be longer than gdist (see `check`).
const ORACLE_SHORT: &[OracleShort] = &[
    // Dragon as stored, the path from pseudo-source 154938
    // (0.12117890963657081) to saddle vertex 154929.
    OracleShort {
        file: "dragon.ply.src12061.txt",
        vertex: 154929,
        gdist: 0.12216043721305382,
        truth: 0.12216043721343962,
    },
    OracleShort {
        file: "dragon.ply.multi.txt",
        vertex: 154929,
        gdist: 0.12216043721305382,
        truth: 0.12216043721343962,
    },
];

/// Checks every reference file of `key` (a manifest key such as
/// `bunny.off` or `dragon.ply.welded`) whose name passes `filter`.
fn check(key: &str, synthetic: bool, filter: &dyn Fn(&str) -> bool) {
    let Some(case) = reference_mesh(&format!("vtp_reference {key}"), key, synthetic) else {
        return;
    };
    let (mesh, load_s) = (&case.mesh, case.load_seconds);
    let pinch: Vec<u32> = (0..mesh.input_vertex_count() as u32)
        .filter(|&v| mesh.is_pinch(mesh.mesh_vertex(v)))
        .collect();
    let pinch_fields: Vec<Vec<f64>> = pinch
        .iter()
        .map(|&v| {
            solve(mesh, &[Source::Vertex(v)], &VtpOptions::default())
                .unwrap()
                .0
                .distance
        })
        .collect();
    let mut failures = Vec::new();
    for reference_file in &case.files {
        let name = &reference_file.name;
        if !filter(name) {
            continue;
        }
        let (sources, max_finite) = (&reference_file.sources, reference_file.max_finite);
        let misses = &reference_file.oracle_misses;
        let reference = reference_file.distances();
        let t = Instant::now();
        let (field, stats, prov) =
            solve_with_provenance(mesh, sources, &VtpOptions::default()).unwrap();
        let mut proof = Proof::new(mesh, &field.distance, &prov);
        let mut proven_oracle_long = 0;
        let mut inherited_oracle_short = 0;
        let oracle_short: Vec<&OracleShort> =
            ORACLE_SHORT.iter().filter(|o| o.file == name).collect();
        let mut longer = Vec::new();
        let solve_s = t.elapsed().as_secs_f64();
        let ours = &field.distance;
        assert_eq!(ours.len(), reference.len(), "{name}: vertex count");
        let tol = EXACT * max_finite;
        let mut worst = 0.0f64;
        let mut bad = Vec::new();
        let mut shorter_through_pinch = 0;
        for (i, (&d, &r)) in ours.iter().zip(&reference).enumerate() {
            assert!(!d.is_nan(), "{name}: NaN at vertex {i}");
            if misses.contains(&i) {
                if !d.is_finite() {
                    bad.push(format!("oracle miss {i} left infinite"));
                }
                continue;
            }
            if r.is_infinite() || d.is_infinite() {
                if r.is_infinite() != d.is_infinite() {
                    bad.push(format!("vertex {i}: ours {d}, reference {r}"));
                }
                continue;
            }
            let err = d - r;
            if err < -tol && !pinch.is_empty() {
                // Shorter than gdist: must be a path through a pinch vertex.
                let through = pinch
                    .iter()
                    .zip(&pinch_fields)
                    .any(|(&p, pf)| (ours[p as usize] + pf[i] - d).abs() <= tol);
                if through {
                    shorter_through_pinch += 1;
                    continue;
                }
            }
            if err < -tol {
                // Shorter than gdist: accepted only with an independent
                // proof, a path of that length walked straight across the
                // faces (see `Proof`).
                let u = proof.bound(mesh.mesh_vertex(i as u32));
                if u <= d + tol && u < r - tol {
                    proven_oracle_long += 1;
                    continue;
                }
            }
            if err > tol && !oracle_short.is_empty() {
                longer.push(i);
                continue;
            }
            worst = worst.max(err.abs());
            if err.abs() > tol {
                bad.push(format!(
                    "vertex {i}: ours {d:.17}, reference {r:.17}, diff {err:.3e}"
                ));
            }
        }
        // Longer than gdist: accepted only where gdist is proven too short
        // (`ORACLE_SHORT`): at that vertex, or where gdist's value is its
        // (wrong) value there plus the distance from there (its path goes
        // through it) and ours is no longer than the corrected route.
        for o in &oracle_short {
            if longer.is_empty() {
                break;
            }
            if reference[o.vertex] != o.gdist || (ours[o.vertex] - o.truth).abs() > tol {
                bad.push(format!(
                    "recorded oracle error at {} does not match",
                    o.vertex
                ));
                continue;
            }
            let reach = longer
                .iter()
                .map(|&i| reference[i] - o.gdist)
                .fold(0.0, f64::max);
            let opts = VtpOptions {
                max_distance: Some(reach + tol),
                ..VtpOptions::default()
            };
            let from = solve(mesh, &[Source::Vertex(o.vertex as u32)], &opts)
                .unwrap()
                .0
                .distance;
            longer.retain(|&i| {
                let via = (reference[i] - (o.gdist + from[i])).abs() <= tol
                    && ours[i] <= o.truth + from[i] + tol;
                if via {
                    inherited_oracle_short += 1;
                }
                !via
            });
        }
        for &i in &longer {
            let (d, r) = (ours[i], reference[i]);
            worst = worst.max((d - r).abs());
            bad.push(format!(
                "vertex {i}: ours {d:.17}, reference {r:.17}, diff {:.3e}",
                d - r
            ));
        }
        eprintln!(
            "vtp_reference {name}: max |err| / max = {:.2e}, {} failures, {} shorter via pinch, {proven_oracle_long} shorter with a walked proof, {inherited_oracle_short} longer where gdist is proven short, load {load_s:.2}s solve {solve_s:.3}s, {} propagations, peak {} windows",
            worst / max_finite,
            bad.len(),
            shorter_through_pinch,
            stats.window_propagations,
            stats.peak_live_windows
        );
        if !bad.is_empty() {
            bad.truncate(10);
            failures.push(format!("{name}: {}", bad.join("; ")));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// Independent upper bounds on geodesic distances: for each vertex, follow
/// its provenance and walk the claimed straight pieces over the surface
/// with plain 3D geometry (no window code), summing the lengths of a real
/// path from a source.
struct Proof<'a> {
    mesh: &'a Mesh,
    prov: &'a [Provenance],
    bound: Vec<f64>,
}

impl<'a> Proof<'a> {
    fn new(mesh: &'a Mesh, _ours: &[f64], prov: &'a [Provenance]) -> Self {
        Proof {
            mesh,
            prov,
            bound: vec![f64::NAN; prov.len()],
        }
    }

    /// Length of a real path from a source to `v` (infinite if the walk
    /// does not land where claimed).
    fn bound(&mut self, v: u32) -> f64 {
        let mut chain = vec![v];
        loop {
            let x = *chain.last().unwrap();
            if !self.bound[x as usize].is_nan() {
                break;
            }
            match self.step(x) {
                (Some(q), _) if (chain.len() < 1_000_000) => chain.push(q),
                _ => break,
            }
        }
        while let Some(x) = chain.pop() {
            if !self.bound[x as usize].is_nan() {
                continue;
            }
            let (q, len) = self.step(x);
            let b = match q {
                None => len,
                Some(q) => {
                    let bq = self.bound[q as usize];
                    if bq.is_nan() { f64::INFINITY } else { bq + len }
                }
            };
            self.bound[x as usize] = b;
        }
        self.bound[v as usize]
    }

    /// The previous vertex on `v`'s path and the length walked to reach
    /// `v` from it (`None`: from a source, the length is the whole bound).
    fn step(&self, v: u32) -> (Option<u32>, f64) {
        match self.prov[v as usize] {
            Provenance::Unreached => (None, f64::INFINITY),
            Provenance::Source(_) => (None, 0.0),
            Provenance::Vertex { from, length } => (Some(from), length),
            Provenance::Window {
                half_edge,
                pseudo_source,
                bend,
                ..
            } => {
                let walked = self.walk(v, half_edge, pseudo_source, bend);
                if walked.0.is_some() {
                    return walked;
                }
                // The path may reach the half-edge exactly at one of its
                // ends (a window lighting the apex around its end, or a ray
                // arriving along the previous face's edge). Then it is a
                // path to that vertex followed by the straight segment from
                // it to `v` inside the face: also a real path.
                self.through_corner(v, half_edge, bend).unwrap_or(walked)
            }
        }
    }

    /// The path to `v` through the end of half-edge `h` at which `bend`
    /// lies (if it lies at one): that vertex and the segment from it to `v`.
    fn through_corner(&self, v: u32, h: u32, bend: f64) -> Option<(Option<u32>, f64)> {
        let m = self.mesh;
        let t = m.position(m.tail(h));
        let e = (m.position(m.head(h)) - t) / m.length(h);
        let q = self.vertex_at(t + e * bend, Mesh::face_of(h))?;
        (q != v).then(|| (Some(q), m.position(q).distance(m.position(v))))
    }

    fn walk(&self, c: u32, h: u32, p: glam::DVec2, bend: f64) -> (Option<u32>, f64) {
        let m = self.mesh;
        let t = m.position(m.tail(h));
        let hd = m.position(m.head(h));
        let l = m.length(h);
        let e = (hd - t) / l;
        let xb = t + e * bend;
        let first = m.position(c).distance(xb);
        let Some(tw) = beyond(m, h) else {
            return (None, f64::INFINITY);
        };
        let d2 = p - glam::DVec2::new(bend, 0.0);
        let rest = d2.length();
        if rest == 0.0 {
            return (self.vertex_at(xb, Mesh::face_of(h)), first);
        }
        let g = Mesh::face_of(tw);
        let dir = e * (d2.x / rest) + inward(m, tw) * (-d2.y / rest);
        match walk_straight(m, g, tw, xb, dir, rest) {
            Some((end, face, slack)) => match self.vertex_at(end, face) {
                Some(q) => (Some(q), first + rest + slack + end.distance(m.position(q))),
                None => (None, f64::INFINITY),
            },
            None => (None, f64::INFINITY),
        }
    }

    /// The corner of `face` at `x` (within a tiny tolerance), if any.
    fn vertex_at(&self, x: DVec3, face: u32) -> Option<u32> {
        let tol = 1e-9 * self.mesh.bbox_diagonal();
        self.mesh
            .face(face)
            .into_iter()
            .map(|v| (self.mesh.position(v).distance(x), v))
            .filter(|(d, _)| *d <= tol)
            .min_by(|a, b| a.0.total_cmp(&b.0))
            .map(|(_, v)| v)
    }
}

/// Unit vector in the plane of the face of `h`, perpendicular to `h`,
/// pointing into the face.
fn inward(m: &Mesh, h: u32) -> DVec3 {
    let t = m.position(m.tail(h));
    let e = (m.position(m.head(h)) - t).normalize();
    let c = m.position(m.opposite_vertex(h)) - t;
    (c - e * c.dot(e)).normalize()
}

/// Walks straight from `x` (on half-edge `entry` of `face`) in direction
/// `dir` (in the face's plane) for `len`, unfolding across edges. Returns
/// the end point, the face it lies in, and the slack to add to `len` for a
/// real path: an edge crossed a little outside its segment (by rounding,
/// next to a corner) is really passed at that corner, which costs at most
/// twice the overshoot.
fn walk_straight(
    m: &Mesh,
    mut face: u32,
    mut entry: u32,
    mut x: DVec3,
    mut dir: DVec3,
    mut len: f64,
) -> Option<(DVec3, u32, f64)> {
    let mut slack = 0.0;
    for _ in 0..10_000_000 {
        // Exit edge: the other two half-edges of the face.
        let mut best: Option<(f64, u32, f64)> = None;
        for h in 3 * face..3 * face + 3 {
            if h == entry {
                continue;
            }
            let a = m.position(m.tail(h));
            let b = m.position(m.head(h));
            // Solve x + s dir = a + r (b - a) in the face plane.
            let ab = b - a;
            let n = ab.cross(m.position(m.opposite_vertex(h)) - a);
            let det = n.dot(dir.cross(ab));
            if det == 0.0 {
                continue;
            }
            let s = n.dot((a - x).cross(ab)) / det;
            let r = n.dot((a - x).cross(dir)) / det;
            if s > 0.0 && (-1e-7..=1.0 + 1e-7).contains(&r) && best.is_none_or(|(bs, ..)| s < bs) {
                let over = (-r).max(r - 1.0).max(0.0) * ab.length();
                best = Some((s, h, over));
            }
        }
        // No exit ahead: the walk ends on this face's boundary (at a corner).
        let Some((s, h, over)) = best else {
            return Some((x + dir * len, face, slack));
        };
        if s >= len {
            return Some((x + dir * len, face, slack));
        }
        // The end point, claimed to lie in this face: the path from the
        // current point `x` (in the face) to a corner near it is in the
        // face and no longer than `len` plus the gap, by the triangle
        // inequality. So a walk meeting the mesh boundary by rounding just
        // before its end (a pseudo-source on the boundary) still counts.
        let end = x + dir * len;
        x += dir * s;
        len -= s;
        let Some(tw) = beyond(m, h) else {
            return Some((end, face, slack));
        };
        slack += 2.0 * over;
        let e = (m.position(m.head(h)) - m.position(m.tail(h))).normalize();
        let along = dir.dot(e);
        let across = (dir - e * along).length();
        dir = e * along + inward(m, tw) * across;
        face = Mesh::face_of(tw);
        entry = tw;
    }
    None
}

/// The half-edge through which a walk leaving its face across half-edge
/// `h` enters the next face of positive area. A zero-area face with two
/// coincident corners is crossed straight: its two long edges are one
/// segment, so the walk goes on beyond the other one.
fn beyond(m: &Mesh, h: u32) -> Option<u32> {
    let mut tw = m.twin(h)?;
    for _ in 0..64 {
        let f = Mesh::face_of(tw);
        if !is_flat_face(m, f) {
            return Some(tw);
        }
        let o = (3 * f..3 * f + 3).find(|&o| o != tw && m.length(o) > 0.0)?;
        tw = m.twin(o)?;
    }
    None
}

fn is_flat_face(m: &Mesh, f: u32) -> bool {
    let [a, b, c] = m.face(f).map(|v| m.position(v));
    (b - a).cross(c - a).length_squared() == 0.0
}

fn all(_: &str) -> bool {
    true
}

macro_rules! mesh_tests {
    ($($name:ident => $key:expr),* $(,)?) => {$(
        #[test]
        fn $name() {
            check($key, false, &all);
        }
    )*};
}

mesh_tests! {
    armadillo => "armadillo.obj",
    blade => "blade.off",
    bunny => "bunny.off",
    bunny_zipper => "bunny_zipper.ply",
    camelhead => "camelhead.off",
    cow => "cow.obj",
    fandisk => "fandisk.obj",
    fertility => "fertility.off",
    hand => "hand.off",
    knot => "knot.stl",
    rockerarm => "rockerarm.off",
    screw => "screw_m3x10.stl",
    skull => "skull.glb",
}

#[test]
fn synthetic_grid() {
    check("grid101.off", true, &all);
}

#[test]
fn synthetic_icosphere() {
    check("icosphere4.off", true, &all);
}

#[test]
fn synthetic_torus() {
    check("torus120x40.off", true, &all);
}

// The dragon (871k faces) one file per test, so they spread over the cores.
macro_rules! dragon_tests {
    ($($name:ident => $key:expr, $suffix:expr),* $(,)?) => {$(
        #[test]
        fn $name() {
            check($key, false, &|f: &str| f.ends_with($suffix) && !f.contains(".welded.") == !$key.ends_with(".welded"));
        }
    )*};
}

dragon_tests! {
    dragon_src0 => "dragon.ply", ".src0.txt",
    dragon_src37523 => "dragon.ply", ".src37523.txt",
    dragon_src12061 => "dragon.ply", ".src12061.txt",
    dragon_multi => "dragon.ply", ".multi.txt",
    dragon_welded_src0 => "dragon.ply.welded", ".src0.txt",
    dragon_welded_src206094 => "dragon.ply.welded", ".src206094.txt",
    dragon_welded_src222921 => "dragon.ply.welded", ".src222921.txt",
    dragon_welded_multi => "dragon.ply.welded", ".multi.txt",
}
