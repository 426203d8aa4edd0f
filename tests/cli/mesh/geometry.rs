//! The mesh's geometry: the unit ball (c = 0) closed, with its radius, volume and normals; the
//! seed's look closed inside its ball and matching `render`'s silhouette; the cut closing the mesh
//! on its plane; the GPU's sampler against its CPU twin on every point's side.

use qjulia::cpu::sample::sample_rows;
use qjulia::mesh::{MeshOptions, grid_for};
use qjulia::{Picture, Precision, Scene, TraceParams};

use super::{assert_closed_manifold, cpu_mesh, volume};
use crate::common;

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
