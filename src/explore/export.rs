//! Export: what the view shows, at the scene's image size, decided and rendered as the
//! headless commands do ([`crate::render::Planner::plan`], on the UI's device), written as a
//! PNG on a thread of its own while the UI goes on; or the set's surface as a mesh (`qjulia
//! mesh`), with its progress in the status line.

use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::mpsc::{Receiver, channel};

use super::app::{ExplorerApp, Mode};
use crate::output::{OutputPaths, write_outputs, write_view_outputs};
use crate::precision::Precision;
use crate::render::Picture;
use crate::scene::View;

/// An export running on its own thread.
pub struct Export {
    path: PathBuf,
    done: Receiver<Result<(), String>>,
    /// A mesh export's grid layers done and in all.
    progress: Option<Arc<[AtomicU32; 2]>>,
}

impl Export {
    /// A mesh export's progress: grid layers done, of the total.
    pub fn progress(&self) -> Option<(u32, u32)> {
        self.progress
            .as_ref()
            .map(|p| (p[0].load(Ordering::Relaxed), p[1].load(Ordering::Relaxed)))
    }
}

impl ExplorerApp {
    /// Exports what the view shows, at the scene's image size through the same kernel, on
    /// another thread: the 3D view (shaded or a step view, as `render`), or in 2D mode the 2D
    /// view (as `render2d`).
    pub fn start_export(&mut self, path: PathBuf) {
        let scene = self.scene.clone();
        let (send, done) = channel();
        let paths = OutputPaths {
            png: Some(path.clone()),
            ..Default::default()
        };
        let picture = match self.mode {
            Mode::Slice3d => Picture::Slice {
                shade: scene.image.view == View::Shaded,
            },
            Mode::Julia2d => Picture::Julia2d,
        };
        let mut planner = self.planner();
        std::thread::spawn(move || {
            // Decided by the scene exported, at its image size, as `render` decides it.
            let export = || -> crate::Result<()> {
                let plan = planner.plan(&scene, picture.into(), &mut |_| {})?;
                let (frame, stats) = plan.renderer.render_frame(&scene, picture)?;
                let mut paths = paths;
                paths.depth_f64 = plan.decision.precision == Precision::F64;
                match picture {
                    Picture::Slice { .. } => write_view_outputs(&paths, &frame, &stats, &scene),
                    Picture::Julia2d => write_outputs(&paths, &frame, &stats, &scene),
                }
            };
            send.send(export().map_err(|e| e.to_string())).ok();
        });
        self.export = Some(Export {
            path,
            done,
            progress: None,
        });
    }

    /// Exports the 3D slice's surface as a mesh at `mesh_resolution` points per axis, as
    /// `qjulia mesh` makes it (the format by the file's extension, the precision by the grid
    /// cell), on the view's GPU where it can, on another thread.
    pub fn start_mesh_export(&mut self, path: PathBuf) {
        let scene = self.scene.clone();
        let options = crate::mesh::MeshOptions {
            resolution: self.mesh_resolution,
            region: None,
        };
        let mut planner = self.planner();
        let progress = Arc::new([AtomicU32::new(0), AtomicU32::new(0)]);
        let shared = progress.clone();
        let (send, done) = channel();
        let out = path.clone();
        std::thread::spawn(move || {
            let work = crate::mesh::work(&scene, &options);
            let result = planner
                .plan(&scene, work, &mut |_| {})
                .and_then(|plan| {
                    crate::mesh::make_mesh(&plan.renderer, &scene, &options, &mut |k, n| {
                        shared[0].store(k, Ordering::Relaxed);
                        shared[1].store(n, Ordering::Relaxed);
                    })
                })
                .and_then(|(mesh, _)| crate::mesh::write_outputs(&out, &mesh, 1.0, None));
            send.send(result.map_err(|e| e.to_string())).ok();
        });
        self.export = Some(Export {
            path,
            done,
            progress: Some(progress),
        });
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
