//! The types of the scene's choice keys (each an enum with `ALL`, its file name and, where the
//! shaders read it, its code): the algebra, the tracing, the colouring, the normal, the view,
//! the shading model and the path tracer's sampler.

use serde::Serialize;

/// The algebra of z and c (`fractal.algebra`): the quaternions and the next two Cayley-Dickson
/// algebras, whose numbers are pairs of numbers of the one before.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum Algebra {
    #[default]
    Quaternion,
    Octonion,
    Sedenion,
}

impl Algebra {
    pub const ALL: [Algebra; 3] = [Algebra::Quaternion, Algebra::Octonion, Algebra::Sedenion];

    pub fn name(self) -> &'static str {
        match self {
            Algebra::Quaternion => "quaternion",
            Algebra::Octonion => "octonion",
            Algebra::Sedenion => "sedenion",
        }
    }

    /// Real dimensions: 4, 8 or 16.
    pub fn dim(self) -> usize {
        4 * self.parts() as usize
    }

    /// Quaternion parts of a number (the shader's `algebra_parts`): 1, 2 or 4.
    pub fn parts(self) -> u32 {
        match self {
            Algebra::Quaternion => 1,
            Algebra::Octonion => 2,
            Algebra::Sedenion => 4,
        }
    }
}

/// How primary rays are traced (`fractal.tracing`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum Tracing {
    #[default]
    Seed,
    Cone,
}

impl Tracing {
    pub const ALL: [Tracing; 2] = [Tracing::Seed, Tracing::Cone];

    pub fn name(self) -> &'static str {
        match self {
            Tracing::Seed => "seed",
            Tracing::Cone => "cone",
        }
    }

    /// The number the shader's `tracing` uses.
    pub fn code(self) -> u32 {
        self as u32
    }
}

/// Where a hit's base colour comes from (`shading.colouring`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum Colouring {
    /// The diffuse colour, everywhere (the seed).
    #[default]
    Flat,
    /// The orbit of the hit point: its closest approach to the trap, through the palette.
    OrbitTrap,
}

impl Colouring {
    pub const ALL: [Colouring; 2] = [Colouring::Flat, Colouring::OrbitTrap];

    pub fn name(self) -> &'static str {
        match self {
            Colouring::Flat => "flat",
            Colouring::OrbitTrap => "orbit_trap",
        }
    }

    /// The number the shader's `colouring` uses.
    pub fn code(self) -> u32 {
        self as u32
    }
}

/// How the shading normal is computed (`shading.normal`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum NormalMethod {
    /// The seed's: central differences of |z_N|, six orbits.
    #[default]
    Central,
    /// Four orbits at the corners of a tetrahedron.
    Tetrahedral,
    /// The exact gradient of |z_N| by the chain rule, one orbit and three derivatives.
    Analytic,
}

impl NormalMethod {
    pub const ALL: [NormalMethod; 3] = [
        NormalMethod::Central,
        NormalMethod::Tetrahedral,
        NormalMethod::Analytic,
    ];

    pub fn name(self) -> &'static str {
        match self {
            NormalMethod::Central => "central",
            NormalMethod::Tetrahedral => "tetrahedral",
            NormalMethod::Analytic => "analytic",
        }
    }

    /// The number the shader's `normal_method` uses.
    pub fn code(self) -> u32 {
        self as u32
    }
}

/// What `render`'s PNG shows (`image.view`); see src/heatmap.rs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum View {
    /// The shaded picture (the contract's shading).
    #[default]
    Shaded,
    /// Sphere-tracing steps per primary ray as a heat map, with a legend.
    Steps,
    /// Wasted steps per pixel in 8x8 tiles (the tile's most steps minus the pixel's), as a
    /// heat map with a legend.
    Divergence,
    /// The samples each pixel took (adaptive sampling, `path.noise_target`) as a heat map, with
    /// a legend.
    Samples,
}

impl View {
    pub const ALL: [View; 4] = [View::Shaded, View::Steps, View::Divergence, View::Samples];

    pub fn name(self) -> &'static str {
        match self {
            View::Shaded => "shaded",
            View::Steps => "steps",
            View::Divergence => "divergence",
            View::Samples => "samples",
        }
    }

    /// Whether the view is made of the shaded picture: the shaded view, and the samples view
    /// (adaptive sampling stops a pixel by its shaded colour's noise). The steps views need
    /// depth and steps alone.
    pub fn needs_shading(self) -> bool {
        matches!(self, View::Shaded | View::Samples)
    }
}

/// How a hit is lit (`shading.model`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum ShadingModel {
    /// The seed's Phong with a point light, and every addition made to it.
    #[default]
    Phong,
    /// The path tracer: a physically based material under sky, sun and sphere light.
    Path,
}

impl ShadingModel {
    pub const ALL: [ShadingModel; 2] = [ShadingModel::Phong, ShadingModel::Path];

    pub fn name(self) -> &'static str {
        match self {
            ShadingModel::Phong => "phong",
            ShadingModel::Path => "path",
        }
    }
}

/// Where the path tracer's random numbers come from (`path.sampler`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum PathSampler {
    /// Owen-scrambled Sobol' (src/cpu/sobol.rs): the same bits on every backend.
    #[default]
    Sobol,
    /// A plain hash of (pixel, sample, dimension), for comparison.
    Random,
}

impl PathSampler {
    pub const ALL: [PathSampler; 2] = [PathSampler::Sobol, PathSampler::Random];

    pub fn name(self) -> &'static str {
        match self {
            PathSampler::Sobol => "sobol",
            PathSampler::Random => "random",
        }
    }

    /// The number the shader's `sampler` uses (`SAMPLER_SOBOL`, `SAMPLER_RANDOM`).
    pub fn code(self) -> u32 {
        match self {
            PathSampler::Sobol => crate::cpu::sobol::SAMPLER_SOBOL,
            PathSampler::Random => crate::cpu::sobol::SAMPLER_RANDOM,
        }
    }
}
