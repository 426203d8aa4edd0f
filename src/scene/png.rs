//! The scene a qjulia PNG carries: the keyword of its iTXt chunk, written by
//! [`crate::output`] and read back here for `--scene FILE.png`.

use std::path::Path;

use super::error::{SceneError, SceneSource};

/// The keyword of the iTXt chunk that carries a PNG's scene as TOML.
pub const SCENE_PNG_KEYWORD: &str = "qjulia-scene";

/// Reads the PNG's embedded scene (an iTXt chunk with keyword `qjulia-scene`).
pub fn scene_from_png(path: &Path) -> Result<String, SceneError> {
    let source = SceneSource::File(path.to_path_buf());
    let file = std::fs::File::open(path)
        .map_err(|e| SceneError::general(&source, format!("cannot read: {e}")))?;
    let reader = png::Decoder::new(std::io::BufReader::new(file))
        .read_info()
        .map_err(|e| SceneError::general(&source, format!("not a readable PNG: {e}")))?;
    let chunk = reader
        .info()
        .utf8_text
        .iter()
        .find(|c| c.keyword == SCENE_PNG_KEYWORD)
        .ok_or_else(|| {
            SceneError::general(
                &source,
                "holds no qjulia scene (no qjulia-scene iTXt chunk)",
            )
        })?;
    chunk
        .get_text()
        .map_err(|e| SceneError::general(&source, format!("unreadable qjulia-scene chunk: {e}")))
}
