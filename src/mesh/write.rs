//! The mesh file formats, chosen by the file's extension: binary little-endian PLY (float32
//! positions and vertex normals, int32 indices), binary STL (a face normal per triangle), and
//! OBJ (`v`, `vn` and `f a//a b//b c//c`, 1-based). Positions are multiplied by the scale on
//! the way out. Each file goes to a temporary file beside its target and is renamed into place
//! only when the caller has written every output (`crate::output::stage`).

use std::io::Write;
use std::path::Path;

use super::Mesh;
use crate::error::{FlagError, Result};

/// A mesh file format.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    Ply,
    Stl,
    Obj,
}

impl Format {
    /// The format of a file by its extension (case-insensitive); any other is bad input.
    pub fn for_path(path: &Path) -> Result<Self, FlagError> {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        match ext.as_deref() {
            Some("ply") => Ok(Format::Ply),
            Some("stl") => Ok(Format::Stl),
            Some("obj") => Ok(Format::Obj),
            _ => Err(FlagError::new(
                format!("-o {}", path.display()),
                "the mesh file must end in .ply, .stl or .obj",
            )),
        }
    }
}

/// Writes the mesh in `format`, positions times `scale`.
pub fn write_mesh(
    w: &mut dyn Write,
    mesh: &Mesh,
    format: Format,
    scale: f64,
) -> std::io::Result<()> {
    let scaled = |p: [f32; 3]| p.map(|v| (v as f64 * scale) as f32);
    match format {
        Format::Ply => {
            write!(
                w,
                "ply\nformat binary_little_endian 1.0\ncomment qjulia mesh\n\
                 element vertex {}\nproperty float x\nproperty float y\nproperty float z\n\
                 property float nx\nproperty float ny\nproperty float nz\n\
                 element face {}\nproperty list uchar int vertex_indices\nend_header\n",
                mesh.positions.len(),
                mesh.triangles.len()
            )?;
            for (p, n) in mesh.positions.iter().zip(&mesh.normals) {
                let mut record = [0u8; 24];
                for (k, v) in scaled(*p).iter().chain(n).enumerate() {
                    record[4 * k..4 * k + 4].copy_from_slice(&v.to_le_bytes());
                }
                w.write_all(&record)?;
            }
            for t in &mesh.triangles {
                let mut record = [3u8; 13];
                for (k, &i) in t.iter().enumerate() {
                    record[1 + 4 * k..5 + 4 * k].copy_from_slice(&(i as i32).to_le_bytes());
                }
                w.write_all(&record)?;
            }
        }
        Format::Stl => {
            let mut header = [b' '; 80];
            let text = b"qjulia mesh (binary STL)";
            header[..text.len()].copy_from_slice(text);
            w.write_all(&header)?;
            let count = u32::try_from(mesh.triangles.len())
                .map_err(|_| std::io::Error::other("too many triangles for STL"))?;
            w.write_all(&count.to_le_bytes())?;
            for t in &mesh.triangles {
                let [a, b, c] = t.map(|i| scaled(mesh.positions[i as usize]));
                let normal = face_normal(a, b, c);
                let mut record = [0u8; 50];
                for (k, v) in normal.iter().chain(&a).chain(&b).chain(&c).enumerate() {
                    record[4 * k..4 * k + 4].copy_from_slice(&v.to_le_bytes());
                }
                w.write_all(&record)?;
            }
        }
        Format::Obj => {
            writeln!(w, "# qjulia mesh")?;
            for p in &mesh.positions {
                let [x, y, z] = scaled(*p);
                writeln!(w, "v {x} {y} {z}")?;
            }
            for n in &mesh.normals {
                writeln!(w, "vn {} {} {}", n[0], n[1], n[2])?;
            }
            for t in &mesh.triangles {
                let [a, b, c] = t.map(|i| i as u64 + 1);
                writeln!(w, "f {a}//{a} {b}//{b} {c}//{c}")?;
            }
        }
    }
    Ok(())
}

/// The unit normal of a triangle wound counter-clockwise (zero for a degenerate one).
fn face_normal(a: [f32; 3], b: [f32; 3], c: [f32; 3]) -> [f32; 3] {
    let (a, b, c) = (a.map(f64::from), b.map(f64::from), c.map(f64::from));
    let (u, v) = (
        [0, 1, 2].map(|k| b[k] - a[k]),
        [0, 1, 2].map(|k| c[k] - a[k]),
    );
    let n = [
        u[1] * v[2] - u[2] * v[1],
        u[2] * v[0] - u[0] * v[2],
        u[0] * v[1] - u[1] * v[0],
    ];
    let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
    if len > 0.0 && len.is_finite() {
        n.map(|v| (v / len) as f32)
    } else {
        [0.0; 3]
    }
}
