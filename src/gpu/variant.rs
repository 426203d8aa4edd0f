//! Per-scene specialisation: the shader a scene runs holds only what it uses. A [`Variant`]
//! names the features a scene needs; it becomes the override constants of shaders/trace.wgsl
//! (`SPECIALISED` and the rest), and the tracer builds and caches one pipeline per variant.

use crate::params::TraceParams;
use crate::scene::{Algebra, NormalMethod};

/// What one pipeline is built for. Keep in sync with the `override` constants of
/// shaders/trace.wgsl.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Variant {
    pub shadows: bool,
    pub normal: NormalMethod,
    /// The slice is x, y, z = 1, i, j: no slice transform.
    pub standard_slice: bool,
    /// step_scale > 1.
    pub over_relaxed: bool,
    /// pixel_epsilon > 0.
    pub pixel_epsilon: bool,
    /// Colour is wanted (false: only depth and steps, no normal, light or shadow).
    pub shade: bool,
    /// fractal.tracing = "cone".
    pub cone: bool,
    /// fractal.algebra.
    pub algebra: Algebra,
}

impl Variant {
    /// The variant a scene needs; `shade` is false when only depth and steps are wanted.
    pub fn of(p: &TraceParams<f32>, shade: bool) -> Self {
        let unit = |v: crate::algebra::Hyper<f32>, k: usize| {
            let a: Vec<f32> = v.iter().flat_map(|q| [q.x, q.y, q.z, q.w]).collect();
            (0..16).all(|i| a[i] == if i == k { 1.0 } else { 0.0 })
        };
        Self {
            shadows: p.shadows,
            normal: p.normal_method,
            standard_slice: unit(p.slice_x, 0) && unit(p.slice_y, 1) && unit(p.slice_z, 2),
            over_relaxed: p.step_scale > 1.0,
            pixel_epsilon: p.pixel_epsilon > 0.0,
            shade,
            cone: p.tracing == crate::scene::Tracing::Cone,
            algebra: match p.algebra_parts {
                1 => Algebra::Quaternion,
                2 => Algebra::Octonion,
                _ => Algebra::Sedenion,
            },
        }
    }

    /// The pipeline override constants for this variant.
    pub fn constants(&self) -> Vec<(&'static str, f64)> {
        let b = |v: bool| if v { 1.0 } else { 0.0 };
        vec![
            ("SPECIALISED", 1.0),
            ("SHADOWS", b(self.shadows)),
            ("NORMAL_METHOD", self.normal.code() as f64),
            ("STANDARD_SLICE", b(self.standard_slice)),
            ("OVER_RELAXED", b(self.over_relaxed)),
            ("PIXEL_EPSILON", b(self.pixel_epsilon)),
            ("SHADE", b(self.shade)),
            ("CONE_TRACING", b(self.cone)),
            ("ALGEBRA_PARTS", self.algebra.parts() as f64),
        ]
    }

    /// Every variant there is.
    pub fn all() -> Vec<Variant> {
        let mut out = Vec::new();
        for (normal, algebra) in NormalMethod::ALL
            .into_iter()
            .flat_map(|n| Algebra::ALL.map(|a| (n, a)))
        {
            for bits in 0..64u32 {
                let bit = |k: u32| bits & (1 << k) != 0;
                out.push(Variant {
                    shadows: bit(0),
                    normal,
                    standard_slice: bit(1),
                    over_relaxed: bit(2),
                    pixel_epsilon: bit(3),
                    shade: bit(4),
                    cone: bit(5),
                    algebra,
                });
            }
        }
        out
    }
}
