//! The scene a qjulia OpenEXR file carries: the name of its header attribute, written by
//! [`crate::hdr`] and read back here for `--scene FILE.exr`.

use std::io::Read;
use std::path::Path;

use super::error::{SceneError, SceneSource};

/// The header attribute (a string) that carries an EXR's scene as TOML, named as the PNG's
/// iTXt chunk is.
pub const SCENE_EXR_ATTRIBUTE: &str = "qjulia-scene";

/// Reads the EXR's embedded scene (the `qjulia-scene` string attribute of its first header);
/// only the headers are read, not the pixels.
pub fn scene_from_exr(path: &Path) -> Result<String, SceneError> {
    let source = SceneSource::File(path.to_path_buf());
    let file = std::fs::File::open(path)
        .map_err(|e| SceneError::general(&source, format!("cannot read: {e}")))?;
    read_scene_attribute(std::io::BufReader::new(file), &source)
}

/// [`scene_from_exr`] of an EXR held in memory (the fuzz target's way in); `source` names it in
/// the errors.
pub fn scene_from_exr_bytes(bytes: &[u8], source: &SceneSource) -> Result<String, SceneError> {
    read_scene_attribute(bytes, source)
}

/// The scene attribute of the EXR whose headers are read from `input`.
fn read_scene_attribute(input: impl Read, source: &SceneSource) -> Result<String, SceneError> {
    let source = source.clone();
    let meta = exr::meta::MetaData::read_from_buffered(input, false).map_err(|e| match e {
        exr::error::Error::Io(e) => SceneError::general(&source, format!("cannot read: {e}")),
        e => SceneError::general(&source, format!("not a readable OpenEXR file: {e}")),
    })?;
    let name = exr::meta::attribute::Text::from(SCENE_EXR_ATTRIBUTE);
    let value = meta
        .headers
        .first()
        .and_then(|h| {
            h.own_attributes
                .other
                .get(&name)
                .or_else(|| h.shared_attributes.other.get(&name))
        })
        .ok_or_else(|| {
            SceneError::general(
                &source,
                "holds no qjulia scene (no qjulia-scene header attribute)",
            )
        })?;
    let exr::meta::attribute::AttributeValue::Text(text) = value else {
        return Err(SceneError::general(
            &source,
            "its qjulia-scene attribute is not a string",
        ));
    };
    String::from_utf8(text.bytes().to_vec()).map_err(|e| {
        SceneError::general(&source, format!("unreadable qjulia-scene attribute: {e}"))
    })
}
