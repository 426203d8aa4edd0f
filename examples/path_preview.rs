//! A path-traced preview of the default set through the GPU path kernel, before path mode has
//! its scene keys: `cargo run --release --example path_preview [OUT.png]` (256x256, 64 samples,
//! 3 bounces, a sky and a sun, a glossy dielectric, ACES); prints the wall and GPU seconds.
use qjulia::algebra::Vec3;
use qjulia::cpu::light::{Sky, Sun};
use qjulia::cpu::path::{PathParams, Strategy};
use qjulia::display::{Display, ToneMap};
use qjulia::gpu::{GpuContext, path::GpuPathTracer};
use qjulia::params::TraceParams;
use qjulia::scene::SceneLoader;

fn main() {
    let mut l = SceneLoader::new();
    for s in ["image.width=256", "image.height=256", "image.samples=64"] {
        l.set(s).unwrap();
    }
    let scene = l.build().unwrap();
    let params = TraceParams::<f32>::new(&scene);
    let sun_dir = Vec3::new(2.0f32, 2.0, 3.0).normalize();
    let path = PathParams {
        sky: Sky {
            zenith: Vec3::new(0.35, 0.5, 0.8),
            horizon: Vec3::new(0.8, 0.85, 0.9),
            ground: Vec3::new(0.25, 0.22, 0.2),
            up: Vec3::new(0.0, 1.0, 0.0),
            intensity: 1.0,
        },
        sun: Sun {
            direction: sun_dir,
            one_minus_cos: qjulia::cpu::light::sun_one_minus_cos(2.0) as f32,
            irradiance: Vec3::splat(3.0),
        },
        light_intensity: Vec3::zero(),
        bounces: 3,
        roulette_start: 3,
        clamp_contribution: 0.0,
        sampler: qjulia::cpu::sobol::SAMPLER_SOBOL,
        strategy: Strategy::Both,
        roughness: 0.3,
        metallic: 0.0,
        specular: 0.5,
        multiscatter: true,
        regularize: 0.0,
        seed: 0,
        step_scale: 1.6,
        emission: Vec3::zero(),
    };
    let t = GpuPathTracer::new(GpuContext::new().unwrap()).unwrap();
    let start = std::time::Instant::now();
    let (img, times) = t.render(&params, &path).unwrap();
    eprintln!(
        "wall {:.2} s, gpu {:?} s",
        start.elapsed().as_secs_f64(),
        times.gpu_seconds
    );
    let d = Display {
        exposure: 0.0,
        tone_map: ToneMap::Aces,
    };
    let rgb = d.rgb8(&img.radiance);
    let out = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "path_preview.png".into());
    image::save_buffer(&out, &rgb, 256, 256, image::ColorType::Rgb8).unwrap();
}
