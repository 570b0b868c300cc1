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
//! | Cases 3, 6 (windows whose rays crossed inside the triangle, so they come out side by side in swapped order) | [`disjoint_pair`] (called by [`prune_adjacent`]) |
//! | Case 13 | skipped, as in the paper |

use glam::DVec2;

use crate::window::{larger, smaller};
use crate::{EndedWindow, Tolerance, Window};

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

/// Rule 1's first pass over a list crossing `tri`: each window's view of
/// the apex ([`EndedWindow::apex_path`]: `(t, sp, d)`) into `paths`
/// (cleared first), and the list's best path to the apex with the index
/// of the window giving it (the first on ties; `(∞, 0)` when none lights
/// it). Filled by one exact-length extend, not a push per window.
#[inline]
pub fn apex_paths(
    list: &[EndedWindow],
    tri: &crate::Triangle,
    paths: &mut Vec<(f64, f64, f64)>,
) -> (f64, usize) {
    paths.clear();
    let mut best = f64::INFINITY;
    let mut at = 0;
    paths.extend(list.iter().enumerate().map(|(i, e)| {
        let path = e.apex_path(tri);
        if path.2 < best {
            best = path.2;
            at = i;
        }
        path
    }));
    (best, at)
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
    vertex_check_ended(
        &EndedWindow::new(*w),
        len,
        d_start,
        d_end,
        third,
        d_third,
        tol,
    )
}

/// [`vertex_check`] on a window whose end distances are cached.
#[inline]
#[allow(clippy::too_many_arguments)]
pub fn vertex_check_ended(
    w: &EndedWindow,
    len: f64,
    d_start: f64,
    d_end: f64,
    third: DVec2,
    d_third: f64,
    tol: &Tolerance,
) -> bool {
    let (b0, b1) = (w.window.b0, w.window.b1);
    // Non-short-circuit `|` and `&`: every test is a few flops, cheaper
    // than a mispredicted branch.
    beaten_from_edge_ends(w, len, d_start, d_end, tol)
        | (reach_beats(d_third, third, b0, w.d0, tol) & reach_beats(d_third, third, b1, w.d1, tol))
}

/// The edge-end half of [`vertex_check_ended`], for a window with no
/// vertex behind it worth checking (a pseudo-source's own window: the
/// vertex behind is its source): a path to an end vertex, then along the
/// edge, beats the window everywhere.
#[inline]
pub fn beaten_from_edge_ends(
    w: &EndedWindow,
    len: f64,
    d_start: f64,
    d_end: f64,
    tol: &Tolerance,
) -> bool {
    tol.beats(d_start + w.window.b1, w.d1) | tol.beats(d_end + (len - w.window.b0), w.d0)
}

/// Whether the path to `(x, 0)` through the point `from` (reached at
/// distance `d_from`) beats `target` by the margin:
/// `tol.beats(d_from + |from − (x, 0)|, target)`, decided on squares so no
/// square root is taken (the rounding differs by a few ulps, far inside
/// the margin).
#[inline]
fn reach_beats(d_from: f64, from: DVec2, x: f64, target: f64, tol: &Tolerance) -> bool {
    let room = target - tol.margin(target) - d_from;
    (room > 0.0) & (from.distance_squared(DVec2::new(x, 0.0)) < room * room)
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
    overlap_dominance_ended(&EndedWindow::new(*w0), &EndedWindow::new(*w1), tol)
}

/// [`overlap_dominance`] on windows whose end distances are cached.
#[inline]
pub fn overlap_dominance_ended(e0: &EndedWindow, e1: &EndedWindow, tol: &Tolerance) -> Dominance {
    compare_on_overlap(e0, e1, tol).0
}

/// What [`compare_on_overlap`] found at the ends `c0 < c1` of the overlap
/// of two windows (unset when they are disjoint).
#[derive(Clone, Copy, Debug)]
struct OverlapEnds {
    c0: f64,
    c1: f64,
    /// `[w0(c0), w1(c0), w0(c1), w1(c1)]`.
    d: [f64; 4],
    /// Whether `w0` beats `w1` at `c0`, and at `c1`.
    first_at: [bool; 2],
    /// Whether `w1` beats `w0` at `c0`, and at `c1`.
    second_at: [bool; 2],
}

impl OverlapEnds {
    /// Whether the shorter window changes between the overlap's ends, each
    /// end decided by more than the margin (then they cross once inside).
    #[inline]
    fn cross(&self) -> bool {
        (self.first_at[0] & self.second_at[1]) | (self.second_at[0] & self.first_at[1])
    }
}

/// The distances `(w0(c), w1(c))` at the overlap end `c` of two windows:
/// the cached end distance (`cached0` of `w0`, `cached1` of `w1`) of the
/// one that ends (or starts) there, `end_of_0` saying which, and
/// `σ + |p − (c, 0)|` of the other. Both branches are selects, not jumps:
/// which window ends first is a coin toss.
#[inline]
fn distances_at_end(
    (w0, w1): (&Window, &Window),
    c: f64,
    end_of_0: bool,
    (cached0, cached1): (f64, f64),
) -> (f64, f64) {
    let (p, sigma) = if end_of_0 {
        (w1.p, w1.sigma)
    } else {
        (w0.p, w0.sigma)
    };
    let other = sigma + p.distance(DVec2::new(c, 0.0));
    if end_of_0 {
        (cached0, other)
    } else {
        (other, cached1)
    }
}

/// [`overlap_dominance_ended`], also giving what was found at the
/// overlap's ends.
#[inline]
fn compare_on_overlap(
    e0: &EndedWindow,
    e1: &EndedWindow,
    tol: &Tolerance,
) -> (Dominance, OverlapEnds) {
    let (w0, w1) = (&e0.window, &e1.window);
    let c0 = larger(w0.b0, w1.b0);
    let c1 = smaller(w0.b1, w1.b1);
    if !(c1 - c0 > tie_sliver(w0, w1)) {
        // Disjoint, or only the sliver two trimmed windows keep around
        // their tie point (comparing them again would settle nothing).
        let unset = OverlapEnds {
            c0,
            c1,
            d: [f64::NAN; 4],
            first_at: [false; 2],
            second_at: [false; 2],
        };
        return (Dominance::Disjoint, unset);
    }
    // Each overlap end is an end of one window, whose cached distance is
    // the same computation bit for bit as evaluating it there.
    let (a0, a1) = distances_at_end((w0, w1), c0, w0.b0 >= w1.b0, (e0.d0, e1.d0));
    let (b0, b1) = distances_at_end((w0, w1), c1, w0.b1 <= w1.b1, (e0.d1, e1.d1));
    let first_at = [tol.beats(a0, a1), tol.beats(b0, b1)];
    let second_at = [tol.beats(a1, a0), tol.beats(b1, b0)];
    let ends = OverlapEnds {
        c0,
        c1,
        d: [a0, a1, b0, b1],
        first_at,
        second_at,
    };
    let mut first = first_at[0] & first_at[1];
    let mut second = second_at[0] & second_at[1];
    if !first && !second {
        return (Dominance::Neither, ends);
    }
    let (p, q) = (w0.p, w1.p);
    if p.y != q.y {
        let xs = p.x + (q.x - p.x) * (-p.y) / (q.y - p.y);
        if xs > c0 && xs < c1 {
            let (d0, d1) = (w0.distance_at(xs), w1.distance_at(xs));
            first &= tol.beats(d0, d1);
            second &= tol.beats(d1, d0);
        }
    }
    let dominance = match (first, second) {
        (true, _) => Dominance::First,
        (_, true) => Dominance::Second,
        _ => Dominance::Neither,
    };
    (dominance, ends)
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
    let mut e0 = EndedWindow::new(*w0);
    let mut e1 = EndedWindow::new(*w1);
    let outcome = prune_adjacent_ended(&mut e0, &mut e1, tol);
    *w0 = e0.window;
    *w1 = e1.window;
    outcome
}

