//! Export, a job of the explorer's runtime: what the view shows, at the scene's image size,
//! decided and rendered as the headless commands do ([`crate::render::Planner::plan`], on the
//! UI's device), written as a PNG on a thread of its own while the UI goes on; or the set's
//! surface as a mesh (`qjulia mesh`), with its progress in the status line.

use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::mpsc::{Receiver, channel};

use crate::output::{OutputPaths, write_outputs, write_view_outputs};
use crate::render::{Picture, Planner};
use crate::scene::Scene;

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

    /// Exports `picture` of `scene` (what the view shows, at the scene's image size) as a PNG
    /// at `path`, on another thread: decided by `planner` as `render` (or `render2d`) decides
    /// it, through the same kernel.
    pub fn png(mut planner: Planner, scene: Scene, picture: Picture, path: PathBuf) -> Self {
        let (send, done) = channel();
        let paths = OutputPaths {
            png: Some(path.clone()),
            ..Default::default()
        };
        std::thread::spawn(move || {
            // Decided by the scene exported, at its image size, as `render` decides it.
            let mut export = || -> crate::Result<()> {
                let plan = planner.plan(&scene, picture.into(), &mut |_| {})?;
                let (frame, stats) = plan.renderer.render_frame(&scene, picture)?;
                match picture {
                    Picture::Slice { .. } => write_view_outputs(&paths, &frame, &stats, &scene),
                    Picture::Julia2d => write_outputs(&paths, &frame, &stats, &scene),
                }
            };
            send.send(export().map_err(|e| e.to_string())).ok();
        });
        Self {
            path,
            done,
            progress: None,
        }
    }

    /// Exports the 3D slice of `scene`'s surface as a mesh at `resolution` points per axis,
    /// as `qjulia mesh` makes it (the format by the file's extension, the precision by the
    /// grid cell, decided by `planner`), on another thread.
    pub fn mesh(mut planner: Planner, scene: Scene, resolution: u32, path: PathBuf) -> Self {
        let options = crate::mesh::MeshOptions {
            resolution,
            region: None,
        };
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
        Self {
            path,
            done,
            progress: Some(progress),
        }
    }

    /// Once the export has ended: the status line's word on it, and whether it is an error.
    pub fn finished(&self) -> Option<(String, bool)> {
        let result = self.done.try_recv().ok()?;
        Some(match result {
            Ok(()) => (format!("exported {}", self.path.display()), false),
            Err(e) => (format!("error: export failed: {e}"), true),
        })
    }
}
