//! The shadow of a saddle vertex: the only directions its pseudo-source
//! windows can light first.
//!
//! A shortest path through a vertex `v` leaves it at an angle of at least
//! π from the direction it arrived from, measured on either side within
//! the surface (otherwise it could be shortened by cutting the corner at
//! `v`; Mitchell, Mount and Papadimitriou 1987, Lemma 3.5). Every shortest
//! path to a point `q` through `v` continues *some* shortest path to `v`,
//! and any shortest path to `v` will do: if `q`'s shortest path is
//! `γ' + [v q]`, then `γ + [v q]` has the same length for every shortest
//! `γ` to `v`, so it is shortest too, and leaves `v` at least π from `γ` on
//! both sides. So a saddle vertex whose total angle is `Θ > 2π`, reached
//! along a direction `α` (an angle around `v`, from where the path came),
//! only needs to emit windows into the directions `β` with
//! `(β − α) mod Θ ∈ [π, Θ − π]`: its shadow, a sector of width `Θ − 2π`,
//! exactly the gap that the windows passing `v` on either side leave
//! behind it. Everywhere else a window from `v` is beaten by a path that
//! does not touch `v`. VTP's emission covers the whole fan instead, and on
//! scanned meshes, whose saddles are mostly noise a few degrees above 2π,
//! those windows were most of the propagations.
//!
//! Angles around `v` are measured counter-clockwise from its first
//! outgoing half-edge ([`Mesh::outgoing`]), summing corner angles. The
//! sector is widened by [`Tolerance::shadow_angle`] on each side, far more
//! than the error of the arrival direction (which comes from a pseudo-source
//! position unfolded across many faces), so nothing needed is dropped; a
//! distance lowered later without a new emission (by less than the margin)
//! can move the arrival, but then every point it misses is reached by the
//! corner-cutting path within that margin.

use std::f64::consts::{FRAC_PI_2, FRAC_PI_4, PI, TAU};

use geodesics_mesh::Mesh;
use glam::DVec2;

use crate::window::{larger, smaller};
use crate::{Tolerance, Window};

/// How the shortest known path reaches a vertex: recorded when its distance
/// drops (cheaply: a vertex is lowered several times before it emits), and
/// turned into a direction ([`Arrival::direction`]) only when it emits.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum Arrival {
    /// From a source, or in a way not recorded: the vertex emits into every
    /// direction.
    #[default]
    Unknown,
    /// Straight through the edge of `half_edge`, whose face has the vertex
    /// as its apex, crossing it at `at` (in the half-edge's frame).
    Window {
        /// The half-edge the path crossed.
        half_edge: u32,
        /// Where it crossed, from the half-edge's tail.
        at: f64,
    },
    /// Along the edge of `half_edge`, an outgoing half-edge of the vertex,
    /// from its head.
    Edge {
        /// The outgoing half-edge pointing back along the path.
        half_edge: u32,
    },
}

impl Arrival {
    /// The direction the path arrives from, as `(g, offset)`: the angle
    /// `offset` counter-clockwise from the outgoing half-edge `g` of the
    /// vertex, within `g`'s corner. `None` when unknown.
    #[inline]
    pub fn direction(&self, mesh: &Mesh) -> Option<(u32, f64)> {
        match *self {
            Arrival::Unknown => None,
            Arrival::Window { half_edge: h, at } => {
                // The corner of the apex in the face of `h` runs from the
                // half-edge before `h` (apex → A) to apex → B,
                // counter-clockwise in `h`'s frame as around the vertex.
                let g = Mesh::prev(h);
                let c = mesh.apex(h);
                let to_a = -c;
                let back = DVec2::new(at, 0.0) - c;
                let psi = fast_atan2(to_a.perp_dot(back), to_a.dot(back));
                Some((g, psi.clamp(0.0, mesh.corner_angle(g))))
            }
            Arrival::Edge { half_edge: g } => Some((g, 0.0)),
        }
    }
}