/// [`prune_adjacent`] on windows whose end distances are cached (trimming
/// keeps the caches exact).
#[inline]
pub fn prune_adjacent_ended(
    w0: &mut EndedWindow,
    w1: &mut EndedWindow,
    tol: &Tolerance,
) -> PairOutcome {
    match prune_pair(w0, w1, tol, false) {
        SplitOutcome::Pair(outcome) => outcome,
        SplitOutcome::FirstSplit(_) | SplitOutcome::SecondSplit(_) => {
            unreachable!("prune_pair splits nothing when splitting is off")
        }
    }
}

/// What [`prune_adjacent_splitting`] decided.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SplitOutcome {
    /// As [`prune_adjacent`].
    Pair(PairOutcome),
    /// The first window lost the middle of its interval to the second: it
    /// is now its left piece, and this is its right piece (it goes after
    /// the second window).
    FirstSplit(EndedWindow),
    /// The second window lost the middle of its interval to the first: it
    /// is now its left piece (it goes before the first window), and this is
    /// its right piece (after the first window).
    SecondSplit(EndedWindow),
}

/// [`prune_adjacent_ended`], except that a window that loses the middle of
/// its interval (the other is shorter on all of it and it sticks out on
/// both sides) is cut into its two outer pieces instead of being kept
/// whole: the trimming of MMP (Surazhsky et al. 2005) carried to the case
/// the paper's Case 2 leaves alone. Pseudo-source windows, which span a
/// whole edge, are the usual losers.
#[inline]
pub fn prune_adjacent_splitting(
    w0: &mut EndedWindow,
    w1: &mut EndedWindow,
    tol: &Tolerance,
) -> SplitOutcome {
    prune_pair(w0, w1, tol, true)
}

#[inline]
fn prune_pair(
    w0: &mut EndedWindow,
    w1: &mut EndedWindow,
    tol: &Tolerance,
    split: bool,
) -> SplitOutcome {
    let (dominance, ends) = compare_on_overlap(w0, w1, tol);
    let outcome = match dominance {
        Dominance::First => {
            if split && w1.window.b0 < w0.window.b0 && w1.window.b1 > w0.window.b1 {
                let right = cut_middle(w1, &w0.window);
                return SplitOutcome::SecondSplit(right);
            }
            trim_loser(&w0.window, w1, PairOutcome::RemoveSecond)
        }
        Dominance::Second => {
            if split && w0.window.b0 < w1.window.b0 && w0.window.b1 > w1.window.b1 {
                let right = cut_middle(w0, &w1.window);
                return SplitOutcome::FirstSplit(right);
            }
            trim_loser(&w1.window, w0, PairOutcome::RemoveFirst)
        }
        Dominance::Neither => {
            // Decided here, not in the call: most such pairs (a window
            // grazing a saddle vertex next to the vertex's own window) tie
            // at one end and cannot cross.
            if ends.cross() {
                match trim_at_tie(w0, w1, ends, tol, split) {
                    Some((true, right)) => return SplitOutcome::FirstSplit(right),
                    Some((false, right)) => return SplitOutcome::SecondSplit(right),
                    None => {}
                }
            }
            PairOutcome::KeepBoth
        }
        Dominance::Disjoint => PairOutcome::KeepBoth,
    };
    if outcome != PairOutcome::KeepBoth {
        return SplitOutcome::Pair(outcome);
    }
    SplitOutcome::Pair(if w0.window.b1 <= w1.window.b0 {
        disjoint_pair(w0, w1, tol)
    } else if w1.window.b1 <= w0.window.b0 {
        match disjoint_pair(w1, w0, tol) {
            PairOutcome::RemoveFirst => PairOutcome::RemoveSecond,
            PairOutcome::RemoveSecond => PairOutcome::RemoveFirst,
            PairOutcome::KeepBoth => PairOutcome::KeepBoth,
        }
    } else {
        PairOutcome::KeepBoth
    })
}

/// Cuts the interval of `winner` out of `loser`: `loser` keeps its left
/// piece, the right piece is returned.
#[inline]
fn cut_middle(loser: &mut EndedWindow, winner: &Window) -> EndedWindow {
    let mut right = *loser;
    right.set_start(winner.b1);
    loser.set_end(winner.b0);
    right
}

/// Two windows side by side on one edge, `left` ending where or before
/// `right` starts (Cases 3 and 6 of Fig 3: after their rays crossed, the
/// windows come out in swapped order and one of them is redundant; the
/// test is sound for any two windows on one edge).
///
/// A path can reach the near end of `left` through `left` and then walk
/// along the edge (Observation (a)). Along the edge `σ + |p x| − x` never
/// increases, so if that walk beats `right` at its far end it beats it
/// everywhere, and `right` is redundant; symmetrically for `left`.
#[inline]
pub fn disjoint_pair(left: &EndedWindow, right: &EndedWindow, tol: &Tolerance) -> PairOutcome {
    let (l, r) = (&left.window, &right.window);
    if tol.beats(left.d1 + (r.b1 - l.b1), right.d1) {
        return PairOutcome::RemoveSecond;
    }
    if tol.beats(right.d0 + (r.b0 - l.b0), left.d0) {
        return PairOutcome::RemoveFirst;
    }
    PairOutcome::KeepBoth
}

