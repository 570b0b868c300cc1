//! One window crossing one face with ICH's two pruning rules: Chen and
//! Han's "one angle one split" and Xin and Wang's vertex filter.
//!
//! Both are pure functions of the window, the triangle (in the frame of the
//! half-edge the window lies on, see `geodesics_window`), the current vertex
//! distances and the per-angle record below, so they are tested here on
//! explicit geometry.

use geodesics_window::prune::{one_angle_two_sides, vertex_check};
use geodesics_window::{Tolerance, Triangle, Window};
use glam::DVec2;

/// The "angle" of Chen and Han: the corner `C` of a face, seen from the
/// half-edge `AB` opposite it. Records the shortest path to `C` found so far
/// through `AB` (its length and where it crosses `AB`). Only the window that
/// set it may split at `C` into two children (Chen and Han's "one angle one
/// split"); see [`one_angle_one_split`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Angle {
    /// Length of the shortest path to `C` through `AB` so far.
    pub d: f64,
    /// Where that path crosses `AB` (the separating point of its window).
    pub sp: f64,
}

impl Angle {
    /// No window has crossed `AB` yet.
    pub const EMPTY: Angle = Angle {
        d: f64::INFINITY,
        sp: 0.0,
    };
}

/// Chen and Han's "one angle one split" in its per-vertex form, for a
/// window whose shortest path to `C` (through its interval) has length `d`
/// and crosses `AB` at `sp`.
///
/// If the window is the best so far through `AB` it becomes the angle's
/// occupant and keeps both children (`None`). If the occupant reaches `C`
/// shorter by more than the tolerance, returns the occupant's separating
/// point: the window then loses the rays that cross the occupant's path from
/// `sp` to `C` (Cases 7–9 of Qin et al. 2016, Fig 3: this is
/// [`one_angle_two_sides`] with the occupant as `w_s`). Soundness does not
/// depend on the order in which windows arrive: a ray of the window that
/// crosses the occupant's path at `X` reaches `X` no shorter than
/// `d − |XC|`, while the occupant's path reaches it in `d_s − |XC|`, shorter
/// by more than the margin; whatever lies beyond `X` on that ray is reached
/// shorter through `X` along the occupant. The occupant's window may be long
/// gone (windows are freed when propagated): its path stays a real path.
/// Near-ties keep both children.
#[inline]
pub(crate) fn one_angle_one_split(
    angle: &mut Angle,
    d: f64,
    sp: f64,
    tol: &Tolerance,
) -> Option<f64> {
    if d < angle.d {
        *angle = Angle { d, sp };
        None
    } else {
        tol.beats(angle.d, d).then_some(angle.sp)
    }
}

/// Current distances of the corners of the crossed face `ABC`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Corners {
    /// `d(A)`, the tail of the half-edge the window lies on.
    pub a: f64,
    /// `d(B)`, its head.
    pub b: f64,
    /// `d(C)`, the apex.
    pub c: f64,
}

/// What one window does crossing one face.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Crossing {
    /// Length of the window's shortest path to the apex `C` (a real path;
    /// the caller lowers `d(C)` to it).
    pub apex: f64,
    /// The child on `AC`, in the frame of the half-edge `A → C` beyond, if
    /// any survives the rules.
    pub left: Option<Window>,
    /// The child on `CB`, in the frame of `C → B` beyond.
    pub right: Option<Window>,
    /// Children computed (before the vertex filter), as the papers count
    /// window propagations.
    pub propagations: u32,
}

