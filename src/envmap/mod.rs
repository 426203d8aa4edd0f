//! The environment map (`[environment]`, issue 38 item 1) on the host: finding its file,
//! loading it, and packing it for the kernels. OpenEXR is read by the exr crate and Radiance
//! `.hdr` by the image crate. A map is refused, with the reason, where it is not exactly twice as
//! wide as it is high, where it cannot be read (missing, corrupt, truncated), where a texel is
//! not finite or is negative, and where it would take more memory than the host has for it
//! (src/memory.rs), which is checked from the file's header before its pixels are decoded. A
//! map whose packed buffer would pass what one GPU binding may hold ([`MAP_MAX_BUFFER_BYTES`])
//! is halved, 2 x 2 texels to 1, until it fits, with a notice. The packed buffer
//! ([`pack`]: the texels, their distribution for importance sampling, the irradiance's
//! spherical harmonics) is what the kernels and their CPU twin (src/cpu/environment.rs) read.

use std::io::{BufRead, Cursor, Seek};
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};
use std::time::Instant;

use crate::memory;

mod pack;

pub use pack::{
    Distribution1d, ENV_HEIGHT, ENV_IRRADIANCE, ENV_TEXELS, ENV_WIDTH, irradiance_basis,
    irradiance_coefficients, pack, packed_floats,
};

/// Bytes a texel takes on the host while it loads: its RGB as decoded (12) and its five floats
/// in the packed buffer (20: RGB, density, its row's CDF entry).
pub const MAP_BYTES_PER_TEXEL: u64 = 12 + 20;

/// The widest map taken: WebGPU's 2D texture limit (8192).
pub const MAP_MAX_WIDTH: u32 = 8192;

/// The most bytes a packed map may take: WebGPU's default `maxStorageBufferBindingSize`, 128
/// MiB, which every adapter offers. A larger map is halved until it fits (2048 x 1024 fits,
/// 4096 x 2048 does not), so that every device, the browser's and the CPU twin's, draws
/// from the same map.
pub const MAP_MAX_BUFFER_BYTES: u64 = 128 << 20;

/// What `environment.file` starts with to name a map built into the binary.
pub const BUILTIN_PREFIX: &str = "qjulia:";

/// The maps built into the binary, by name (`environment.file = "qjulia:NAME"`): made by the
/// project (examples/dusk_sky.rs writes dusk.hdr), so that a preset can show a map.
pub const BUILTIN_MAPS: &[(&str, &[u8])] = &[(
    "dusk.hdr",
    include_bytes!("../../assets/environment/dusk.hdr"),
)];

/// A loaded map: `width` = 2 `height` texels of linear RGB, row 0 at the top (the zenith), and
/// the CRC-32 of the file's bytes (the scene records it; loading again verifies it).
#[derive(Clone, Debug, PartialEq)]
pub struct MapImage {
    pub width: usize,
    pub height: usize,
    pub texels: Vec<[f32; 3]>,
    pub checksum: u32,
}

/// The file formats read, by the file's extension (any case): `.exr` and `.hdr`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MapFormat {
    OpenExr,
    Radiance,
}

impl MapFormat {
    /// The format of `path` by its extension, or the reason it is none.
    pub fn of(path: &Path) -> Result<Self, String> {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        match ext.as_deref() {
            Some("exr") => Ok(MapFormat::OpenExr),
            Some("hdr") => Ok(MapFormat::Radiance),
            _ => Err("must be an OpenEXR (.exr) or Radiance (.hdr) file".into()),
        }
    }
}

/// Reads the map at `path`, or the reason it cannot be used (for a one-line error that names
/// the file and the key).
pub fn load(path: &Path) -> Result<MapImage, String> {
    let format = MapFormat::of(path)?;
    let bytes = std::fs::read(path).map_err(|e| format!("cannot read: {e}"))?;
    from_bytes(&bytes, format, memory::available())
}