/// Two windows that cross on their overlap (neither dominates it): each
/// loses the part beyond their tie point where the other is shorter, as in
/// MMP's interval trimming (Surazhsky et al. 2005, Section 3.3), only
/// after checking that the other window beats it there by the margin, and
/// (unless `split`) only where the lost part ends the window. With `split`
/// a window that runs on past the other loses the middle part instead: it
/// keeps its left piece and the right piece is returned, with whether it
/// belongs to `w0`. A
/// sliver around the tie point stays in both: `TIE_GAP` of the overlap on
/// each side, or wider where the two distances part slowly, so that at
/// each cut the winner leads by a few margins.
fn trim_at_tie(
    w0: &mut EndedWindow,
    w1: &mut EndedWindow,
    ends: OverlapEnds,
    tol: &Tolerance,
    split: bool,
) -> Option<(bool, EndedWindow)> {
    let OverlapEnds {
        c0,
        c1,
        d: [a0, a1, b0, b1],
        first_at,
        second_at,
    } = ends;
    if !ends.cross() {
        return None;
    }
    let left_is_0 = first_at[0] & second_at[1];
    let x = single_tie_point(&w0.window, &w1.window, c0, c1)?;
    // Step far enough from the tie that the winner is ahead by the margin
    // at the cut: the gap between the two distances grows about as
    // |slope difference| × step there (beats_from still checks it).
    let slope = |w: &Window| {
        let r = w.p.distance(DVec2::new(x, 0.0));
        if r > 0.0 { (x - w.p.x) / r } else { 0.0 }
    };
    let spread = (slope(&w0.window) - slope(&w1.window)).abs();
    let margin = tol.margin(a0.max(a1).max(b0).max(b1));
    let gap = (TIE_GAP * (c1 - c0)).max(TIE_STEP_MARGINS * margin / spread);
    let (winner_left, winner_right) = if left_is_0 { (w0, w1) } else { (w1, w0) };
    let mut piece = None;
    // The losers' distances at the overlap ends, known from the
    // comparison: the right winner's at c0, the left winner's at c1.
    let (loser_left_at_c0, loser_right_at_c1) = if left_is_0 { (a1, b0) } else { (a0, b1) };
    // The right winner loses [c0, x): trim its start if it starts at c0,
    // else (splitting) cut that part out of its middle.
    let cut = x - gap;
    if cut > c0
        && let Some(d) = beats_from(&winner_left.window, &winner_right.window, c0, cut, tol)
    {
        if winner_right.window.b0 == c0 {
            winner_right.set_start_known(cut, d);
        } else if split {
            let mut right = *winner_right;
            right.set_start_known(cut, d);
            winner_right.set_end_known(c0, loser_left_at_c0);
            piece = Some((!left_is_0, right));
        }
    }
    // The left winner loses (x, c1]: trim its end if it ends at c1.
    let cut = x + gap;
    if cut < c1
        && let Some(d) = beats_from(&winner_right.window, &winner_left.window, c1, cut, tol)
    {
        if winner_left.window.b1 == c1 {
            winner_left.set_end_known(cut, d);
        } else if split && piece.is_none() {
            let mut right = *winner_left;
            right.set_start_known(c1, loser_right_at_c1);
            winner_left.set_end_known(cut, d);
            piece = Some((left_is_0, right));
        }
    }
    piece
}

/// Part of the overlap (relative to its width) left to both windows around
/// their tie point.
const TIE_GAP: f64 = 1e-9;

/// How many tolerance margins apart the two distances should be where a
/// window is cut near a tie point.
const TIE_STEP_MARGINS: f64 = 4.0;

/// An overlap this narrow is what two windows trimmed at their tie point
/// keep at least: `2·TIE_GAP` times the old overlap, which is at most twice
/// the wider of the two trimmed windows. (Where the step from the tie was
/// set by the margin the sliver is wider; comparing such a pair again
/// finds nothing more to cut, only costs the check.)
#[inline]
fn tie_sliver(w0: &Window, w1: &Window) -> f64 {
    4.0 * TIE_GAP * larger(w0.width(), w1.width())
}

/// How much of an edge two windows on it share (negative: the gap between
/// them).
#[inline]
fn shared_width(w0: &Window, w1: &Window) -> f64 {
    smaller(w0.b1, w1.b1) - larger(w0.b0, w1.b0)
}

/// Part of the narrower window that two windows must share before the
/// sorted merge compares them.
const WORTH_COMPARING: f64 = 0.7;

/// Whether the sorted merge leaves two partly overlapping windows (sharing
/// `shared > 0`) to both without comparing them: they share less than 70 %
/// of the narrower one.
///
/// Such a comparison can at best trim the part they share. On bunny.off
/// 92 % of the merge's comparisons were of this kind and settled nothing:
/// the two windows tie at one end of what they share (the children of two
/// windows trimmed at their tie point, a window passing a saddle vertex
/// and the vertex's own window) or cross near an end. Leaving it to both
/// discards nothing, so it is always sound: on bunny.off, armadillo.obj and
/// the Loop×1 bunny a factor of one half cost 0.6–1.2 % more propagations
/// and saved a quarter of the time; leaving every partial overlap to both
/// (a factor of 1) costs 47 % more propagations. Once crossing windows
/// with equal σ were trimmed reliably, 0.7 beat 0.5 by 1–2 % of time on
/// all three for 0.3–0.5 % more propagations.
#[inline]
fn not_worth_comparing(w0: &Window, w1: &Window, shared: f64) -> bool {
    shared <= WORTH_COMPARING * smaller(w0.width(), w1.width())
}

/// The one point of `(c0, c1)` where two windows give equal distances, or
/// `None` if there are zero or two there (then nothing is trimmed).
///
/// With `s = σ1 − σ0`, `|p x| − |q x| = s` squared twice gives the
/// quadratic `(a² − 4s²) x² + (2ab + 8s² q.x) x + b² − 4s² |q|² = 0`, where
/// `a x + b = |p x|² − |q x|² − s²`, `a = 2(q.x − p.x)`,
/// `b = |p|² − |q|² − s²`; a root is real only if `a x + b` has the sign of
/// `s` (Surazhsky et al. 2005, Section 3.3).
fn single_tie_point(w0: &Window, w1: &Window, c0: f64, c1: f64) -> Option<f64> {
    let (p, q) = (w0.p, w1.p);
    let s = w1.sigma - w0.sigma;
    let a = 2.0 * (q.x - p.x);
    let b = p.length_squared() - q.length_squared() - s * s;
    if s == 0.0 {
        // Equal σ (every window straight from one source vertex): the tie
        // is where the perpendicular bisector of `pq` meets the edge,
        // `a x + b = 0`. The quadratic below is then `(a x + b)² = 0`,
        // whose double root rounding splits in two or makes complex.
        let x = -b / a;
        return (x > c0 && x < c1).then_some(x);
    }
    let qa = a * a - 4.0 * s * s;
    let qb = 2.0 * a * b + 8.0 * s * s * q.x;
    let qc = b * b - 4.0 * s * s * q.length_squared();
    let mut roots = [f64::NAN; 2];
    if qa == 0.0 {
        if qb != 0.0 {
            roots[0] = -qc / qb;
        }
    } else {
        let disc = qb * qb - 4.0 * qa * qc;
        if !(disc >= 0.0) {
            return None;
        }
        // Numerically stable pair of roots.
        let r = -0.5 * (qb + qb.signum() * disc.sqrt());
        roots[0] = r / qa;
        if r != 0.0 {
            roots[1] = qc / r;
        }
    }
    let mut found = None;
    for x in roots {
        let genuine = x > c0 && x < c1 && (a * x + b) * s >= 0.0;
        if genuine {
            if found.is_some_and(|f| f != x) {
                return None;
            }
            found = Some(x);
        }
    }
    found
}

