//! What a scene's path keys' files hold, loaded: the environment map (`environment.file`). The
//! loader (`Scene::load_environment`, in src/scene/load) resolves and loads them once all layers
//! are in; the scene carries them to the renderers, which never read a file themselves.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use crate::envmap::EnvironmentData;

/// The files a scene's path keys name, loaded. Equal where they hold the same maps
/// ([`EnvironmentData`]'s equality: the same file's bytes packed alike).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Loaded {
    /// `environment.file`'s map, packed for the kernels; None: the scene names none.
    pub environment: Option<Arc<EnvironmentData>>,
}

/// Where a relative path given by a scene file at `path` resolves: the file's folder, and for
/// a PNG's or an EXR's scene then the current directory.
pub fn bases_of_file(path: &Path) -> Vec<PathBuf> {
    let folder = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .map_or_else(|| PathBuf::from("."), Path::to_path_buf);
    let image = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("png") || e.eq_ignore_ascii_case("exr"));
    match image {
        true => vec![folder, PathBuf::from(".")],
        false => vec![folder],
    }
}