/// The sector of directions around a vertex that its pseudo-source windows
/// may light (see the module docs), in the vertex's angle coordinate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Shadow {
    /// First direction of the sector, in `[0, total)`.
    start: f64,
    /// Last direction (`start < end < start + total`; past `total` it
    /// wraps to the beginning of the fan).
    end: f64,
    /// The vertex's angle sum.
    total: f64,
}

impl Shadow {
    /// The shadow of interior vertex `v` (its faces all proper, its angle
    /// sum flat or above `2π`) reached by `arrival`; `None` when the vertex
    /// must emit everywhere (arrival unknown, or a sector covering the
    /// whole fan).
    pub fn of(mesh: &Mesh, v: u32, arrival: Arrival, tol: &Tolerance) -> Option<Shadow> {
        Shadow::of_fan(mesh, v, mesh.fan(v).iter().copied(), arrival, tol)
    }

    /// [`Shadow::of`] with the fan of `v` given: its outgoing half-edges
    /// in the order of [`Mesh::outgoing`] (as [`Mesh::fan`] lists them; a
    /// solver that already holds the fan passes it on).
    pub fn of_fan(
        mesh: &Mesh,
        v: u32,
        fan: impl IntoIterator<Item = u32>,
        arrival: Arrival,
        tol: &Tolerance,
    ) -> Option<Shadow> {
        let (g, offset) = arrival.direction(mesh)?;
        let mut fan_angle = 0.0;
        for h in fan {
            if h == g {
                return Shadow::around(mesh.angle_sum(v), fan_angle + offset, tol);
            }
            fan_angle += mesh.corner_angle(h);
        }
        None
    }

    /// The shadow of a vertex with angle sum `total` whose path arrives
    /// from the direction at angle `arrival` of its fan; `None` when the
    /// sector would cover the whole fan.
    fn around(total: f64, arrival: f64, tol: &Tolerance) -> Option<Shadow> {
        let margin = tol.shadow_angle;
        let width = (total - TAU).max(0.0) + 2.0 * margin;
        if !(width < total) {
            return None;
        }
        // `arrival` lies in [0, total) and total > π, so one turn back
        // at most brings the start into [0, total) (no `fmod`).
        let start = arrival + PI - margin;
        let start = if start >= total { start - total } else { start };
        Some(Shadow {
            start,
            end: start + width,
            total,
        })
    }

    /// Per corner of a pseudo-source's fan (its outgoing half-edges `fan`,
    /// in the order of [`Mesh::outgoing`]): the half-edge and the rays the
    /// vertex emits into through that corner, for
    /// [`pseudo_source_window`]. Without a shadow every corner gives
    /// [`ALL_RAYS`] (and no corner angle is read); with one, `None` for a
    /// corner outside it.
    pub fn fan_rays<'m>(
        shadow: Option<Shadow>,
        mesh: &'m Mesh,
        fan: impl IntoIterator<Item = u32> + 'm,
    ) -> impl Iterator<Item = (u32, Option<(f64, f64)>)> + 'm {
        let mut fan_angle = 0.0;
        fan.into_iter().map(move |h| {
            let rays = match shadow {
                None => Some(ALL_RAYS),
                Some(s) => {
                    let (start, corner) = (fan_angle, mesh.corner_angle(h));
                    fan_angle += corner;
                    s.corner_part(start, corner)
                }
            };
            (h, rays)
        })
    }

    /// The part of the corner spanning `[fan_angle, fan_angle + corner]`
    /// inside the sector, as offsets `(ψ0, ψ1)` from the corner's first
    /// direction (`ψ1` infinite when it runs to the corner's end), or
    /// `None` if they do not meet.
    #[inline]
    pub fn corner_part(&self, fan_angle: f64, corner: f64) -> Option<(f64, f64)> {
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        // The sector as it lies, and wrapped once around the fan.
        for shift in [0.0, self.total] {
            let a = larger(self.start - shift, fan_angle);
            let b = smaller(self.end - shift, fan_angle + corner);
            if a <= b {
                lo = smaller(lo, a);
                hi = larger(hi, b);
            }
        }
        // A sector reaching the corner's last direction takes all of its
        // rays there ([`ALL_RAYS`]' end): the window then ends exactly at
        // the vertex, not an ulp short of it.
        let end = if hi >= fan_angle + corner {
            f64::INFINITY
        } else {
            hi - fan_angle
        };
        (lo <= hi).then_some((lo - fan_angle, end))
    }
}

