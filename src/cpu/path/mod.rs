//! The path tracer (`shading.model = "path"`): the twin of shaders/path.wgsl, same names, same
//! order (tests/architecture/twins.rs), generic over f32 and f64 (the shader's material, light and radiance
//! are f32 in both of its precisions). The book's chapter "Path tracing" gives the estimator.
//! This module is the root's twin (the camera ray, the path loop, `sample_valid`) with the row
//! driver the renderer calls (`render_path_rows`); `uniform` and `vertex` are the twins of
//! shaders/path_uniform.wgsl and shaders/path_vertex.wgsl, re-exported here.

mod uniform;
mod vertex;

pub use uniform::{PathParams, ROULETTE_START, Strategy};
pub use vertex::{Light, PathFog, SURFACE_OFFSET};

use crate::algebra::{Real, Vec3};
use crate::cpu::bsdf::{
    Basis, Material, basis_from_normal, bsdf_sample, specular_probability, to_local, to_world,
};
use crate::cpu::light::intersect_sphere;
use crate::cpu::medium::sample_hg;
use crate::cpu::sobol::{
    DIM_BOUNCE_BASE, DIM_BSDF, DIM_BSDF_CHOICE, DIM_LENS, DIM_PIXEL, DIMS_PER_BOUNCE,
};
use crate::cpu::trace::{
    Aovs, Halves, Primary, Streams, Trace, add_aovs, add_to_halves, finish_aovs, halves_mean,
    streams_halves,
};
use crate::params::TraceParams;
use vertex::{EXHAUSTED_RAYS, any_positive};

/// Path mode's counter word's layout, defined with the frame that reads it back.
pub use crate::frame::{COUNTER_DROPPED_BITS, COUNTER_DROPPED_MASK};

/// The least cosine between the shading normal and the direction back along the ray
/// ([`TraceParams::face_viewer`]).
pub const MIN_FACING: f64 = 1e-3;

/// One sample of a pixel: its linear radiance, its primary ray's depth and steps and whether it
/// hit, and there the material's albedo and the shading normal (0 on a miss); the direct light
/// its first hit reflected by the specular lobes (the denoiser's specular signal:
/// [`TraceParams::trace_path_from`]), and there the cosine of the view direction to the
/// shading normal (0 on a miss or a first vertex in the fog).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PathResult<F> {
    pub radiance: Vec3<F>,
    pub depth: F,
    pub steps: u32,
    pub hit: bool,
    pub albedo: Vec3<F>,
    pub normal: Vec3<F>,
    pub specular: Vec3<F>,
    pub cosine: F,
}

impl<F: Real> TraceParams<F> {
    /// The shading normal turned toward `v` (the direction back along the ray) where it faces
    /// away: at a sharp crease the estimated normal can, and the path would end black there.
    /// Bent within the plane of n and v until cos(n, v) >= [`MIN_FACING`] (unchanged
    /// everywhere else).
    pub fn face_viewer(&self, n: Vec3<F>, v: Vec3<F>) -> Vec3<F> {
        let c = n.dot(v);
        let min = F::lit(MIN_FACING);
        if c >= min {
            return n;
        }
        (n + v * (min - c)).normalize()
    }

    /// The camera ray of sample `sample` of pixel (i, j): sample 0 through the pixel's centre,
    /// the others at the sampler's image-plane dimensions, and where the aperture is open every
    /// sample (sample 0 too) through the lens at its lens dimensions; against the bounds (the
    /// whole stretch within the ball).
    pub fn path_camera_ray(&self, path: &PathParams<F>, i: u32, j: u32, sample: u32) -> Primary<F> {
        let half = F::lit(0.5);
        let mut s = (half, half);
        if sample > 0 {
            s = (
                self.path_random(path, i, j, sample, DIM_PIXEL),
                self.path_random(path, i, j, sample, DIM_PIXEL + 1),
            );
        }
        let x = F::lit(i as f64) + s.0;
        let y = F::lit(j as f64) + s.1;
        let mut dir = self.camera_ray_at(x, y);
        let mut origin = self.eye;
        // Through the thin lens (every sample where the aperture is open): the lens point from
        // the sampler's lens dimensions.
        if self.lens_open() {
            let uv = (
                self.path_random(path, i, j, sample, DIM_LENS).to_f64() as f32,
                self.path_random(path, i, j, sample, DIM_LENS + 1).to_f64() as f32,
            );
            let ray = self.thin_lens_ray(x, y, self.aperture_point(uv));
            origin = ray.origin;
            dir = ray.dir;
        }
        let bounds = self.intersect_bounds(origin, dir);
        Primary {
            origin,
            dir,
            t_start: bounds.t_enter,
            t_end: bounds.t_exit,
            hit: bounds.hit,
        }
    }

