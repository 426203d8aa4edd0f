//! The scene a qjulia PNG carries: the keyword of its iTXt chunk, written by
//! [`crate::output`] and read back here for `--scene FILE.png`.

use std::io::{BufRead, Seek};
use std::path::Path;

use super::error::{SceneError, SceneSource};
use super::limits::SCENE_TEXT_LIMIT;

/// The keyword of the iTXt chunk that carries a PNG's scene as TOML.
pub const SCENE_PNG_KEYWORD: &str = "qjulia-scene";

/// Reads the PNG's embedded scene (an iTXt chunk with keyword `qjulia-scene`).
pub fn scene_from_png(path: &Path) -> Result<String, SceneError> {
    let source = SceneSource::File(path.to_path_buf());
    let file = std::fs::File::open(path)
        .map_err(|e| SceneError::general(&source, format!("cannot read: {e}")))?;
    read_scene_chunk(std::io::BufReader::new(file), &source)
}

/// [`scene_from_png`] of a PNG held in memory (the fuzz target's way in); `source` names it in
/// the errors.
pub fn scene_from_png_bytes(bytes: &[u8], source: &SceneSource) -> Result<String, SceneError> {
    read_scene_chunk(std::io::Cursor::new(bytes), source)
}

/// The scene of the PNG read from `input`: its chunks up to the image data, no pixels.
fn read_scene_chunk(
    input: impl BufRead + Seek,
    source: &SceneSource,
) -> Result<String, SceneError> {
    let source = source.clone();
    // The chunks before the image data are held in memory: cap what that may take.
    let limits = png::Limits {
        bytes: 4 * SCENE_TEXT_LIMIT,
    };
    let reader = png::Decoder::new_with_limits(input, limits)
        .read_info()
        .map_err(|e| SceneError::general(&source, format!("not a readable PNG: {e}")))?;
    let mut chunk = reader
        .info()
        .utf8_text
        .iter()
        .find(|c| c.keyword == SCENE_PNG_KEYWORD)
        .cloned()
        .ok_or_else(|| {
            SceneError::general(
                &source,
                "holds no qjulia scene (no qjulia-scene iTXt chunk)",
            )
        })?;
    // A compressed chunk is inflated to at most the longest scene the loader takes.
    let unreadable = |e: png::DecodingError| {
        SceneError::general(&source, format!("unreadable qjulia-scene chunk: {e}"))
    };
    chunk
        .decompress_text_with_limit(SCENE_TEXT_LIMIT)
        .map_err(|e| {
            // png's words for the limit ("Out of decompression space. Try with a larger
            // limit.") name a limit the user cannot set: say what it is.
            if e.to_string().contains("decompression space") {
                SceneError::general(
                    &source,
                    format!(
                        "its qjulia-scene chunk inflates to more than a scene may be ({} bytes)",
                        SCENE_TEXT_LIMIT
                    ),
                )
            } else {
                unreadable(e)
            }
        })?;
    chunk.get_text().map_err(unreadable)
}
