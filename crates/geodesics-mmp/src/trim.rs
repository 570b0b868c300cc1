//! Interval trimming (Section 3.3 of Surazhsky et al. 2005, after step 2 of
//! Mitchell, Mount and Papadimitriou's Insert-Interval): where two windows
//! overlap on an edge, each point keeps only the window giving it the
//! shorter distance, cut at the exact tie point.
//!
//! A window's distance along its edge is a cone `σ + √((x − px)² + py²)`
//! ([`Cone`]); which side of the edge its pseudo-source lies on does not
//! matter (`py ≥ 0`), so windows crossing the edge in opposite directions
//! are compared the same way. The difference `g` of two cones has one
//! critical point, where the line through the two pseudo-sources (put on the
//! same side) meets the edge, and is monotone on each side of it: so it has
//! at most two zeros, each found by a bracketed root search on a monotone
//! piece (never by the closed-form quadratic, whose coefficients cancel
//! catastrophically when the pseudo-sources are close).

use geodesics_window::Tolerance;

/// A window's distance function along its edge: `σ + √((x − px)² + py²)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Cone {
    /// Foot of the pseudo-source along the edge.
    pub px: f64,
    /// Distance of the pseudo-source from the edge line (`≥ 0`).
    pub py: f64,
    /// Distance of the pseudo-source from the source.
    pub sigma: f64,
}

impl Cone {
    /// Distance at `x`.
    #[inline]
    pub fn at(&self, x: f64) -> f64 {
        let dx = x - self.px;
        self.sigma + (dx * dx + self.py * self.py).sqrt()
    }

    /// Smallest distance over `[x0, x1]` (the queue key of a window).
    #[inline]
    pub fn min_on(&self, x0: f64, x1: f64) -> f64 {
        self.at(self.px.clamp(x0, x1))
    }
}

/// Up to two disjoint sub-intervals, in increasing order.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Pieces {
    pub n: usize,
    pub iv: [(f64, f64); 2],
}

impl Pieces {
    fn push(&mut self, a: f64, b: f64) {
        if !(a < b) {
            return;
        }
        if self.n > 0 && self.iv[self.n - 1].1 == a {
            self.iv[self.n - 1].1 = b;
        } else {
            self.iv[self.n] = (a, b);
            self.n += 1;
        }
    }

    /// The intervals.
    pub fn as_slice(&self) -> &[(f64, f64)] {
        &self.iv[..self.n]
    }
}

/// The parts of the overlap `[c0, c1]` where `new` is strictly shorter than
/// `old` (at most two intervals). Ties go to `old`: exactly at a tie point,
/// and on the whole overlap when the two cones never differ by more than
/// the tolerance there (duplicates: the same wavefront reached twice).
pub(crate) fn new_wins(new: &Cone, old: &Cone, c0: f64, c1: f64, tol: &Tolerance) -> Pieces {
    let mut out = Pieces::default();
    if !(c0 < c1) {
        return out;
    }
    let g = |x: f64| new.at(x) - old.at(x);
    // The critical point of g: where the line through both pseudo-sources
    // (on the same side) meets the edge.
    let mut xs = f64::NAN;
    if new.py != old.py {
        let x = new.px + (old.px - new.px) * new.py / (new.py - old.py);
        if x > c0 && x < c1 {
            xs = x;
        }
    }
    let (g0, g1) = (g(c0), g(c1));
    let gs = if xs.is_nan() { 0.0 } else { g(xs) };
    // |g| is largest at a breakpoint (g is monotone between them).
    let tied = |gv: f64, x: f64| gv.abs() <= tol.margin(old.at(x));
    if tied(g0, c0) && tied(g1, c1) && (xs.is_nan() || tied(gs, xs)) {
        return out;
    }
    if xs.is_nan() {
        monotone_piece(new, old, (c0, g0), (c1, g1), &mut out);
    } else {
        monotone_piece(new, old, (c0, g0), (xs, gs), &mut out);
        monotone_piece(new, old, (xs, gs), (c1, g1), &mut out);
    }
    out
}