    /// One path through sample `sample` of pixel (i, j) from its camera ray `camera`
    /// (`path_camera_ray`) and that ray's trace `first` (`trace_primary`, or a pair's): WGSL's
    /// `trace_path`, which takes the camera ray and its trace (this file's `trace_path` takes
    /// the sample alone, as its callers want). At each of up to `bounces` hits add the direct light and scatter by the BSDF; a ray that leaves
    /// the region takes the sky and the sun, one that meets the sphere light first its
    /// emission. The last scattered ray is traced for that alone.
    pub fn trace_path_from(
        &self,
        path: &PathParams<F>,
        (i, j, sample): (u32, u32, u32),
        camera: &Primary<F>,
        first: Trace<F>,
    ) -> PathResult<F> {
        let mut dir = camera.dir;
        let mut origin = camera.origin;
        let mut throughput = Vec3::splat(F::one());
        let mut radiance = Vec3::zero();
        let mut result = PathResult {
            radiance: Vec3::zero(),
            depth: -F::one(),
            steps: 0,
            hit: false,
            albedo: Vec3::zero(),
            normal: Vec3::zero(),
            specular: Vec3::zero(),
            cosine: F::zero(),
        };
        let mut pdf_prev = F::zero();
        // The first hit's specular light (the denoiser's specular signal): the part of the
        // direct light there that its specular lobes reflect (`Light::specular`). The light
        // gathered after the first bounce stays with the diffuse signal (the kernel's comment
        // says why). A first vertex in the fog has none: its light is diffuse.
        let mut specular = Vec3::zero();
        // Whether the path has scattered by the cosine lobe (`regularized`), with
        // path.regularize on.
        let mut diffuse_before = false;
        let light_on = self.light_radius > F::zero() && any_positive(path.light_intensity);
        for bounce in 0..=path.bounces {
            // The camera ray's trace is given; a scattered ray's is made here (no pixel
            // epsilon).
            let mut trace = first;
            // A scattered ray that ran out of steps: it sees the sphere light only short of
            // where it stopped, and ends its path there, dark.
            let mut ran_out = false;
            if bounce > 0 {
                trace = Trace::untraced();
                let bounds = self.intersect_bounds(origin, dir);
                if bounds.hit {
                    let (t_enter, t_exit) = (bounds.t_enter, bounds.t_exit);
                    trace = self.sphere_trace_by(
                        origin,
                        dir,
                        t_enter,
                        t_exit,
                        F::zero(),
                        path.step_scale,
                    );
                    // Only scattered rays end so: a camera ray that runs out stays a miss, as
                    // in phong mode.
                    if self.exhausted(trace, t_exit) {
                        EXHAUSTED_RAYS.set(EXHAUSTED_RAYS.get() + 1);
                        ran_out = true;
                    }
                }
            } else if camera.hit && self.exhausted(trace, camera.t_end) {
                EXHAUSTED_RAYS.set(EXHAUSTED_RAYS.get() + 1);
            }
            // The light this ray meets left the path's last scattering event, bounce - 1
            // (none for the camera ray): clamp_indirect's vertex.
            let vertex = bounce.max(1) - 1;
            if bounce == 0 {
                result.depth = trace.t;
                result.steps = trace.steps;
                result.hit = trace.hit;
            }
            // Whether the ray meets the sphere light before the set (or before leaving), at
            // t_light.
            let mut t_light = -F::one();
            if light_on {
                let light = self.path_sphere_light(path);
                t_light = intersect_sphere(origin, dir, light.center, light.radius);
            }
            let left = !trace.hit && !ran_out;
            let meets_light = t_light > F::zero() && (left || t_light < trace.t);
            // In fog, the ray may scatter before its stretch ends (at the light, the set, where
            // it ran out, or where it leaves): a scattering event is the path's next vertex, lit
            // by next-event estimation and left by phase sampling, and counts as a bounce.
            let mut in_fog = false;
            let mut p = origin;
            if self.fog_on() {
                let mut t_stop = trace.t;
                if meets_light {
                    t_stop = t_light;
                } else if left {
                    t_stop = F::lit(3.0e38);
                }
                let fog = self.path_fog(path, (i, j, sample), bounce, (origin, dir), t_stop);
                throughput = throughput.mul_elem(fog.weight);
                if fog.scattered {
                    if bounce == path.bounces {
                        break;
                    }
                    in_fog = true;
                    p = fog.point;
                }
            }
            // A surface vertex's normal, frame, wo and material (unused in the fog).
            let mut n = Vec3::new(F::zero(), F::zero(), F::one());
            let mut f = Basis {
                t: Vec3::new(F::one(), F::zero(), F::zero()),
                b: Vec3::new(F::zero(), F::one(), F::zero()),
                n,
            };
            let mut wo = n;
            let mut m = Material {
                albedo: Vec3::zero(),
                roughness: F::one(),
                metallic: F::zero(),
                specular: F::zero(),
                multiscatter: false,
            };
            if !in_fog {
                if meets_light {
                    let e = self.light_emission(path, origin, dir, bounce, pdf_prev);
                    radiance += self.clamp_indirect(path, throughput.mul_elem(e), vertex);
                    break;
                }
                if ran_out {
                    break;
                }
                if !trace.hit {
                    let e = self.escaped(path, dir, bounce, pdf_prev);
                    radiance += self.clamp_indirect(path, throughput.mul_elem(e), vertex);
                    break;
                }
                p = origin + dir * trace.t;
                // material.emission: the set's own light, the hit's albedo times the emission
                // (found by the rays alone: no light sampling aims at it).
                if any_positive(path.emission) {
                    let e = path.emission.mul_elem(self.hit_albedo(p));
                    radiance += self.clamp_indirect(path, throughput.mul_elem(e), vertex);
                }
                if bounce == path.bounces {
                    break;
                }
                n = self.face_viewer(self.estimate_normal(p, dir), -dir);
                f = basis_from_normal(n);
                wo = to_local(f, -dir);
                m = self.path_material(path, p);
                if diffuse_before {
                    m = self.regularized(path, m);
                }
                if bounce == 0 {
                    result.albedo = m.albedo;
                    result.normal = n;
                    result.cosine = wo.z.max(F::zero());
                }
                if wo.z <= F::zero() {
                    break;
                }
            }
            if path.strategy != Strategy::Bsdf {
                let at = (i, j, sample);
                let light = self.direct_light(path, at, bounce, in_fog, p, (f, wo, m), dir);
                radiance += self.clamp_indirect(path, throughput.mul_elem(light.total), bounce);
                if bounce == 0 {
                    specular = throughput.mul_elem(light.specular);
                }
            }
            let dim = DIM_BOUNCE_BASE + bounce * DIMS_PER_BOUNCE;
            let u = crate::algebra::Vec2::new(
                self.path_random(path, i, j, sample, dim + DIM_BSDF),
                self.path_random(path, i, j, sample, dim + DIM_BSDF + 1),
            );
            if in_fog {
                let ps = sample_hg(self.fog_anisotropy, dir, u);
                // The phase sample's weight, phase / pdf, is 1.
                pdf_prev = ps.pdf;
                origin = p;
                dir = ps.wi.normalize();
            } else {
                let lobe = self.path_random(path, i, j, sample, dim + DIM_BSDF_CHOICE);
                let bs = bsdf_sample(m, wo, lobe, u);
                if bs.pdf <= F::zero() {
                    break;
                }
                if path.regularize > F::zero() && lobe >= specular_probability(m, wo) {
                    diffuse_before = true;
                }
                throughput = throughput.mul_elem(bs.f) * (bs.wi.z / bs.pdf);
                pdf_prev = bs.pdf;
                origin = p + n * (F::lit(SURFACE_OFFSET) * self.epsilon);
                dir = to_world(f, bs.wi).normalize();
            }
            let q = self.roulette(path, (i, j, sample), bounce, throughput);
            if q <= F::zero() {
                break;
            }
            throughput = throughput / q;
        }
        result.radiance = radiance;
        result.specular = specular;
        result
    }

