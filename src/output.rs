//! Writing a frame: PNG (carrying its scene), NumPy depth and steps maps, JSON stats, OpenEXR
//! (`--hdr`, [`crate::hdr`]). All or nothing: every file goes to a temporary file beside its
//! target first, and all are renamed into place only once every one is written.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

use tempfile::NamedTempFile;

use crate::error::{Error, Result};
use crate::frame::Frame;
use crate::hdr::HdrImage;
use crate::scene::{SCENE_PNG_KEYWORD, Scene};
use crate::stats::RenderStats;

/// Which files a render writes; `None` for those not asked for.
#[derive(Clone, Debug, Default)]
pub struct OutputPaths {
    pub png: Option<PathBuf>,
    pub depth: Option<PathBuf>,
    pub steps: Option<PathBuf>,
    pub stats: Option<PathBuf>,
    /// The OpenEXR of the linear mean, the AOVs and the depth (`--hdr`): the frames written
    /// must carry their AOVs ([`crate::Readback::Hdr`]).
    pub hdr: Option<PathBuf>,
    /// Write the depth as float64 (`<f8`): the render runs in f64, whose depth float32 cannot
    /// hold at a deep zoom.
    pub depth_f64: bool,
}

/// Writes every requested output of a whole frame, whole or not at all.
pub fn write_outputs(
    paths: &OutputPaths,
    frame: &Frame,
    stats: &RenderStats,
    scene: &Scene,
) -> Result<()> {
    let mut outputs = StreamingOutputs::create(paths, scene)?;
    outputs.write_band(frame)?;
    outputs.finish(stats)
}

/// As [`write_outputs`], with the PNG showing the scene's `image.view`: the shaded picture, or
/// a heat map of the steps with its legend strip below (then the PNG is [`LEGEND_HEIGHT`] rows
/// taller than the image).
///
/// [`LEGEND_HEIGHT`]: crate::heatmap::LEGEND_HEIGHT
pub fn write_view_outputs(
    paths: &OutputPaths,
    frame: &Frame,
    stats: &RenderStats,
    scene: &Scene,
) -> Result<()> {
    if scene.image.view == crate::scene::View::Shaded || paths.png.is_none() {
        return write_outputs(paths, frame, stats, scene);
    }
    let (width, height, rgb) = crate::heatmap::view_image(frame, scene.image.view);
    let mut outputs = StreamingOutputs::create_sized(paths, scene, [width, height])?;
    outputs.write_png_rows(&rgb)?;
    outputs.write_maps(frame)?;
    outputs.finish(stats)
}

/// Writes a PNG of `[width, height]` RGB8 pixels carrying `scene`, as [`StreamingOutputs`]
/// writes it (the same bytes as `render -o` of the same pixels), whole or not at all.
pub fn write_png(path: &Path, scene: &Scene, size: [u32; 2], rgb: &[u8]) -> Result<()> {
    let paths = OutputPaths {
        png: Some(path.to_path_buf()),
        ..Default::default()
    };
    let mut outputs = StreamingOutputs::create_sized(&paths, scene, size)?;
    outputs.write_png_rows(rgb)?;
    outputs.finish_files()
}

/// Writes the OpenEXR of a whole frame rendered with its AOVs, carrying `scene`, as `render
/// --hdr` writes it, whole or not at all.
pub fn write_hdr(path: &Path, scene: &Scene, image: HdrImage) -> Result<()> {
    let temp = stage(path, |_| Ok(()))?;
    write_exr(&temp, path, scene, image)?;
    temp.persist(path).map_err(|e| io_error(path, e.error))?;
    Ok(())
}

/// Writes `image` into the staged temporary file of `path`.
fn write_exr(temp: &NamedTempFile, path: &Path, scene: &Scene, image: HdrImage) -> Result<()> {
    let mut file = BufWriter::new(temp.as_file());
    image
        .write(scene, &mut file)
        .and_then(|()| file.flush())
        .map_err(|e| io_error(path, e))
}

