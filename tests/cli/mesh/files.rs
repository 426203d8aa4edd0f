//! The mesh's files and command line: each format read back by an independent reader (ply-rs-bw,
//! stl_io, tobj) as the same triangles, the default file and its stats, an empty region, a box's
//! detail, and the refusals.

use std::path::Path;

use qjulia::Precision;
use qjulia::mesh::{Mesh, MeshOptions, make_mesh};

use super::{cpu_mesh, edge_counts};
use crate::common;

/// The triangles as position triples (scaled), for comparing what a reader gives back.
fn triangle_corners(mesh: &Mesh, scale: f32) -> Vec<[[f32; 3]; 3]> {
    mesh.triangles
        .iter()
        .map(|t| t.map(|i| mesh.positions[i as usize].map(|v| (v as f64 * scale as f64) as f32)))
        .collect()
}

fn run_ok(dir: &Path, args: &[&str]) -> String {
    let out = common::qjulia(dir, args);
    let stderr = common::stderr(&out);
    assert!(out.status.success(), "{}: {stderr}", args.join(" "));
    stderr
}

#[test]
fn each_format_reads_back_as_the_same_triangles() {
    let dir = tempfile::tempdir().unwrap();
    let scene = common::scene(&[]);
    let mesh = cpu_mesh(&scene, 24);
    let scale = 10.0_f32;
    let expected = triangle_corners(&mesh, scale);
    for ext in ["ply", "stl", "obj"] {
        let name = format!("seed.{ext}");
        run_ok(
            dir.path(),
            &[
                "mesh",
                "--resolution",
                "24",
                "--backend",
                "cpu",
                "--scale",
                "10",
                "-o",
                &name,
            ],
        );
        let path = dir.path().join(&name);
        let (got, normals): ReadBack = match ext {
            "ply" => read_ply(&path),
            "stl" => {
                let mut f = std::fs::File::open(&path).unwrap();
                let tris: Vec<_> = stl_io::create_stl_reader(&mut f)
                    .expect("an STL")
                    .map(|t| t.expect("a triangle").vertices.map(|v| v.0))
                    .collect();
                (tris, None)
            }
            _ => {
                let (models, _) = tobj::load_obj(&path, &tobj::GPU_LOAD_OPTIONS).expect("an OBJ");
                assert_eq!(models.len(), 1);
                let m = &models[0].mesh;
                let at = |v: &[f32], i: u32| [0, 1, 2].map(|k| v[3 * i as usize + k]);
                let tris = m
                    .indices
                    .chunks(3)
                    .map(|t| {
                        [
                            at(&m.positions, t[0]),
                            at(&m.positions, t[1]),
                            at(&m.positions, t[2]),
                        ]
                    })
                    .collect();
                let normals = (0..m.normals.len() as u32 / 3)
                    .map(|i| at(&m.normals, i))
                    .collect();
                (tris, Some(normals))
            }
        };
        assert_eq!(got.len(), expected.len(), "{ext}: triangle count");
        // OBJ's text rounds to the shortest decimal that reads back as the same f32.
        assert!(got == expected, "{ext}: the triangles read back differ");
        if let Some(normals) = normals {
            assert_eq!(normals.len(), mesh.normals.len(), "{ext}: normal count");
            let mut sorted_got = normals.clone();
            let mut sorted_expected = mesh.normals.clone();
            let key = |v: &[f32; 3]| v.map(f32::to_bits);
            sorted_got.sort_by_key(key);
            sorted_expected.sort_by_key(key);
            assert!(
                sorted_got == sorted_expected,
                "{ext}: the normals read back differ"
            );
        }
    }
}

/// A file's triangles (as their corners' positions) and, where it has them, vertex normals.
type ReadBack = (Vec<[[f32; 3]; 3]>, Option<Vec<[f32; 3]>>);

/// A PLY's triangles (as positions) and vertex normals, read by ply-rs.
fn read_ply(path: &Path) -> ReadBack {
    use ply_rs_bw::parser::Parser;
    use ply_rs_bw::ply::{DefaultElement, Property};
    let mut f = std::fs::File::open(path).unwrap();
    let ply = Parser::<DefaultElement>::new()
        .read_ply(&mut f)
        .expect("a PLY");
    let float = |e: &DefaultElement, k: &str| match e.get(k) {
        Some(Property::Float(v)) => *v,
        other => panic!("{k}: {other:?}"),
    };
    let vertices = &ply.payload["vertex"];
    let positions: Vec<[f32; 3]> = vertices
        .iter()
        .map(|e| [float(e, "x"), float(e, "y"), float(e, "z")])
        .collect();
    let normals = vertices
        .iter()
        .map(|e| [float(e, "nx"), float(e, "ny"), float(e, "nz")])
        .collect();
    let tris = ply.payload["face"]
        .iter()
        .map(|e| match e.get("vertex_indices") {
            Some(Property::ListInt(v)) => {
                assert_eq!(v.len(), 3);
                [0, 1, 2].map(|k| positions[v[k] as usize])
            }
            other => panic!("vertex_indices: {other:?}"),
        })
        .collect();
    (tris, Some(normals))
}

