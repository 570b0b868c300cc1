//! `Shape`: a parsed shape description such as `"torus:120x40"`.

use std::fmt;
use std::str::FromStr;

use geodesics_mesh::IndexedTriangles;

use crate::{
    MAX_GRID_JITTER, MAX_SPHERE_JITTER, MAX_SPHERE_SUBDIVISIONS, ShapeError, bumpy_sphere,
    flat_grid, icosphere, jittered_flat_grid, jittered_icosphere, regular_torus,
};

/// Largest vertex count a [`Shape`] may ask for (about 10⁸; the generators
/// themselves accept up to 32-bit limits).
pub const MAX_SHAPE_VERTICES: u64 = 100_000_000;

/// One procedural shape with all of its parameters: what `from_spec` parses
/// and [`Shape::build`] generates.
///
/// The spec syntax is `KIND:SIZE[,KEY=VALUE]*`:
///
/// | spec | shape | keys (defaults) |
/// |------|-------|-----------------|
/// | `icosphere:4` | [`icosphere`] | `radius` (1) |
/// | `jittered-icosphere:4` | [`jittered_icosphere`] | `radius` (1), `jitter` (0.1), `seed` (0) |
/// | `torus:120x40` | [`regular_torus`] | `major` (1), `minor` (0.3) |
/// | `grid:100x100` | [`flat_grid`] | `spacing` (1) |
/// | `jittered-grid:100x100` | [`jittered_flat_grid`] | `spacing` (1), `jitter` (0.3), `seed` (0) |
/// | `bumpy:5` | [`bumpy_sphere`] | `radius` (1), `bumps` (40), `amplitude` (0.2), `seed` (0) |
///
/// [`Display`](fmt::Display) prints the full spec with every key, and
/// parsing it gives the same shape back.
///
/// ```
/// use geodesics_shapes::Shape;
/// let torus = Shape::from_spec("torus:120x40").unwrap();
/// assert_eq!(torus, Shape::Torus { major_segments: 120, minor_segments: 40, major_radius: 1.0, minor_radius: 0.3 });
/// assert_eq!(torus.to_string(), "torus:120x40,major=1,minor=0.3");
/// assert_eq!(torus.build().unwrap().triangles.len(), 9600);
///
/// let bumpy: Shape = "bumpy:3,seed=9,bumps=10".parse().unwrap();
/// assert_eq!(bumpy.to_string().parse::<Shape>().unwrap(), bumpy);
///
/// let err = Shape::from_spec("cube:3").unwrap_err();
/// assert!(err.to_string().contains("unknown shape kind \"cube\""));
/// ```
#[derive(Clone, Debug, PartialEq)]
pub enum Shape {
    /// [`icosphere`].
    Icosphere {
        /// Number of 1→4 splits of the icosahedron.
        subdivisions: u32,
        /// Sphere radius.
        radius: f64,
    },
    /// [`jittered_icosphere`].
    JitteredIcosphere {
        /// Number of 1→4 splits of the icosahedron.
        subdivisions: u32,
        /// Sphere radius.
        radius: f64,
        /// Largest tangential step, as a fraction of the shortest edge.
        jitter: f64,
        /// Random seed.
        seed: u64,
    },
    /// [`regular_torus`].
    Torus {
        /// Segments around the z axis.
        major_segments: u32,
        /// Segments around the tube.
        minor_segments: u32,
        /// Radius of the tube's centre circle.
        major_radius: f64,
        /// Radius of the tube.
        minor_radius: f64,
    },
    /// [`flat_grid`].
    Grid {
        /// Cells along x.
        nx: u32,
        /// Cells along y.
        ny: u32,
        /// Cell side.
        spacing: f64,
    },
    /// [`jittered_flat_grid`].
    JitteredGrid {
        /// Cells along x.
        nx: u32,
        /// Cells along y.
        ny: u32,
        /// Cell side.
        spacing: f64,
        /// Largest vertex displacement, as a fraction of the spacing.
        jitter: f64,
        /// Random seed.
        seed: u64,
    },
    /// [`bumpy_sphere`].
    Bumpy {
        /// Number of 1→4 splits of the icosahedron.
        subdivisions: u32,
        /// Base radius.
        radius: f64,
        /// Number of bumps and dents.
        bumps: u32,
        /// Largest log-radius height of one bump.
        amplitude: f64,
        /// Random seed.
        seed: u64,
    },
}

/// The shape kinds `from_spec` understands, with a sample spec each.
pub const SHAPE_KINDS: &[(&str, &str)] = &[
    ("icosphere", "icosphere:4"),
    ("jittered-icosphere", "jittered-icosphere:4"),
    ("torus", "torus:120x40"),
    ("grid", "grid:100x100"),
    ("jittered-grid", "jittered-grid:100x100"),
    ("bumpy", "bumpy:5"),
];