/// Propagates `w` through `tri` (a proper triangle) with both ICH rules.
///
/// 1. Lights the apex: `apex` is the window's shortest path to `C`, and the
///    corner distance `d(C)` used below is lowered to it.
/// 2. One angle one split (see [`one_angle_one_split`]) decides which rays
///    go on to `AC` and to `CB`.
/// 3. The vertex filter of Xin and Wang (Theorem 3.2 there; Case 12 of Qin
///    et al., [`vertex_check`]): a child is dropped when one of the three
///    corners of `ABC`, with its current distance, gives a shorter path to
///    both ends of the child, hence to all of it. For the child on `AC` the
///    ends are `A` and `C` and the third corner is `B` (below `AC`, on the
///    source side); for `CB` they are `C`, `B` and `A`.
pub(crate) fn cross(
    w: &Window,
    tri: &Triangle,
    angle: &mut Angle,
    corners: Corners,
    tol: &Tolerance,
) -> Crossing {
    let t = w.split_parameter(tri);
    let (d, sp) = w.apex_distance(tri);
    let cut = one_angle_one_split(angle, d, sp, tol);
    let r = one_angle_two_sides(w, t, sp, cut);
    let dc = if d < corners.c { d } else { corners.c };
    let mut out = Crossing {
        apex: d,
        left: None,
        right: None,
        propagations: 0,
    };
    if let Some((x0, x1, reach)) = r.left {
        out.propagations += 1;
        let b_left = tri.to_left_frame(DVec2::new(tri.l, 0.0));
        out.left = w
            .child_left(tri, x0, x1, reach)
            .filter(|cw| !vertex_check(cw, tri.lac, corners.a, dc, b_left, corners.b, tol));
    }
    if let Some((x0, x1, from)) = r.right {
        out.propagations += 1;
        let a_right = tri.to_right_frame(DVec2::ZERO);
        out.right = w
            .child_right(tri, x0, x1, from)
            .filter(|cw| !vertex_check(cw, tri.lcb, dc, corners.b, a_right, corners.a, tol));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    const INF: f64 = f64::INFINITY;

    fn tol() -> Tolerance {
        Tolerance::for_scale(1.0)
    }

    /// A = (0, 0), B = (2, 0), C = (1, 1).
    fn tri() -> Triangle {
        Triangle::new(2.0, DVec2::new(1.0, 1.0))
    }

    fn win(b0: f64, b1: f64, p: (f64, f64), sigma: f64) -> Window {
        Window {
            b0,
            b1,
            p: DVec2::new(p.0, p.1),
            sigma,
            source: 0,
        }
    }

    const FAR: Corners = Corners {
        a: INF,
        b: INF,
        c: INF,
    };

    #[test]
    fn the_first_window_through_an_angle_splits_in_two() {
        let t = tri();
        let mut angle = Angle::EMPTY;
        let w = win(0.0, 2.0, (1.0, -1.0), 0.0);
        let c = cross(&w, &t, &mut angle, FAR, &tol());
        assert_eq!(c.apex, 2.0);
        assert_eq!(angle, Angle { d: 2.0, sp: 1.0 });
        assert_eq!(c.propagations, 2);
        let (l, r) = (c.left.unwrap(), c.right.unwrap());
        // Both children reach C (whole edges, C at distance 2).
        assert!((l.b1 - t.lac).abs() < 1e-15 && (r.b0 - 0.0).abs() < 1e-15);
        assert!((l.distance_at(l.b1) - 2.0).abs() < 1e-14);
        assert!((r.distance_at(r.b0) - 2.0).abs() < 1e-14);
    }

    #[test]
    fn a_worse_window_through_an_occupied_angle_loses_the_crossing_rays() {
        let t = tri();
        let tol = tol();
        let mut angle = Angle::EMPTY;
        // Occupant: straight below C, reaches C at 2 crossing AB at 1.
        let best = win(0.0, 2.0, (1.0, -1.0), 0.0);
        cross(&best, &t, &mut angle, FAR, &tol);
        // A worse window from lower left: its line to C crosses AB at 0.6,
        // it reaches C at 0.5 + |(0.2,-1)(1,1)| = 0.5 + sqrt(4.64) > 2.
        let w = win(0.0, 2.0, (0.2, -1.0), 0.5);
        let split = w.split_parameter(&t);
        assert!((split - 0.6).abs() < 1e-15);
        let c = cross(&w, &t, &mut angle, FAR, &tol);
        assert!((c.apex - (0.5 + 4.64f64.sqrt())).abs() < 1e-14);
        // The occupant stays.
        assert_eq!(angle, Angle { d: 2.0, sp: 1.0 });
        assert_eq!(c.propagations, 2);
        // Left: all rays left of its own split [0, 0.6], ending at C.
        let l = c.left.unwrap();
        assert!((l.b0 - 0.0).abs() < 1e-15 && (l.b1 - t.lac).abs() < 1e-15);
        // Right: only the rays entering right of the occupant's crossing
        // (x >= 1): rays through (0.6, 1) cross the occupant's path to C.
        let r = c.right.unwrap();
        let start = r.b0;
        // The ray of w through x = 1 meets CB at the child's start.
        let q = w.p + (DVec2::new(1.0, 0.0) - w.p) * 1.0;
        let dir = (q - w.p).normalize();
        let on_cb = t.c + t.v * start;
        assert!((on_cb - w.p).normalize().distance(dir) < 1e-12);
        assert!(start > 0.0);
        // And the pruned part really is beaten: a ray through x = 0.8 meets
        // the segment from (1, 0) to C at X, where the occupant is shorter.
        let x = DVec2::new(0.8, 0.0);
        let dir = (x - w.p).normalize();
        // Segment (1, 0) -> (1, 1): X has x = 1.
        let s = (1.0 - w.p.x) / dir.x;
        let hit = w.p + dir * s;
        assert!(hit.y > 0.0 && hit.y < 1.0);
        let via_occupant = best.distance_to(DVec2::new(1.0, 0.0)) + hit.y;
        assert!(tol.beats(via_occupant, w.distance_to(hit)));
    }

    #[test]
    fn a_better_window_takes_the_angle_over_whatever_the_order() {
        let t = tri();
        let tol = tol();
        let mut angle = Angle::EMPTY;
        let worse = win(0.0, 2.0, (0.2, -1.0), 0.5);
        let better = win(0.0, 2.0, (1.0, -1.0), 0.0);
        // Worse first: it is the occupant for now and splits.
        let c = cross(&worse, &t, &mut angle, FAR, &tol);
        assert!(c.left.is_some() && c.right.is_some());
        let r = c.right.unwrap();
        assert!(r.b0 == 0.0, "the first window splits at C");
        // The better one takes over, also splitting.
        let c = cross(&better, &t, &mut angle, FAR, &tol);
        assert!(c.left.is_some() && c.right.is_some());
        assert_eq!(angle, Angle { d: 2.0, sp: 1.0 });
    }

    #[test]
    fn near_ties_at_the_apex_keep_both_children() {
        let t = tri();
        let tol = tol();
        let mut angle = Angle::EMPTY;
        // Two sources symmetric about the line x = 1: the same distance to C.
        let w0 = win(0.0, 2.0, (0.5, -1.0), 0.0);
        let w1 = win(0.0, 2.0, (1.5, -1.0), 0.0);
        let c0 = cross(&w0, &t, &mut angle, FAR, &tol);
        let c1 = cross(&w1, &t, &mut angle, FAR, &tol);
        assert!((c0.apex - c1.apex).abs() < 1e-15);
        assert!(c1.left.is_some() && c1.right.is_some());
        assert!(c1.right.unwrap().b0 == 0.0 && (c1.left.unwrap().b1 - t.lac).abs() < 1e-15);
        // One angle one split, directly: a tie is not a cut.
        let mut a = Angle { d: 1.0, sp: 0.3 };
        assert_eq!(one_angle_one_split(&mut a, 1.0, 0.7, &tol), None);
        assert_eq!(
            one_angle_one_split(&mut a, 1.0 + 1e-9, 0.7, &tol),
            Some(0.3)
        );
        assert_eq!(one_angle_one_split(&mut a, 0.5, 0.7, &tol), None);
        assert_eq!(a, Angle { d: 0.5, sp: 0.7 });
    }

    #[test]
    fn the_vertex_filter_drops_children_beaten_by_a_corner() {
        let t = tri();
        let tol = tol();
        // A window from far away (sigma 10) straight below C.
        let w = win(0.0, 2.0, (1.0, -1.0), 10.0);
        // B is already at distance 0.5: B beats the whole left child on AC
        // (through B, the ends A and C are at 2.5 and 0.5 + sqrt 2, against
        // 10 + sqrt 2 and 12). On CB, B is an end of the edge and wins too.
        let corners = Corners {
            a: INF,
            b: 0.5,
            c: INF,
        };
        let mut angle = Angle::EMPTY;
        let c = cross(&w, &t, &mut angle, corners, &tol);
        assert_eq!(c.propagations, 2, "children are computed, then filtered");
        assert!(c.left.is_none() && c.right.is_none());
        // The apex is still lit (a real path): the caller lowers d(C).
        assert!((c.apex - 12.0).abs() < 1e-14);

        // Only A is known, at a distance that beats the left child at its
        // far end C (A is its start: d(A) + |AC| < sigma + |pC|) but not
        // the right child at either end.
        let corners = Corners {
            a: 10.0,
            b: INF,
            c: INF,
        };
        let mut angle = Angle::EMPTY;
        let c = cross(&w, &t, &mut angle, corners, &tol);
        // Left child: A at 10 gives C at 10 + sqrt 2 < 12: dropped.
        assert!(c.left.is_none());
        // Right child on CB: A is the third corner; through A, C is at
        // 10 + sqrt 2 < 12 but B at 12 > 10 + sqrt 2: kept.
        assert!(c.right.is_some());

        // The window's own distances never filter its children.
        let corners = Corners {
            a: w.distance_at(0.0),
            b: w.distance_at(2.0),
            c: INF,
        };
        let mut angle = Angle::EMPTY;
        let c = cross(&w, &t, &mut angle, corners, &tol);
        assert!(c.left.is_some() && c.right.is_some());
    }

    #[test]
    fn grazing_windows_light_the_apex_but_have_no_children() {
        let t = tri();
        let mut angle = Angle::EMPTY;
        let w = win(0.0, 2.0, (-1.0, 0.0), 0.0);
        let c = cross(&w, &t, &mut angle, FAR, &tol());
        assert!(c.left.is_none() && c.right.is_none());
        assert!(c.apex.is_finite());
    }

    #[test]
    fn the_queue_key_is_the_nearest_point_of_the_interval() {
        let w = win(0.0, 2.0, (1.0, -1.0), 0.5);
        assert_eq!(w.least_distance(), 1.5);
        let w = win(1.5, 2.0, (1.0, -1.0), 0.5);
        assert!((w.least_distance() - (0.5 + 1.25f64.sqrt())).abs() < 1e-15);
        let w = win(0.0, 0.5, (1.0, -1.0), 0.0);
        assert!((w.least_distance() - 1.25f64.sqrt()).abs() < 1e-15);
    }
}