/// On `[a, b]` where `g` is monotone, appends where `g < 0`.
fn monotone_piece(
    new: &Cone,
    old: &Cone,
    (a, ga): (f64, f64),
    (b, gb): (f64, f64),
    out: &mut Pieces,
) {
    match (ga < 0.0, gb < 0.0) {
        (true, true) => out.push(a, b),
        (false, false) => {}
        (true, false) => out.push(a, root(new, old, a, ga, b, gb)),
        (false, true) => out.push(root(new, old, a, ga, b, gb), b),
    }
}

/// A zero of `g = new − old` in `[a, b]`, where `g` is monotone and
/// `g(a)`, `g(b)` differ in sign: Newton's method safeguarded by the
/// bracket (bisection when a step leaves it), started at the secant point,
/// until `g` is zero, Newton stalls, or the bracket cannot be split in
/// floating point: the tie point to the last bit, so that no point is given
/// to a window longer there by more than rounding (a cut off by the length
/// margin would let paths pass up to `√(margin · length)` beside vertices).
fn root(new: &Cone, old: &Cone, mut a: f64, ga: f64, mut b: f64, gb: f64) -> f64 {
    let neg_a = ga < 0.0;
    let mut x = (a * gb - b * ga) / (gb - ga);
    if !(x > a && x < b) {
        x = 0.5 * (a + b);
    }
    for _ in 0..100 {
        let (dn, d_o) = (x - new.px, x - old.px);
        let rn = (dn * dn + new.py * new.py).sqrt();
        let ro = (d_o * d_o + old.py * old.py).sqrt();
        let gx = new.sigma + rn - old.sigma - ro;
        if gx == 0.0 {
            return x;
        }
        if (gx < 0.0) == neg_a {
            a = x;
        } else {
            b = x;
        }
        // g' = cos(new) − cos(old); NaN or zero slopes fall back to bisection.
        let slope = dn / rn - d_o / ro;
        let mut next = x - gx / slope;
        if next == x {
            break;
        }
        if !(next > a && next < b) {
            next = 0.5 * (a + b);
            if !(next > a && next < b) {
                break;
            }
        }
        x = next;
    }
    x
}