fn kinds_list() -> String {
    SHAPE_KINDS
        .iter()
        .map(|(_, example)| *example)
        .collect::<Vec<_>>()
        .join(", ")
}

/// Parsed `KEY=VALUE` pairs, each consumed at most once.
struct Params<'a> {
    spec: &'a str,
    pairs: Vec<(&'a str, &'a str, bool)>,
}

impl<'a> Params<'a> {
    fn new(spec: &'a str, rest: &[&'a str]) -> Result<Self, ShapeError> {
        let mut pairs: Vec<(&str, &str, bool)> = Vec::new();
        for item in rest {
            let (key, value) = item
                .split_once('=')
                .ok_or_else(|| invalid(spec, format!("expected KEY=VALUE, found \"{item}\"")))?;
            let (key, value) = (key.trim(), value.trim());
            if pairs.iter().any(|(k, _, _)| *k == key) {
                return Err(invalid(spec, format!("key \"{key}\" given twice")));
            }
            pairs.push((key, value, false));
        }
        Ok(Self { spec, pairs })
    }

    fn get<T: FromStr>(&mut self, key: &str, default: T) -> Result<T, ShapeError> {
        let spec = self.spec;
        match self.pairs.iter_mut().find(|(k, _, _)| *k == key) {
            None => Ok(default),
            Some((_, value, used)) => {
                *used = true;
                value
                    .parse()
                    .map_err(|_| invalid(spec, format!("cannot parse {key}=\"{value}\"")))
            }
        }
    }

    /// Fails on keys no getter asked for.
    fn finish(self, allowed: &[&str]) -> Result<(), ShapeError> {
        match self.pairs.iter().find(|(_, _, used)| !used) {
            None => Ok(()),
            Some((key, _, _)) => Err(invalid(
                self.spec,
                format!(
                    "unknown key \"{key}\"; this shape takes {}",
                    allowed.join(", ")
                ),
            )),
        }
    }
}

fn invalid(spec: &str, reason: String) -> ShapeError {
    ShapeError::InvalidSpec {
        spec: spec.to_owned(),
        reason,
    }
}

fn parse_count(spec: &str, text: &str, what: &str) -> Result<u32, ShapeError> {
    text.trim().parse().map_err(|_| {
        invalid(
            spec,
            format!("{what} must be a non-negative integer, found \"{text}\""),
        )
    })
}

fn parse_pair(spec: &str, text: &str, what: &str) -> Result<(u32, u32), ShapeError> {
    let (a, b) = text.split_once(['x', 'X']).ok_or_else(|| {
        invalid(
            spec,
            format!("{what} must look like 120x40, found \"{text}\""),
        )
    })?;
    Ok((parse_count(spec, a, what)?, parse_count(spec, b, what)?))
}

impl Shape {
    /// Parses a spec such as `"icosphere:4"`, `"torus:120x40"`,
    /// `"grid:100x100"`, `"bumpy:5"` or `"bumpy:5,seed=3,amplitude=0.2"` (see
    /// the table on [`Shape`]), and validates the parameters like
    /// [`Shape::validate`].
    ///
    /// # Errors
    ///
    /// [`ShapeError::UnknownShape`] for an unknown kind,
    /// [`ShapeError::InvalidSpec`] for malformed sizes or keys, and
    /// [`ShapeError::InvalidParameter`] for out-of-range values.
    pub fn from_spec(spec: &str) -> Result<Shape, ShapeError> {
        let mut items = spec.split(',');
        let head = items.next().unwrap_or_default().trim();
        let rest: Vec<&str> = items.collect();
        let (kind, size) = head
            .split_once(':')
            .ok_or_else(|| invalid(spec, format!("expected KIND:SIZE, one of {}", kinds_list())))?;
        let kind = kind.trim();
        let mut params = Params::new(spec, &rest)?;
        let shape = match kind.to_ascii_lowercase().as_str() {
            "icosphere" => {
                let shape = Shape::Icosphere {
                    subdivisions: parse_count(spec, size, "subdivisions")?,
                    radius: params.get("radius", 1.0)?,
                };
                params.finish(&["radius"])?;
                shape
            }
            "jittered-icosphere" => {
                let shape = Shape::JitteredIcosphere {
                    subdivisions: parse_count(spec, size, "subdivisions")?,
                    radius: params.get("radius", 1.0)?,
                    jitter: params.get("jitter", 0.1)?,
                    seed: params.get("seed", 0)?,
                };
                params.finish(&["radius", "jitter", "seed"])?;
                shape
            }
            "torus" => {
                let (major_segments, minor_segments) = parse_pair(spec, size, "torus segments")?;
                let shape = Shape::Torus {
                    major_segments,
                    minor_segments,
                    major_radius: params.get("major", 1.0)?,
                    minor_radius: params.get("minor", 0.3)?,
                };
                params.finish(&["major", "minor"])?;
                shape
            }
            "grid" => {
                let (nx, ny) = parse_pair(spec, size, "grid size")?;
                let shape = Shape::Grid {
                    nx,
                    ny,
                    spacing: params.get("spacing", 1.0)?,
                };
                params.finish(&["spacing"])?;
                shape
            }
            "jittered-grid" => {
                let (nx, ny) = parse_pair(spec, size, "grid size")?;
                let shape = Shape::JitteredGrid {
                    nx,
                    ny,
                    spacing: params.get("spacing", 1.0)?,
                    jitter: params.get("jitter", 0.3)?,
                    seed: params.get("seed", 0)?,
                };
                params.finish(&["spacing", "jitter", "seed"])?;
                shape
            }
            "bumpy" => {
                let shape = Shape::Bumpy {
                    subdivisions: parse_count(spec, size, "subdivisions")?,
                    radius: params.get("radius", 1.0)?,
                    bumps: params.get("bumps", 40)?,
                    amplitude: params.get("amplitude", 0.2)?,
                    seed: params.get("seed", 0)?,
                };
                params.finish(&["radius", "bumps", "amplitude", "seed"])?;
                shape
            }
            _ => {
                return Err(ShapeError::UnknownShape {
                    kind: kind.to_owned(),
                    known: kinds_list(),
                });
            }
        };
        shape.validate()?;
        Ok(shape)
    }

