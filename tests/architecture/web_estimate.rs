//! The browser's twin of the error estimate (web/src/estimate.ts) is held to the library's: the
//! fixture web/test/fixtures/estimate.json holds accumulators (the three planes the page reads
//! back: the mean colour, then halves A and B, four f32s a pixel) with the library's raw
//! estimate of each ([`qjulia::estimate::raw`] of the frame the GPU readback builds from them,
//! through [`qjulia::estimate::half_colour`]), and the pass schedule's cases with
//! [`qjulia::render::target::next_samples`]' answers, and estimates with the text a PNG records
//! of them ([`qjulia::output::error_text_of`]). `QJULIA_BLESS=1 cargo test --release
//! --test architecture web` writes it again.

use crate::common::SplitMix;
use crate::web::{b64, check_file, web};
use qjulia::estimate::{half_colour, raw};
use qjulia::frame::Frame;
use qjulia::render::target::next_samples;

/// An accumulator of `width` x `height` pixels: colours over six decades, a share of halves
/// empty (no sample in them), and a few pixels whose halves are far apart (glints).
fn planes(draws: &mut SplitMix, width: u32, height: u32, empty: f64) -> Vec<[f32; 4]> {
    let pixels = (width * height) as usize;
    let mut colour = || -> f32 { (10f64.powf(6.0 * draws.next() - 4.0)) as f32 };
    let mut halves = Vec::new();
    for _ in 0..2 * pixels {
        halves.push([colour(), colour(), colour()]);
    }
    let mut out = Vec::with_capacity(3 * pixels);
    for k in 0..pixels {
        let (a, b) = (halves[k], halves[pixels + k]);
        let m = [0, 1, 2].map(|c| (a[c] + b[c]) / 2.0);
        out.push([m[0], m[1], m[2], 8.0]);
    }
    for h in &halves {
        let samples = if draws.next() < empty { 0.0 } else { 4.0 };
        out.push([h[0], h[1], h[2], samples]);
    }
    out
}

/// The frame the GPU readback builds of `planes` (src/gpu/image.rs): the mean colour as the
/// radiance, each half through `half_colour`.
fn frame_of(planes: &[[f32; 4]], width: u32, height: u32) -> Frame {
    let pixels = (width * height) as usize;
    let mut frame = Frame::empty(width);
    frame.height = height;
    frame.radiance = planes[..pixels]
        .iter()
        .map(|m| [m[0], m[1], m[2]])
        .collect();
    frame.halves = (0..pixels)
        .map(|k| {
            [
                half_colour(&planes[pixels + k]),
                half_colour(&planes[2 * pixels + k]),
            ]
        })
        .collect();
    frame
}

#[test]
fn the_estimate_fixture_is_the_librarys() {
    let mut draws = SplitMix(49);
    let mut cases = Vec::new();
    // (width, height, share of empty halves): one row, one column, a square, an image where
    // most halves are empty, and one where all are (no estimate).
    for (width, height, empty) in [
        (9, 1, 0.0),
        (1, 7, 0.1),
        (16, 12, 0.05),
        (5, 4, 0.6),
        (3, 3, 1.0),
    ] {
        let planes = planes(&mut draws, width, height, empty);
        let estimate = raw(&frame_of(&planes, width, height));
        let bytes: Vec<u8> = planes
            .iter()
            .flatten()
            .flat_map(|v| v.to_le_bytes())
            .collect();
        cases.push(serde_json::json!({
            "width": width,
            "height": height,
            "planes": b64(&bytes),
            "rmse": estimate.map(|e| e.rmse),
            "relative": estimate.map(|e| e.relative),
        }));
    }
    // The schedule: estimates swept over two decades about each target, none, and counts at
    // and near `image.samples` (odd ones too).
    let mut schedule = Vec::new();
    for (samples, target, most) in [
        (16, 0.02, 4096),
        (15, 0.05, 1000),
        (78, 0.01, 1025),
        (2, 0.1, 3),
        (16, 0.02, 21),
    ] {
        let mut estimates: Vec<Option<f64>> = vec![None, Some(target), Some(target * 1.0001)];
        estimates.extend((0..40).map(|_| Some(target * 10f64.powf(2.0 * draws.next() - 0.5))));
        for estimate in estimates {
            schedule.push(serde_json::json!({
                "samples": samples, "estimate": estimate, "target": target, "most": most,
                "next": next_samples(samples, estimate, target, most),
            }));
        }
    }
    // What a PNG records of an estimate (qjulia::output::error_text_of): f64s as Rust's
    // Display writes them (every digit, never an exponent), from tiny to huge.
    let mut texts = Vec::new();
    let mut values = vec![
        0.0, 1.0, 0.1, 1e-7, 1.5e-12, 123456.789, 1e21, 2.5e22, 5e-324,
    ];
    values.extend((0..24).map(|_| 10f64.powf(12.0 * draws.next() - 9.0)));
    for (k, &rmse) in values.iter().enumerate() {
        let relative = rmse / (0.1 + draws.next());
        let target = match k % 3 {
            0 => None,
            1 => Some(("target_error", 2 * k as u32 + 16)),
            _ => Some(("samples", 4096)),
        };
        texts.push(serde_json::json!({
            "rmse": rmse, "relative": relative,
            "stopped_by": target.map(|t| t.0), "samples": target.map(|t| t.1),
            "text": qjulia::output::error_text_of(rmse, relative, target),
        }));
    }
    let fixture = serde_json::json!({ "images": cases, "schedule": schedule, "texts": texts });
    let mut made = serde_json::to_string_pretty(&fixture).unwrap();
    made.push('\n');
    check_file(&web().join("test/fixtures/estimate.json"), &made);
}