#[test]
fn mesh_writes_the_default_file_and_its_stats() {
    let dir = tempfile::tempdir().unwrap();
    let stderr = run_ok(
        dir.path(),
        &[
            "mesh",
            "--resolution",
            "16",
            "--backend",
            "cpu",
            "--stats",
            "m.json",
        ],
    );
    assert!(stderr.contains("triangles"), "{stderr}");
    assert_eq!(common::files_in(dir.path()), ["m.json", "qjulia.ply"]);
    let stats: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.path().join("m.json")).unwrap()).unwrap();
    for key in [
        "grid_points",
        "triangles",
        "vertices",
        "seconds",
        "grid_points_per_second",
    ] {
        assert!(
            stats[key].as_f64().is_some_and(|v| v > 0.0),
            "{key}: {stats}"
        );
    }
    assert_eq!(stats["grid_points"], 16 * 16 * 16);
    assert_eq!(stats["backend"], "cpu");
    assert_eq!(stats["precision"], "f32");
}

#[test]
fn an_empty_region_writes_an_empty_mesh_and_says_so() {
    let dir = tempfile::tempdir().unwrap();
    // The slice misses the 4D ball: nothing to mesh.
    let stderr = run_ok(
        dir.path(),
        &[
            "mesh",
            "--set",
            "slice.offset=[0,0,0,2]",
            "--backend",
            "cpu",
            "-o",
            "e.stl",
        ],
    );
    assert!(stderr.contains("empty"), "{stderr}");
    let bytes = std::fs::read(dir.path().join("e.stl")).unwrap();
    assert_eq!(bytes.len(), 84, "an STL of no triangles");
    // A box beside the set: empty too.
    let stderr = run_ok(
        dir.path(),
        &[
            "mesh",
            "--box",
            "5,5,5,6,6,6",
            "--resolution",
            "8",
            "--backend",
            "cpu",
            "-o",
            "b.ply",
        ],
    );
    assert!(stderr.contains("empty"), "{stderr}");
}

#[test]
fn a_box_meshes_a_detail_open_only_where_it_cuts_the_surface() {
    let scene = common::scene(&[]);
    let options = MeshOptions {
        resolution: 32,
        region: Some([[-0.5, -0.5, -0.5], [0.5, 0.5, 0.5]]),
    };
    let (mesh, stats) = make_mesh(
        &common::cpu_renderer(&scene, Precision::F32),
        &scene,
        &options,
        &mut |_, _| {},
    )
    .unwrap();
    assert_eq!(stats.box_min, [-0.5; 3]);
    assert_eq!(stats.box_max, [0.5; 3]);
    assert!(!mesh.is_empty());
    assert!(
        mesh.positions
            .iter()
            .all(|p| p.iter().all(|&c| (-0.5..=0.5).contains(&c)))
    );
    // Edges in one triangle lie on the box's faces only.
    let edges = edge_counts(&mesh);
    for (&(a, b), &(count, _)) in &edges {
        if count == 1 {
            let (pa, pb) = (mesh.positions[a as usize], mesh.positions[b as usize]);
            let on_face = (0..3).any(|k| {
                [-0.5f32, 0.5]
                    .iter()
                    .any(|&f| (pa[k] - f).abs() < 1e-5 && (pb[k] - f).abs() < 1e-5)
            });
            assert!(on_face, "an open edge inside the box: {pa:?} {pb:?}");
        } else {
            assert_eq!(count, 2);
        }
    }
}

#[test]
fn bad_mesh_input_is_refused_in_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    common::assert_refused(
        d,
        &["mesh", "--resolution", "7"],
        "error: --resolution 7",
        "--resolution",
    );
    common::assert_refused(
        d,
        &["mesh", "--resolution", "4097"],
        "error: --resolution 4097",
        "--resolution",
    );
    common::assert_refused(
        d,
        &["mesh", "--resolution", "-3"],
        "error: --resolution -3",
        "--resolution",
    );
    common::assert_refused(
        d,
        &["mesh", "--box", "0,0,0,1,1"],
        "error: --box 0,0,0,1,1",
        "--box",
    );
    common::assert_refused(
        d,
        &["mesh", "--box", "0,0,0,1,-1,1"],
        "error: --box",
        "--box",
    );
    common::assert_refused(
        d,
        &["mesh", "--box", "0,0,0,1,1,inf"],
        "error: --box",
        "--box",
    );
    common::assert_refused(d, &["mesh", "--scale", "0"], "error: --scale 0", "--scale");
    common::assert_refused(d, &["mesh", "--scale", "nan"], "error: --scale", "--scale");
    common::assert_refused(
        d,
        &["mesh", "-o", "shape.png"],
        "error: -o shape.png",
        ".ply",
    );
    common::assert_refused(
        d,
        &["mesh", "--set", "fractal.epsilon=0"],
        "error: --set",
        "fractal.epsilon",
    );
}

#[test]
fn f64_on_the_gpu_is_refused_as_render_refuses_it() {
    let dir = tempfile::tempdir().unwrap();
    let out = common::qjulia(
        dir.path(),
        &[
            "mesh",
            "--backend",
            "gpu",
            "--precision",
            "f64",
            "--resolution",
            "8",
        ],
    );
    assert_eq!(out.status.code(), Some(1), "{}", common::stderr(&out));
    assert!(common::files_in(dir.path()).is_empty());
}
