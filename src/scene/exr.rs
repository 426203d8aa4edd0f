//! The scene a qjulia OpenEXR file carries: the name of its header attribute, written by
//! [`crate::hdr`] and read back here for `--scene FILE.exr`.

use std::path::Path;

use super::error::{SceneError, SceneSource};

/// The header attribute (a string) that carries an EXR's scene as TOML, named as the PNG's
/// iTXt chunk is.
pub const SCENE_EXR_ATTRIBUTE: &str = "qjulia-scene";

/// Reads the EXR's embedded scene (the `qjulia-scene` string attribute of its first header);
/// only the headers are read, not the pixels.
pub fn scene_from_exr(path: &Path) -> Result<String, SceneError> {
    let source = SceneSource::File(path.to_path_buf());
    let meta = exr::meta::MetaData::read_from_file(path, false).map_err(|e| match e {
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