/// [`load`] of a file's bytes in `format`, against `available` bytes of memory (None: not
/// known, nothing refused for size); the fuzz targets' way in.
pub fn from_bytes(
    bytes: &[u8],
    format: MapFormat,
    available: Option<u64>,
) -> Result<MapImage, String> {
    let (width, height, texels) = match format {
        MapFormat::OpenExr => read_exr(Cursor::new(bytes), available)?,
        MapFormat::Radiance => read_hdr(Cursor::new(bytes), available)?,
    };
    if let Some((k, t)) = texels
        .iter()
        .enumerate()
        .find(|(_, t)| t.iter().any(|c| !c.is_finite() || *c < 0.0))
    {
        return Err(format!(
            "texel ({}, {}) is {t:?}: every channel must be finite and >= 0",
            k % width,
            k / width
        ));
    }
    Ok(MapImage {
        width,
        height,
        texels,
        checksum: crc32fast::hash(bytes),
    })
}

/// The size checks a map's header allows before its pixels are read: at least 2 x 1, exactly
/// twice as wide as high, at most [`MAP_MAX_WIDTH`] wide, and within the memory available.
fn check_size(width: u64, height: u64, available: Option<u64>) -> Result<(), String> {
    if width == 0 || height == 0 || width != 2 * height {
        return Err(format!(
            "is {width}x{height}: an equirectangular map is exactly twice as wide as it is high"
        ));
    }
    if width > u64::from(MAP_MAX_WIDTH) {
        return Err(format!(
            "is {width}x{height}: at most {MAP_MAX_WIDTH} wide (downsample it)"
        ));
    }
    memory::check_within(
        "the environment map",
        width * height * MAP_BYTES_PER_TEXEL,
        available,
    )
    .map_err(|e| e.to_string())
}

/// An OpenEXR file's first layer of RGB(A) channels, as linear RGB, row 0 at the top.
fn read_exr(
    mut input: impl BufRead + Seek,
    available: Option<u64>,
) -> Result<(usize, usize, Vec<[f32; 3]>), String> {
    use exr::prelude::{ReadChannels, ReadLayers};
    let unreadable = |e: exr::error::Error| format!("not a readable OpenEXR file: {e}");
    let start = input.stream_position().map_err(|e| e.to_string())?;
    let meta = exr::meta::MetaData::read_from_buffered(&mut input, false).map_err(unreadable)?;
    let header = meta.headers.first().ok_or("holds no image")?;
    let size = header.layer_size;
    check_size(size.width() as u64, size.height() as u64, available)?;
    input
        .seek(std::io::SeekFrom::Start(start))
        .map_err(|e| e.to_string())?;
    let image = exr::prelude::read()
        .no_deep_data()
        .largest_resolution_level()
        .rgba_channels(
            |resolution, _| {
                (
                    resolution.width(),
                    vec![[0.0f32; 3]; resolution.width() * resolution.height()],
                )
            },
            |(width, texels), position, (r, g, b, _a): (f32, f32, f32, f32)| {
                texels[position.y() * *width + position.x()] = [r, g, b];
            },
        )
        .first_valid_layer()
        .all_attributes()
        .from_buffered(input)
        .map_err(unreadable)?;
    let (width, texels) = image.layer_data.channel_data.pixels;
    let height = texels.len() / width.max(1);
    check_size(width as u64, height as u64, available)?;
    Ok((width, height, texels))
}

/// A Radiance RGBE file, as linear RGB, row 0 at the top.
fn read_hdr(
    input: impl BufRead + Seek,
    available: Option<u64>,
) -> Result<(usize, usize, Vec<[f32; 3]>), String> {
    use image::ImageDecoder;
    let unreadable = |e: image::ImageError| format!("not a readable Radiance .hdr file: {e}");
    let decoder = image::codecs::hdr::HdrDecoder::new(input).map_err(unreadable)?;
    let (width, height) = decoder.dimensions();
    check_size(u64::from(width), u64::from(height), available)?;
    let image = image::DynamicImage::from_decoder(decoder).map_err(unreadable)?;
    let rgb = image.into_rgb32f();
    let texels = rgb.pixels().map(|p| p.0).collect();
    Ok((width as usize, height as usize, texels))
}

