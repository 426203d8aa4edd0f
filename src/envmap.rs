//! Loading an environment map (`environment.file`, issue 38 item 1; not wired into the renderer
//! yet): an equirectangular image of linear RGB, OpenEXR read by the exr crate and Radiance
//! `.hdr` by the image crate. A map is refused, with the reason, where it is not exactly twice
//! as wide as it is high, where it cannot be read (missing, corrupt, truncated), where a texel
//! is not finite or is negative, and where it would take more memory than the host has for it
//! (src/memory.rs), which is checked from the file's header before its pixels are decoded.

use std::io::{BufRead, Cursor, Seek};
use std::path::Path;

use crate::memory;

/// Bytes a texel takes once loaded: its RGB (12) and its two distributions' entries (the
/// function and the CDF, 8).
pub const MAP_BYTES_PER_TEXEL: u64 = 12 + 8;

/// The widest map taken: WebGPU's 2D texture limit (8192), which a storage buffer of f32 RGB
/// texels also fits within its 128 MiB binding limit (8192 x 4096 x 12 bytes = 384 MiB does
/// not; 8192 x 4096 texels of 3 f32 each are refused by the budget below on most hosts).
pub const MAP_MAX_WIDTH: u32 = 8192;

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
        // 8 x 4 texels take 640 bytes.
        let big = from_bytes(&exr, MapFormat::OpenExr, Some(600)).unwrap_err();
        assert!(big.contains("environment map"), "{big}");
        assert!(from_bytes(&exr, MapFormat::OpenExr, Some(700)).is_ok());
        assert!(MapFormat::of(Path::new("sky.png")).is_err());
        assert_eq!(MapFormat::of(Path::new("SKY.HDR")), Ok(MapFormat::Radiance));
    }
}
