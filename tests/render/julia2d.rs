//! The 2D Julia view (`render2d`): the GPU kernel against its CPU twin, and what the picture must
//! show: c = 0 is the unit disk, the set is symmetric under z -> -z, and the imaginary axis
//! points up.

use crate::common;

use qjulia::compare::{Agreement, JULIA2D_TOLERANCE};
use qjulia::cpu::julia2d::render_rows;
use qjulia::frame::unpack_rgb;
use qjulia::gpu::GpuJulia2d;
use qjulia::{Frame, Julia2dParams, Scene};

/// The seed's "rabbit ears" (Crane's Figure 3).
const RABBIT: &str = "fractal.c=[-0.12, 0.75, 0.0, 0.0]";

fn cpu<F: qjulia::algebra::Real>(scene: &Scene) -> Frame {
    let p = Julia2dParams::<F>::new(scene);
    render_rows(&p, 0..p.height)
}

fn gpu(test: &str, scene: &Scene) -> Option<Frame> {
    let tracer = common::gpu(test)?;
    let julia = GpuJulia2d::new(tracer.context().clone()).expect("the julia2d pipeline");
    Some(
        julia
            .render(&Julia2dParams::<f32>::new(scene))
            .expect("GPU render")
            .0,
    )
}

fn grey(frame: &Frame, i: u32, j: u32) -> u8 {
    let [r, g, b] = unpack_rgb(frame.colour[(j * frame.width + i) as usize]);
    assert!(r == g && g == b, "not grey");
    r
}

/// The pixel whose centre is nearest to z, with the imaginary axis up.
fn pixel_of(scene: &Scene, z: [f64; 2]) -> (u32, u32) {
    let (w, h) = (scene.image.width as f64, scene.image.height as f64);
    let half_x = 0.5 * scene.view2d.extent;
    let half_y = half_x * h / w;
    let i = ((z[0] - scene.view2d.center[0]) / half_x + 1.0) * w / 2.0 - 0.5;
    let j = (1.0 - (z[1] - scene.view2d.center[1]) / half_y) * h / 2.0 - 0.5;
    (i.round() as u32, j.round() as u32)
}

#[test]
fn gpu_agrees_with_the_cpu_twin() {
    for (name, sets) in [
        (
            "julia2d_rabbit",
            &[RABBIT, "image.width=128", "image.height=128"][..],
        ),
        (
            "julia2d_disk",
            &[
                "fractal.c=[0, 0, 0, 0]",
                "image.width=96",
                "image.height=64",
            ],
        ),
        (
            "julia2d_zoomed_rabbit_boundary",
            &[
                RABBIT,
                "image.width=160",
                "image.height=96",
                "view2d.center=[-0.3, 0.45]",
                "view2d.extent=0.4",
                "view2d.max_iterations=1000",
            ],
        ),
        (
            "julia2d_basilica_few_iterations",
            &[
                "fractal.c=[-1, 0, 0, 0]",
                "image.width=100",
                "image.height=100",
                "view2d.max_iterations=12",
            ],
        ),
    ] {
        let scene = common::scene(sets);
        let Some(actual) = gpu(name, &scene) else {
            return;
        };
        let expected = cpu::<f32>(&scene);
        assert!(
            expected.hit_mask().iter().any(|&h| h) && expected.hit_mask().iter().any(|&h| !h),
            "{name}: the test picture is all in or all out"
        );
        common::assert_agree(name, &expected, &actual, &JULIA2D_TOLERANCE);
        let same = expected
            .steps
            .iter()
            .zip(&actual.steps)
            .filter(|(a, b)| a == b)
            .count();
        assert!(
            same as f64 >= 0.99 * expected.pixel_count() as f64,
            "{name}: iterations agree on only {same} of {} pixels",
            expected.pixel_count()
        );
    }
}