/// The RGB8 pixels and size of a PNG (8-bit RGB, as qjulia writes them).
pub fn read_png_rgb(path: &Path) -> Result<([u32; 2], Vec<u8>)> {
    let io = |e: std::io::Error| io_error(path, e);
    let decoder = png::Decoder::new(std::io::BufReader::new(File::open(path).map_err(io)?));
    let mut reader = decoder
        .read_info()
        .map_err(|e| io(std::io::Error::other(e)))?;
    let mut rgb = vec![0; reader.output_buffer_size().unwrap_or(0)];
    let info = reader
        .next_frame(&mut rgb)
        .map_err(|e| io(std::io::Error::other(e)))?;
    if info.color_type != png::ColorType::Rgb || info.bit_depth != png::BitDepth::Eight {
        return Err(io(std::io::Error::other("not an 8-bit RGB PNG")));
    }
    rgb.truncate(info.buffer_size());
    Ok(([info.width, info.height], rgb))
}

/// Writes `value` as pretty JSON (and a newline) to `path`, whole or not at all.
pub fn write_json(path: &Path, value: &impl serde::Serialize) -> Result<()> {
    let temp = stage(path, |w| {
        serde_json::to_writer_pretty(&mut *w, value)?;
        w.write_all(b"\n")
    })?;
    temp.persist(path).map_err(|e| io_error(path, e.error))?;
    Ok(())
}

/// The prefix and suffix of the temporary files staged for `path`: `.NAME.qjulia-XXXXXX.tmp`
/// beside it (hidden, never taken for an output), named after the output they become.
pub fn staging_name(path: &Path) -> (String, &'static str) {
    let name = path
        .file_name()
        .map_or_else(|| "output".into(), |n| n.to_string_lossy().into_owned());
    (format!(".{name}.qjulia-"), ".tmp")
}

/// The folder `path` is written in.
fn folder_of(path: &Path) -> &Path {
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    }
}

/// Removes what a killed run left while writing `path`: its staged temporary files (of
/// [`staging_name`]). Only the run that writes `path` calls it, so no other run's file goes.
pub fn remove_stale_staging(path: &Path) {
    let (prefix, suffix) = staging_name(path);
    let Ok(entries) = std::fs::read_dir(folder_of(path)) else {
        return;
    };
    for entry in entries.flatten() {
        let name = entry.file_name();
        let name = name.to_string_lossy();
        if name.starts_with(&prefix) && name.ends_with(suffix) {
            let _ = std::fs::remove_file(entry.path());
        }
    }
}

/// Writes one output to a temporary file in its target's directory (after removing the stale
/// temporaries of that target).
pub(crate) fn stage(
    path: &Path,
    write: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
) -> Result<NamedTempFile> {
    let dir = folder_of(path);
    remove_stale_staging(path);
    let (prefix, suffix) = staging_name(path);
    let mut builder = tempfile::Builder::new();
    builder.prefix(&prefix).suffix(suffix);
    // Temporary files are private by default; the outputs are ordinary files.
    #[cfg(unix)]
    builder.permissions(std::os::unix::fs::PermissionsExt::from_mode(0o644));
    let mut temp = builder.tempfile_in(dir).map_err(|e| io_error(path, e))?;
    {
        let mut w = BufWriter::new(temp.as_file_mut());
        write(&mut w).map_err(|e| io_error(path, e))?;
        w.flush().map_err(|e| io_error(path, e))?;
    }
    Ok(temp)
}

pub(crate) fn io_error(path: &Path, cause: std::io::Error) -> Error {
    Error::Io {
        path: path.to_path_buf(),
        cause,
    }
}

fn write_stats(w: &mut dyn Write, stats: &RenderStats) -> std::io::Result<()> {
    serde_json::to_writer_pretty(&mut *w, stats)?;
    w.write_all(b"\n")
}

/// The PNG encoder's level. Measured with png 0.18 on this machine (median of 9 encodes of a
/// 512x512 frame, file included): the seed's look 1.65 ms / 179,821 bytes (Fastest), 2.11 ms /
/// 166,223 (Fast), 31.5 ms / 155,822 (Balanced, the crate's default), 78.4 ms / 154,497 (High);
/// the gallery preset 1.87 / 2.27 / 27.3 / 60.9 ms for 214,583 / 187,134 / 169,017 / 168,189
/// bytes. Fast costs 7-11% more bytes than Balanced for a fourteenth of the time: an animation
/// frame or a render's PNG no longer waits ~30 ms on the encoder.
pub const PNG_COMPRESSION: png::Compression = png::Compression::Fast;