    /// Checks every parameter against what the generator accepts (and caps
    /// the size at [`MAX_SHAPE_VERTICES`]), so that [`Shape::build`] cannot
    /// panic.
    ///
    /// # Errors
    ///
    /// [`ShapeError::InvalidParameter`] naming the first bad parameter.
    pub fn validate(&self) -> Result<(), ShapeError> {
        let shape = self.kind();
        let bad = |parameter: &'static str, value: String, requirement: String| {
            Err(ShapeError::InvalidParameter {
                shape,
                parameter,
                value,
                requirement,
            })
        };
        let positive = |parameter: &'static str, x: f64| {
            if x.is_finite() && x > 0.0 {
                Ok(())
            } else {
                bad(parameter, x.to_string(), "finite and positive".into())
            }
        };
        let jitter_in = |x: f64, max: f64| {
            if (0.0..=max).contains(&x) {
                Ok(())
            } else {
                bad("jitter", x.to_string(), format!("within 0..={max}"))
            }
        };
        let sphere = |subdivisions: u32| {
            let too_big = subdivisions > MAX_SPHERE_SUBDIVISIONS
                || (10u64 << (2 * subdivisions)) + 2 > MAX_SHAPE_VERTICES;
            if too_big {
                bad(
                    "subdivisions",
                    subdivisions.to_string(),
                    format!("at most {MAX_SHAPE_VERTICES} vertices"),
                )
            } else {
                Ok(())
            }
        };
        let grid = |nx: u32, ny: u32| {
            if nx == 0 || ny == 0 {
                bad("size", format!("{nx}x{ny}"), "at least 1x1".into())
            } else if (u64::from(nx) + 1) * (u64::from(ny) + 1) > MAX_SHAPE_VERTICES {
                bad(
                    "size",
                    format!("{nx}x{ny}"),
                    format!("at most {MAX_SHAPE_VERTICES} vertices"),
                )
            } else {
                Ok(())
            }
        };
        match *self {
            Shape::Icosphere {
                subdivisions,
                radius,
            } => {
                sphere(subdivisions)?;
                positive("radius", radius)
            }
            Shape::JitteredIcosphere {
                subdivisions,
                radius,
                jitter,
                ..
            } => {
                sphere(subdivisions)?;
                positive("radius", radius)?;
                jitter_in(jitter, MAX_SPHERE_JITTER)
            }
            Shape::Torus {
                major_segments,
                minor_segments,
                major_radius,
                minor_radius,
            } => {
                let size = format!("{major_segments}x{minor_segments}");
                if major_segments < 3 || minor_segments < 3 {
                    return bad("segments", size, "at least 3x3".into());
                }
                if u64::from(major_segments) * u64::from(minor_segments) > MAX_SHAPE_VERTICES {
                    return bad(
                        "segments",
                        size,
                        format!("at most {MAX_SHAPE_VERTICES} vertices"),
                    );
                }
                positive("minor", minor_radius)?;
                positive("major", major_radius)?;
                if minor_radius >= major_radius {
                    return bad(
                        "minor",
                        minor_radius.to_string(),
                        format!("less than major ({major_radius})"),
                    );
                }
                Ok(())
            }
            Shape::Grid { nx, ny, spacing } => {
                grid(nx, ny)?;
                positive("spacing", spacing)
            }
            Shape::JitteredGrid {
                nx,
                ny,
                spacing,
                jitter,
                ..
            } => {
                grid(nx, ny)?;
                positive("spacing", spacing)?;
                jitter_in(jitter, MAX_GRID_JITTER)
            }
            Shape::Bumpy {
                subdivisions,
                radius,
                amplitude,
                ..
            } => {
                sphere(subdivisions)?;
                positive("radius", radius)?;
                if amplitude.is_finite() && amplitude.abs() <= 10.0 {
                    Ok(())
                } else {
                    bad("amplitude", amplitude.to_string(), "within -10..=10".into())
                }
            }
        }
    }

    /// The kind name used in specs (`"icosphere"`, `"torus"`, ...).
    pub fn kind(&self) -> &'static str {
        match self {
            Shape::Icosphere { .. } => "icosphere",
            Shape::JitteredIcosphere { .. } => "jittered-icosphere",
            Shape::Torus { .. } => "torus",
            Shape::Grid { .. } => "grid",
            Shape::JitteredGrid { .. } => "jittered-grid",
            Shape::Bumpy { .. } => "bumpy",
        }
    }

    /// Validates the parameters and generates the mesh.
    ///
    /// # Errors
    ///
    /// As [`Shape::validate`].
    pub fn build(&self) -> Result<IndexedTriangles, ShapeError> {
        self.validate()?;
        Ok(match *self {
            Shape::Icosphere {
                subdivisions,
                radius,
            } => icosphere(subdivisions, radius),
            Shape::JitteredIcosphere {
                subdivisions,
                radius,
                jitter,
                seed,
            } => jittered_icosphere(subdivisions, radius, jitter, seed),
            Shape::Torus {
                major_segments,
                minor_segments,
                major_radius,
                minor_radius,
            } => regular_torus(major_segments, minor_segments, major_radius, minor_radius),
            Shape::Grid { nx, ny, spacing } => flat_grid(nx, ny, spacing),
            Shape::JitteredGrid {
                nx,
                ny,
                spacing,
                jitter,
                seed,
            } => jittered_flat_grid(nx, ny, spacing, jitter, seed),
            Shape::Bumpy {
                subdivisions,
                radius,
                bumps,
                amplitude,
                seed,
            } => bumpy_sphere(subdivisions, radius, bumps, amplitude, seed),
        })
    }
}