/// The two other corners of the face of `h` as seen from its tail `v`
/// (a pseudo-source relaxing its neighbours along the edges): each vertex,
/// the length of its edge to `v`, and how a path from `v` along that edge
/// arrives there. The head of `h` comes back to `v` along the twin of `h`
/// (unknown on a boundary), the tail of the half-edge before `h` along
/// that half-edge.
#[inline]
pub fn corner_neighbours(mesh: &Mesh, h: u32) -> [(u32, f64, Arrival); 2] {
    let p = Mesh::prev(h);
    let back_along_h = mesh
        .twin(h)
        .map_or(Arrival::Unknown, |t| Arrival::Edge { half_edge: t });
    [
        (mesh.head(h), mesh.length(h), back_along_h),
        (mesh.tail(p), mesh.length(p), Arrival::Edge { half_edge: p }),
    ]
}

/// Every ray of a corner: `(0, ∞)` for [`pseudo_source_window`].
pub const ALL_RAYS: (f64, f64) = (0.0, f64::INFINITY);

/// The pseudo-source window of vertex `v = tail(h)` at distance `sigma` on
/// the edge opposite its corner in the face of `h` (on the twin of
/// `next(h)`, lighting the face beyond), made of the rays that leave `v`
/// at offsets `rays = (ψ0, ψ1)` from the direction of `h` ([`ALL_RAYS`]:
/// the whole corner, exactly the full edge). `None` if that edge is a
/// boundary or the rays light none of it.
#[inline]
pub fn pseudo_source_window(
    mesh: &Mesh,
    h: u32,
    sigma: f64,
    source: u32,
    (psi0, psi1): (f64, f64),
) -> Option<(u32, Window)> {
    let o = Mesh::next(h);
    let t = mesh.twin(o)?;
    let l = mesh.length(o);
    let mut w = Window::across_edge(l, mesh.apex(o), sigma, source);
    // In the triangle v, a = head(h), b: the ray at offset ψ from v → a
    // meets a → b at s(ψ) = |va| sin ψ / sin(ψ + A) from a (law of sines;
    // A the angle at a, ψ + A < π). The twin runs b → a.
    let (va, angle_a) = (mesh.length(h), mesh.corner_angle(o));
    let from_a = |psi: f64| (va * half_turn_sin(psi) / half_turn_sin(psi + angle_a)).clamp(0.0, l);
    if psi0 > 0.0 {
        w.b1 = l - from_a(psi0);
    }
    if psi1 < mesh.corner_angle(h) {
        w.b0 = l - from_a(psi1);
    }
    (w.b0 < w.b1).then_some((t, w))
}

/// `tan(π/8)`: above it, [`fast_atan2`] works on `(a − 1)/(a + 1)`.
const TAN_PI_8: f64 = 0.414_213_562_373_095_05;

/// `(−1)^k / (2k + 1)`: the series of `atan(t)/t` in `t²`. Eighteen terms
/// leave an error below `0.4143^37 / 37 ≈ 2e-16` for `|t| ≤ tan(π/8)`.
const ATAN_SERIES: [f64; 18] = {
    let mut c = [0.0; 18];
    let mut k = 0;
    while k < 18 {
        let term = 1.0 / (2 * k + 1) as f64;
        c[k] = if k % 2 == 0 { term } else { -term };
        k += 1;
    }
    c
};

