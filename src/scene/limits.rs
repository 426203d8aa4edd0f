//! How long scene text may be: what the loader (src/scene/load) and the PNG reader
//! (src/scene/png.rs) both bound, in a module of its own so that neither imports the other.

/// The most bytes of scene text (a file, or the scene a PNG or EXR carries) the loader takes:
/// scenes are a few kilobytes, a long keyframed animation a few hundred.
pub const SCENE_TEXT_LIMIT: usize = 1 << 20;
/// The most bytes one `--set KEY=VALUE` may have.
pub const SET_LIMIT: usize = 1 << 16;
