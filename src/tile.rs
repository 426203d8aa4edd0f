//! Tiles for farms: `render --tile K/N` renders the K-th of N bands of rows and writes a
//! partial OpenEXR; `merge` reads the parts, checks that they are one scene's and cover every
//! row once, and puts the whole frame together for the final stage `render` runs too
//! ([`crate::output::write_view_outputs`]), so that its outputs are byte-identical to one
//! render's on the same adapter.
//!
//! # The partial EXR (format version [`FORMAT_VERSION`])
//!
//! One part, scan lines, ZIP (lossless). The display window is the whole image (0, 0) to
//! (width - 1, height - 1); the data window is the tile's rows [K*H/N, (K+1)*H/N), full width,
//! so that any EXR viewer shows the tile in place. Channels (stored sorted by name):
//!
//! | channel | type | holds |
//! |---|---|---|
//! | `R`, `G`, `B` | float32 | the linear mean, bit for bit what the accumulator holds: path mode's radiance, phong mode's unclamped colour mean (as `--hdr`) |
//! | `albedo.R/G/B`, `N.X/Y/Z` | float32 | the AOVs, as `--hdr` |
//! | `Z` | float32 | the depth, NaN where the ray hits nothing, as `--hdr` |
//! | `colour8` | uint32 | the 8-bit colour the tracer made, 0xFFBBGGRR (phong mode's PNG pixels: the mean of the clamped samples, rounded on the device; path mode's is the display transform of `R`, `G`, `B`, which `merge` makes again) |
//! | `steps` | uint32 | primary-ray steps (for `--stats` and the heat-map views) |
//! | `luminance.M2` | float32 | the sum of the squared deviations of the samples' luminances from their mean (Welford's M2, the AOVs' fourth float of the albedo): the denoiser's variance |
//! | `hits` | float32 | how many of the samples the pixel's mean holds hit ([`Frame::hits`]): the denoiser's hit fraction |
//! | `Z.mean` | float32 | the depth of the hits, averaged over them, 0 where none hit ([`Frame::hit_depth`]): the denoiser's depth guide |
//! | `samples` | uint32 | samples each pixel took: `image.samples`, or fewer where adaptive sampling (`path.noise_target`) stopped it; each pixel decides alone, so a tile's counts are the whole render's |
//!
//! The accumulators keep a running mean in float32 (m_k = m_(k-1) + (x_k - m_(k-1)) / (k + 1)),
//! not a sum, so the mean itself goes in float32 channels with nothing lost; a sum, where one is
//! wanted (runs combined), is mean x `samples`. No float64 is needed.
//! `merge` runs the denoiser (`image.denoise`) over the whole frame, as `render` does, from
//! these channels alone. A reader must ignore channels it does not know.
//!
//! Header attributes: `qjulia-scene` (string, the scene's TOML, as the PNG's chunk and
//! `--hdr`'s attribute; `--scene PART.exr` reads it), `qjulia-partial` (int, the format
//! version), `qjulia-tile` (string, `K/N`), `qjulia-backend`, `qjulia-adapter`,
//! `qjulia-precision`, `qjulia-precision-reason` (strings, as `--stats` names them),
//! `qjulia-render-seconds` (double), `qjulia-gpu-seconds` (double, absent where the device has
//! no timestamps), `qjulia-estimates` (string, a decimal u64: distance estimates made for the
//! tile's pixels), and in path mode `qjulia-nonfinite-samples` and `qjulia-exhausted-rays`
//! (strings, decimal u64s: `--stats`' counts of the tile; absent, from an older binary, they
//! count 0).

use std::io::{Seek, Write};
use std::ops::Range;
use std::path::{Path, PathBuf};

use exr::meta::attribute::{AttributeValue, IntegerBounds, Text};
use exr::prelude::{AnyChannel, FlatSamples, ImageAttributes, LayerAttributes, SmallVec, Vec2};

use crate::display::Display;
use crate::error::{Error, FlagError, Result};
use crate::frame::Frame;
use crate::output::{io_error, stage};
use crate::picture::Picture;
use crate::scene::{SCENE_EXR_ATTRIBUTE, Scene, SceneLoader, SceneSource};
use crate::stats::{RenderStats, Summary};

/// The partial format's version (`qjulia-partial`); `merge` reads this one only.
pub const FORMAT_VERSION: i32 = 2;

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
const NONFINITE_SAMPLES: &str = "qjulia-nonfinite-samples";
const EXHAUSTED_RAYS: &str = "qjulia-exhausted-rays";

/// `--tile K/N`: the K-th (0-based) of N bands of rows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Tile {
    pub index: u32,
    pub count: u32,
}

impl Tile {
    /// Parses `K/N` for an image `height` rows high: 0 <= K < N <= height, else an error
    /// naming `--tile`.
    pub fn parse(text: &str, height: u32) -> Result<Self> {
        let bad = |why: String| Error::from(FlagError::new(format!("--tile {text}"), why));
        let (k, n) = text
            .split_once('/')
            .ok_or_else(|| bad("expected K/N, e.g. 0/4".into()))?;
        let number = |s: &str| s.trim().parse::<u32>().ok();
        let (Some(index), Some(count)) = (number(k), number(n)) else {
            return Err(bad("K and N must be whole numbers, as in 0/4".into()));
        };
        if count == 0 || index >= count {
            return Err(bad(format!("K must be in 0..N, here 0..{count}")));
        }
        if count > height {
            return Err(bad(format!(
                "N must be at most the image's height ({height} rows)"
            )));
        }
        Ok(Self { index, count })
    }

    /// The rows of this tile of an image `height` rows high: [K*H/N, (K+1)*H/N).
    pub fn rows(&self, height: u32) -> Range<u32> {
        let at = |k: u32| (k as u64 * height as u64 / self.count as u64) as u32;
        at(self.index)..at(self.index + 1)
    }
}

impl std::fmt::Display for Tile {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

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
    let samples = match band.samples.len() == pixels {
        true => band.samples.clone(),
        false => vec![scene.image.samples.max(1); pixels],
    };
    let uints = [band.colour.clone(), band.steps.clone(), samples];
    let channels: SmallVec<[AnyChannel<FlatSamples>; 4]> = FLOAT_CHANNELS
        .iter()
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
struct Part {
    path: PathBuf,
    scene_text: String,
    scene: Scene,
    tile: String,
    rows: Range<u32>,
    /// backend, adapter, precision, precision reason.
    made_by: [String; 4],
    render_seconds: f64,
    gpu_seconds: Option<f64>,
    frame: Frame,
}

/// A bad part: one line naming its file.
fn bad(path: &Path, message: impl Into<String>) -> Error {
    Error::Part {
        path: path.to_path_buf(),
        message: message.into(),
    }
}

/// Reads and checks one partial EXR.
fn read_part(path: &Path, memory: Option<u64>) -> Result<Part> {
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
const PART_BYTES_PER_PIXEL: u64 = 2 * 4 * (FLOAT_CHANNELS.len() + UINT_CHANNELS.len()) as u64;

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
    let count = |name: &str| -> Result<u64> {
        text(name)?
            .parse()
            .map_err(|_| bad(path, format!("its {name} attribute is not a count")))
    };
    frame.estimates = count(ESTIMATES)?;
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
    let stats = RenderStats {
        backend,
        adapter,
        precision,
        precision_reason,
        width: scene.image.width,
        height,
        render_seconds,
        gpu_seconds,
        denoise: None,
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
