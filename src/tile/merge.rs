//! `merge`: the parts read back ([`super::partial`]), checked to be one scene's, made on one
//! adapter in one precision, covering every row once, and put together into the whole frame.

use std::ops::Range;
use std::path::PathBuf;

use super::Tile;
use super::partial::{PART_BYTES_PER_PIXEL, Part, bad, read_part};
use crate::display::Display;
use crate::error::{Error, FlagError, Result};
use crate::frame::Frame;
use crate::picture::Picture;
use crate::scene::Scene;
use crate::stats::{RenderStats, Summary};

/// The whole frame of the partial EXRs at `paths` and its stats, once they are checked: one
/// scene, made on one adapter in one precision, every row once; not yet denoised (the caller
/// runs [`crate::Renderer::denoise`] where the scene asks, on the parts' backend). Path mode's colour is the
/// display transform of the merged radiance (as `render` makes it); phong mode's is the
/// tracer's own 8-bit colour. The stats are those `render` gives but for the times:
/// `render_seconds` is the sum of the parts', `gpu_seconds` too (null if a part has none).
/// Any bad part is an error naming its file.
pub fn merge(paths: &[PathBuf]) -> Result<(Scene, Frame, RenderStats)> {
    let memory = crate::memory::available();
    let mut parts: Vec<Part> = Vec::with_capacity(paths.len());
    for path in paths {
        let part = read_part(path, memory)?;
        if parts.is_empty() {
            // The parts, then the whole frame made of them: refused before a second is read.
            let (width, height) = (part.scene.image.width, part.scene.image.height);
            crate::memory::check_within(
                &format!("merge's {width}x{height} image"),
                u64::from(width) * u64::from(height) * PART_BYTES_PER_PIXEL,
                memory,
            )?;
        }
        if let Some(first) = parts.first() {
            check_same(first, &part)?;
        }
        parts.push(part);
    }
    let first = parts
        .first()
        .ok_or_else(|| Error::from(FlagError::new("merge", "no parts given")))?;
    let (scene, made_by) = (first.scene.clone(), first.made_by.clone());
    let height = scene.image.height;
    parts.sort_by_key(|p| (p.rows.start, p.rows.end));
    let mut next = 0;
    for (k, part) in parts.iter().enumerate() {
        if part.rows.start < next {
            let before = &parts[k - 1];
            return Err(bad(
                &part.path,
                format!(
                    "its rows {}..{} (tile {}) overlap those of {} ({}..{}, tile {})",
                    part.rows.start,
                    part.rows.end,
                    part.tile,
                    before.path.display(),
                    before.rows.start,
                    before.rows.end,
                    before.tile
                ),
            ));
        }
        if part.rows.start > next {
            return Err(missing(next..part.rows.start, &parts));
        }
        next = part.rows.end;
    }
    if next < height {
        return Err(missing(next..height, &parts));
    }
    let mut whole = Frame::empty(scene.image.width);
    let (mut render_seconds, mut gpu_seconds) = (0.0, Some(0.0));
    for part in &parts {
        whole.append(&part.frame);
        render_seconds += part.render_seconds;
        gpu_seconds = gpu_seconds.zip(part.gpu_seconds).map(|(a, b)| a + b);
    }
    if Picture::SHADED.path_traced(&scene) {
        Display::of(&scene).show(&mut whole);
    }
    let [backend, adapter, precision, precision_reason] = made_by;
    // The kernel a GPU render of the whole scene records: this binary's composition of it.
    #[cfg(not(feature = "gpu"))]
    let kernel = None;
    #[cfg(feature = "gpu")]
    let kernel = (backend == "gpu").then(|| {
        let precision = crate::Precision::of_name(&precision);
        crate::gpu::scene_kernel::kernel_stats(&scene, Picture::SHADED, precision)
    });
    let stats = RenderStats {
        backend,
        adapter,
        precision,
        precision_reason,
        width: scene.image.width,
        height,
        render_seconds,
        gpu_seconds,
        environment_seconds: scene.loaded.environment.as_ref().map(|e| e.seconds),
        denoise: None,
        target: None,
        kernel,
        summary: Summary::of(&whole),
    };
    Ok((scene, whole, stats))
}

/// A part of another scene, or made on another adapter or in another precision than the
/// first part: an error naming it.
fn check_same(first: &Part, part: &Part) -> Result<()> {
    let first_name = first.path.display();
    if part.scene_text != first.scene_text {
        return Err(bad(
            &part.path,
            format!("a tile of another scene than {first_name}'s"),
        ));
    }
    if part.made_by[..3] != first.made_by[..3] {
        let made = |p: &Part| format!("{} on {} ({})", p.made_by[0], p.made_by[1], p.made_by[2]);
        return Err(bad(
            &part.path,
            format!(
                "rendered {}, but {first_name} {}: tiles of one image come from one adapter in one precision",
                made(part),
                made(first)
            ),
        ));
    }
    Ok(())
}

/// The error for rows that no part holds: it names the missing tile where every part is a
/// tile of one split.
fn missing(rows: Range<u32>, parts: &[Part]) -> Error {
    let height = parts[0].scene.image.height;
    let split: Option<Vec<Tile>> = parts
        .iter()
        .map(|p| Tile::parse(&p.tile, height).ok())
        .collect();
    let named = split.and_then(|tiles| {
        let count = tiles[0].count;
        (tiles.iter().all(|t| t.count == count)).then(|| {
            (0..count)
                .map(|index| Tile { index, count })
                .filter(|t| {
                    let r = t.rows(height);
                    r.start < rows.end && rows.start < r.end
                })
                .map(|t| t.to_string())
                .collect::<Vec<_>>()
                .join(", ")
        })
    });
    let what = match named {
        Some(tiles) => format!(": tile {tiles} is missing"),
        None => String::new(),
    };
    Error::from(FlagError::new(
        "merge",
        format!(
            "rows {}..{} of {height} are in no part{what}",
            rows.start, rows.end
        ),
    ))
}