/// Outputs written band by band while the render goes (any image size in bounded memory):
/// headers first, rows as they come, the stats last; then every file renamed into place, or none.
/// The PNG is 8-bit RGB with no gamma curve and the scene in an iTXt chunk; depth and steps are
/// little-endian `.npy` of shape (height, width). The EXR's channels are gathered in host memory
/// (40 bytes a pixel) and encoded at the end.
pub struct StreamingOutputs {
    png: Option<StagedPng>,
    depth: Option<(NamedTempFile, PathBuf, BufWriter<File>)>,
    depth_f64: bool,
    steps: Option<(NamedTempFile, PathBuf, BufWriter<File>)>,
    stats: Option<PathBuf>,
    /// The EXR's temporary file, its path, its channels so far and the scene it carries.
    hdr: Option<(NamedTempFile, PathBuf, HdrImage, Box<Scene>)>,
}

/// The PNG being written: its temporary file, its final path, the encoder's stream and the
/// first error its writer met.
type StagedPng = (
    NamedTempFile,
    PathBuf,
    png::StreamWriter<'static, Checked>,
    ErrorSlot,
);

/// Where a [`Checked`] writer keeps its first error.
type ErrorSlot = Arc<Mutex<Option<std::io::Error>>>;

/// A buffered writer into a file that keeps the first error it meets, its last flush's (when
/// dropped) included: the PNG encoder owns its writer and drops it unflushed-checked, so a full
/// disk at the last bytes would otherwise leave a short file that looks finished.
pub struct Checked {
    file: BufWriter<File>,
    error: ErrorSlot,
}

impl Checked {
    fn keep<T>(&self, result: std::io::Result<T>) -> std::io::Result<T> {
        if let Err(e) = &result {
            let mut slot = self.error.lock().expect("the error slot");
            slot.get_or_insert_with(|| std::io::Error::new(e.kind(), e.to_string()));
        }
        result
    }
}

impl Write for Checked {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        let r = self.file.write(buf);
        self.keep(r)
    }
    fn flush(&mut self) -> std::io::Result<()> {
        let r = self.file.flush();
        self.keep(r)
    }
}

impl Drop for Checked {
    fn drop(&mut self) {
        let r = self.file.flush();
        let _ = self.keep(r);
    }
}

/// A temporary file beside `path` and a buffered writer into it.
fn temp_writer(path: &Path) -> Result<(NamedTempFile, PathBuf, BufWriter<File>)> {
    let temp = stage(path, |_| Ok(()))?;
    let file = temp.as_file().try_clone().map_err(|e| io_error(path, e))?;
    Ok((temp, path.to_path_buf(), BufWriter::new(file)))
}

/// The header of a `.npy` (format 1.0) of shape (height, width).
fn npy_header(w: &mut dyn Write, descr: &str, width: u32, height: u32) -> std::io::Result<()> {
    let dict =
        format!("{{'descr': '{descr}', 'fortran_order': False, 'shape': ({height}, {width}), }}");
    // Magic (6) + version (2) + header length (2) + dict + padding + newline, to a multiple of 64.
    let unpadded = 10 + dict.len() + 1;
    let header = format!(
        "{dict}{}\n",
        " ".repeat(unpadded.next_multiple_of(64) - unpadded)
    );
    w.write_all(b"\x93NUMPY\x01\x00")?;
    w.write_all(&(header.len() as u16).to_le_bytes())?;
    w.write_all(header.as_bytes())
}

/// The PNG's text chunk that records a render's estimated error (docs/CONTRACT.md, "The error
/// on request"), after the image data.
pub const ERROR_PNG_KEYWORD: &str = "qjulia-error";