/// `(−1)^k / (2k + 1)!`: the series of `sin(z)/z` in `z²`. Ten terms leave
/// an error below `(π/2)^21 / 21! ≈ 3e-16` for `|z| ≤ π/2`.
const SIN_SERIES: [f64; 10] = {
    let mut c = [0.0; 10];
    let mut factorial = 1.0;
    let mut k = 0;
    while k < 10 {
        if k > 0 {
            factorial *= (2 * k) as f64 * (2 * k + 1) as f64;
        }
        c[k] = if k % 2 == 0 {
            1.0 / factorial
        } else {
            -1.0 / factorial
        };
        k += 1;
    }
    c
};

/// `atan2(y, x)` to within 1e-15 rad without the library call: libm's
/// `atan2` and `sin` (see [`half_turn_sin`]) took 4–5 % of AVTP's time at
/// λ = 8 on the 940K-face coarse bunny (one arrival direction per
/// emitting vertex, a sine per cut ray). The shadow is widened by
/// [`Tolerance::shadow_angle`] (1e-5 rad) on each side, far beyond this
/// error, and the distances of every benchmark mesh came out
/// bit-identical.
#[inline]
fn fast_atan2(y: f64, x: f64) -> f64 {
    let (ax, ay) = (x.abs(), y.abs());
    let (num, den) = if ay > ax { (ax, ay) } else { (ay, ax) };
    if den.is_nan() || den == 0.0 || num.is_nan() {
        return y.atan2(x); // zeros and NaNs: the library's conventions
    }
    // atan of a ∈ [0, 1], reduced to |t| ≤ tan(π/8) by
    // atan(a) = π/4 + atan((a − 1)/(a + 1)).
    let a = num / den;
    let (t, base) = if a > TAN_PI_8 {
        ((a - 1.0) / (a + 1.0), FRAC_PI_4)
    } else {
        (a, 0.0)
    };
    let s = t * t;
    let series = ATAN_SERIES.iter().rev().fold(0.0, |acc, &c| c + s * acc);
    let mut r = base + t * series;
    if ay > ax {
        r = FRAC_PI_2 - r;
    }
    if x < 0.0 {
        r = PI - r;
    }
    if y < 0.0 { -r } else { r }
}

/// `sin(z)` for `z ∈ [0, π]` (a ray's angle within a corner, or that plus
/// the next corner angle of its triangle) to within 1e-15, without the
/// library call (see [`fast_atan2`]).
#[inline]
fn half_turn_sin(z: f64) -> f64 {
    let z = if z > FRAC_PI_2 { PI - z } else { z };
    let s = z * z;
    z * SIN_SERIES.iter().rev().fold(0.0, |acc, &c| c + s * acc)
}

#[cfg(test)]
mod tests {
    use super::*;
    use geodesics_mesh::{BuildOptions, IndexedTriangles};
    use glam::DVec3;

    /// A fan of `n` triangles around vertex 0 at the origin, rim points on
    /// a zigzag so the angle sum exceeds 2π when `lift` is not zero, closed
    /// by a second fan below (so every edge has a twin).
    fn saddle(n: usize, lift: f64) -> Mesh {
        let mut positions = vec![DVec3::ZERO];
        for k in 0..n {
            let a = TAU * k as f64 / n as f64;
            let z = if k % 2 == 0 { lift } else { -lift };
            positions.push(DVec3::new(a.cos(), a.sin(), z));
        }
        positions.push(DVec3::new(0.0, 0.0, -2.0));
        let (n32, bottom) = (n as u32, n as u32 + 1);
        let triangles = (0..n32)
            .flat_map(|k| {
                let (a, b) = (1 + k, 1 + (k + 1) % n32);
                [[0, a, b], [bottom, b, a]]
            })
            .collect();
        Mesh::build(
            IndexedTriangles {
                positions,
                triangles,
            },
            &BuildOptions::default(),
        )
        .unwrap()
    }

    fn tol() -> Tolerance {
        Tolerance::for_scale(1.0)
    }

