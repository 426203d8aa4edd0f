//! `qjulia mesh` (issue 14): the mesh against exact truth (c = 0, the unit ball), the seed's
//! look against `render`'s hit mask, the GPU's sampler against its CPU twin, each format read
//! back by an independent reader, and the command line's refusals.

mod common;

use std::collections::HashMap;
use std::path::Path;

use qjulia::cpu::sample::sample_rows;
use qjulia::mesh::{Mesh, MeshOptions, grid_for, make_mesh};
use qjulia::{Picture, Precision, Scene, TraceParams};

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

#[test]
fn the_unit_ball_is_a_closed_sphere_of_the_right_radius_volume_and_normals() {
    // c = 0: d(p) = 0.5 |p| ln|p| exactly, so d = epsilon at r ln r = 2 epsilon, r ~ 1 + 2 epsilon.
    let scene = common::scene(&["fractal.c=[0,0,0,0]"]);
    let eps = scene.fractal.epsilon;
    let radius = 1.0 + 2.0 * eps;
    let n = 128;
    let mesh = cpu_mesh(&scene, n);
    let chi = assert_closed_manifold("ball", &mesh);
    assert_eq!(chi, 2, "the ball's Euler characteristic");
    let options = MeshOptions {
        resolution: n,
        region: None,
    };
    let cell = grid_for(&scene, &options).unwrap().step[0];
    let mut worst_radius: f64 = 0.0;
    let mut worst_angle: f64 = 0.0;
    for (p, nrm) in mesh.positions.iter().zip(&mesh.normals) {
        let p = p.map(f64::from);
        let r = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
        worst_radius = worst_radius.max((r - radius).abs());
        let cos = (p[0] * nrm[0] as f64 + p[1] * nrm[1] as f64 + p[2] * nrm[2] as f64) / r;
        worst_angle = worst_angle.max(cos.clamp(-1.0, 1.0).acos().to_degrees());
    }
    eprintln!(
        "ball at N = {n}: {} vertices, {} triangles, cell {cell:.4}, worst |r - (1 + 2 eps)| {worst_radius:.2e}, worst normal {worst_angle:.3} degrees",
        mesh.positions.len(),
        mesh.triangles.len()
    );
    assert!(
        worst_radius <= cell,
        "a vertex {worst_radius} from the sphere, more than a cell ({cell})"
    );
    assert!(
        worst_angle <= 5.0,
        "a normal {worst_angle} degrees from radial"
    );
    let exact = 4.0 / 3.0 * std::f64::consts::PI * radius.powi(3);
    let v = volume(&mesh);
    eprintln!(
        "volume {v:.5} against {exact:.5}: {:+.3}%",
        (v / exact - 1.0) * 100.0
    );
    assert!(
        (v / exact - 1.0).abs() <= 0.01,
        "volume {v} against {exact}"
    );
}

/// Pixels of `render`'s hit mask of a scene (CPU, f32, depth only).
fn hit_mask(scene: &Scene) -> Vec<bool> {
    let renderer = common::cpu_renderer(scene, Precision::F32);
    let (frame, _) = renderer
        .render_frame(scene, Picture::Slice { shade: false })
        .expect("render");
    frame.depth.iter().map(|d| !d.is_nan()).collect()
}

#[test]
fn the_seeds_look_is_closed_inside_its_ball_and_matches_the_renders_silhouette() {
    let scene = common::scene(&["image.width=256", "image.height=256"]);
    let mesh = cpu_mesh(&scene, 128);
    assert_closed_manifold("seed", &mesh);
    let finite = |v: &[f32; 3]| v.iter().all(|c| c.is_finite());
    assert!(
        mesh.positions.iter().all(finite),
        "a position is not finite"
    );
    assert!(mesh.normals.iter().all(finite), "a normal is not finite");
    let bounds = scene.slice_bounds();
    let outside = mesh
        .positions
        .iter()
        .filter(|p| {
            let d2: f64 = (0..3)
                .map(|k| (p[k] as f64 - bounds.center[k]).powi(2))
                .sum();
            d2 > bounds.radius_squared * (1.0 + 1e-6)
        })
        .count();
    assert_eq!(outside, 0, "vertices outside the bounding ball");
    // Project every vertex with docs/CONTRACT.md's camera and look it up in the render's hit mask.
    let (w, h) = (scene.image.width as i64, scene.image.height as i64);
    let mask = hit_mask(&scene);
    let frame = scene.camera_frame();
    let eye = scene.camera.eye;
    let aspect = w as f64 / h as f64;
    let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let on_hit = |i: i64, j: i64| {
        (i - 1..=i + 1).any(|a| {
            (j - 1..=j + 1)
                .any(|b| (0..w).contains(&a) && (0..h).contains(&b) && mask[(b * w + a) as usize])
        })
    };
    let agree = mesh
        .positions
        .iter()
        .filter(|p| {
            let d = [0, 1, 2].map(|k| p[k] as f64 - eye[k]);
            let z = dot(d, frame.forward);
            let (px, py) = (dot(d, frame.right) / z, dot(d, frame.up) / z);
            let i = ((px / (frame.tan_half_fov_y * aspect) + 1.0) * w as f64 / 2.0 - 0.5).round();
            let j = ((1.0 - py / frame.tan_half_fov_y) * h as f64 / 2.0 - 0.5).round();
            on_hit(i as i64, j as i64)
        })
        .count();
    let fraction = agree as f64 / mesh.positions.len() as f64;
    eprintln!(
        "seed at N = 128: {} vertices, {} triangles; {:.3}% project onto hit pixels or their neighbours",
        mesh.positions.len(),
        mesh.triangles.len(),
        fraction * 100.0
    );
    assert!(
        fraction >= 0.97,
        "only {:.2}% of the vertices on the silhouette",
        fraction * 100.0
    );
}

