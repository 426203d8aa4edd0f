//! Draws meshes that `qjulia mesh` wrote (binary PLY), side by side, into one PNG: each read
//! back with ply-rs, its triangles rasterised with a z-buffer and shaded by their interpolated
//! vertex normals (diffuse and a little ambient), optionally with their edges drawn. This is
//! how docs/mesh.png is made (the book's docs/book/meshes.md):
//!
//! ```text
//! qjulia mesh --resolution 256 -o seed256.ply
//! qjulia mesh --resolution 40 -o seed40.ply
//! cargo run --release --example mesh_picture -- docs/mesh.png seed256.ply seed40.ply:edges
//! ```

use ply_rs_bw::parser::Parser;
use ply_rs_bw::ply::{DefaultElement, Property};

const PANEL: usize = 400;

type V3 = [f64; 3];

fn sub(a: V3, b: V3) -> V3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn dot(a: V3, b: V3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn cross(a: V3, b: V3) -> V3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
fn unit(a: V3) -> V3 {
    let l = dot(a, a).sqrt().max(1e-30);
    a.map(|v| v / l)
}

/// Positions, normals and triangles of a PLY.
fn read(path: &str) -> (Vec<V3>, Vec<V3>, Vec<[usize; 3]>) {
    let mut f = std::fs::File::open(path).unwrap_or_else(|e| panic!("{path}: {e}"));
    let ply = Parser::<DefaultElement>::new()
        .read_ply(&mut f)
        .expect("a PLY");
    let get = |e: &DefaultElement, k: &str| match e.get(k) {
        Some(Property::Float(v)) => *v as f64,
        _ => panic!("{path}: no float {k}"),
    };
    let vertices = &ply.payload["vertex"];
    let p = vertices
        .iter()
        .map(|e| [get(e, "x"), get(e, "y"), get(e, "z")])
        .collect();
    let n = vertices
        .iter()
        .map(|e| [get(e, "nx"), get(e, "ny"), get(e, "nz")])
        .collect();
    let t = ply.payload["face"]
        .iter()
        .map(|e| match e.get("vertex_indices") {
            Some(Property::ListInt(v)) => [v[0] as usize, v[1] as usize, v[2] as usize],
            _ => panic!("{path}: no vertex_indices"),
        })
        .collect();
    (p, n, t)
}

/// One panel: the mesh seen from `eye` toward the origin, RGB8.
fn draw(path: &str, edges: bool) -> Vec<[u8; 3]> {
    let (positions, normals, triangles) = read(path);
    let eye = [1.9, 1.4, 2.3];
    let f = unit(sub([0.0; 3], eye));
    let r = unit(cross(f, [0.0, 1.0, 0.0]));
    let u = cross(r, f);
    let scale = PANEL as f64 / (2.0 * (22.5f64).to_radians().tan());
    let project = |p: V3| {
        let d = sub(p, eye);
        let z = dot(d, f);
        [
            PANEL as f64 / 2.0 + scale * dot(d, r) / z,
            PANEL as f64 / 2.0 - scale * dot(d, u) / z,
            z,
        ]
    };
    let screen: Vec<V3> = positions.iter().map(|&p| project(p)).collect();
    let light = unit([0.6, 0.9, 0.7]);
    let mut depth = vec![f64::INFINITY; PANEL * PANEL];
    let mut rgb = vec![[77u8; 3]; PANEL * PANEL];
    for t in &triangles {
        let [a, b, c] = t.map(|i| screen[i]);
        let area = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
        if area.abs() < 1e-12 {
            continue;
        }
        let x0 = a[0].min(b[0]).min(c[0]).floor().max(0.0) as usize;
        let x1 = (a[0].max(b[0]).max(c[0]).ceil() as usize).min(PANEL - 1);
        let y0 = a[1].min(b[1]).min(c[1]).floor().max(0.0) as usize;
        let y1 = (a[1].max(b[1]).max(c[1]).ceil() as usize).min(PANEL - 1);
        for y in y0..=y1 {
            for x in x0..=x1 {
                let (px, py) = (x as f64 + 0.5, y as f64 + 0.5);
                let w0 = ((b[0] - px) * (c[1] - py) - (b[1] - py) * (c[0] - px)) / area;
                let w1 = ((c[0] - px) * (a[1] - py) - (c[1] - py) * (a[0] - px)) / area;
                let w2 = 1.0 - w0 - w1;
                if w0 < 0.0 || w1 < 0.0 || w2 < 0.0 {
                    continue;
                }
                let z = w0 * a[2] + w1 * b[2] + w2 * c[2];
                let k = y * PANEL + x;
                if z >= depth[k] {
                    continue;
                }
                depth[k] = z;
                let n = [0, 1, 2]
                    .map(|j| w0 * normals[t[0]][j] + w1 * normals[t[1]][j] + w2 * normals[t[2]][j]);
                let lit = 0.15 + 0.85 * dot(unit(n), light).max(0.0);
                let edge = edges && w0.min(w1).min(w2) < 0.06;
                let colour = if edge {
                    [0.1, 0.1, 0.12]
                } else {
                    [1.0, 0.55, 0.3].map(|c| c * lit)
                };
                rgb[k] = colour.map(|c| (c.clamp(0.0, 1.0) * 255.0).round() as u8);
            }
        }
    }
    rgb
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [out, meshes @ ..] = args.as_slice() else {
        panic!("usage: mesh_picture OUT.png MESH.ply[:edges]...");
    };
    let panels: Vec<Vec<[u8; 3]>> = meshes
        .iter()
        .map(|m| match m.strip_suffix(":edges") {
            Some(path) => draw(path, true),
            None => draw(m, false),
        })
        .collect();
    let width = PANEL * panels.len();
    let mut image = image::RgbImage::new(width as u32, PANEL as u32);
    for (i, panel) in panels.iter().enumerate() {
        for (k, px) in panel.iter().enumerate() {
            image.put_pixel(
                (i * PANEL + k % PANEL) as u32,
                (k / PANEL) as u32,
                image::Rgb(*px),
            );
        }
    }
    image.save(out).expect("write the PNG");
}