#[test]
fn c_zero_is_the_unit_disk() {
    let scene = common::scene(&[
        "fractal.c=[0, 0, 0, 0]",
        "image.width=81",
        "image.height=81",
        "view2d.extent=40",
    ]);
    let mut frames = vec![
        ("cpu f32", cpu::<f32>(&scene)),
        ("cpu f64", cpu::<f64>(&scene)),
    ];
    if let Some(f) = gpu("julia2d_unit_disk", &scene) {
        frames.push(("gpu", f));
    }
    let p = Julia2dParams::<f64>::new(&scene);
    for (name, frame) in &frames {
        let (mut inside, mut far) = (0, 0);
        for j in 0..81 {
            for i in 0..81 {
                let z = p.pixel_point(i, j);
                let r = z.dot(z).sqrt();
                let g = grey(frame, i, j);
                if r < 0.98 {
                    assert_eq!(g, 255, "{name}: ({i}, {j}) at |z| = {r} is not white");
                    inside += 1;
                } else if r > 1.02 && r <= 16.0 {
                    assert!(g < 255, "{name}: ({i}, {j}) at |z| = {r} is white");
                } else if r > 16.0 {
                    assert_eq!(g, 0, "{name}: ({i}, {j}) at |z| = {r} is not black");
                    far += 1;
                }
            }
        }
        assert!(
            inside > 8 && far > 1000,
            "{name}: {inside} inside, {far} far"
        );
    }
    // Brighter the longer a point takes: along the real axis from the disk outwards.
    let f = &frames[0].1;
    let row: Vec<u8> = (41..81).map(|i| grey(f, i, 40)).collect();
    assert!(row.windows(2).all(|w| w[0] >= w[1]), "{row:?}");
}

#[test]
fn the_picture_is_symmetric_under_z_to_minus_z() {
    // f(-z) = f(z): the set and every escape time are symmetric about 0.
    let scene = common::scene(&[RABBIT, "image.width=120", "image.height=90"]);
    let mut frames = vec![("cpu", cpu::<f32>(&scene))];
    if let Some(f) = gpu("julia2d_symmetry", &scene) {
        frames.push(("gpu", f));
    }
    for (name, frame) in &frames {
        let mut rotated = frame.clone();
        let n = frame.pixel_count();
        for k in 0..n {
            rotated.colour[k] = frame.colour[n - 1 - k];
            rotated.depth[k] = frame.depth[n - 1 - k];
        }
        let agreement = Agreement::measure(frame, &rotated, &JULIA2D_TOLERANCE);
        assert!(
            agreement.within(&JULIA2D_TOLERANCE),
            "{name}: not symmetric under z -> -z: {agreement}"
        );
    }
}

#[test]
fn the_imaginary_axis_points_up() {
    // For the rabbit, c lies on the attracting 3-cycle of 0, deep in the set; its mirror image
    // conj(c) escapes. The picture is not symmetric about the real axis, so which one is white
    // says which way up it is.
    let scene = common::scene(&[
        RABBIT,
        "image.width=129",
        "image.height=129",
        "view2d.extent=3",
    ]);
    let c = [-0.12, 0.75];
    let exact = Julia2dParams::<f64>::new(&scene);
    let e = exact.escape(qjulia::algebra::Vec2::new(c[0], c[1]));
    assert!(!e.escaped, "c is not in its own rabbit");
    let e = exact.escape(qjulia::algebra::Vec2::new(c[0], -c[1]));
    assert!(
        e.escaped && e.n < 20,
        "conj(c) does not escape quickly: {e:?}"
    );
    let up = pixel_of(&scene, c);
    let down = pixel_of(&scene, [c[0], -c[1]]);
    assert!(up.1 < 64 && down.1 > 64, "{up:?} {down:?}");
    let mut frames = vec![("cpu", cpu::<f32>(&scene))];
    if let Some(f) = gpu("julia2d_orientation", &scene) {
        frames.push(("gpu", f));
    }
    for (name, frame) in &frames {
        assert_eq!(grey(frame, up.0, up.1), 255, "{name}: c is not white");
        assert!(
            grey(frame, down.0, down.1) < 200,
            "{name}: conj(c) is white"
        );
    }
}