/// Whether `winner`, known to be shorter than `loser` by the margin at
/// `known`, is so on the whole segment from `known` to `cut`: the other end
/// and the interior extremum decide, as in [`overlap_dominance`]. If so,
/// returns the loser's distance at `cut` (its new end distance there).
fn beats_from(
    winner: &Window,
    loser: &Window,
    known: f64,
    cut: f64,
    tol: &Tolerance,
) -> Option<f64> {
    let at_cut = loser.distance_at(cut);
    if !tol.beats(winner.distance_at(cut), at_cut) {
        return None;
    }
    let (lo, hi) = if known < cut {
        (known, cut)
    } else {
        (cut, known)
    };
    let (p, q) = (winner.p, loser.p);
    if p.y != q.y {
        let xs = p.x + (q.x - p.x) * (-p.y) / (q.y - p.y);
        if xs > lo && xs < hi && !tol.beats(winner.distance_at(xs), loser.distance_at(xs)) {
            return None;
        }
    }
    Some(at_cut)
}

#[inline]
fn trim_loser(winner: &Window, loser: &mut EndedWindow, remove: PairOutcome) -> PairOutcome {
    let left_out = loser.window.b0 < winner.b0;
    let right_out = loser.window.b1 > winner.b1;
    match (left_out, right_out) {
        (false, false) => remove,
        (true, false) => {
            loser.set_end(winner.b0);
            PairOutcome::KeepBoth
        }
        (false, true) => {
            loser.set_start(winner.b1);
            PairOutcome::KeepBoth
        }
        (true, true) => PairOutcome::KeepBoth,
    }
}

/// Rules 2 and 3 with the order-free merge (Section 4.2): `w` goes behind
/// `list`, checked against the window before it, and on while it removes
/// windows. A window that loses the middle of its interval is split
/// ([`prune_adjacent_splitting`]). Returns whether `w` (or its right piece)
/// was kept.
#[inline]
pub fn merge_behind(list: &mut Vec<EndedWindow>, mut w: EndedWindow, tol: &Tolerance) -> bool {
    loop {
        let Some(top) = list.last_mut() else {
            list.push(w);
            return true;
        };
        match prune_adjacent_splitting(top, &mut w, tol) {
            SplitOutcome::Pair(PairOutcome::KeepBoth) => {
                list.push(w);
                return true;
            }
            SplitOutcome::Pair(PairOutcome::RemoveSecond) => return false,
            SplitOutcome::Pair(PairOutcome::RemoveFirst) => {
                list.pop();
            }
            SplitOutcome::FirstSplit(right) => {
                // [top's left piece, w, top's right piece]
                list.push(w);
                w = right;
            }
            SplitOutcome::SecondSplit(right) => {
                // [w's left piece, top, w's right piece]
                list.insert(list.len() - 1, w);
                w = right;
            }
        }
    }
}

/// Scratch space of one list's crossing, kept by a sequential solver's
/// loop (VTP's, and each region's in PVTP) and lent to every crossing, so
/// no crossing allocates or moves buffers in and out of the solver:
/// Rule 1's `(t, sp, d)` per window ([`apex_paths`]) and the children
/// bound beyond each of the face's other two edges (`left` and `right`
/// keep at least a slot per window of the longest list so far; a
/// crossing fills their fronts).
#[derive(Debug, Default)]
pub struct CrossBuffers {
    /// Rule 1's view of the apex, per window of the list crossed.
    pub info: Vec<(f64, f64, f64)>,
    /// Children bound beyond `AC`.
    pub left: Vec<EndedWindow>,
    /// Children bound beyond `CB`.
    pub right: Vec<EndedWindow>,
}

/// Spare buffers for [`merge_sorted`], kept by a solver so merging
/// allocates nothing once they have grown.
#[derive(Debug, Default)]
pub struct MergeBuffers {
    /// The old windows that start after the first incoming one.
    out: Vec<EndedWindow>,
    /// Per window of the merged list: whether it is one of the incoming
    /// windows.
    out_new: Vec<bool>,
    /// Right pieces cut off a window, waiting for their turn (sorted by
    /// start, largest first).
    pending: Vec<(EndedWindow, bool)>,
}

/// Rules 2 and 3 on lists kept in edge order (sorted by start): merges
/// `incoming` (any order; it is sorted in place) into `list` in one linear
/// pass, checking each window against the windows before it that it
/// overlaps, and the nearest one it does not (Cases 3 and 6), trimming
/// and splitting as [`prune_adjacent_splitting`]. Two windows that were
/// both in `list` are not compared again, nor two that share less than
/// 70 % of the narrower one (see `not_worth_comparing`: both keep that
/// part).
///
/// The order is kept up to one exception: a window already placed that
/// loses the start of its interval at a tie point keeps its place, and may
/// then start after the window behind it (about 4 % of the lists on
/// armadillo.obj and bunny.off). Nothing unsound follows, only fewer pairs
/// compared in later merges of that list; re-sorting such lists cost more
/// than the windows it pruned.
///
/// Compared with the order-free merge ([`merge_behind`]), a window meets
/// every window it overlaps substantially, not just the one it happens to
/// follow, so fewer redundant windows survive.
pub fn merge_sorted(
    list: &mut Vec<EndedWindow>,
    incoming: &mut [EndedWindow],
    buffers: &mut MergeBuffers,
    tol: &Tolerance,
) {
    match incoming {
        [] => return,
        // One window into an empty list (a pseudo-source's window, a list
        // with a single child): nothing to meet.
        [w] if list.is_empty() => {
            list.push(*w);
            return;
        }
        _ => {}
    }
    sort_by_start(incoming, &mut buffers.out);
    let MergeBuffers {
        out: tail,
        out_new,
        pending,
    } = buffers;
    pending.clear();
    if list.is_empty() {
        // Two thirds of the merges fill an empty list: every window is
        // new, so there is no tail to interleave and nothing to track.
        let mut j = 0;
        loop {
            let w = match (incoming.get(j), pending.last()) {
                (Some(e), Some((piece, _))) if piece.window.b0 < e.window.b0 => {
                    pending.pop().expect("a pending piece was seen").0
                }
                (Some(e), _) => {
                    j += 1;
                    *e
                }
                (None, Some(_)) => pending.pop().expect("a pending piece was seen").0,
                (None, None) => return,
            };
            push_checked::<false>(list, out_new, pending, w, true, tol);
        }
    }
    // Windows of `list` that start before every incoming one stay where
    // they are; the rest (the tail) is merged with the incoming windows
    // behind them.
    let first = incoming[0].window.b0;
    let keep = list.partition_point(|e| e.window.b0 <= first);
    tail.clear();
    tail.extend_from_slice(&list[keep..]);
    list.truncate(keep);
    out_new.clear();
    out_new.resize(keep, false);
    let (mut i, mut j) = (0, 0);
    loop {
        // The next window in edge order among the tail, the incoming
        // windows and the pending pieces (old first on ties).
        let mut pick = 3;
        let mut start = f64::INFINITY;
        if let Some(e) = tail.get(i) {
            pick = 0;
            start = e.window.b0;
        }
        if let Some(e) = incoming.get(j)
            && e.window.b0 < start
        {
            pick = 1;
            start = e.window.b0;
        }
        if let Some((e, _)) = pending.last()
            && e.window.b0 < start
        {
            pick = 2;
        }
        let (w, is_new) = match pick {
            0 => {
                i += 1;
                (tail[i - 1], false)
            }
            1 => {
                j += 1;
                (incoming[j - 1], true)
            }
            2 => pending
                .pop()
                .expect("picked a pending piece, so there is one"),
            _ => break,
        };
        push_checked::<true>(list, out_new, pending, w, is_new, tol);
    }
}

