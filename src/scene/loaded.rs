//! What a scene's path keys' files hold, loaded: the environment map (`environment.file`). The
//! loader ([`super::SceneLoader`]) resolves and loads them once all layers are in; the scene
//! carries them to the renderers, which never read a file themselves.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use crate::envmap::{EnvironmentData, load_source, resolve};

/// The files a scene's path keys name, loaded. Equal where they hold the same maps
/// ([`EnvironmentData`]'s equality: the same file's bytes packed alike).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Loaded {
    /// `environment.file`'s map, packed for the kernels; None: the scene names none.
    pub environment: Option<Arc<EnvironmentData>>,
}

impl super::Scene {
    /// Loads the map `environment.file` names (none where it is empty), a relative path
    /// resolved against each folder of `bases` in turn (the current directory where `bases` is
    /// empty); a checksum the scene records (`environment.checksum`, not 0) must be the
    /// file's where `verify` (else the file's is recorded). The reason, and the key at fault,
    /// where it cannot be used.
    pub fn load_environment(
        &mut self,
        bases: &[PathBuf],
        verify: bool,
    ) -> Result<(), (&'static str, String)> {
        if self.environment.file.is_empty() {
            self.loaded.environment = None;
            self.environment.checksum = 0;
            return Ok(());
        }
        let source = resolve(&self.environment.file, bases).map_err(|e| ("environment.file", e))?;
        let data = load_source(&source).map_err(|e| ("environment.file", e))?;
        let recorded = self.environment.checksum;
        if verify && recorded != 0 && recorded != data.checksum {
            return Err((
                "environment.checksum",
                format!(
                    "is {recorded}, but {source}'s CRC-32 is {}: the map is not the one the \
                     scene was rendered with",
                    data.checksum
                ),
            ));
        }
        self.environment.checksum = data.checksum;
        self.loaded.environment = Some(data);
        Ok(())
    }
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
