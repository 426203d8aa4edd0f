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

use crate::cpu::environment::{ENV_HEIGHT, ENV_IRRADIANCE, ENV_TEXELS, ENV_WIDTH};
use crate::memory;

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
pub const BUILTIN_MAPS: &[(&str, &[u8])] =
    &[("dusk.hdr", include_bytes!("../assets/environment/dusk.hdr"))];

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

/// Floats of a `width` x `height` map packed ([`pack`]).
pub fn packed_floats(width: usize, height: usize) -> usize {
    ENV_TEXELS as usize + 5 * width * height + 2 * height + 1
}

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

/// A piecewise-constant distribution over [0, 1) in `func.len()` equal pieces: `cdf[k]` is the
/// mass of the pieces before k (`cdf[0] = 0`, `cdf[n] = 1`), `integral` the mean of `func`. A
/// distribution of no mass (every piece 0) is uniform, so that sampling never divides by 0.
#[derive(Clone, Debug, PartialEq)]
pub struct Distribution1d {
    pub func: Vec<f32>,
    pub cdf: Vec<f32>,
    pub integral: f32,
}

impl Distribution1d {
    /// The distribution of `func` (each value >= 0 and finite).
    pub fn new(func: &[f32]) -> Self {
        let n = func.len();
        let mut cdf = vec![0.0f64; n + 1];
        for k in 0..n {
            cdf[k + 1] = cdf[k] + f64::from(func[k]) / n as f64;
        }
        let integral = cdf[n];
        let cdf = if integral > 0.0 {
            cdf.iter().map(|c| (c / integral) as f32).collect()
        } else {
            (0..=n).map(|k| k as f32 / n as f32).collect()
        };
        Self {
            func: func.to_vec(),
            cdf,
            integral: integral as f32,
        }
    }

    /// The density of piece k: func[k] / integral (1, uniform, for a distribution of no mass).
    pub fn pdf_piece(&self, k: usize) -> f32 {
        if self.integral > 0.0 {
            self.func[k] / self.integral
        } else {
            1.0
        }
    }
}

/// Rec. 709 luminance, as the sampling weighs texels.
fn luminance(c: [f32; 3]) -> f32 {
    0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]
}

/// The kernels' buffer of a `width` x `height` map (src/cpu/environment.rs states the layout):
/// the size; the irradiance's nine spherical-harmonic coefficients per channel, each already
/// times its band's cosine-lobe factor and divided by pi (Ramamoorthi and Hanrahan 2001: for a
/// normal n, E(n) / pi = sum k_lm y_lm(n) in the map's own frame); each texel's RGB and its
/// density over the map's [0, 1)^2; the marginal CDF over rows; each row's CDF over its texels.
/// The distribution is of luminance times sin(theta) at the row's centre (theta from the
/// zenith), so that a direction's density per solid angle follows its radiance.
pub fn pack(width: usize, height: usize, texels: &[[f32; 3]]) -> Vec<f32> {
    let sin_row = |j: usize| (std::f64::consts::PI * (j as f64 + 0.5) / height as f64).sin();
    let rows: Vec<Distribution1d> = texels
        .chunks(width)
        .enumerate()
        .map(|(j, row)| {
            let func: Vec<f32> = row
                .iter()
                .map(|&t| (f64::from(luminance(t).max(0.0)) * sin_row(j)) as f32)
                .collect();
            Distribution1d::new(&func)
        })
        .collect();
    let marginal = Distribution1d::new(&rows.iter().map(|r| r.integral).collect::<Vec<_>>());
    let mut out = vec![0.0f32; packed_floats(width, height)];
    out[ENV_WIDTH as usize] = width as f32;
    out[ENV_HEIGHT as usize] = height as f32;
    let irradiance = irradiance_coefficients(width, height, texels);
    for (k, c) in irradiance.iter().enumerate() {
        let at = ENV_IRRADIANCE as usize + 4 * k;
        out[at..at + 3].copy_from_slice(&c.map(|x| x as f32));
    }
    for (k, t) in texels.iter().enumerate() {
        let (i, j) = (k % width, k / width);
        let at = ENV_TEXELS as usize + 4 * k;
        out[at..at + 3].copy_from_slice(t);
        out[at + 3] = marginal.pdf_piece(j) * rows[j].pdf_piece(i);
    }
    let marginal_at = ENV_TEXELS as usize + 4 * width * height;
    out[marginal_at..marginal_at + height + 1].copy_from_slice(&marginal.cdf);
    for (j, row) in rows.iter().enumerate() {
        let at = marginal_at + height + 1 + j * (width + 1);
        out[at..at + width + 1].copy_from_slice(&row.cdf);
    }
    out
}

/// The irradiance's coefficients (nine, RGB each) as [`pack`] stores them: the projection of
/// the map onto the real spherical harmonics of bands 0 to 2, each texel weighed by its exact
/// solid angle, times A_l / pi (1, 2/3 and 1/4) and times the basis function's constant, so that
/// E(n) / pi = k0 + k1 y + k2 z + k3 x + k4 x y + k5 y z + k6 (3 z^2 - 1) + k7 x z + k8 (x^2 -
/// y^2), with x toward u = 0, y toward u = 1/4 and z up.
pub fn irradiance_coefficients(width: usize, height: usize, texels: &[[f32; 3]]) -> [[f64; 3]; 9] {
    use std::f64::consts::PI;
    // Each band's constant, squared into the evaluation: c_lm^2 times A_l / pi.
    let c0 = 0.282_094_791_773_878_1_f64;
    let c1 = 0.488_602_511_902_919_9_f64;
    let c2 = 1.092_548_430_592_079_2_f64;
    let c20 = 0.315_391_565_252_52_f64;
    let c22 = 0.546_274_215_296_039_6_f64;
    let scale = [
        c0 * c0,
        c1 * c1 * 2.0 / 3.0,
        c1 * c1 * 2.0 / 3.0,
        c1 * c1 * 2.0 / 3.0,
        c2 * c2 / 4.0,
        c2 * c2 / 4.0,
        c20 * c20 / 4.0,
        c2 * c2 / 4.0,
        c22 * c22 / 4.0,
    ];
    let mut sums = [[0.0f64; 3]; 9];
    for j in 0..height {
        let (t0, t1) = (
            PI * j as f64 / height as f64,
            PI * (j + 1) as f64 / height as f64,
        );
        let omega = 2.0 * PI / width as f64 * (t0.cos() - t1.cos());
        let theta = 0.5 * (t0 + t1);
        for i in 0..width {
            let phi = 2.0 * PI * (i as f64 + 0.5) / width as f64;
            let (x, y, z) = (
                theta.sin() * phi.cos(),
                theta.sin() * phi.sin(),
                theta.cos(),
            );
            let basis = [
                1.0,
                y,
                z,
                x,
                x * y,
                y * z,
                3.0 * z * z - 1.0,
                x * z,
                x * x - y * y,
            ];
            let t = texels[j * width + i];
            for (k, b) in basis.iter().enumerate() {
                for c in 0..3 {
                    sums[k][c] += f64::from(t[c]) * b * omega;
                }
            }
        }
    }
    std::array::from_fn(|k| sums[k].map(|s| s * scale[k]))
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
