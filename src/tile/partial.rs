//! The partial EXR of a tile (the format is the parent module's documentation, [`super`]): its
//! one writer ([`write_partial`]) and its one reader, which checks a part whole before `merge`
//! takes it.

use std::io::{Seek, Write};
use std::ops::Range;
use std::path::{Path, PathBuf};

use exr::meta::attribute::{AttributeValue, IntegerBounds, Text};
use exr::prelude::{AnyChannel, FlatSamples, ImageAttributes, LayerAttributes, SmallVec, Vec2};

use super::Tile;
use crate::error::{Error, Result};
use crate::frame::Frame;
use crate::output::{io_error, stage};
use crate::picture::Picture;
use crate::scene::{SCENE_EXR_ATTRIBUTE, Scene, SceneLoader, SceneSource};
use crate::stats::RenderStats;

/// The partial format's version (`qjulia-partial`); `merge` reads this one only.
pub const FORMAT_VERSION: i32 = 5;

/// The float32 channels, in the order [`Frame`] gives them (the `--hdr` channels).
const FLOAT_CHANNELS: [&str; 13] = [
    "R",
    "G",
    "B",
    "albedo.R",
    "albedo.G",
    "albedo.B",
    "N.X",
    "N.Y",
    "N.Z",
    "Z",
    "luminance.M2",
    "hits",
    "Z.mean",
];
/// Path mode's float32 channels beside those: each pixel's two halves ([`Frame::halves`]; NaN in
/// a half that holds no sample), so that `merge` estimates the error as one render does; its
/// first hits' specular light and view cosine ([`Frame::specular`], [`Frame::view_cosine`]),
/// so that `merge` denoises as one render does.
const HALF_CHANNELS: [&str; 10] = [
    "half.A.R",
    "half.A.G",
    "half.A.B",
    "half.B.R",
    "half.B.G",
    "half.B.B",
    "specular.R",
    "specular.G",
    "specular.B",
    "view.cosine",
];
/// The uint32 channels.
const UINT_CHANNELS: [&str; 3] = ["colour8", "steps", "samples"];

const PARTIAL: &str = "qjulia-partial";
const TILE: &str = "qjulia-tile";
const BACKEND: &str = "qjulia-backend";
const ADAPTER: &str = "qjulia-adapter";
const PRECISION: &str = "qjulia-precision";
const PRECISION_REASON: &str = "qjulia-precision-reason";
const RENDER_SECONDS: &str = "qjulia-render-seconds";
const GPU_SECONDS: &str = "qjulia-gpu-seconds";
const ESTIMATES: &str = "qjulia-estimates";
const ITERATIONS: &str = "qjulia-iterations";
const NONFINITE_SAMPLES: &str = "qjulia-nonfinite-samples";
const EXHAUSTED_RAYS: &str = "qjulia-exhausted-rays";

/// Writes the partial EXR of `tile` (its rows of `scene` in `band`, rendered with their AOVs)
/// to `path`, and `stats` as JSON where asked: whole or not at all.
pub fn write_partial(
    path: &Path,
    stats_path: Option<&Path>,
    scene: &Scene,
    tile: Tile,
    band: &Frame,
    stats: &RenderStats,
) -> Result<()> {
    let rows = tile.rows(scene.image.height);
    assert_eq!(band.height, rows.end - rows.start, "the tile's rows");
    let mut staged = Vec::new();
    if let Some(stats_path) = stats_path {
        let temp = stage(stats_path, |w| {
            serde_json::to_writer_pretty(&mut *w, stats)?;
            w.write_all(b"\n")
        })?;
        staged.push((temp, stats_path.to_path_buf()));
    }
    let temp = stage(path, |_| Ok(()))?;
    {
        let mut file = std::io::BufWriter::new(temp.as_file());
        write_exr(scene, tile, band, stats, &mut file)
            .and_then(|()| file.flush())
            .map_err(|e| io_error(path, e))?;
    }
    staged.push((temp, path.to_path_buf()));
    for (temp, path) in staged {
        temp.persist(&path).map_err(|e| io_error(&path, e.error))?;
    }
    Ok(())
}