/// Parses a spec (see [`Shape`]) and generates the mesh: shorthand for
/// `Shape::from_spec(spec)?.build()`, what the CLI's `--demo` uses.
///
/// # Errors
///
/// As [`Shape::from_spec`].
///
/// ```
/// let sphere = geodesics_shapes::from_spec("icosphere:4").unwrap();
/// assert_eq!(sphere.positions.len(), 2562);
/// assert!(geodesics_shapes::from_spec("icosphere:four").is_err());
/// ```
pub fn from_spec(spec: &str) -> Result<IndexedTriangles, ShapeError> {
    Shape::from_spec(spec)?.build()
}

impl FromStr for Shape {
    type Err = ShapeError;

    fn from_str(spec: &str) -> Result<Self, Self::Err> {
        Shape::from_spec(spec)
    }
}

impl fmt::Display for Shape {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Shape::Icosphere {
                subdivisions,
                radius,
            } => write!(f, "icosphere:{subdivisions},radius={radius}"),
            Shape::JitteredIcosphere {
                subdivisions,
                radius,
                jitter,
                seed,
            } => write!(
                f,
                "jittered-icosphere:{subdivisions},radius={radius},jitter={jitter},seed={seed}"
            ),
            Shape::Torus {
                major_segments,
                minor_segments,
                major_radius,
                minor_radius,
            } => write!(
                f,
                "torus:{major_segments}x{minor_segments},major={major_radius},minor={minor_radius}"
            ),
            Shape::Grid { nx, ny, spacing } => write!(f, "grid:{nx}x{ny},spacing={spacing}"),
            Shape::JitteredGrid {
                nx,
                ny,
                spacing,
                jitter,
                seed,
            } => write!(
                f,
                "jittered-grid:{nx}x{ny},spacing={spacing},jitter={jitter},seed={seed}"
            ),
            Shape::Bumpy {
                subdivisions,
                radius,
                bumps,
                amplitude,
                seed,
            } => write!(
                f,
                "bumpy:{subdivisions},radius={radius},bumps={bumps},amplitude={amplitude},seed={seed}"
            ),
        }
    }
}
