//! Pruning predicates (Section 3 and 4 of Qin et al. 2016).
//!
//! Every predicate here only discards a window, or part of one, when a real
//! path on the surface (through another window, a vertex, or a window end)
//! is shorter by more than the [`Tolerance`] margin at every point the
//! discarded part could reach. The proofs are Proposition A.1 of the paper;
//! each function names the case it implements.
//!
//! | paper | here |
//! |---|---|
//! | Situation 1–2, Cases 1, 2, 4, 5 (overlapping windows on one edge, from the same or from two edges) | [`overlap_dominance`], [`prune_adjacent`] |
//! | Situation 3, Cases 7–9 (one list, two sides: Rule 1, "one angle two sides") | [`one_angle_two_sides`] |
//! | Situation 4, Cases 10–12 (checking with vertices, the ICH filter) | [`vertex_check`] |
//! | Cases 3, 6 (windows whose rays crossed inside the triangle) | not pruned pairwise: they are disjoint on the edge and the vertex check and Rule 1 of the next face catch them |
//! | Case 13 | skipped, as in the paper |

use glam::DVec2;

use crate::{Tolerance, Window};

/// The sub-ranges of a window's interval that go to each side of the apex
/// after Rule 1 (`[x0, x1]` on `AB`, plus whether the range ends exactly at
/// the split parameter, i.e. its ray hits `C`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SideRanges {
    /// Rays that reach `AC`: `(x0, x1, reaches_apex)`.
    pub left: Option<(f64, f64, bool)>,
    /// Rays that reach `CB`: `(x0, x1, from_apex)`.
    pub right: Option<(f64, f64, bool)>,
}

/// Rule 1, "one angle two sides" (Proposition 4.1; Cases 7–9 of Fig 3).
///
/// `t` is the window's split parameter (where its line to `C` crosses `AB`)
/// and `sp` its separating point. `cut` is the separating point of the
/// list's best window `w_s` when `w_s` reaches `C` shorter than this window
/// by more than the tolerance (`None` for `w_s` itself or a near-tie).
///
/// Soundness (our proof, stricter than the paper's statement): if
/// `w.sp < w_s.sp`, a ray of `w` entering `AB` left of `w_s.sp` and leaving
/// through `CB` must cross the segment from `w_s.sp` to `C`, where the path
/// through `w_s` is shorter (Observation (d)); such rays are pruned. Rays of
/// `w` entering right of `w_s.sp` cross nothing and are kept. Symmetrically
/// for `w.sp > w_s.sp` and the side `AC`.
#[inline]
pub fn one_angle_two_sides(w: &Window, t: f64, sp: f64, cut: Option<f64>) -> SideRanges {
    let (mut lx1, mut reach) = if t <= w.b1 { (t, true) } else { (w.b1, false) };
    let (mut rx0, mut from) = if t >= w.b0 { (t, true) } else { (w.b0, false) };
    if let Some(s) = cut {
        if sp > s && s < lx1 {
            lx1 = s;
            reach = false;
        } else if sp < s && s > rx0 {
            rx0 = s;
            from = false;
        }
    }
    SideRanges {
        left: (w.b0 < lx1).then_some((w.b0, lx1, reach)),
        right: (rx0 < w.b1).then_some((rx0, w.b1, from)),
    }
}

/// Checking with vertices (Cases 10–12 of Fig 3, the filter of ICH).
///
/// `w` lies on an edge of length `len` whose ends are vertices at current
/// distances `d_start` (at 0) and `d_end` (at `len`); `third` is the
/// remaining vertex of the triangle the window just crossed (on the source
/// side, in the edge's frame) at distance `d_third`. Returns `true` when the
/// window is redundant:
///
/// - `d_start + b1 < σ + |p b1|`: the start vertex, going along the edge,
///   beats the window at its far end, hence everywhere (σ + |p x| − x does
///   not increase along the edge), so every path through the window is
///   beaten by one through the start vertex (Observation (a));
/// - `d_end + (len − b0) < σ + |p b0|`: the same from the other end;
/// - the third vertex beats the window at both ends: `|p x| − |third x|`
///   has its only interior extremum, a maximum, on the line through `p` and
///   `third` (both are below the edge and `third` cannot be behind `p`), so
///   it beats it on the whole interval.
#[inline]
#[allow(clippy::too_many_arguments)]
pub fn vertex_check(
    w: &Window,
    len: f64,
    d_start: f64,
    d_end: f64,
    third: DVec2,
    d_third: f64,
    tol: &Tolerance,
) -> bool {
    let e0 = w.distance_at(w.b0);
    let e1 = w.distance_at(w.b1);
    if tol.beats(d_start + w.b1, e1) || tol.beats(d_end + (len - w.b0), e0) {
        return true;
    }
    d_third.is_finite()
        && tol.beats(d_third + third.distance(DVec2::new(w.b0, 0.0)), e0)
        && tol.beats(d_third + third.distance(DVec2::new(w.b1, 0.0)), e1)
}