/// Where a map comes from: built into the binary, or a file.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub enum MapSource {
    /// A name of [`BUILTIN_MAPS`].
    Builtin(&'static str),
    /// A file, as found.
    File(PathBuf),
}

impl std::fmt::Display for MapSource {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            MapSource::Builtin(name) => write!(f, "{BUILTIN_PREFIX}{name}"),
            MapSource::File(path) => write!(f, "{}", path.display()),
        }
    }
}

/// Where `environment.file`'s value `file` is: a built-in map by its name, an absolute path as
/// it is, a relative one against each folder of `bases` in turn (the first where a file is
/// found; a path relative to the current directory where `bases` is empty). The reason where
/// none is found.
pub fn resolve(file: &str, bases: &[PathBuf]) -> Result<MapSource, String> {
    if let Some(name) = file.strip_prefix(BUILTIN_PREFIX) {
        return BUILTIN_MAPS
            .iter()
            .find(|(n, _)| *n == name)
            .map(|(n, _)| MapSource::Builtin(n))
            .ok_or_else(|| {
                let names: Vec<String> = BUILTIN_MAPS
                    .iter()
                    .map(|(n, _)| format!("\"{BUILTIN_PREFIX}{n}\""))
                    .collect();
                format!("names no built-in map; they are {}", names.join(", "))
            });
    }
    let path = Path::new(file);
    MapFormat::of(path)?;
    if path.is_absolute() || bases.is_empty() {
        return match path.is_file() {
            true => Ok(MapSource::File(path.to_path_buf())),
            false => Err("no such file".into()),
        };
    }
    let tried: Vec<PathBuf> = bases.iter().map(|b| b.join(path)).collect();
    if let Some(found) = tried.iter().find(|p| p.is_file()) {
        return Ok(MapSource::File(found.clone()));
    }
    let places: Vec<String> = tried.iter().map(|p| p.display().to_string()).collect();
    Err(format!(
        "no such file (looked for {})",
        places.join(" and ")
    ))
}

/// A map loaded and packed for the kernels: what a scene's `loaded.environment` holds.
pub struct EnvironmentData {
    /// Where it came from.
    pub source: MapSource,
    /// Its size as packed (after any halving).
    pub width: usize,
    pub height: usize,
    /// Its size in the file, where it was halved to fit [`MAP_MAX_BUFFER_BYTES`].
    pub downsampled_from: Option<(usize, usize)>,
    /// The CRC-32 of the file's bytes.
    pub checksum: u32,
    /// The buffer the kernels read ([`pack`]).
    pub packed: Vec<f32>,
    /// Seconds to read the file, decode it and pack it (`--stats`' environment_seconds).
    pub seconds: f64,
}

impl std::fmt::Debug for EnvironmentData {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "EnvironmentData({}, {}x{}, crc {:08x})",
            self.source, self.width, self.height, self.checksum
        )
    }
}

/// Two loads are the same map where they are the same file's bytes packed alike.
impl PartialEq for EnvironmentData {
    fn eq(&self, other: &Self) -> bool {
        (self.checksum, self.width, self.height, self.packed.len())
            == (
                other.checksum,
                other.width,
                other.height,
                other.packed.len(),
            )
    }
}

impl EnvironmentData {
    /// A map of `texels` (`width` = 2 `height`, row 0 at the zenith) made in memory rather than
    /// read from a file (the tests'): packed as a file's would be, checksum 0.
    pub fn of_texels(width: usize, height: usize, texels: &[[f32; 3]]) -> Self {
        assert!(width == 2 * height && texels.len() == width * height);
        Self {
            source: MapSource::Builtin("memory"),
            width,
            height,
            downsampled_from: None,
            checksum: 0,
            packed: pack(width, height, texels),
            seconds: 0.0,
        }
    }

