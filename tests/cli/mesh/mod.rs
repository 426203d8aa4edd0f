//! `qjulia mesh` (issue 14): the mesh against exact truth (c = 0, the unit ball), the seed's
//! look against `render`'s hit mask, the GPU's sampler against its CPU twin, each format read
//! back by an independent reader, and the command line's refusals.
//!
//! The mesh's geometry is tested in `geometry.rs`, its files and the command line in `files.rs`;
//! the CPU mesh and the checks of a closed mesh they share are here.

use crate::common;
mod files;
mod geometry;

use std::collections::HashMap;

use qjulia::mesh::{Mesh, MeshOptions, make_mesh};
use qjulia::{Precision, Scene};

/// The mesh of a scene on the CPU in f32 at N points per axis.
fn cpu_mesh(scene: &Scene, n: u32) -> Mesh {
    let options = MeshOptions {
        resolution: n,
        region: None,
    };
    make_mesh(
        &common::cpu_renderer(scene, Precision::F32),
        scene,
        &options,
        &mut |_, _| {},
    )
    .expect("mesh")
    .0
}

/// Edges (as sorted vertex pairs) and how many triangles hold each; panics unless the winding
/// is consistent (each edge once in each direction, where it is in two triangles).
fn edge_counts(mesh: &Mesh) -> HashMap<(u32, u32), (u32, i32)> {
    let mut edges: HashMap<(u32, u32), (u32, i32)> = HashMap::new();
    for t in &mesh.triangles {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            let e = edges.entry((a.min(b), a.max(b))).or_default();
            e.0 += 1;
            e.1 += if a < b { 1 } else { -1 };
        }
    }
    edges
}

/// Closed and edge-manifold: every edge in exactly two triangles, wound opposite ways in them;
/// returns the Euler characteristic V - E + F.
fn assert_closed_manifold(name: &str, mesh: &Mesh) -> i64 {
    assert!(!mesh.is_empty(), "{name}: an empty mesh");
    let edges = edge_counts(mesh);
    let bad = edges.values().filter(|&&(n, _)| n != 2).count();
    assert_eq!(bad, 0, "{name}: {bad} edges not in exactly two triangles");
    let flipped = edges.values().filter(|&&(_, s)| s != 0).count();
    assert_eq!(
        flipped, 0,
        "{name}: {flipped} edges wound the same way twice"
    );
    let used: std::collections::HashSet<u32> = mesh.triangles.iter().flatten().copied().collect();
    assert_eq!(used.len(), mesh.positions.len(), "{name}: unused vertices");
    mesh.positions.len() as i64 - edges.len() as i64 + mesh.triangles.len() as i64
}

/// The signed volume the triangles enclose (positive when they wind outward).
fn volume(mesh: &Mesh) -> f64 {
    mesh.triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| mesh.positions[i as usize].map(f64::from));
            let cross = [
                b[1] * c[2] - b[2] * c[1],
                b[2] * c[0] - b[0] * c[2],
                b[0] * c[1] - b[1] * c[0],
            ];
            (a[0] * cross[0] + a[1] * cross[1] + a[2] * cross[2]) / 6.0
        })
        .sum()
}