/// What the PNG records of `stats`' estimated error, as TOML (`estimated_rmse`,
/// `estimated_relative_rmse`, and with `image.target_error` `stopped_by` and the last pass's
/// `samples`); None where the render has no estimate.
pub fn error_text(stats: &RenderStats) -> Option<String> {
    let target = stats.target.as_ref().map(|t| (t.stopped_by, t.samples()));
    Some(error_text_of(
        stats.summary.estimated_rmse?,
        stats.summary.estimated_relative_rmse?,
        target,
    ))
}

/// [`error_text`] of an estimate and, with `image.target_error`, what stopped the render and
/// its last pass's samples (web/src/estimate.ts's `errorText` is its twin).
pub fn error_text_of(rmse: f64, relative: f64, target: Option<(&str, u32)>) -> String {
    let mut text = format!("estimated_rmse = {rmse}\nestimated_relative_rmse = {relative}\n");
    if let Some((stopped_by, samples)) = target {
        text += &format!("stopped_by = \"{stopped_by}\"\nsamples = {samples}\n");
    }
    text
}

/// Appends a tEXt chunk `keyword: text` (Latin-1) to the finished PNG at `path`, before its
/// IEND chunk (the last 12 bytes): the stream writer cannot add a chunk after the image data.
fn append_png_text(path: &Path, keyword: &str, text: &str) -> std::io::Result<()> {
    use std::io::{Seek, SeekFrom};
    let mut file = std::fs::OpenOptions::new()
        .read(true)
        .write(true)
        .open(path)?;
    let end = file.seek(SeekFrom::End(-12))?;
    let mut data = keyword.as_bytes().to_vec();
    data.push(0);
    data.extend_from_slice(text.as_bytes());
    let chunk = |kind: &[u8; 4], data: &[u8]| {
        let mut out = (data.len() as u32).to_be_bytes().to_vec();
        out.extend_from_slice(kind);
        out.extend_from_slice(data);
        let mut crc = crc32fast::Hasher::new();
        crc.update(kind);
        crc.update(data);
        out.extend_from_slice(&crc.finalize().to_be_bytes());
        out
    };
    file.set_len(end)?;
    file.write_all(&chunk(b"tEXt", &data))?;
    file.write_all(&chunk(b"IEND", &[]))?;
    file.flush()
}

impl StreamingOutputs {
    /// Opens temporary files for every requested output and writes their headers.
    pub fn create(paths: &OutputPaths, scene: &Scene) -> Result<Self> {
        Self::create_sized(paths, scene, [scene.image.width, scene.image.height])
    }

    /// As [`Self::create`], with a PNG of `png_size` pixels (a view with a legend strip).
    pub fn create_sized(paths: &OutputPaths, scene: &Scene, png_size: [u32; 2]) -> Result<Self> {
        let (width, height) = (scene.image.width, scene.image.height);
        if paths.hdr.is_some() {
            // The EXR is held whole until it is written: refused before any file is made.
            crate::memory::check(
                &format!("--hdr's {width}x{height} image"),
                u64::from(width) * u64::from(height) * crate::memory::HDR_BYTES_PER_PIXEL,
            )?;
        }
        let png = match &paths.png {
            Some(path) => {
                let (temp, path, file) = temp_writer(path)?;
                let error = Arc::new(Mutex::new(None));
                let file = Checked {
                    file,
                    error: error.clone(),
                };
                let mut encoder = png::Encoder::new(file, png_size[0], png_size[1]);
                encoder.set_color(png::ColorType::Rgb);
                encoder.set_depth(png::BitDepth::Eight);
                encoder.set_compression(PNG_COMPRESSION);
                let to_io = |e: png::EncodingError| io_error(&path, std::io::Error::other(e));
                encoder
                    .add_itxt_chunk(SCENE_PNG_KEYWORD.to_string(), scene.to_toml())
                    .map_err(to_io)?;
                let stream = encoder
                    .write_header()
                    .map_err(to_io)?
                    .into_stream_writer()
                    .map_err(to_io)?;
                Some((temp, path, stream, error))
            }
            None => None,
        };
        let npy = |path: &Option<PathBuf>, descr: &str| -> Result<_> {
            match path {
                Some(path) => {
                    let (temp, path, mut file) = temp_writer(path)?;
                    npy_header(&mut file, descr, width, height).map_err(|e| io_error(&path, e))?;
                    Ok(Some((temp, path, file)))
                }
                None => Ok(None),
            }
        };
        let depth_descr = if paths.depth_f64 { "<f8" } else { "<f4" };
        let hdr = match &paths.hdr {
            Some(path) => Some((
                stage(path, |_| Ok(()))?,
                path.clone(),
                HdrImage::new(width, height),
                Box::new(scene.clone()),
            )),
            None => None,
        };
        Ok(Self {
            png,
            depth: npy(&paths.depth, depth_descr)?,
            depth_f64: paths.depth_f64,
            steps: npy(&paths.steps, "<u4")?,
            stats: paths.stats.clone(),
            hdr,
        })
    }