    #[test]
    fn corner_neighbours_are_the_face_s_other_corners_each_pointing_back() {
        let mesh = saddle(6, 0.2);
        for &h in mesh.fan(0) {
            let [(a, la, back_a), (b, lb, back_b)] = corner_neighbours(&mesh, h);
            let mut others: Vec<u32> = mesh.face(Mesh::face_of(h)).into_iter().collect();
            others.retain(|&u| u != 0);
            assert_eq!(others.len(), 2);
            assert!(others.contains(&a) && others.contains(&b) && a != b);
            for (u, l, back) in [(a, la, back_a), (b, lb, back_b)] {
                assert_eq!(
                    l,
                    (mesh.position(u) - mesh.position(0)).length(),
                    "vertex {u}"
                );
                // An outgoing half-edge of the vertex reached, pointing back
                // to 0 (closed mesh: every edge has a twin).
                let Arrival::Edge { half_edge: g } = back else {
                    panic!("vertex {u}: arrival {back:?}");
                };
                assert_eq!((mesh.tail(g), mesh.head(g)), (u, 0));
            }
        }
    }

    #[test]
    fn a_saddle_reached_along_an_edge_shadows_the_opposite_side() {
        let mesh = saddle(6, 0.5);
        let total = mesh.angle_sum(0);
        assert!(total > TAU);
        let first = mesh.outgoing(0).next().unwrap();
        let shadow = Shadow::of(&mesh, 0, Arrival::Edge { half_edge: first }, &tol()).unwrap();
        // The sector starts π (less the margin) from the arrival and is
        // Θ − 2π (plus two margins) wide.
        let m = tol().shadow_angle;
        assert!((shadow.start - (PI - m)).abs() < 1e-12);
        assert!((shadow.end - shadow.start - (total - TAU + 2.0 * m)).abs() < 1e-12);
        // The first corner (directions 0 .. its angle) is far from it.
        assert_eq!(shadow.corner_part(0.0, mesh.corner_angle(first)), None);
        // Exactly one or two corners around the opposite direction meet it,
        // and what they get adds up to the sector's width.
        let mut fan = 0.0;
        let mut lit = 0.0;
        for h in mesh.outgoing(0) {
            let c = mesh.corner_angle(h);
            if let Some((a, b)) = shadow.corner_part(fan, c) {
                let b = b.min(c);
                assert!(0.0 <= a && a <= b);
                lit += b - a;
            }
            fan += c;
        }
        assert!((lit - (shadow.end - shadow.start)).abs() < 1e-12);
    }

    #[test]
    fn a_sector_wraps_around_the_start_of_the_fan() {
        let s = Shadow {
            start: 6.0,
            end: 7.0,
            total: 6.5,
        };
        assert_eq!(s.corner_part(5.5, 1.0), Some((0.5, f64::INFINITY)));
        let (a, b) = s.corner_part(0.0, 1.0).unwrap();
        assert_eq!(a, 0.0);
        assert!((b - 0.5).abs() < 1e-15);
        assert_eq!(s.corner_part(1.0, 1.0), None);
    }

    #[test]
    fn arriving_through_a_window_measures_the_direction_inside_the_corner() {
        let mesh = saddle(6, 0.5);
        // The face of a half-edge opposite vertex 0: its apex is vertex 0.
        let h = (0..mesh.half_edge_count() as u32)
            .find(|&h| mesh.opposite_vertex(h) == 0)
            .unwrap();
        let g = Mesh::prev(h);
        let mut fan = 0.0;
        for k in mesh.outgoing(0) {
            if k == g {
                break;
            }
            fan += mesh.corner_angle(k);
        }
        // Crossing at the tail A of `h` is arriving along `v → A`; at the
        // head B, along the far side of the corner.
        let total = mesh.angle_sum(0);
        let m = tol().shadow_angle;
        for (at, offset) in [(0.0, 0.0), (mesh.length(h), mesh.corner_angle(g))] {
            let s = Shadow::of(&mesh, 0, Arrival::Window { half_edge: h, at }, &tol()).unwrap();
            let want = (fan + offset + PI - m).rem_euclid(total);
            assert!(
                (s.start - want).abs() < 1e-12,
                "{at}: {} vs {want}",
                s.start
            );
        }
    }