/// Sorts windows by start. A propagated list's children come out nearly
/// in edge order (their parents were), so an insertion sort does about one
/// comparison per window. A long batch is usually a few runs already in
/// order (a parallel job sends the children of two lists and a
/// pseudo-source window across one edge at once): those are merged through
/// `scratch` (left empty). Both keep windows with equal starts in their
/// order. Any other long batch, where a bad order could cost quadratic
/// time, goes to the library's unstable sort.
#[inline]
fn sort_by_start(windows: &mut [EndedWindow], scratch: &mut Vec<EndedWindow>) {
    const INSERTION_MAX: usize = 32;
    const RUNS_MAX: usize = 4;
    if windows.len() > INSERTION_MAX {
        let descents = windows
            .windows(2)
            .filter(|p| p[0].window.b0 > p[1].window.b0)
            .count();
        if descents < RUNS_MAX {
            merge_runs(windows, scratch);
        } else {
            windows.sort_unstable_by(|a, b| a.window.b0.total_cmp(&b.window.b0));
        }
        return;
    }
    for i in 1..windows.len() {
        if windows[i - 1].window.b0 <= windows[i].window.b0 {
            continue; // in place already: the usual case, no copy
        }
        let w = windows[i];
        let mut k = i;
        while k > 0 && windows[k - 1].window.b0 > w.window.b0 {
            windows[k] = windows[k - 1];
            k -= 1;
        }
        windows[k] = w;
    }
}

/// Sorts `windows`, a few runs each in order by start, by merging each run
/// into the sorted prefix before it (the prefix's window first on equal
/// starts, as a stable sort would).
fn merge_runs(windows: &mut [EndedWindow], scratch: &mut Vec<EndedWindow>) {
    let n = windows.len();
    let run_end = |windows: &[EndedWindow], from: usize| {
        (from + 1..n)
            .find(|&i| windows[i - 1].window.b0 > windows[i].window.b0)
            .unwrap_or(n)
    };
    let mut sorted = run_end(windows, 0);
    while sorted < n {
        let end = run_end(windows, sorted);
        scratch.clear();
        let (mut i, mut j) = (0, sorted);
        while i < sorted && j < end {
            if windows[j].window.b0 < windows[i].window.b0 {
                scratch.push(windows[j]);
                j += 1;
            } else {
                scratch.push(windows[i]);
                i += 1;
            }
        }
        scratch.extend_from_slice(&windows[i..sorted]);
        scratch.extend_from_slice(&windows[j..end]);
        windows[..end].copy_from_slice(scratch);
        sorted = end;
    }
    scratch.clear();
}

