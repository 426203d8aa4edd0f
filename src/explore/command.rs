//! What the explorer's panels, menus and keys ask of the app beyond what they edit themselves:
//! each returns [`Command`]s, which the app (`ExplorerApp::apply`) carries out once they are
//! drawn (the keys' before the panels, the panels' before the windows over them, the windows'
//! after the frame).

use std::path::PathBuf;

use super::file_dialog::Purpose;
use crate::scene::Algebra;

/// One thing for the app to do.
#[derive(Clone, Debug, PartialEq)]
pub enum Command {
    /// Opens the file dialog for this purpose, in the last folder used.
    OpenDialog(Purpose),
    /// Loads a scene file, its `[animation]` into the timeline.
    OpenScene(PathBuf),
    /// Saves the scene with the timeline's `[animation]`.
    SaveScene(PathBuf),
    /// Exports what the view shows as a PNG.
    ExportPng(PathBuf),
    /// Exports the 3D slice's surface as a mesh.
    ExportMesh(PathBuf),
    /// Replaces the scene by a preset's (`scene::presets::PRESETS[k]`), in the preset's mode.
    Preset(usize),
    /// Puts the camera back where the scene had it.
    ResetCamera,
    /// Switches the algebra (c, slice and offset cut or padded), the rotation starting afresh.
    SetAlgebra(Algebra),
    /// Plays or pauses the c-loop.
    ToggleCLoop,
    /// Shows a frame of the timeline's animation in the view.
    ShowFrame(u32),
    /// Plays or pauses the timeline's animation in the view.
    ToggleTimelinePlay,
    /// Adds a keyframe at the timeline's frame from the view.
    AddKey,
    /// Opens the "Render animation…" window.
    OpenRenderWindow,
    /// Starts the render the "Render animation…" window asks for.
    RenderAnimation,
    /// Opens the help window.
    ShowHelp,
    /// Opens or closes the help window.
    ToggleHelp,
    /// Sets `environment.file` (empty: no map) and loads the map, or says why it cannot.
    SetEnvironment(String),
    /// Says this in the status line (true: as an error).
    Tell(String, bool),
}