/// Which of two windows on the same edge (same frame) is shorter on their
/// common interval.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Dominance {
    /// The intervals do not overlap (or only touch).
    Disjoint,
    /// The first window is shorter by more than the tolerance everywhere on
    /// the overlap.
    First,
    /// The second window is.
    Second,
    /// Neither (they cross, or are within the tolerance somewhere).
    Neither,
}

/// Compares two windows on their overlap (Cases 2 and 5 of Fig 3, as in
/// step 2 of Mitchell et al.'s Insert-Interval but without solving the
/// quadratic for the tie point).
///
/// The difference `|q x| − |p x|` of distances to two points on the same
/// side of the edge is monotone on each side of `x*`, where the line `pq`
/// meets the edge, and extremal at `x*`; so checking the overlap ends and
/// `x*` (if inside) decides "everywhere".
pub fn overlap_dominance(w0: &Window, w1: &Window, tol: &Tolerance) -> Dominance {
    let c0 = w0.b0.max(w1.b0);
    let c1 = w0.b1.min(w1.b1);
    if !(c0 < c1) {
        return Dominance::Disjoint;
    }
    let mut first = true;
    let mut second = true;
    let mut test = |x: f64| {
        let d0 = w0.distance_at(x);
        let d1 = w1.distance_at(x);
        first &= tol.beats(d0, d1);
        second &= tol.beats(d1, d0);
    };
    test(c0);
    test(c1);
    let (p, q) = (w0.p, w1.p);
    if p.y != q.y {
        let xs = p.x + (q.x - p.x) * (-p.y) / (q.y - p.y);
        if xs > c0 && xs < c1 {
            test(xs);
        }
    }
    match (first, second) {
        (true, _) => Dominance::First,
        (_, true) => Dominance::Second,
        _ => Dominance::Neither,
    }
}

/// What [`prune_adjacent`] decided.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PairOutcome {
    /// Both windows stay (possibly trimmed).
    KeepBoth,
    /// The first window is redundant.
    RemoveFirst,
    /// The second window is redundant.
    RemoveSecond,
}

/// Pairwise pruning of two windows adjacent in a list on the same edge
/// (Rules 2 and 3: Cases 1, 2, 4 and 5 of Fig 3). Where one window is
/// shorter on their whole overlap, the other loses the overlap: removed if
/// it lies inside it, trimmed if it sticks out on one side, kept whole if it
/// sticks out on both (trimming would split it).
pub fn prune_adjacent(w0: &mut Window, w1: &mut Window, tol: &Tolerance) -> PairOutcome {
    match overlap_dominance(w0, w1, tol) {
        Dominance::First => trim_loser(w0, w1, PairOutcome::RemoveSecond),
        Dominance::Second => trim_loser(w1, w0, PairOutcome::RemoveFirst),
        Dominance::Disjoint | Dominance::Neither => PairOutcome::KeepBoth,
    }
}