    #[test]
    fn a_convex_or_unknown_arrival_is_not_restricted_wrongly() {
        let mesh = saddle(6, 0.5);
        assert_eq!(Shadow::of(&mesh, 0, Arrival::Unknown, &tol()), None);
        // A half-edge that does not leave the vertex tells nothing.
        let other = (0..mesh.half_edge_count() as u32)
            .find(|&h| mesh.tail(h) != 0)
            .unwrap();
        assert_eq!(
            Shadow::of(&mesh, 0, Arrival::Edge { half_edge: other }, &tol()),
            None
        );
    }

    #[test]
    fn rays_of_a_corner_light_the_matching_part_of_the_opposite_edge() {
        let mesh = saddle(6, 0.0);
        let h = mesh.outgoing(0).next().unwrap();
        let corner = mesh.corner_angle(h);
        let (t, full) = pseudo_source_window(&mesh, h, 1.0, 0, ALL_RAYS).unwrap();
        assert_eq!((full.b0, full.b1), (0.0, mesh.length(t)));
        // The middle third of the directions: a ray at ψ from v → a hits
        // the edge where the window's source sees it at that angle.
        let (psi0, psi1) = (corner / 3.0, 2.0 * corner / 3.0);
        let (_, part) = pseudo_source_window(&mesh, h, 1.0, 0, (psi0, psi1)).unwrap();
        assert!(0.0 < part.b0 && part.b0 < part.b1 && part.b1 < full.b1);
        let a = DVec2::new(mesh.length(t), 0.0); // head of the twin: vertex a
        let angle_to = |x: f64| {
            let (u, w) = (a - part.p, DVec2::new(x, 0.0) - part.p);
            u.perp_dot(w).atan2(u.dot(w)).abs()
        };
        assert!((angle_to(part.b1) - psi0).abs() < 1e-12);
        assert!((angle_to(part.b0) - psi1).abs() < 1e-12);
        // Rays outside the corner's range light nothing.
        assert!(pseudo_source_window(&mesh, h, 1.0, 0, (corner, corner)).is_none());
    }

    #[test]
    fn fast_trig_agrees_with_the_library() {
        let mut rng = geodesics_shapes::SplitMix64::new(7);
        let (mut worst_atan, mut worst_sin) = (0.0f64, 0.0f64);
        for _ in 0..100_000 {
            let (x, y) = (rng.next_f64() * 2.0 - 1.0, rng.next_f64() * 2.0 - 1.0);
            worst_atan = worst_atan.max((fast_atan2(y, x) - y.atan2(x)).abs());
            let z = rng.next_f64() * PI;
            worst_sin = worst_sin.max((half_turn_sin(z) - z.sin()).abs());
        }
        assert!(
            worst_atan < 1e-15 && worst_sin < 1e-15,
            "{worst_atan} {worst_sin}"
        );
        // Axes, the reduction's seam, tiny and huge scales.
        for (y, x) in [
            (0.0, 1.0),
            (1.0, 0.0),
            (0.0, -1.0),
            (-1.0, 0.0),
            (TAN_PI_8, 1.0),
            (1e-300, 1.0),
            (1.0, 1e-300),
            (-3e200, -2e200),
        ] {
            assert!((fast_atan2(y, x) - y.atan2(x)).abs() < 1e-15, "({y}, {x})");
        }
        for z in [0.0, FRAC_PI_2, PI, 1e-12] {
            assert!((half_turn_sin(z) - z.sin()).abs() < 1e-15, "{z}");
        }
        assert!(fast_atan2(f64::NAN, 1.0).is_nan());
        assert_eq!(fast_atan2(0.0, -1.0), PI);
    }
}