    /// The notice a halved map gives, where it was.
    pub fn notice(&self) -> Option<String> {
        let (w, h) = self.downsampled_from?;
        Some(format!(
            "environment.file {}: {w}x{h} would pack to more than one GPU binding holds \
             ({} MiB), so it was halved to {}x{}",
            self.source,
            MAP_MAX_BUFFER_BYTES >> 20,
            self.width,
            self.height
        ))
    }
}

/// A map as loaded, by where it came from and its file's length and modification time.
type LoadedMap = (
    MapSource,
    Option<(u64, std::time::SystemTime)>,
    Arc<EnvironmentData>,
);

/// The last maps loaded, by where they came from and the file's length and modification
/// time: a scene built again (the explorer, an animation's frames, a test) does not read and
/// pack its map again.
static LOADED: Mutex<Vec<LoadedMap>> = Mutex::new(Vec::new());

/// Maps kept in [`LOADED`].
const LOADED_KEPT: usize = 2;

/// The map at `source`, loaded and packed (or as loaded before, where its file has not
/// changed), or the reason it cannot be used.
pub fn load_source(source: &MapSource) -> Result<Arc<EnvironmentData>, String> {
    let stamp = match source {
        MapSource::Builtin(_) => None,
        MapSource::File(path) => {
            let meta = std::fs::metadata(path).map_err(|e| format!("cannot read: {e}"))?;
            Some((meta.len(), meta.modified().map_err(|e| e.to_string())?))
        }
    };
    let mut loaded = LOADED.lock().unwrap_or_else(|e| e.into_inner());
    if let Some((_, _, data)) = loaded.iter().find(|(s, t, _)| s == source && *t == stamp) {
        return Ok(data.clone());
    }
    let start = Instant::now();
    let image = match source {
        MapSource::Builtin(name) => {
            let bytes = BUILTIN_MAPS
                .iter()
                .find(|(n, _)| n == name)
                .map(|(_, b)| *b)
                .ok_or("names no built-in map")?;
            from_bytes(bytes, MapFormat::of(Path::new(name))?, memory::available())?
        }
        MapSource::File(path) => load(path)?,
    };
    let checksum = image.checksum;
    let (width, height, texels, downsampled_from) = fit_buffer(image);
    let packed = pack(width, height, &texels);
    let data = Arc::new(EnvironmentData {
        source: source.clone(),
        width,
        height,
        downsampled_from,
        checksum,
        packed,
        seconds: start.elapsed().as_secs_f64(),
    });
    if let Some(notice) = data.notice() {
        eprintln!("qjulia: {notice}");
    }
    if loaded.len() >= LOADED_KEPT {
        loaded.remove(0);
    }
    loaded.push((source.clone(), stamp, data.clone()));
    Ok(data)
}

/// A map's width and height in texels.
type Size = (usize, usize);