#[inline]
fn trim_loser(winner: &Window, loser: &mut Window, remove: PairOutcome) -> PairOutcome {
    let left_out = loser.b0 < winner.b0;
    let right_out = loser.b1 > winner.b1;
    match (left_out, right_out) {
        (false, false) => remove,
        (true, false) => {
            loser.b1 = winner.b0;
            PairOutcome::KeepBoth
        }
        (false, true) => {
            loser.b0 = winner.b1;
            PairOutcome::KeepBoth
        }
        (true, true) => PairOutcome::KeepBoth,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tol() -> Tolerance {
        Tolerance::for_scale(1.0)
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

    #[test]
    fn rule1_prunes_only_rays_crossing_the_best_path() {
        // w_s splits at 1.0; w lies left of it with its own split at 0.3.
        let w = win(0.0, 1.5, (0.3, -1.0), 0.0);
        let r = one_angle_two_sides(&w, 0.3, 0.3, Some(1.0));
        assert_eq!(r.left, Some((0.0, 0.3, true)));
        // Right rays through [0.3, 1.0) cross w_s's path to C: pruned.
        assert_eq!(r.right, Some((1.0, 1.5, false)));
        // Without a dominating best window both sides stay whole.
        let r = one_angle_two_sides(&w, 0.3, 0.3, None);
        assert_eq!(r.right, Some((0.3, 1.5, true)));
        // Symmetric side: w right of w_s loses its left rays left of cut.
        let w = win(0.5, 2.0, (1.8, -1.0), 0.0);
        let r = one_angle_two_sides(&w, 1.8, 1.8, Some(1.0));
        assert_eq!(r.left, Some((0.5, 1.0, false)));
        assert_eq!(r.right, Some((1.8, 2.0, true)));
    }

    #[test]
    fn vertex_check_by_edge_ends_and_third_vertex() {
        let t = tol();
        // Window far from its source: the start vertex at distance 0 wins.
        let w = win(0.5, 1.0, (0.7, -1.0), 5.0);
        assert!(vertex_check(
            &w,
            2.0,
            0.0,
            f64::INFINITY,
            DVec2::new(1.0, -1.0),
            f64::INFINITY,
            &t
        ));
        assert!(vertex_check(
            &w,
            2.0,
            f64::INFINITY,
            0.0,
            DVec2::new(1.0, -1.0),
            f64::INFINITY,
            &t
        ));
        assert!(vertex_check(
            &w,
            2.0,
            f64::INFINITY,
            f64::INFINITY,
            DVec2::new(1.0, -1.0),
            0.0,
            &t
        ));
        // A window that is the best path is kept.
        let w = win(0.5, 1.0, (0.7, -1.0), 0.0);
        assert!(!vertex_check(
            &w,
            2.0,
            1.0,
            2.0,
            DVec2::new(1.0, -1.0),
            1.0,
            &t
        ));
        // Ties are kept.
        let d1 = w.distance_at(1.0);
        assert!(!vertex_check(
            &w,
            2.0,
            d1 - 1.0,
            f64::INFINITY,
            DVec2::ZERO,
            f64::INFINITY,
            &t
        ));
    }

    #[test]
    fn overlap_dominance_cases() {
        let t = tol();
        let a = win(0.0, 1.0, (0.5, -1.0), 0.0);
        let b = win(0.5, 1.5, (1.0, -1.0), 1.0);
        assert_eq!(overlap_dominance(&a, &b, &t), Dominance::First);
        assert_eq!(overlap_dominance(&b, &a, &t), Dominance::Second);
        let c = win(2.0, 3.0, (1.0, -1.0), 0.0);
        assert_eq!(overlap_dominance(&a, &c, &t), Dominance::Disjoint);
        // Two equal sources side by side cross in the middle.
        let d = win(0.0, 1.0, (1.0, -1.0), 0.0);
        assert_eq!(overlap_dominance(&a, &d, &t), Dominance::Neither);
        // Identical windows: a tie, kept.
        assert_eq!(overlap_dominance(&a, &a, &t), Dominance::Neither);
    }

    #[test]
    fn dominance_sees_an_interior_extremum() {
        let t = tol();
        // q lies straight behind p along a line hitting the edge inside the
        // overlap: |q x| - |p x| peaks there, so checking ends is not enough.
        let p = win(0.0, 2.0, (1.0, -0.1), 9.5);
        let q = win(0.0, 2.0, (1.0, -10.0), 0.0);
        // At the ends q is better (10.05 vs 10.5); at x = 1, where the line
        // pq meets the edge, p is (9.6 vs 10.0): neither dominates.
        assert!(q.distance_at(0.0) < p.distance_at(0.0));
        assert!(q.distance_at(2.0) < p.distance_at(2.0));
        assert!(q.distance_at(1.0) > p.distance_at(1.0));
        assert_eq!(overlap_dominance(&p, &q, &t), Dominance::Neither);
    }

    #[test]
    fn adjacent_pruning_trims_removes_or_keeps() {
        let t = tol();
        let mut a = win(0.0, 1.0, (0.5, -1.0), 0.0);
        let mut b = win(0.5, 1.5, (1.0, -1.0), 1.0);
        assert_eq!(prune_adjacent(&mut a, &mut b, &t), PairOutcome::KeepBoth);
        assert_eq!((b.b0, b.b1), (1.0, 1.5));
        let mut a = win(0.0, 1.0, (0.5, -1.0), 0.0);
        let mut b = win(0.2, 0.8, (1.0, -1.0), 1.0);
        assert_eq!(
            prune_adjacent(&mut a, &mut b, &t),
            PairOutcome::RemoveSecond
        );
        let mut a = win(0.0, 1.0, (0.5, -1.0), 3.0);
        let mut b = win(0.2, 0.8, (0.5, -1.0), 0.0);
        // b better on the overlap, a sticks out on both sides: kept.
        assert_eq!(prune_adjacent(&mut a, &mut b, &t), PairOutcome::KeepBoth);
        assert_eq!((a.b0, a.b1), (0.0, 1.0));
        let mut a = win(0.0, 1.0, (0.5, -1.0), 3.0);
        let mut b = win(0.0, 1.0, (0.5, -1.0), 0.0);
        assert_eq!(prune_adjacent(&mut a, &mut b, &t), PairOutcome::RemoveFirst);
    }
}
