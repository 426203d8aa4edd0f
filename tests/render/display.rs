//! The display transform of path mode (src/display.rs): each tone map, the sRGB transfer
//! function and the rounding against their formulas, evaluated independently (the literals were
//! computed with Python's float arithmetic from the formulas in docs/book/display.md).

use qjulia::display::{Display, ToneMap, aces_narkowicz, quantise, reinhard, srgb_encode};

/// (x, reinhard, ACES fit clamped, sRGB of min(x, 1)), from Python.
const TABLE: [(f64, f64, f64, f64); 6] = [
    (
        0.001,
        0.0009990009990009992,
        0.0002312357784839482,
        0.012920000000000001,
    ),
    (
        0.18,
        0.15254237288135594,
        0.2668989203894968,
        0.46135612950044164,
    ),
    (
        0.5,
        0.3333333333333333,
        0.6163069544364508,
        0.7353569830524495,
    ),
    (1.0, 0.5, 0.8037974683544302, 0.9999999999999999),
    (4.0, 0.8, 0.9734171097148379, 0.9999999999999999),
    (16.0, 0.9411764705882353, 1.0, 0.9999999999999999),
];

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-15 * b.abs().max(1.0)
}

#[test]
fn each_curve_matches_its_formula() {
    for (x, r, a, s) in TABLE {
        assert!(close(reinhard(x), r), "reinhard({x}) = {}", reinhard(x));
        assert!(close(ToneMap::Reinhard.apply(x), r));
        assert!(close(ToneMap::Aces.apply(x), a), "aces({x})");
        assert!(close(ToneMap::None.apply(x), x.min(1.0)));
        assert!(close(srgb_encode(x.min(1.0)), s), "srgb({x})");
    }
    // The fit itself goes above 1 before the clamp.
    assert!(aces_narkowicz(16.0) > 1.0);
    // Below the sRGB knee the function is linear; at the knee the standard's two pieces meet
    // to within 7e-8 (its constants are rounded), far below an 8-bit step.
    assert_eq!(srgb_encode(0.002), 12.92 * 0.002);
    assert!((srgb_encode(0.003_130_8) - srgb_encode(0.003_130_800_1)).abs() < 1e-7);
}

#[test]
fn negative_and_nan_radiance_show_black() {
    for t in ToneMap::ALL {
        assert_eq!(t.apply(-1.0), 0.0);
        assert_eq!(t.apply(f64::NAN), 0.0);
        assert_eq!(t.apply(0.0), 0.0);
    }
    assert_eq!(Display::default().encode(f32::NAN), 0);
    assert_eq!(Display::default().encode(-3.0), 0);
}

#[test]
fn the_chain_is_exposure_then_curve_then_srgb_then_rounding() {
    assert_eq!(quantise(0.0), 0);
    assert_eq!(quantise(1.0), 255);
    assert_eq!(quantise(0.5 / 255.0), 1, "half a step rounds up");
    assert_eq!(quantise(0.499 / 255.0), 0);
    // 0.18 at exposure 0, "none": sRGB 0.46136 -> 117.65 -> 118.
    let none = Display::default();
    assert_eq!(none.encode(0.18), 118);
    // One stop up doubles the radiance: 0.09 at +1 is 0.18 at 0.
    let up = Display {
        exposure: 1.0,
        tone_map: ToneMap::None,
    };
    assert_eq!(up.encode(0.09), 118);
    // Reinhard of 1.0 is 0.5: sRGB 0.73536 -> 187.52 -> 188.
    let reinhard = Display {
        exposure: 0.0,
        tone_map: ToneMap::Reinhard,
    };
    assert_eq!(reinhard.encode(1.0), 188);
    // "none" clamps: anything above 1 is white.
    assert_eq!(none.encode(7.5), 255);
    assert_eq!(none.rgb8(&[[0.18, 1.0, 0.0], [2.0, 0.0, 0.5]]), {
        let b = |x: f64| quantise(srgb_encode(x));
        vec![118, 255, 0, 255, 0, b(0.5)]
    });
}

#[test]
fn every_curve_is_monotonic() {
    for t in ToneMap::ALL {
        let d = Display {
            exposure: 0.0,
            tone_map: t,
        };
        let mut last = 0;
        for k in 0..20_000 {
            let b = d.encode(k as f32 * 1e-3);
            assert!(b >= last, "{t}: not monotonic at {}", k as f32 * 1e-3);
            last = b;
        }
    }
}

#[test]
fn tone_maps_parse_by_name() {
    for t in ToneMap::ALL {
        assert_eq!(t.name().parse::<ToneMap>(), Ok(t));
    }
    let e = "filmic".parse::<ToneMap>().unwrap_err();
    assert_eq!(
        e,
        "unknown tone map \"filmic\" (expected \"none\", \"reinhard\", \"aces\")"
    );
}