/// The partial EXR's bytes (see the module's documentation).
fn write_exr(
    scene: &Scene,
    tile: Tile,
    band: &Frame,
    stats: &RenderStats,
    to: impl Write + Seek,
) -> std::io::Result<()> {
    let (width, height) = (scene.image.width as usize, scene.image.height as usize);
    let rows = tile.rows(scene.image.height);
    let pixels = band.pixel_count();
    let linear = band.linear();
    assert!(
        linear.len() == pixels
            && band.albedo.len() == pixels
            && band.normal.len() == pixels
            && band.luminance_m2.len() == pixels
            && band.hits.len() == pixels
            && band.hit_depth.len() == pixels,
        "a tile carries its AOVs (Readback::Hdr)"
    );
    let mut floats: Vec<Vec<f32>> = Vec::new();
    for values in [linear, &band.albedo, &band.normal] {
        for c in 0..3 {
            floats.push(values.iter().map(|v| v[c]).collect());
        }
    }
    floats.push(band.depth.clone());
    floats.push(band.luminance_m2.clone());
    floats.push(band.hits.clone());
    floats.push(band.hit_depth.clone());
    let halves = match band.halves.len() == pixels && band.specular.len() == pixels {
        true => HALF_CHANNELS.as_slice(),
        false => &[],
    };
    if !halves.is_empty() {
        for h in 0..2 {
            for c in 0..3 {
                floats.push(band.halves.iter().map(|v| v[h][c]).collect());
            }
        }
        for c in 0..3 {
            floats.push(band.specular.iter().map(|v| v[c]).collect());
        }
        floats.push(band.view_cosine.clone());
    }
    let samples = match band.samples.len() == pixels {
        true => band.samples.clone(),
        false => vec![scene.image.samples.max(1); pixels],
    };
    let uints = [band.colour.clone(), band.steps.clone(), samples];
    let channels: SmallVec<[AnyChannel<FlatSamples>; 4]> = FLOAT_CHANNELS
        .iter()
        .chain(halves)
        .zip(floats)
        .map(|(name, v)| AnyChannel::new(*name, FlatSamples::F32(v)))
        .chain(
            UINT_CHANNELS
                .iter()
                .zip(uints)
                .map(|(name, v)| AnyChannel::new(*name, FlatSamples::U32(v))),
        )
        .collect();
    let layer = LayerAttributes {
        software_name: Some(Text::from(concat!("qjulia ", env!("CARGO_PKG_VERSION")))),
        layer_position: Vec2(0, rows.start as i32),
        ..Default::default()
    };
    let mut attributes = ImageAttributes::new(IntegerBounds::new((0, 0), (width, height)));
    let text = |s: &str| AttributeValue::Text(Text::from_slice_unchecked(s.as_bytes()));
    let mut set = |name: &str, value: AttributeValue| {
        attributes.other.insert(Text::from(name), value);
    };
    set(SCENE_EXR_ATTRIBUTE, text(&scene.to_toml()));
    set(PARTIAL, AttributeValue::I32(FORMAT_VERSION));
    set(TILE, text(&tile.to_string()));
    set(BACKEND, text(&stats.backend));
    set(ADAPTER, text(&stats.adapter));
    set(PRECISION, text(&stats.precision));
    set(PRECISION_REASON, text(&stats.precision_reason));
    set(RENDER_SECONDS, AttributeValue::F64(stats.render_seconds));
    if let Some(s) = stats.gpu_seconds {
        set(GPU_SECONDS, AttributeValue::F64(s));
    }
    set(ESTIMATES, text(&band.estimates.to_string()));
    set(ITERATIONS, text(&band.iterations.to_string()));
    if !band.radiance.is_empty() {
        set(NONFINITE_SAMPLES, text(&band.nonfinite_samples.to_string()));
        set(EXHAUSTED_RAYS, text(&band.exhausted_rays.to_string()));
    }
    crate::hdr::write_exr(
        attributes,
        (width, band.height as usize),
        layer,
        channels,
        to,
    )
}

/// One part as `merge` read it.
pub(super) struct Part {
    pub(super) path: PathBuf,
    pub(super) scene_text: String,
    pub(super) scene: Scene,
    pub(super) tile: String,
    pub(super) rows: Range<u32>,
    /// backend, adapter, precision, precision reason.
    pub(super) made_by: [String; 4],
    pub(super) render_seconds: f64,
    pub(super) gpu_seconds: Option<f64>,
    pub(super) frame: Frame,
}

/// A bad part: one line naming its file.
pub(super) fn bad(path: &Path, message: impl Into<String>) -> Error {
    Error::Part {
        path: path.to_path_buf(),
        message: message.into(),
    }
}