    /// Appends a band of whole rows, top to bottom.
    pub fn write_band(&mut self, band: &Frame) -> Result<()> {
        if self.png.is_some() {
            self.write_png_rows(&band.rgb8())?;
        }
        self.write_maps(band)
    }

    /// Appends whole rows of RGB8 pixels to the PNG.
    pub fn write_png_rows(&mut self, rgb: &[u8]) -> Result<()> {
        if let Some((_, path, stream, _)) = &mut self.png {
            stream.write_all(rgb).map_err(|e| io_error(path, e))?;
        }
        Ok(())
    }

    /// Appends a band of whole rows to the depth and steps maps and the EXR.
    pub fn write_maps(&mut self, band: &Frame) -> Result<()> {
        if let Some((_, _, image, _)) = &mut self.hdr {
            image.add_band(band);
        }
        if let Some((_, path, file)) = &mut self.depth {
            let written = match (self.depth_f64, band.depth_f64.is_empty()) {
                (false, _) => file.write_all(bytemuck::cast_slice(&band.depth)),
                (true, false) => file.write_all(bytemuck::cast_slice(&band.depth_f64)),
                // An f64 render whose tracer kept only f32 depths.
                (true, true) => {
                    let wide: Vec<f64> = band.depth.iter().map(|&d| d as f64).collect();
                    file.write_all(bytemuck::cast_slice(&wide))
                }
            };
            written.map_err(|e| io_error(path, e))?;
        }
        if let Some((_, path, file)) = &mut self.steps {
            file.write_all(bytemuck::cast_slice(&band.steps))
                .map_err(|e| io_error(path, e))?;
        }
        Ok(())
    }

    /// Finishes every file (no stats were asked for), and renames all into place.
    pub fn finish_files(self) -> Result<()> {
        assert!(self.stats.is_none(), "stats asked for: use finish");
        self.finish_with(None)
    }

    /// Finishes every file, writes the stats, and renames all into place.
    pub fn finish(self, stats: &RenderStats) -> Result<()> {
        self.finish_with(Some(stats))
    }

    fn finish_with(self, stats: Option<&RenderStats>) -> Result<()> {
        let mut staged: Vec<(NamedTempFile, PathBuf)> = Vec::new();
        if let Some((temp, path, stream, error)) = self.png {
            stream
                .finish()
                .map_err(|e| io_error(&path, std::io::Error::other(e)))?;
            // The encoder has dropped its writer, whose last flush may have failed.
            if let Some(e) = error.lock().expect("the error slot").take() {
                return Err(io_error(&path, e));
            }
            if let Some(text) = stats.and_then(error_text) {
                append_png_text(temp.path(), ERROR_PNG_KEYWORD, &text)
                    .map_err(|e| io_error(&path, e))?;
            }
            staged.push((temp, path));
        }
        for (temp, path, mut file) in [self.depth, self.steps].into_iter().flatten() {
            file.flush().map_err(|e| io_error(&path, e))?;
            staged.push((temp, path));
        }
        if let (Some(path), Some(stats)) = (self.stats, stats) {
            staged.push((stage(&path, |w| write_stats(w, stats))?, path));
        }
        if let Some((temp, path, image, scene)) = self.hdr {
            write_exr(&temp, &path, &scene, image)?;
            staged.push((temp, path));
        }
        for (temp, path) in staged {
            temp.persist(&path).map_err(|e| io_error(&path, e.error))?;
        }
        Ok(())
    }
}
