//! Parsing shape specs.

use geodesics_shapes::*;

#[test]
fn parses_the_documented_specs() {
    let cases = [
        (
            "icosphere:4",
            Shape::Icosphere {
                subdivisions: 4,
                radius: 1.0,
            },
        ),
        (
            "torus:120x40",
            Shape::Torus {
                major_segments: 120,
                minor_segments: 40,
                major_radius: 1.0,
                minor_radius: 0.3,
            },
        ),
        (
            "grid:100x100",
            Shape::Grid {
                nx: 100,
                ny: 100,
                spacing: 1.0,
            },
        ),
        (
            "bumpy:5",
            Shape::Bumpy {
                subdivisions: 5,
                radius: 1.0,
                bumps: 40,
                amplitude: 0.2,
                seed: 0,
            },
        ),
        (
            "jittered-icosphere:3,seed=4",
            Shape::JitteredIcosphere {
                subdivisions: 3,
                radius: 1.0,
                jitter: 0.1,
                seed: 4,
            },
        ),
        (
            " Jittered-Grid:7X3 , jitter=0.1 ,spacing=2",
            Shape::JitteredGrid {
                nx: 7,
                ny: 3,
                spacing: 2.0,
                jitter: 0.1,
                seed: 0,
            },
        ),
        (
            "torus:6x5,minor=0.5,major=2.5",
            Shape::Torus {
                major_segments: 6,
                minor_segments: 5,
                major_radius: 2.5,
                minor_radius: 0.5,
            },
        ),
    ];
    for (spec, shape) in cases {
        assert_eq!(Shape::from_spec(spec).expect(spec), shape, "{spec}");
        // Display → parse round trip.
        assert_eq!(shape.to_string().parse::<Shape>().expect(spec), shape);
    }
    for (_, example) in SHAPE_KINDS {
        let shape = Shape::from_spec(example).expect(example);
        assert!(example.starts_with(shape.kind()));
    }
}

#[test]
fn builds_what_the_functions_build() {
    assert_eq!(
        Shape::from_spec("icosphere:3").and_then(|s| s.build()),
        Ok(icosphere(3, 1.0))
    );
    assert_eq!(
        Shape::from_spec("torus:120x40").and_then(|s| s.build()),
        Ok(regular_torus(120, 40, 1.0, 0.3))
    );
    assert_eq!(
        Shape::from_spec("grid:10x4").and_then(|s| s.build()),
        Ok(flat_grid(10, 4, 1.0))
    );
    assert_eq!(
        Shape::from_spec("bumpy:3,seed=2").and_then(|s| s.build()),
        Ok(bumpy_sphere(3, 1.0, 40, 0.2, 2))
    );
    assert_eq!(
        Shape::from_spec("jittered-grid:5x5,seed=9").and_then(|s| s.build()),
        Ok(jittered_flat_grid(5, 5, 1.0, 0.3, 9))
    );
}

#[test]
fn rejects_bad_specs_with_clear_errors() {
    let cases = [
        (
            "cube:3",
            "unknown shape kind \"cube\"; expected one of: icosphere:4, jittered-icosphere:4, torus:120x40, grid:100x100, jittered-grid:100x100, bumpy:5",
        ),
        (
            "icosphere",
            "invalid shape spec \"icosphere\": expected KIND:SIZE, one of icosphere:4,",
        ),
        ("", "invalid shape spec \"\": expected KIND:SIZE"),
        (
            "icosphere:x",
            "subdivisions must be a non-negative integer, found \"x\"",
        ),
        (
            "icosphere:-1",
            "subdivisions must be a non-negative integer",
        ),
        (
            "torus:120",
            "torus segments must look like 120x40, found \"120\"",
        ),
        (
            "torus:2x40",
            "torus: segments = 2x40 is out of range (must be at least 3x3)",
        ),
        (
            "torus:10x10,minor=2",
            "torus: minor = 2 is out of range (must be less than major (1))",
        ),
        (
            "torus:10x10,minor=-1",
            "torus: minor = -1 is out of range (must be finite and positive)",
        ),
        (
            "grid:0x5",
            "grid: size = 0x5 is out of range (must be at least 1x1)",
        ),
        ("grid:100000x100000", "at most 100000000 vertices"),
        (
            "icosphere:20",
            "icosphere: subdivisions = 20 is out of range",
        ),
        (
            "icosphere:4,foo=1",
            "unknown key \"foo\"; this shape takes radius",
        ),
        ("icosphere:4,radius=abc", "cannot parse radius=\"abc\""),
        (
            "icosphere:4,radius=nan",
            "icosphere: radius = NaN is out of range",
        ),
        (
            "icosphere:4,radius=1,radius=2",
            "key \"radius\" given twice",
        ),
        ("icosphere:4,radius", "expected KEY=VALUE, found \"radius\""),
        (
            "jittered-icosphere:4,jitter=0.5",
            "jitter = 0.5 is out of range (must be within 0..=0.1)",
        ),
        (
            "jittered-grid:4x4,jitter=0.5",
            "jitter = 0.5 is out of range (must be within 0..=0.35)",
        ),
        ("bumpy:4,amplitude=inf", "amplitude = inf is out of range"),
        ("bumpy:4,bumps=-3", "cannot parse bumps=\"-3\""),
    ];
    for (spec, message) in cases {
        let err = Shape::from_spec(spec).expect_err(spec).to_string();
        assert!(err.contains(message), "{spec}: got \"{err}\"");
    }
}

#[test]
fn build_validates_hand_made_shapes() {
    let shape = Shape::Torus {
        major_segments: 10,
        minor_segments: 10,
        major_radius: 1.0,
        minor_radius: 1.0,
    };
    assert!(matches!(
        shape.build(),
        Err(ShapeError::InvalidParameter {
            parameter: "minor",
            ..
        })
    ));
    let shape = Shape::Grid {
        nx: 3,
        ny: 3,
        spacing: f64::INFINITY,
    };
    assert!(shape.build().is_err());
}

#[test]
fn free_from_spec_builds() {
    assert_eq!(from_spec("grid:3x2"), Ok(flat_grid(3, 2, 1.0)));
    let demo = from_spec("bumpy:4").expect("demo shape");
    assert_eq!(demo.positions.len(), 2562);
    assert!(matches!(
        from_spec("klein:3"),
        Err(ShapeError::UnknownShape { .. })
    ));
}
