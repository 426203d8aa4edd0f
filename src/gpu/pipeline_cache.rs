//! A persistent pipeline cache: wgpu's [`wgpu::PipelineCache`] where the device has
//! `PIPELINE_CACHE` (Vulkan), kept in the user's cache folder (`~/.cache/qjulia` on Linux, or
//! `QJULIA_CACHE_DIR`), so that a second process does not compile the same pipelines again.
//! One file per adapter and driver (wgpu's `pipeline_cache_key`) and set of shaders (a hash of
//! every module's source and this build's version): `KEY-HASH.bin`, written atomically. A file
//! that is corrupt, cut short or foreign is ignored and replaced: it carries its own length and
//! checksum, checked before the driver sees a byte. `QJULIA_NO_PIPELINE_CACHE=1` turns it off.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

use super::shaders::ALL_MODULES;

/// The file's first bytes, then a u64 payload length and its FNV-1a 64 hash (little-endian).
const MAGIC: &[u8; 8] = b"QJPCACH1";
const HEADER: usize = 8 + 8 + 8;

/// A pipeline cache and the file it is kept in.
pub struct DiskPipelineCache {
    cache: wgpu::PipelineCache,
    path: PathBuf,
    /// What the file holds now (its payload's length), so that an unchanged cache is not
    /// written again.
    saved: Mutex<Option<usize>>,
}

impl std::fmt::Debug for DiskPipelineCache {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("DiskPipelineCache")
            .field("path", &self.path)
            .finish()
    }
}

/// The folder the caches are kept in: `QJULIA_CACHE_DIR`, else the user's cache folder's
/// `qjulia`.
pub fn cache_dir() -> Option<PathBuf> {
    match std::env::var_os("QJULIA_CACHE_DIR") {
        Some(dir) if !dir.is_empty() => Some(PathBuf::from(dir)),
        _ => dirs::cache_dir().map(|d| d.join("qjulia")),
    }
}

/// FNV-1a, 64 bits.
fn fnv(bytes: &[u8]) -> u64 {
    super::compose::fnv1a(bytes)
}

/// The hash of what the pipelines are made of: every module's source, this build's version and
/// wgpu's.
fn shaders_hash() -> u64 {
    let mut text = format!("qjulia {} wgpu 30.0.1\n", env!("CARGO_PKG_VERSION"));
    for m in ALL_MODULES {
        text.push_str(m.name);
        text.push_str(&m.source());
    }
    fnv(text.as_bytes())
}

/// The payload of a cache file, or None where it is missing, short, foreign or corrupt.
fn read_verified(path: &Path) -> Option<Vec<u8>> {
    let bytes = std::fs::read(path).ok()?;
    if bytes.len() < HEADER || &bytes[..8] != MAGIC {
        return None;
    }
    let length = u64::from_le_bytes(bytes[8..16].try_into().ok()?) as usize;
    let hash = u64::from_le_bytes(bytes[16..24].try_into().ok()?);
    let payload = &bytes[HEADER..];
    (payload.len() == length && fnv(payload) == hash).then(|| payload.to_vec())
}

impl DiskPipelineCache {
    /// The cache for this device, filled from its file where that is good; None where the
    /// device has no pipeline cache, there is no cache folder, or `QJULIA_NO_PIPELINE_CACHE=1`.
    pub fn open(device: &wgpu::Device, info: &wgpu::AdapterInfo) -> Option<Self> {
        if std::env::var_os("QJULIA_NO_PIPELINE_CACHE").is_some_and(|v| v == "1") {
            return None;
        }
        if !device.features().contains(wgpu::Features::PIPELINE_CACHE) {
            return None;
        }
        let key = wgpu::util::pipeline_cache_key(info)?;
        let path = cache_dir()?.join(format!("{key}-{:016x}.bin", shaders_hash()));
        let data = read_verified(&path);
        // SAFETY: `data` is what `get_data` gave an earlier process for this adapter, driver
        // and shaders (the file's name), whole (its length and checksum are checked above);
        // wgpu checks its own header too, and falls back to an empty cache where it is not
        // what this device made.
        let cache = unsafe {
            device.create_pipeline_cache(&wgpu::PipelineCacheDescriptor {
                label: Some("qjulia"),
                data: data.as_deref(),
                fallback: true,
            })
        };
        Some(Self {
            cache,
            path,
            saved: Mutex::new(data.map(|d| d.len())),
        })
    }

    pub fn cache(&self) -> &wgpu::PipelineCache {
        &self.cache
    }

    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Writes the cache to its file where it has changed, atomically (a temporary file renamed
    /// over it). A cache is an optimisation: a failure to write it is not the run's, and says
    /// nothing.
    pub fn save(&self) {
        let Some(data) = self.cache.get_data() else {
            return;
        };
        let mut saved = self.saved.lock().expect("the cache's state");
        if *saved == Some(data.len()) {
            return;
        }
        let Some(dir) = self.path.parent() else {
            return;
        };
        if std::fs::create_dir_all(dir).is_err() {
            return;
        }
        let write = || -> std::io::Result<()> {
            let mut temp = tempfile::Builder::new()
                .prefix(".pipeline-cache-")
                .suffix(".tmp")
                .tempfile_in(dir)?;
            temp.write_all(MAGIC)?;
            temp.write_all(&(data.len() as u64).to_le_bytes())?;
            temp.write_all(&fnv(&data).to_le_bytes())?;
            temp.write_all(&data)?;
            temp.flush()?;
            temp.persist(&self.path).map_err(|e| e.error)?;
            Ok(())
        };
        if write().is_ok() {
            *saved = Some(data.len());
        }
    }
}

impl Drop for DiskPipelineCache {
    fn drop(&mut self) {
        self.save();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_file_is_taken_only_whole_and_ours() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("c.bin");
        let payload = b"driver bytes".to_vec();
        let mut file = MAGIC.to_vec();
        file.extend((payload.len() as u64).to_le_bytes());
        file.extend(fnv(&payload).to_le_bytes());
        file.extend(&payload);
        std::fs::write(&path, &file).unwrap();
        assert_eq!(read_verified(&path), Some(payload.clone()));
        let mut cut = file.clone();
        cut.pop();
        std::fs::write(&path, &cut).unwrap();
        assert_eq!(read_verified(&path), None, "cut short");
        let mut flipped = file.clone();
        *flipped.last_mut().unwrap() ^= 1;
        std::fs::write(&path, &flipped).unwrap();
        assert_eq!(read_verified(&path), None, "corrupt");
        std::fs::write(&path, b"something else entirely, long enough").unwrap();
        assert_eq!(read_verified(&path), None, "foreign");
        assert_eq!(read_verified(&dir.path().join("missing")), None);
    }
}