/// One step of [`merge_sorted`]: `w` goes behind `out` after meeting the
/// windows before it that it overlaps. With `OLD`, `out_new` says which
/// windows of `out` are new (two old ones were checked against each other
/// already); without, every window is new and `out_new` is left alone.
#[inline]
fn push_checked<const OLD: bool>(
    out: &mut Vec<EndedWindow>,
    out_new: &mut Vec<bool>,
    pending: &mut Vec<(EndedWindow, bool)>,
    mut w: EndedWindow,
    is_new: bool,
    tol: &Tolerance,
) {
    let mut k = out.len();
    let mut nearest = true;
    while k > 0 {
        k -= 1;
        let shared = shared_width(&out[k].window, &w.window);
        let overlaps = shared > tie_sliver(&out[k].window, &w.window);
        if overlaps && not_worth_comparing(&out[k].window, &w.window, shared) {
            // What lies before overlaps `w` less still, as for a window
            // that does not overlap it at all.
            break;
        }
        if !overlaps && !nearest {
            break;
        }
        nearest = false;
        if OLD && !is_new && !out_new[k] {
            // Both were in the list: already checked against each other.
            if !overlaps {
                break;
            }
            continue;
        }
        match prune_adjacent_splitting(&mut out[k], &mut w, tol) {
            SplitOutcome::Pair(PairOutcome::KeepBoth) => {
                if !overlaps {
                    break;
                }
            }
            SplitOutcome::Pair(PairOutcome::RemoveSecond) => return,
            SplitOutcome::Pair(PairOutcome::RemoveFirst) => {
                out.remove(k);
                if OLD {
                    out_new.remove(k);
                }
                // The window before the removed one is `w`'s nearest now.
                nearest = k == out.len();
            }
            SplitOutcome::FirstSplit(right) => {
                // `w` won the middle of `out[k]`, whose right piece starts
                // where `w` ends: it waits for its turn.
                let piece = (right, !OLD || out_new[k]);
                let at = pending.partition_point(|(e, _)| e.window.b0 > right.window.b0);
                pending.insert(at, piece);
            }
            SplitOutcome::SecondSplit(right) => {
                // `w` lies across `out[k]` (equal starts only): its left
                // piece goes on, its right piece waits.
                let at = pending.partition_point(|(e, _)| e.window.b0 > right.window.b0);
                pending.insert(at, (right, is_new));
            }
        }
    }
    out.push(w);
    if OLD {
        out_new.push(is_new);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use geodesics_shapes::SplitMix64;

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
    fn apex_paths_finds_the_list_s_best_path_to_the_apex_first_on_ties() {
        // Apex C = (1, 1) over AB of length 2; sources below.
        let tri = crate::Triangle::new(2.0, DVec2::new(1.0, 1.0));
        let list: Vec<EndedWindow> = [
            win(0.0, 2.0, (1.0, -1.0), 1.0), // sees C straight: 1 + 2 = 3
            win(0.0, 2.0, (1.0, -1.0), 0.5), // the same, shorter: 2.5
            win(0.0, 2.0, (1.0, -1.0), 0.5), // ties with the second
            win(0.0, 0.5, (1.0, -1.0), 1.0), // bent at b1 = 0.5: 1 + √5 ≈ 3.24
        ]
        .map(EndedWindow::new)
        .to_vec();
        let mut paths = vec![(9.0, 9.0, 9.0)]; // stale content is cleared
        let (best, at) = apex_paths(&list, &tri, &mut paths);
        assert_eq!(paths.len(), list.len());
        for (e, p) in list.iter().zip(&paths) {
            assert_eq!(*p, e.apex_path(&tri));
        }
        assert!((paths[0].2 - 3.0).abs() < 1e-12);
        assert!((best - 2.5).abs() < 1e-12);
        assert_eq!(at, 1, "the first of two equal paths");
        assert!((paths[3].2 - (1.0 + 5f64.sqrt())).abs() < 1e-12);
        assert_eq!(paths[3].1, 0.5, "its separating point is its end");
        // An empty list: no path, and the scratch is left empty.
        let (best, at) = apex_paths(&[], &tri, &mut paths);
        assert_eq!((best, at), (f64::INFINITY, 0));
        assert!(paths.is_empty());
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
    fn edge_ends_alone_beat_a_window_only_by_the_margin() {
        let t = tol();
        // A full-edge window from a source 1 below the middle of [0, 2],
        // at σ = 1: its ends are at 1 + √2.
        let w = EndedWindow::new(win(0.0, 2.0, (1.0, -1.0), 1.0));
        // Start vertex at 0 walks the edge to the far end in 2 < 2.414.
        assert!(beaten_from_edge_ends(&w, 2.0, 0.0, f64::INFINITY, &t));
        assert!(beaten_from_edge_ends(&w, 2.0, f64::INFINITY, 0.0, &t));
        // A tie at the far end is no reason to drop it.
        let tie = w.d1 - 2.0;
        assert!(!beaten_from_edge_ends(&w, 2.0, tie, f64::INFINITY, &t));
        assert!(!beaten_from_edge_ends(
            &w,
            2.0,
            f64::INFINITY,
            f64::INFINITY,
            &t
        ));
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
        let mut b = win(0.5, 1.5, (1.0, -1.0), 0.3);
        assert_eq!(prune_adjacent(&mut a, &mut b, &t), PairOutcome::KeepBoth);
        assert_eq!((b.b0, b.b1), (1.0, 1.5));
        // With σ = 1 the trimmed rest of b is beaten by walking along the
        // edge from a's end (Case 3): removed.
        let mut a = win(0.0, 1.0, (0.5, -1.0), 0.0);
        let mut b = win(0.5, 1.5, (1.0, -1.0), 1.0);
        assert_eq!(
            prune_adjacent(&mut a, &mut b, &t),
            PairOutcome::RemoveSecond
        );
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

    #[test]
    fn crossed_rays_side_by_side_cases_3_and_6() {
        let t = tol();
        // Left window close to its source, right one far: walking along
        // the edge from the left window's end beats the right one.
        let left = EndedWindow::new(win(0.0, 1.0, (0.5, -0.5), 0.0));
        let right = EndedWindow::new(win(1.0, 2.0, (1.5, -0.5), 3.0));
        assert_eq!(disjoint_pair(&left, &right, &t), PairOutcome::RemoveSecond);
        // And the mirror image.
        let left = EndedWindow::new(win(0.0, 1.0, (0.5, -0.5), 3.0));
        let right = EndedWindow::new(win(1.0, 2.0, (1.5, -0.5), 0.0));
        assert_eq!(disjoint_pair(&left, &right, &t), PairOutcome::RemoveFirst);
        // Comparable windows stay.
        let right = EndedWindow::new(win(1.0, 2.0, (1.5, -0.5), 2.5));
        assert_eq!(disjoint_pair(&left, &right, &t), PairOutcome::KeepBoth);
    }

    #[test]
    fn crossing_windows_are_trimmed_at_their_tie_point() {
        let t = tol();
        // Equal σ, sources under 0.5 and 1.5: they tie at x = 1.
        let mut a = EndedWindow::new(win(0.0, 1.5, (0.5, -1.0), 0.0));
        let mut b = EndedWindow::new(win(0.5, 2.0, (1.5, -1.0), 0.0));
        assert_eq!(
            prune_adjacent_ended(&mut a, &mut b, &t),
            PairOutcome::KeepBoth
        );
        assert!((a.window.b1 - 1.0).abs() < 1e-8 && a.window.b1 > 1.0);
        assert!((b.window.b0 - 1.0).abs() < 1e-8 && b.window.b0 < 1.0);
        // The caches follow the trims.
        assert_eq!(a.d1, a.window.distance_at(a.window.b1));
        assert_eq!(b.d0, b.window.distance_at(b.window.b0));
        // A tie point with unequal σ solves the quadratic.
        let w0 = win(0.0, 2.0, (0.0, -1.0), 0.0);
        let w1 = win(0.0, 2.0, (2.0, -1.0), 0.5);
        let x = single_tie_point(&w0, &w1, 0.0, 2.0).unwrap();
        assert!((w0.distance_at(x) - w1.distance_at(x)).abs() < 1e-12);
    }

    #[test]
    fn equal_sigma_windows_always_find_their_tie_point() {
        // Windows straight from one source vertex all have σ = 0; their tie
        // is the bisector of their sources. Squared twice it is a double
        // root, which rounding used to split in two or make complex: on
        // armadillo.obj a third of such pairs went untrimmed.
        let mut seed = 0x2545_f491_4f6c_dd1d_u64;
        let mut next = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        for _ in 0..2000 {
            let p = (3.0 * next() - 1.0, -0.01 - 2.0 * next());
            let q = (3.0 * next() - 1.0, -0.01 - 2.0 * next());
            let sigma = 5.0 * next();
            let (w0, w1) = (win(0.0, 1.0, p, sigma), win(0.0, 1.0, q, sigma));
            let bisector = (DVec2::from(q).length_squared() - DVec2::from(p).length_squared())
                / (2.0 * (q.0 - p.0));
            if !(bisector > 0.01 && bisector < 0.99) {
                continue;
            }
            let x = single_tie_point(&w0, &w1, 0.0, 1.0)
                .unwrap_or_else(|| panic!("no tie found for p = {p:?}, q = {q:?}"));
            assert!((x - bisector).abs() < 1e-9, "{x} vs {bisector}");
            assert!((w0.distance_at(x) - w1.distance_at(x)).abs() < 1e-12);
        }
    }

    #[test]
    fn a_loser_sticking_out_on_both_sides_is_split() {
        let t = tol();
        // b, close to its source, is shorter on all of a's middle.
        let mut a = EndedWindow::new(win(0.0, 3.0, (1.5, -1.0), 2.0));
        let mut b = EndedWindow::new(win(1.0, 2.0, (1.5, -0.5), 0.0));
        match prune_adjacent_splitting(&mut a, &mut b, &t) {
            SplitOutcome::FirstSplit(right) => {
                assert_eq!((a.window.b0, a.window.b1), (0.0, 1.0));
                assert_eq!((right.window.b0, right.window.b1), (2.0, 3.0));
                assert_eq!(right.d0, right.window.distance_at(2.0));
            }
            other => panic!("expected a split, got {other:?}"),
        }
        let mut a = EndedWindow::new(win(1.0, 2.0, (1.5, -0.5), 0.0));
        let mut b = EndedWindow::new(win(0.0, 3.0, (1.5, -1.0), 2.0));
        assert!(matches!(
            prune_adjacent_splitting(&mut a, &mut b, &t),
            SplitOutcome::SecondSplit(_)
        ));
        assert_eq!((b.window.b0, b.window.b1), (0.0, 1.0));
        // Without splitting the loser is kept whole.
        let mut a = EndedWindow::new(win(0.0, 3.0, (1.5, -1.0), 2.0));
        let mut b = EndedWindow::new(win(1.0, 2.0, (1.5, -0.5), 0.0));
        assert_eq!(
            prune_adjacent_ended(&mut a, &mut b, &t),
            PairOutcome::KeepBoth
        );
        assert_eq!((a.window.b0, a.window.b1), (0.0, 3.0));
    }

    #[test]
    fn crossing_windows_split_at_their_tie_point_when_splitting() {
        let t = tol();
        // Equal σ, sources under 0.5 and 2.5: they tie at x = 1.5. `a`
        // wins left of it and runs on past `b`, so it loses the middle.
        let mut a = EndedWindow::new(win(0.0, 3.0, (0.5, -1.0), 0.0));
        let mut b = EndedWindow::new(win(1.0, 2.0, (2.5, -1.0), 0.0));
        match prune_adjacent_splitting(&mut a, &mut b, &t) {
            SplitOutcome::FirstSplit(right) => {
                assert!((a.window.b1 - 1.5).abs() < 1e-8 && a.window.b1 > 1.5);
                assert_eq!((right.window.b0, right.window.b1), (2.0, 3.0));
                assert!((b.window.b0 - 1.5).abs() < 1e-8 && b.window.b0 < 1.5);
                assert_eq!(b.window.b1, 2.0);
            }
            other => panic!("expected a split, got {other:?}"),
        }
        // Without splitting `a` keeps its middle; `b` is still trimmed.
        let mut a = EndedWindow::new(win(0.0, 3.0, (0.5, -1.0), 0.0));
        let mut b = EndedWindow::new(win(1.0, 2.0, (2.5, -1.0), 0.0));
        assert_eq!(
            prune_adjacent_ended(&mut a, &mut b, &t),
            PairOutcome::KeepBoth
        );
        assert_eq!((a.window.b0, a.window.b1), (0.0, 3.0));
        assert!((b.window.b0 - 1.5).abs() < 1e-8);
    }

    fn starts(list: &[EndedWindow]) -> Vec<(f64, f64)> {
        list.iter().map(|e| (e.window.b0, e.window.b1)).collect()
    }

    #[test]
    fn merge_behind_removes_what_the_new_window_beats() {
        let t = tol();
        let mut list = vec![EndedWindow::new(win(0.0, 1.0, (0.5, -1.0), 0.0))];
        // Far worse on all of [0, 1]: dropped.
        assert!(!merge_behind(
            &mut list,
            EndedWindow::new(win(0.0, 1.0, (0.5, -1.0), 5.0)),
            &t
        ));
        // Better on all of [0, 1]: it replaces the old one.
        assert!(merge_behind(
            &mut list,
            EndedWindow::new(win(0.0, 1.0, (0.5, -0.5), 0.0)),
            &t
        ));
        assert_eq!(list.len(), 1);
        assert_eq!(list[0].window.p.y, -0.5);
    }

    #[test]
    fn reaching_through_a_point_is_decided_on_squares_as_with_the_root() {
        let t = tol();
        let from = DVec2::new(0.3, -0.4);
        // |from - (0.3 + 0.3, 0)| = 0.5 exactly in reals.
        let x = 0.6;
        for (d_from, target) in [
            (1.0, 1.6),           // clearly beats
            (1.0, 1.4),           // clearly loses
            (1.0, 1.5),           // a tie: no margin, no discard
            (1.0, 1.5 + 1e-9),    // beats by far more than the margin
            (f64::INFINITY, 2.0), // an unreached vertex beats nothing
            (0.0, f64::INFINITY), // an infinite target's margin is infinite: never beaten
        ] {
            let with_root = t.beats(d_from + from.distance(DVec2::new(x, 0.0)), target);
            assert_eq!(
                reach_beats(d_from, from, x, target, &t),
                with_root,
                "{d_from} -> {target}"
            );
        }
    }

    #[test]
    fn windows_are_sorted_by_start_short_or_long() {
        for n in [0usize, 1, 5, 31, 32, 33, 100] {
            // Reversed: the worst order for the insertion sort.
            let mut ws: Vec<EndedWindow> = (0..n)
                .map(|i| {
                    EndedWindow::new(win((n - i) as f64, (n - i) as f64 + 0.5, (0.0, -1.0), 0.0))
                })
                .collect();
            sort_by_start(&mut ws, &mut Vec::new());
            assert!(
                ws.windows(2).all(|p| p[0].window.b0 <= p[1].window.b0),
                "n = {n}"
            );
            assert_eq!(ws.len(), n);
        }
    }

    #[test]
    fn long_batches_of_a_few_runs_sort_as_a_stable_sort_would() {
        // Up to four runs, each in order, starts drawn from a few values
        // so that ties are common; `sigma` tells equal starts apart.
        let mut rng = SplitMix64::new(0x2545_f491_4f6c_dd1d);
        let mut next = |m: u64| rng.next_u64() % m;
        let mut scratch = Vec::new();
        for round in 0..300 {
            let runs = 1 + round % 4;
            let mut ws = Vec::new();
            for _ in 0..runs {
                let len = 9 + next(30) as usize;
                let mut starts: Vec<f64> = (0..len).map(|_| next(16) as f64).collect();
                starts.sort_by(f64::total_cmp);
                for b0 in starts {
                    let id = ws.len() as f64;
                    ws.push(EndedWindow::new(win(b0, b0 + 1.0, (b0 + 0.5, -1.0), id)));
                }
            }
            let mut expected = ws.clone();
            expected.sort_by(|a, b| a.window.b0.total_cmp(&b.window.b0));
            sort_by_start(&mut ws, &mut scratch);
            let key = |w: &EndedWindow| (w.window.b0, w.window.sigma);
            assert_eq!(
                ws.iter().map(key).collect::<Vec<_>>(),
                expected.iter().map(key).collect::<Vec<_>>(),
                "round {round}"
            );
            assert!(scratch.is_empty());
        }
    }

    #[test]
    fn merge_sorted_keeps_edge_order_and_prunes_every_overlap() {
        let t = tol();
        let mut buffers = MergeBuffers::default();
        let mut list = vec![
            EndedWindow::new(win(0.0, 1.0, (0.5, -1.0), 0.0)),
            EndedWindow::new(win(1.0, 2.0, (1.5, -1.0), 0.0)),
        ];
        // Out of order, one of them beaten on its whole interval by the
        // two old windows together (each beats it on its own part).
        let mut incoming = [
            EndedWindow::new(win(2.0, 3.0, (2.5, -1.0), 0.0)),
            EndedWindow::new(win(0.2, 0.9, (0.5, -1.0), 4.0)),
            EndedWindow::new(win(1.1, 1.9, (1.5, -1.0), 4.0)),
        ];
        merge_sorted(&mut list, &mut incoming, &mut buffers, &t);
        assert_eq!(starts(&list), vec![(0.0, 1.0), (1.0, 2.0), (2.0, 3.0)]);
        // Merging nothing changes nothing.
        merge_sorted(&mut list, &mut [], &mut buffers, &t);
        assert_eq!(list.len(), 3);
    }

    #[test]
    fn a_single_window_joins_an_empty_list_whole_and_a_full_one_checked() {
        let t = tol();
        let mut buffers = MergeBuffers::default();
        let w = EndedWindow::new(win(0.2, 0.9, (0.5, -1.0), 4.0));
        let mut list = Vec::new();
        merge_sorted(&mut list, &mut [w], &mut buffers, &t);
        assert_eq!(list, vec![w]);
        // Into a list holding a window that beats it everywhere, the same
        // window is checked and dropped.
        let mut list = vec![EndedWindow::new(win(0.0, 1.0, (0.5, -1.0), 0.0))];
        merge_sorted(&mut list, &mut [w], &mut buffers, &t);
        assert_eq!(starts(&list), vec![(0.0, 1.0)]);
    }

    #[test]
    fn merging_into_an_empty_list_matches_the_general_merge() {
        // The empty-list path skips the old/new bookkeeping; the general
        // path runs when the list holds one window far left of every
        // incoming one (disjoint from them, never nearest after the
        // first). Both must keep the same windows, bit for bit.
        let t = tol();
        let mut buffers = MergeBuffers::default();
        let mut state = 0x9e37_79b9_7f4a_7c15_u64;
        let mut unit = || {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let far = EndedWindow::new(win(-100.0, -99.0, (-99.5, -1.0), 2.0));
        for round in 0..500 {
            let n = 2 + round % 12;
            let incoming: Vec<EndedWindow> = (0..n)
                .map(|_| {
                    let b0 = 2.0 * unit();
                    let b1 = b0 + 0.05 + unit();
                    let p = (b0 + (b1 - b0) * unit(), -0.2 - unit());
                    EndedWindow::new(win(b0, b1, p, 0.5 * unit()))
                })
                .collect();
            let mut empty = Vec::new();
            merge_sorted(&mut empty, &mut incoming.clone(), &mut buffers, &t);
            let mut general = vec![far];
            merge_sorted(&mut general, &mut incoming.clone(), &mut buffers, &t);
            assert_eq!(general[0], far, "round {round}");
            assert_eq!(&general[1..], &empty[..], "round {round}");
        }
    }

    #[test]
    fn merge_sorted_compares_windows_sharing_at_least_half_the_narrower() {
        let t = tol();
        let mut buffers = MergeBuffers::default();
        let good = EndedWindow::new(win(0.0, 1.0, (0.5, -1.0), 0.0));
        // Far worse everywhere (σ = 5): sharing 0.1 of its 1.1 with `good`,
        // it is not compared with it and stays whole.
        let sliver = EndedWindow::new(win(0.9, 2.0, (1.5, -1.0), 5.0));
        let mut list = vec![good];
        merge_sorted(&mut list, &mut [sliver], &mut buffers, &t);
        assert_eq!(starts(&list), vec![(0.0, 1.0), (0.9, 2.0)]);
        // Sharing 0.6 of its 0.8, it is: it loses what it shares, and
        // walking along the edge from `good`'s end beats the rest (Case 3).
        let half = EndedWindow::new(win(0.4, 1.2, (1.5, -1.0), 5.0));
        let mut list = vec![good];
        merge_sorted(&mut list, &mut [half], &mut buffers, &t);
        assert_eq!(starts(&list), vec![(0.0, 1.0)]);
    }

    #[test]
    fn merge_sorted_splits_an_old_window_around_a_winner() {
        let t = tol();
        let mut buffers = MergeBuffers::default();
        // The new window is shorter on all of [1, 2]; the old one's outer
        // pieces are not beaten by walking along the edge from it.
        let mut list = vec![EndedWindow::new(win(0.0, 3.0, (1.5, -1.0), 0.3))];
        let mut incoming = [EndedWindow::new(win(1.0, 2.0, (1.5, -0.5), 0.5))];
        merge_sorted(&mut list, &mut incoming, &mut buffers, &t);
        assert_eq!(starts(&list), vec![(0.0, 1.0), (1.0, 2.0), (2.0, 3.0)]);
        assert_eq!(list[1].window.sigma, 0.5);
        assert_eq!(list[2].window.sigma, 0.3);
        for e in &list {
            assert_eq!(e.d0, e.window.distance_at(e.window.b0));
            assert_eq!(e.d1, e.window.distance_at(e.window.b1));
        }
    }

    #[test]
    fn windows_parting_slowly_are_cut_where_the_margin_is_met() {
        let t = tol();
        // Sources far below the edge: at the tie x = 1 the two distances
        // part at a slope difference of only 0.002, so a cut 1e-9 of the
        // overlap away would not be decided by the margin; the step grows.
        let mut a = EndedWindow::new(win(0.0, 2.0, (0.0, -1000.0), 0.0));
        let mut b = EndedWindow::new(win(0.0, 2.0, (2.0, -1000.0), 0.0));
        assert_eq!(
            prune_adjacent_ended(&mut a, &mut b, &t),
            PairOutcome::KeepBoth
        );
        assert!(a.window.b1 > 1.0 && a.window.b1 < 1.0 + 1e-6, "{a:?}");
        assert!(b.window.b0 < 1.0 && b.window.b0 > 1.0 - 1e-6, "{b:?}");
        // At each cut the window that keeps the point leads by the margin.
        let (x, y) = (a.window.b1, b.window.b0);
        assert!(t.beats(b.window.distance_at(x), a.window.distance_at(x)));
        assert!(t.beats(a.window.distance_at(y), b.window.distance_at(y)));
    }
}