#[test]
fn the_cut_closes_the_mesh_on_its_plane() {
    let scene = common::scene(&["cut.enabled=true", "cut.normal=[0,0,1]", "cut.offset=0.1"]);
    let mesh = cpu_mesh(&scene, 64);
    assert_closed_manifold("cut", &mesh);
    let cell = grid_for(
        &scene,
        &MeshOptions {
            resolution: 64,
            region: None,
        },
    )
    .unwrap()
    .step[2];
    let eps = scene.fractal.epsilon;
    let beyond = mesh
        .positions
        .iter()
        .filter(|p| p[2] as f64 > 0.1 + eps + 1e-6)
        .count();
    assert_eq!(beyond, 0, "vertices beyond the cut plane");
    let on_plane = mesh
        .positions
        .iter()
        .filter(|p| (p[2] as f64 - (0.1 + eps)).abs() < cell)
        .count();
    assert!(on_plane > 100, "the cut face has {on_plane} vertices");
}

#[test]
fn gpu_and_cpu_sampling_agree_on_every_points_side() {
    let Some(gpu) = common::gpu("gpu_and_cpu_sampling_agree_on_every_points_side") else {
        return;
    };
    let sampler = qjulia::gpu::GpuSampler::new(gpu.context().clone()).expect("sampler");
    for (name, sets) in [
        ("seed", vec![]),
        (
            "cut",
            vec!["cut.enabled=true", "cut.normal=[1,1,0]", "cut.offset=0.2"],
        ),
        (
            "rotated slice",
            vec![
                "slice.x=[0.6,0,0,0.8]",
                "slice.z=[0,0,1,0]",
                "slice.offset=[0,0,0,0.1]",
            ],
        ),
    ] {
        let scene = common::scene(&sets);
        let options = MeshOptions {
            resolution: 48,
            region: None,
        };
        let grid = grid_for(&scene, &options).unwrap();
        let params = TraceParams::<f32>::new(&scene);
        let sgrid = grid.in_precision::<f32>();
        let rows = grid.size[1] * grid.size[2];
        let cpu = sample_rows(&params, &sgrid, 0..rows);
        let mut gpu_levels = vec![f32::NAN; cpu.len()];
        let width = grid.size[0] as usize;
        sampler
            .sample(&params, &sgrid, rows, &mut |row, levels| {
                let at = row as usize * width;
                gpu_levels[at..at + levels.len()].copy_from_slice(levels);
                Ok(())
            })
            .expect("GPU sampling");
        let (mut inside, mut differ, mut beyond_rounding) = (0, 0, 0);
        for (c, g) in cpu.iter().zip(&gpu_levels) {
            assert!(g.is_finite(), "{name}: a GPU level is {g}");
            inside += (*c < 0.0) as usize;
            if (*c < 0.0) != (*g < 0.0) {
                differ += 1;
                // Within rounding of the level: both next to 0.
                if c.abs().max(g.abs()) > 1e-4 {
                    beyond_rounding += 1;
                }
            }
        }
        eprintln!(
            "{name}: {} points, {inside} inside; sides differ at {differ}, {beyond_rounding} of them beyond rounding",
            cpu.len()
        );
        assert!(inside > 1000, "{name}: only {inside} points inside");
        assert_eq!(
            beyond_rounding, 0,
            "{name}: GPU and CPU disagree beyond rounding"
        );
    }
}

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
