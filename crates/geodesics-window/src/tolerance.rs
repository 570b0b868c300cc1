//! The one tolerance policy every predicate of every exact solver uses.

use geodesics_mesh::Mesh;

/// Multiple of machine epsilon used for absolute (scale-relative) and
/// relative length margins. Rounding in a distance evaluated through a few
/// hundred rigid transforms stays far below `64 ε` of the mesh scale.
const EPS_MULTIPLE: f64 = 64.0;

/// Angle (radians) below a full turn from which an interior vertex counts
/// as "flat or saddle" and becomes a pseudo-source. The authors of VTP and
/// MMP use the same value (`2π − 1e-5`); treating a few nearly flat convex
/// vertices as pseudo-sources only costs windows, never exactness.
const FLAT_ANGLE_MARGIN: f64 = 1e-5;

/// Angle (radians) by which the shadow of a saddle vertex is widened on
/// each side (see [`crate::Shadow`]). The direction a path arrives from is
/// known to about 1e-12 rad (a pseudo-source unfolded across many faces);
/// where a path that bends slightly at a window end ties the straight one
/// within the length margin, its direction differs by under 1e-7 rad.
/// A wider sector only costs windows.
const SHADOW_ANGLE_MARGIN: f64 = 1e-5;

/// Tolerance policy, derived from the scale of one mesh.
///
/// Every comparison between two path lengths goes through
/// [`Tolerance::beats`]: a competitor prunes a window only when it is shorter
/// by more than the margin. In doubt a window is kept (that costs time),
/// never discarded (that would cost exactness).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tolerance {
    /// Absolute part of the length margin: `64 ε ×` the mesh's scale.
    pub absolute: f64,
    /// Relative part of the length margin, applied to the larger length compared.
    pub relative: f64,
    /// Margin below `2π` of the angle sum above which an interior vertex
    /// is treated as a pseudo-source (flat or saddle).
    pub flat_angle: f64,
    /// Widening, on each side, of the sector of directions a saddle vertex
    /// emits into (see [`crate::Shadow`]).
    pub shadow_angle: f64,
}

impl Tolerance {
    /// The policy for a mesh whose scale (bounding-box diagonal) is `scale`.
    /// A non-positive or non-finite scale falls back to 1.
    pub fn for_scale(scale: f64) -> Tolerance {
        let scale = if scale.is_finite() && scale > 0.0 {
            scale
        } else {
            1.0
        };
        Tolerance {
            absolute: EPS_MULTIPLE * f64::EPSILON * scale,
            relative: EPS_MULTIPLE * f64::EPSILON,
            flat_angle: FLAT_ANGLE_MARGIN,
            shadow_angle: SHADOW_ANGLE_MARGIN,
        }
    }

    /// The policy for `mesh`: scale = [`Mesh::length_scale`], its
    /// bounding-box diagonal unless a few far-out vertices inflate that.
    pub fn for_mesh(mesh: &Mesh) -> Tolerance {
        Tolerance::for_scale(mesh.length_scale())
    }

    /// Length margin when comparing lengths of magnitude about `magnitude`.
    #[inline]
    pub fn margin(&self, magnitude: f64) -> f64 {
        self.absolute + self.relative * magnitude.abs()
    }

    /// Whether a path of length `a` is shorter than one of length `b` by
    /// more than the margin: the only test allowed to discard a window.
    #[inline]
    pub fn beats(&self, a: f64, b: f64) -> bool {
        a + self.margin(b) < b
    }

    /// Whether a pseudo-source now at distance `d`, which last emitted its
    /// windows at `emitted` (infinite: never), must emit (again): only when
    /// its distance dropped by more than the margin, so rounding-level
    /// improvements do not re-emit.
    #[inline]
    pub fn must_emit(&self, d: f64, emitted: f64) -> bool {
        emitted == f64::INFINITY || self.beats(d, emitted)
    }

    /// Whether an interior vertex with this angle sum is flat or a saddle
    /// (a geodesic may pass through it, so it must act as a pseudo-source).
    #[inline]
    pub fn is_flat_or_saddle(&self, angle_sum: f64) -> bool {
        angle_sum > std::f64::consts::TAU - self.flat_angle
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn margins_scale_with_the_mesh() {
        let small = Tolerance::for_scale(1e-6);
        let big = Tolerance::for_scale(1e6);
        assert!((big.absolute / small.absolute - 1e12).abs() < 1e-3);
        assert!(small.beats(1.0e-6, 1.1e-6));
        assert!(!small.beats(1.0e-6, 1.0e-6 + 1e-22));
        assert!(!big.beats(1.0e6, 1.0e6 + 1e-9));
        assert!(big.beats(1.0e6, 1.0e6 + 1e-6));
        assert_eq!(Tolerance::for_scale(f64::NAN), Tolerance::for_scale(1.0));
    }

    #[test]
    fn a_pseudo_source_emits_first_and_again_only_on_a_real_drop() {
        let t = Tolerance::for_scale(1.0);
        assert!(t.must_emit(2.0, f64::INFINITY));
        assert!(!t.must_emit(2.0, 2.0));
        assert!(
            2.0 - 1e-15 < 2.0 && !t.must_emit(2.0 - 1e-15, 2.0),
            "a rounding-level drop"
        );
        assert!(t.must_emit(1.9, 2.0));
    }

    #[test]
    fn flat_vertices_count_as_pseudo_sources() {
        let t = Tolerance::for_scale(1.0);
        assert!(t.is_flat_or_saddle(std::f64::consts::TAU));
        assert!(t.is_flat_or_saddle(std::f64::consts::TAU - 1e-7));
        assert!(!t.is_flat_or_saddle(6.0));
    }
}
