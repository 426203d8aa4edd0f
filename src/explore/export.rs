//! Export: what the view shows, at the scene's image size, through the same kernel as the
//! headless commands, written as a PNG on a thread of its own while the UI goes on.

use std::path::PathBuf;
use std::sync::Arc;
use std::sync::mpsc::{Receiver, channel};

use super::app::{ExplorerApp, Mode};
use crate::output::{OutputPaths, write_outputs, write_view_outputs};
use crate::render::{GpuKernels, Picture, Renderer};
use crate::scene::View;

/// An export running on its own thread.
pub struct Export {
    path: PathBuf,
    done: Receiver<Result<(), String>>,
}

impl ExplorerApp {
    /// Exports what the view shows, at the scene's image size through the same kernel, on
    /// another thread: the 3D view (shaded or a step view, as `render`), or in 2D mode the 2D
    /// view (as `render2d`).
    pub(super) fn start_export(&mut self, path: PathBuf) {
        let scene = self.scene.clone();
        let (send, done) = channel();
        let paths = OutputPaths {
            png: Some(path.clone()),
            ..Default::default()
        };
        let job: Box<dyn FnOnce() -> crate::Result<()> + Send> = match self.mode {
            Mode::Slice3d => {
                let Some(view) = &self.slice_texture else {
                    return;
                };
                let renderer = Renderer::on_tracer(view.tracer().clone());
                Box::new(move || {
                    let picture = Picture::Slice {
                        shade: scene.image.view == View::Shaded,
                    };
                    let (frame, stats) = renderer.render_frame(&scene, picture)?;
                    write_view_outputs(&paths, &frame, &stats, &scene)
                })
            }
            Mode::Julia2d => {
                let Some(view2d) = &self.julia2d_texture else {
                    return;
                };
                let kernels = GpuKernels::with(None, Some(view2d.julia().clone()));
                let renderer = Renderer::gpu(Arc::new(kernels));
                Box::new(move || {
                    let (frame, stats) = renderer.render_frame(&scene, Picture::Julia2d)?;
                    write_outputs(&paths, &frame, &stats, &scene)
                })
            }
        };
        std::thread::spawn(move || {
            send.send(job().map_err(|e| e.to_string())).ok();
        });
        self.export = Some(Export { path, done });
    }

    /// Says in the status line how a finished export went.
    pub(super) fn poll_export(&mut self) {
        let Some(export) = &self.export else { return };
        if let Ok(result) = export.done.try_recv() {
            self.message = Some(match result {
                Ok(()) => (format!("exported {}", export.path.display()), false),
                Err(e) => (format!("error: export failed: {e}"), true),
            });
            self.export = None;
        }
    }
}