/// Reads and checks one partial EXR.
pub(super) fn read_part(path: &Path, memory: Option<u64>) -> Result<Part> {
    let file = std::fs::File::open(path).map_err(|e| bad(path, format!("cannot read: {e}")))?;
    read_part_from(std::io::BufReader::new(file), path, memory)
}

/// Reads the partial EXR held in `bytes` as `merge` reads a file (the fuzz target's way in),
/// `path` naming it in the errors, with `memory` bytes to hold its pixels in; Ok when it is a
/// whole part.
pub fn check_part_bytes(bytes: &[u8], path: &Path, memory: u64) -> Result<()> {
    read_part_from(std::io::Cursor::new(bytes), path, Some(memory)).map(|_| ())
}

/// The bytes a part's pixel holds while it is read: its channels as the EXR reader gives them,
/// and again in the [`Frame`] made of them.
pub(super) const PART_BYTES_PER_PIXEL: u64 =
    2 * 4 * (FLOAT_CHANNELS.len() + UINT_CHANNELS.len()) as u64;

/// The part read from `input`, the file at `path`. Its header is read and checked first
/// (partial, scene, tile, windows), and its pixels only when they fit in `memory` bytes (None:
/// unknown): a header cannot make the reader allocate more than its own scene's rows.
fn read_part_from(
    mut input: impl std::io::Read + std::io::Seek,
    path: &Path,
    memory: Option<u64>,
) -> Result<Part> {
    use exr::prelude::traits::*;
    let unreadable = |e: exr::error::Error| match e {
        exr::error::Error::Io(e) => bad(path, format!("cannot read: {e}")),
        e => bad(path, format!("not a readable OpenEXR file: {e}")),
    };
    let meta = exr::meta::MetaData::read_from_buffered(&mut input, true).map_err(unreadable)?;
    let [header] = meta.headers.as_slice() else {
        return Err(bad(
            path,
            format!("has {} layers; a partial has one", meta.headers.len()),
        ));
    };
    let attribute = |name: &str| {
        let name = Text::from(name);
        header
            .own_attributes
            .other
            .get(&name)
            .or_else(|| header.shared_attributes.other.get(&name))
    };
    let text = |name: &str| match attribute(name) {
        Some(AttributeValue::Text(t)) => String::from_utf8(t.bytes().to_vec())
            .map_err(|_| bad(path, format!("its {name} attribute is not UTF-8"))),
        Some(_) => Err(bad(path, format!("its {name} attribute is not a string"))),
        None => Err(bad(path, format!("has no {name} attribute"))),
    };
    match attribute(PARTIAL) {
        Some(AttributeValue::I32(FORMAT_VERSION)) => {}
        Some(AttributeValue::I32(v)) => {
            return Err(bad(
                path,
                format!("a partial of format {v}; this qjulia reads format {FORMAT_VERSION}"),
            ));
        }
        _ => {
            return Err(bad(
                path,
                "not a partial of `render --tile` (no qjulia-partial attribute)",
            ));
        }
    }
    let scene_text = text(SCENE_EXR_ATTRIBUTE)?;
    let mut loader = SceneLoader::new();
    loader.toml_str(&scene_text, SceneSource::File(path.to_path_buf()))?;
    let scene = loader.build()?;
    let tile = text(TILE)?;
    let (width, height) = (scene.image.width, scene.image.height);
    let display = header.shared_attributes.display_window;
    if display.position != Vec2(0, 0) || display.size != Vec2(width as usize, height as usize) {
        return Err(bad(
            path,
            format!(
                "its display window is {}x{}, not the scene's {width}x{height}",
                display.size.0, display.size.1
            ),
        ));
    }
    let expected_rows = Tile::parse(&tile, height)
        .map_err(|_| {
            bad(
                path,
                format!("its qjulia-tile \"{tile}\" is not a tile of {height} rows"),
            )
        })?
        .rows(height);
    let start = header.own_attributes.layer_position;
    let size = header.layer_size;
    let rows = start.1.max(0) as u32..(start.1.max(0) as u32).saturating_add(size.1 as u32);
    if start.0 != 0 || size.0 != width as usize || rows != expected_rows {
        return Err(bad(
            path,
            format!(
                "its data window is not the rows {}..{} of tile {tile}",
                expected_rows.start, expected_rows.end
            ),
        ));
    }
    crate::memory::check_within(
        &format!("{}'s {width}x{} rows", path.display(), rows.len()),
        u64::from(width) * rows.len() as u64 * PART_BYTES_PER_PIXEL,
        memory,
    )?;
    input
        .seek(std::io::SeekFrom::Start(0))
        .map_err(|e| bad(path, format!("cannot read: {e}")))?;
    // Pedantic: a truncated or damaged file is an error, not a part with holes.
    let image = exr::prelude::read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .first_valid_layer()
        .all_attributes()
        .pedantic()
        .from_buffered(input)
        .map_err(unreadable)?;
    let layer = &image.layer_data;
    if layer.size != size {
        return Err(bad(path, "its pixels are not those of its header"));
    }
    let pixels = width as usize * rows.len();
    let channel = |name: &str| {
        layer
            .channel_data
            .list
            .iter()
            .find(|c| c.name == *name)
            .map(|c| &c.sample_data)
            .ok_or_else(|| bad(path, format!("has no {name} channel")))
    };
    let float = |name: &str| -> Result<&[f32]> {
        match channel(name)? {
            FlatSamples::F32(v) if v.len() == pixels => Ok(v.as_slice()),
            _ => Err(bad(path, format!("its {name} channel is not float32"))),
        }
    };
    let uint = |name: &str| -> Result<&[u32]> {
        match channel(name)? {
            FlatSamples::U32(v) if v.len() == pixels => Ok(v.as_slice()),
            _ => Err(bad(path, format!("its {name} channel is not uint32"))),
        }
    };
    let triple = |names: &[&str]| -> Result<Vec<[f32; 3]>> {
        let (x, y, z) = (float(names[0])?, float(names[1])?, float(names[2])?);
        Ok((0..pixels).map(|k| [x[k], y[k], z[k]]).collect())
    };
    let linear = triple(&FLOAT_CHANNELS[0..3])?;
    let path_traced = Picture::SHADED.path_traced(&scene);
    let mut frame = Frame::empty(width);
    frame.height = rows.len() as u32;
    frame.albedo = triple(&FLOAT_CHANNELS[3..6])?;
    frame.normal = triple(&FLOAT_CHANNELS[6..9])?;
    frame.depth = float("Z")?.to_vec();
    frame.luminance_m2 = float("luminance.M2")?.to_vec();
    frame.hits = float("hits")?.to_vec();
    frame.hit_depth = float("Z.mean")?.to_vec();
    frame.colour = uint("colour8")?.to_vec();
    frame.steps = uint("steps")?.to_vec();
    frame.samples = uint("samples")?.to_vec();
    let most = scene.image.samples.max(1);
    if let Some(n) = frame.samples.iter().find(|&&n| n == 0 || n > most) {
        return Err(bad(
            path,
            format!("its samples channel holds {n}, outside 1..={most} (image.samples)"),
        ));
    }
    match path_traced {
        true => frame.radiance = linear,
        false => frame.unclamped = linear,
    }
    if path_traced {
        let (a, b) = (triple(&HALF_CHANNELS[0..3])?, triple(&HALF_CHANNELS[3..6])?);
        frame.halves = a.into_iter().zip(b).map(|(a, b)| [a, b]).collect();
        frame.specular = triple(&HALF_CHANNELS[6..9])?;
        frame.view_cosine = float(HALF_CHANNELS[9])?.to_vec();
    }
    let count = |name: &str| -> Result<u64> {
        text(name)?
            .parse()
            .map_err(|_| bad(path, format!("its {name} attribute is not a count")))
    };
    frame.estimates = count(ESTIMATES)?;
    frame.iterations = count(ITERATIONS)?;
    // Path mode's counts: absent (0) in a part from before they were written.
    for (name, value) in [
        (NONFINITE_SAMPLES, &mut frame.nonfinite_samples),
        (EXHAUSTED_RAYS, &mut frame.exhausted_rays),
    ] {
        if attribute(name).is_some() {
            *value = count(name)?;
        }
    }
    let seconds = |name: &str| match attribute(name) {
        Some(&AttributeValue::F64(s)) => Ok(Some(s)),
        None => Ok(None),
        Some(_) => Err(bad(path, format!("its {name} attribute is not a double"))),
    };
    Ok(Part {
        path: path.to_path_buf(),
        made_by: [
            text(BACKEND)?,
            text(ADAPTER)?,
            text(PRECISION)?,
            text(PRECISION_REASON)?,
        ],
        render_seconds: seconds(RENDER_SECONDS)?.unwrap_or(0.0),
        gpu_seconds: seconds(GPU_SECONDS)?,
        scene_text,
        scene,
        tile,
        rows,
        frame,
    })
}