    /// One path through sample `sample` of pixel (i, j), its camera ray traced alone
    /// (`trace_path_from` of `path_camera_ray` and `trace_primary`): WGSL's `trace_path` with
    /// its camera ray traced here.
    pub fn trace_path(&self, path: &PathParams<F>, i: u32, j: u32, sample: u32) -> PathResult<F> {
        let camera = self.path_camera_ray(path, i, j, sample);
        let first = self.trace_primary(&camera);
        self.trace_path_from(path, (i, j, sample), &camera, first)
    }
}

/// Whether a sample's radiance may enter the pixel's mean: every channel finite (neither NaN
/// nor infinite) and not negative.
pub fn sample_valid<F: Real>(c: Vec3<F>) -> bool {
    [c.x, c.y, c.z]
        .iter()
        .all(|v| v.is_finite() && *v >= F::zero())
}

/// Renders the rows `rows` (0 at the top) of the path-traced image, in parallel over rows, as
/// `path_main` does: each pixel's mean linear radiance over its `samples` paths (the running
/// mean the kernel keeps), sample 0's depth and steps, and with `aovs` the AOVs (`add_aovs`,
/// as the kernel's AOVS override adds them). A sample whose radiance is not valid
/// ([`sample_valid`]) is dropped, as `path_main` drops it. The colour holds the kernel's counter
/// word ([`COUNTER_DROPPED_BITS`]): the renderer takes it out and makes the colour from the
/// radiance by the display transform.
pub fn render_path_rows<F: Real>(
    params: &TraceParams<F>,
    path: &PathParams<F>,
    aovs: bool,
    rows: std::ops::Range<u32>,
) -> crate::frame::Frame {
    let keep = super::Keep {
        f64: super::is_f64::<F>(),
        radiance: true,
        aovs,
        samples: params.adaptive(),
    };
    super::fill_rows(params.width, rows, keep, |j| {
        move |i| {
            let before = (super::ESTIMATES.get(), super::ITERATIONS.get());
            EXHAUSTED_RAYS.set(0);
            // Where the lens is open, the depth and the steps are the pinhole ray's, traced for
            // them alone.
            let pinhole = params
                .lens_open()
                .then(|| params.trace_primary(&params.pinhole_ray(i, j, 0, F::zero())));
            let mut dropped = 0u32;
            // Without adaptive sampling, the pixel's halves (`add_to_halves`), in f32 as the
            // kernel keeps them.
            let mut halves = Halves::default();
            let mut first = None;
            let mut made = Aovs::default();
            // As `path_main` with INTERLEAVE 2: the camera rays of samples k and k + 1 traced as
            // a pair at k (`trace_primary_pair`), k + 1's trace kept for it; an odd one left
            // traced alone.
            let samples = params.samples.max(1);
            // Adaptive sampling's state, as `path_main` keeps it: the pixel's streams
            // (`add_to_streams`), and the samples taken.
            let (mut streams, mut taken) = (Streams::default(), samples);
            let mut second = None;
            for k in 0..samples {
                let camera = params.path_camera_ray(path, i, j, k);
                let traced = match second.take() {
                    Some(trace) => trace,
                    None if k + 1 < samples => {
                        let next = params.path_camera_ray(path, i, j, k + 1);
                        let [a, b] = params.trace_primary_pair(&camera, &next);
                        second = Some(b);
                        a
                    }
                    None => params.trace_primary(&camera),
                };
                let r = params.trace_path_from(path, (i, j, k), &camera, traced);
                first.get_or_insert(r);
                let valid = sample_valid(r.radiance);
                if !valid {
                    dropped += 1;
                }
                let add = |made: Aovs, n: u32| {
                    let (radiance, albedo) = (r.radiance.to_f32(), r.albedo.to_f32());
                    let (normal, depth) = (r.normal.to_f32(), r.depth.to_f64() as f32);
                    let first = (r.specular.to_f32(), r.cosine.to_f64() as f32);
                    add_aovs(made, n - 1, radiance, r.hit, albedo, normal, depth, first)
                };
                if params.adaptive() {
                    // The samples the pixel's colours hold, and whether this one joined them.
                    let before = streams.rule_a[3] + streams.b[3];
                    streams = params.add_to_streams(streams, k, valid, r.radiance.to_f32());
                    let n = streams.rule_a[3] + streams.b[3];
                    if aovs && n > before {
                        made = add(made, n as u32);
                    }
                    if params.sampling_done(&streams, k + 1) {
                        taken = k + 1;
                        break;
                    }
                } else if valid {
                    // The samples the halves hold, this one with them: the samples kept.
                    let n = k + 1 - dropped;
                    halves = add_to_halves(halves, k, r.radiance.to_f32());
                    if aovs {
                        made = add(made, n);
                    }
                }
            }
            if params.adaptive() {
                // Every pixel is done by its last sample (`sampling_done`).
                if aovs {
                    made = finish_aovs(made, &streams, taken);
                }
                halves = streams_halves(&streams);
            }
            let first = first.expect("at least one sample");
            let mean = halves_mean(&halves);
            let radiance = [mean.x, mean.y, mean.z];
            let (hit, depth, steps) = match pinhole {
                Some(t) => (t.hit, t.t, t.steps),
                None => (first.hit, first.depth, first.steps),
            };
            super::PixelOut {
                colour: dropped | (EXHAUSTED_RAYS.get() << COUNTER_DROPPED_BITS),
                depth: if hit { depth.to_f64() } else { f64::NAN },
                steps,
                non_finite: radiance.iter().filter(|c| !c.is_finite()).count() as u64,
                estimates: super::ESTIMATES.get() - before.0,
                iterations: super::ITERATIONS.get() - before.1,
                radiance,
                halves: [halves.a, halves.b].map(|m| crate::estimate::half_colour(&m)),
                aovs: made,
                samples: taken,
            }
        }
    })
}
