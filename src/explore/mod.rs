//! `qjulia explore`: the desktop explorer, an eframe/egui app on winit whose view is drawn by
//! the same GPU tracer as `qjulia render`, on the same device as the UI. The app and its frame
//! loop are `app`'s; what the user edits is `state`'s, the panels' `menu`, `panels`, `status`,
//! `viewport` and `timeline::panel`, the jobs `export` and `timeline::job`; the 3D view's
//! textures `slice_texture`, which the render module's live view draws into.

pub mod app;
pub mod c_loop;
pub mod camera;
pub mod command;
pub mod export;
pub mod file_dialog;
mod heat_texture;
mod hypersphere;
pub mod input;
mod kernel_texture;
mod menu;
mod panels;
pub mod persistence;
pub mod slice_texture;
pub mod state;
pub mod status;
pub mod timeline;
pub mod viewport;

use std::sync::Arc;

pub use app::ExplorerApp;
pub use state::ExplorerState;

use crate::error::{Error, INSTALL_ADAPTER_HINT, Result};
use crate::scene::Scene;

/// eframe's wgpu setup for qjulia: our adapter choice (honouring `WGPU_BACKEND` and
/// `WGPU_ADAPTER_NAME`) and a device with the adapter's limits, since eframe's default device on
/// the GL backend has no compute at all.
pub fn wgpu_setup() -> egui_wgpu::WgpuSetup {
    let mut setup = egui_wgpu::WgpuSetupCreateNew::without_display_handle();
    setup.native_adapter_selector = Some(Arc::new(|adapters, surface| {
        let usable: Vec<wgpu::Adapter> = adapters
            .iter()
            .filter(|a| surface.is_none_or(|s| a.is_surface_supported(s)))
            .cloned()
            .collect();
        crate::gpu::choose_adapter(usable).map_err(|e| e.to_string())
    }));
    setup.device_descriptor = Arc::new(crate::gpu::device_descriptor);
    egui_wgpu::WgpuSetup::CreateNew(setup)
}

/// Whether a display server is there to open a window on.
pub fn display_available() -> bool {
    ["DISPLAY", "WAYLAND_DISPLAY"]
        .iter()
        .any(|v| std::env::var_os(v).is_some_and(|s| !s.is_empty()))
}

/// Runs the explorer until its window closes. `initial` is the scene from the command line and
/// its `[animation]`, which the timeline shows.
pub fn run(initial: Option<(Scene, crate::animation::Animation)>) -> Result<()> {
    // Say clearly when there is no adapter, before eframe fails less clearly.
    pollster::block_on(crate::gpu::select_adapter())?;
    let options = eframe::NativeOptions {
        viewport: egui::ViewportBuilder::default()
            .with_title("qjulia")
            .with_inner_size([1280.0, 800.0]),
        renderer: eframe::Renderer::Wgpu,
        wgpu_options: egui_wgpu::WgpuConfiguration {
            wgpu_setup: wgpu_setup(),
            ..Default::default()
        },
        persist_window: true,
        // Dithering would nudge the view's pixels off the values the PNG holds.
        dithering: false,
        ..Default::default()
    };
    eframe::run_native(
        "qjulia",
        options,
        Box::new(move |cc| Ok(Box::new(ExplorerApp::new(cc, initial)))),
    )
    .map_err(|e| {
        Error::NoAdapter(format!(
            "cannot start the explorer: {e}; {INSTALL_ADAPTER_HINT}"
        ))
    })
}