/// `[lo, hi]` minus the sorted, disjoint intervals `cut` (each inside or
/// overlapping `[lo, hi]`), appended to `out`.
pub(crate) fn subtract(lo: f64, hi: f64, cut: &[(f64, f64)], out: &mut Vec<(f64, f64)>) {
    let mut at = lo;
    for &(a, b) in cut {
        if a > at {
            out.push((at, a.min(hi)));
        }
        if b > at {
            at = b;
        }
        if at >= hi {
            return;
        }
    }
    if at < hi {
        out.push((at, hi));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tol() -> Tolerance {
        Tolerance::for_scale(10.0)
    }

    fn cone(px: f64, py: f64, sigma: f64) -> Cone {
        Cone { px, py, sigma }
    }

    #[test]
    fn equal_sources_side_by_side_tie_at_the_bisector() {
        // Two sources at the same height and distance: the tie point is
        // midway between their feet; the new one (left) wins left of it.
        let a = cone(0.0, 1.0, 0.0);
        let b = cone(2.0, 1.0, 0.0);
        let w = new_wins(&a, &b, -1.0, 3.0, &tol());
        assert_eq!(w.as_slice(), &[(-1.0, 1.0)]);
        let w = new_wins(&b, &a, -1.0, 3.0, &tol());
        assert_eq!(w.as_slice(), &[(1.0, 3.0)]);
    }

    #[test]
    fn different_sigmas_cut_at_the_hyperbola() {
        // sigma_a + |x| = sigma_b + |2 - x| with both sources on the edge
        // line's neighbourhood: check the tie point solves the equation.
        let a = cone(0.0, 0.5, 0.3);
        let b = cone(2.0, 0.8, 0.0);
        let w = new_wins(&a, &b, 0.0, 2.0, &tol());
        assert_eq!(w.n, 1);
        let (lo, r) = w.iv[0];
        assert_eq!(lo, 0.0);
        assert!((a.at(r) - b.at(r)).abs() <= tol().margin(1.0), "tie at {r}");
        assert!(a.at(r - 1e-6) < b.at(r - 1e-6) && a.at(r + 1e-6) > b.at(r + 1e-6));
    }

    #[test]
    fn full_dominance_either_way() {
        let near = cone(1.0, 1.0, 0.0);
        let far = cone(1.0, 1.0, 0.5);
        assert_eq!(
            new_wins(&near, &far, 0.0, 2.0, &tol()).as_slice(),
            &[(0.0, 2.0)]
        );
        assert_eq!(new_wins(&far, &near, 0.0, 2.0, &tol()).n, 0);
    }

    #[test]
    fn two_tie_points_new_wins_in_the_middle() {
        // The new source is close to the edge at x = 1 with a larger sigma;
        // the old one is far below: the new wins only around x = 1
        // (the case Lemma 2.1 of L'Hostis misses: ends alone decide nothing).
        let new = cone(1.0, 0.1, 9.5);
        let old = cone(1.0, 10.0, 0.0);
        let w = new_wins(&new, &old, 0.0, 2.0, &tol());
        assert_eq!(w.n, 1);
        let (r0, r1) = w.iv[0];
        assert!(r0 > 0.0 && r1 < 2.0 && r0 < 1.0 && r1 > 1.0);
        assert!((new.at(r0) - old.at(r0)).abs() <= tol().margin(10.0));
        assert!((new.at(r1) - old.at(r1)).abs() <= tol().margin(10.0));
        // And the other way round the old one is split into two pieces.
        let w = new_wins(&old, &new, 0.0, 2.0, &tol());
        assert_eq!(w.n, 2);
        assert_eq!(w.iv[0].0, 0.0);
        assert_eq!(w.iv[1].1, 2.0);
        assert!((w.iv[0].1 - r0).abs() < 1e-12 && (w.iv[1].0 - r1).abs() < 1e-12);
    }

    #[test]
    fn duplicates_and_mirror_images_keep_the_old_window() {
        let a = cone(0.7, 0.4, 1.0);
        assert_eq!(new_wins(&a, &a, 0.0, 2.0, &tol()).n, 0);
        // A hair better everywhere, within the tolerance: still a tie.
        let b = cone(0.7, 0.4, 1.0 - 1e-16);
        assert_eq!(new_wins(&b, &a, 0.0, 2.0, &tol()).n, 0);
        // Clearly better: wins.
        let c = cone(0.7, 0.4, 1.0 - 1e-9);
        assert_eq!(new_wins(&c, &a, 0.0, 2.0, &tol()).as_slice(), &[(0.0, 2.0)]);
    }

    #[test]
    fn touching_intervals_do_not_interact() {
        let a = cone(0.0, 1.0, 0.0);
        assert_eq!(new_wins(&a, &a, 1.0, 1.0, &tol()).n, 0);
    }

    #[test]
    fn subtracting_pieces() {
        let mut out = Vec::new();
        subtract(0.0, 10.0, &[(2.0, 3.0), (5.0, 6.0)], &mut out);
        assert_eq!(out, vec![(0.0, 2.0), (3.0, 5.0), (6.0, 10.0)]);
        out.clear();
        subtract(0.0, 10.0, &[(0.0, 3.0), (5.0, 10.0)], &mut out);
        assert_eq!(out, vec![(3.0, 5.0)]);
        out.clear();
        subtract(0.0, 10.0, &[(-1.0, 11.0)], &mut out);
        assert!(out.is_empty());
    }

    #[test]
    fn cone_minimum_on_an_interval() {
        let a = cone(1.0, 1.0, 0.5);
        assert_eq!(a.min_on(0.0, 2.0), 1.5);
        assert!((a.min_on(2.0, 3.0) - (0.5 + 2f64.sqrt())).abs() < 1e-15);
    }
}