/// The map halved (each texel the mean of 2 x 2) until it packs within
/// [`MAP_MAX_BUFFER_BYTES`]: its size, texels, and the size it had where it was halved.
fn fit_buffer(image: MapImage) -> (usize, usize, Vec<[f32; 3]>, Option<Size>) {
    let (mut w, mut h, mut texels) = (image.width, image.height, image.texels);
    let original = (w, h);
    while packed_floats(w, h) as u64 * 4 > MAP_MAX_BUFFER_BYTES && h > 1 {
        let (hw, hh) = (w / 2, h / 2);
        let mut out = vec![[0.0f32; 3]; hw * hh];
        for (k, t) in out.iter_mut().enumerate() {
            let (i, j) = (k % hw, k / hw);
            for c in 0..3 {
                let s = |x: usize, y: usize| f64::from(texels[y * w + x][c]);
                let sum = s(2 * i, 2 * j)
                    + s(2 * i + 1, 2 * j)
                    + s(2 * i, 2 * j + 1)
                    + s(2 * i + 1, 2 * j + 1);
                t[c] = (sum / 4.0) as f32;
            }
        }
        (w, h, texels) = (hw, hh, out);
    }
    let halved = ((w, h) != original).then_some(original);
    (w, h, texels, halved)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An EXR of `width` x `height` with texel (i, j) = (i, j, 0.5), in memory.
    fn exr_bytes(width: usize, height: usize) -> Vec<u8> {
        use exr::prelude::*;
        let mut out = Cursor::new(Vec::new());
        let channels = SpecificChannels::rgb(|p: Vec2<usize>| (p.x() as f32, p.y() as f32, 0.5f32));
        Image::from_channels((width, height), channels)
            .write()
            .to_buffered(&mut out)
            .unwrap();
        out.into_inner()
    }

    /// A Radiance file of `width` x `height` with texel (i, j) = (i, j, 0.5) (RGBE keeps 8 bits
    /// of mantissa: small integers exactly).
    fn hdr_bytes(width: u32, height: u32) -> Vec<u8> {
        let pixels: Vec<image::Rgb<f32>> = (0..height)
            .flat_map(|j| (0..width).map(move |i| image::Rgb([i as f32, j as f32, 0.5])))
            .collect();
        let mut out = Vec::new();
        image::codecs::hdr::HdrEncoder::new(&mut out)
            .encode(&pixels, width as usize, height as usize)
            .unwrap();
        out
    }

    #[test]
    fn both_formats_read_row_zero_at_the_top() {
        for (format, bytes) in [
            (MapFormat::OpenExr, exr_bytes(8, 4)),
            (MapFormat::Radiance, hdr_bytes(8, 4)),
        ] {
            let map = from_bytes(&bytes, format, None).unwrap();
            assert_eq!((map.width, map.height), (8, 4));
            assert_eq!(map.texels[0], [0.0, 0.0, 0.5]);
            assert_eq!(map.texels[3 * 8 + 5], [5.0, 3.0, 0.5], "{format:?}");
            assert_eq!(map.checksum, crc32fast::hash(&bytes));
        }
    }

    #[test]
    fn bad_maps_are_refused_with_the_reason() {
        let square = from_bytes(&exr_bytes(8, 8), MapFormat::OpenExr, None).unwrap_err();
        assert!(
            square.contains("8x8") && square.contains("twice"),
            "{square}"
        );
        let tall = from_bytes(&hdr_bytes(4, 8), MapFormat::Radiance, None).unwrap_err();
        assert!(tall.contains("4x8"), "{tall}");
        let exr = exr_bytes(8, 4);
        let truncated = from_bytes(&exr[..exr.len() / 2], MapFormat::OpenExr, None).unwrap_err();
        assert!(truncated.contains("OpenEXR"), "{truncated}");
        let hdr = hdr_bytes(8, 4);
        let cut = from_bytes(&hdr[..hdr.len() - 20], MapFormat::Radiance, None).unwrap_err();
        assert!(cut.contains("Radiance"), "{cut}");
        let garbage = from_bytes(b"not an image at all", MapFormat::OpenExr, None).unwrap_err();
        assert!(garbage.contains("OpenEXR"), "{garbage}");
        // 8 x 4 texels take 1,024 bytes.
        let big = from_bytes(&exr, MapFormat::OpenExr, Some(1000)).unwrap_err();
        assert!(big.contains("environment map"), "{big}");
        assert!(from_bytes(&exr, MapFormat::OpenExr, Some(1100)).is_ok());
        assert!(MapFormat::of(Path::new("sky.png")).is_err());
        assert_eq!(MapFormat::of(Path::new("SKY.HDR")), Ok(MapFormat::Radiance));
    }
}
