//! Named scenes that show the range of quaternion Julia sets, as TOML over the defaults: the
//! explorer's Presets menu, and `--preset SLUG` on the command line.

/// A named scene.
pub struct Preset {
    pub name: &'static str,
    /// The command line's name for it (`--preset SLUG`): lower case, words joined by '-'.
    pub slug: &'static str,
    pub about: &'static str,
    /// TOML layered over the defaults.
    pub toml: &'static str,
    /// Shown in the explorer's 2D mode (the 2D Julia set of c's first two components).
    pub two_d: bool,
}

pub const PRESETS: &[Preset] = &[
    Preset {
        name: "Seed's look",
        slug: "seed",
        about: "Crane's constants: c = (-0.2, 0.6, 0.2, 0.2), shadows on",
        toml: "",
        two_d: false,
    },
    Preset {
        name: "Unit ball",
        slug: "unit-ball",
        about: "c = 0: the set is exactly the unit ball",
        toml: "[fractal]\nc = [0.0, 0.0, 0.0, 0.0]\n",
        two_d: false,
    },
    Preset {
        name: "Basilica revolved",
        slug: "basilica",
        about: "c = -1, real: the 2D basilica turned about the real axis",
        toml: "[fractal]\nc = [-1.0, 0.0, 0.0, 0.0]\nmax_iterations = 16\n\
               [camera]\neye = [0.4, 2.2, 2.2]\n[light]\nposition = [1.0, 3.0, 2.0]\n",
        two_d: false,
    },
    Preset {
        name: "Rabbit",
        slug: "rabbit",
        about: "the seed's 'rabbit ears' c = -0.12 + 0.75i, in 3D",
        toml: "[fractal]\nc = [-0.12, 0.75, 0.0, 0.0]\nmax_iterations = 14\n\
               [camera]\neye = [0.0, 0.8, 2.8]\n",
        two_d: false,
    },
    Preset {
        name: "Dendrite",
        slug: "dendrite",
        about: "c = i: no interior, a tree of thin branches",
        toml: "[fractal]\nc = [0.0, 1.0, 0.0, 0.0]\nmax_iterations = 20\nepsilon = 0.002\n\
               [camera]\neye = [1.2, 0.6, 2.6]\n",
        two_d: false,
    },
    Preset {
        name: "Siegel disk",
        slug: "siegel-disk",
        about: "c = -0.390541 - 0.586788i, with a Siegel disk around a fixed point",
        toml: "[fractal]\nc = [-0.390541, -0.586788, 0.0, 0.0]\nmax_iterations = 30\n\
               [camera]\neye = [0.0, -1.0, 2.8]\n",
        two_d: false,
    },
    Preset {
        name: "Tentacles",
        slug: "tentacles",
        about: "c = (-0.125, -0.256, 0.847, 0.0895), all four components at work",
        toml: "[fractal]\nc = [-0.125, -0.256, 0.847, 0.0895]\nmax_iterations = 12\n\
               [camera]\neye = [1.5, 1.5, 2.0]\n",
        two_d: false,
    },
    Preset {
        name: "Turned slice",
        slug: "turned-slice",
        about: "the seed's set seen through a slice turned in 4D and moved off the origin",
        toml: "[slice]\nx = [0.838386643594204, 0.0, 0.093833584680988, 0.536938631715731]\n\
               y = [0.0, 1.0, 0.0, 0.0]\nz = [-0.259343380052231, 0.0, 0.935095941414137, 0.241529690874419]\n\
               offset = [0.0, 0.0, 0.0, 0.1]\n",
        two_d: false,
    },
    Preset {
        name: "Rabbit ears (2D)",
        slug: "rabbit-2d",
        about: "the seed's Figure 3: the filled Julia set of c = -0.12 + 0.75i in the plane",
        toml: "[fractal]\nc = [-0.12, 0.75, 0.0, 0.0]\n\
               [view2d]\ncenter = [0.0, 0.0]\nextent = 3.2\nmax_iterations = 256\n",
        two_d: true,
    },
    Preset {
        name: "Deep zoom",
        slug: "deep-zoom",
        about: "the seed's set 3e-8 across a pixel: ridges in f64, a flat patch in f32",
        toml: "[fractal]\nmax_iterations = 30\nepsilon = 1e-12\npixel_epsilon = 1.0\n\
               [camera]\nfov_y_degrees = 1.5e-4\n[shading]\nnormal = \"analytic\"\n",
        two_d: false,
    },
    Preset {
        name: "Deep zoom (2D)",
        slug: "deep-zoom-2d",
        about: "the rabbit's alpha fixed point, where three parts meet, 1e-9 across: lace in f64, white in f32",
        toml: "[fractal]\nc = [-0.12, 0.75, 0.0, 0.0]\n\
               [view2d]\ncenter = [-0.2766277683299133, 0.48285680127870356]\nextent = 1e-9\n\
               max_iterations = 2000\n",
        two_d: true,
    },
    Preset {
        name: "Gallery",
        slug: "gallery",
        about: "the seed's set at its best: cut open, 16 samples, soft shadows, occlusion, orbit-trap colour",
        toml: "[image]\nsamples = 16\n\
               [camera]\neye = [2.0, 2.2, 1.8]\n\
               [light]\nposition = [3.0, 2.0, 1.0]\nradius = 0.2\n\
               [shading]\nambient = 0.15\nocclusion = 0.8\ncolouring = \"orbit_trap\"\n\
               normal_tint = 0.0\nspecular = 0.3\n\
               [cut]\nenabled = true\nnormal = [0.2, 1.0, 0.5]\noffset = 0.2\n",
        two_d: false,
    },
    Preset {
        name: "Fog shafts",
        slug: "fog-shafts",
        about: "the basilica in fog under a low sun, path traced: its shadows fall through the fog as light shafts",
        toml: "[fractal]\nc = [-1.0, 0.0, 0.0, 0.0]\nmax_iterations = 16\nbounding_radius_squared = 7.0\n\
               [camera]\neye = [0.6, -1.3, 2.7]\n\
               [shading]\nmodel = \"path\"\ncolouring = \"orbit_trap\"\n\
               [sun]\ndirection = [0.5, 1.0, -0.6]\nintensity = 8.0\nangular_radius_degrees = 0.5\n\
               [sky]\nintensity = 0.01\n\
               [fog]\ndensity = 0.15\nanisotropy = 0.4\ncolour = [0.95, 0.9, 0.85]\n\
               [path]\nbounces = 2\n\
               [image]\nsamples = 256\nexposure = -1.0\ntone_map = \"aces\"\ndenoise = \"atrous\"\n",
        two_d: false,
    },
    Preset {
        name: "Glow",
        slug: "glow",
        about: "the tentacles' set in phong mode with an orange halo where rays pass close to it",
        toml: "[fractal]\nc = [-0.125, -0.256, 0.847, 0.0895]\nmax_iterations = 12\n\
               [camera]\neye = [1.5, 1.5, 2.0]\n\
               [shading]\ncolouring = \"orbit_trap\"\nbackground = [0.01, 0.01, 0.02]\n\
               [glow]\nstrength = 1.2\nradius = 0.08\ncolour = [1.0, 0.55, 0.2]\n\
               [image]\nsamples = 4\n",
        two_d: false,
    },
    Preset {
        name: "Environment",
        slug: "environment",
        about: "the seed's set as gold under the built-in dusk sky (qjulia:dusk.hdr), path traced: the map lights it and is seen behind it",
        toml: "[shading]\nmodel = \"path\"\ndiffuse = [0.95, 0.72, 0.45]\n\
               [material]\nmetallic = 1.0\nroughness = 0.22\n\
               [environment]\nfile = \"qjulia:dusk.hdr\"\nrotation_degrees = -12.0\n\
               [camera]\neye = [0.3, 0.25, 3.0]\n\
               [image]\nsamples = 128\ntone_map = \"aces\"\ndenoise = \"atrous\"\n",
        two_d: false,
    },
    Preset {
        name: "Path traced",
        slug: "path-traced",
        about: "the seed's set path traced under sky and sun: a glossy material, 3 bounces, a little depth of field",
        toml: "[shading]\nmodel = \"path\"\ndiffuse = [0.9, 0.3, 0.12]\n\
               [material]\nroughness = 0.25\nspecular = 0.6\n\
               [sun]\ndirection = [-1.0, 2.0, 1.0]\nintensity = 3.0\nangular_radius_degrees = 1.5\n\
               [camera]\neye = [1.8, -0.6, 2.2]\naperture = 0.02\n\
               [image]\nsamples = 64\nexposure = -0.5\ntone_map = \"aces\"\n",
        two_d: false,
    },
    Preset {
        name: "Path gallery",
        slug: "path-gallery",
        about: "the gallery's cut and orbit-trap colour, path traced in the soft light of a sphere and the sky",
        toml: "[shading]\nmodel = \"path\"\ncolouring = \"orbit_trap\"\n\
               [image]\nsamples = 64\ntone_map = \"aces\"\n\
               [camera]\neye = [2.0, 2.2, 1.8]\n\
               [light]\nposition = [3.0, 2.0, 1.0]\nradius = 0.6\nintensity = 8.0\n\
               [sky]\nintensity = 0.6\n\
               [material]\nroughness = 0.45\n\
               [cut]\nenabled = true\nnormal = [0.2, 1.0, 0.5]\noffset = 0.2\n",
        two_d: false,
    },
];

/// The preset of this slug.
pub fn find(slug: &str) -> Option<&'static Preset> {
    PRESETS.iter().find(|p| p.slug == slug)
}

/// Every slug, comma-separated, for messages.
pub fn slugs() -> String {
    PRESETS
        .iter()
        .map(|p| p.slug)
        .collect::<Vec<_>>()
        .join(", ")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Scene;

    #[test]
    fn every_preset_is_a_valid_scene_and_they_differ() {
        let scenes: Vec<Scene> = PRESETS.iter().map(Preset::scene).collect();
        for (i, a) in scenes.iter().enumerate() {
            for b in &scenes[i + 1..] {
                assert_ne!(a, b);
            }
        }
        assert!(PRESETS.len() >= 6);
    }

    #[test]
    fn slugs_are_distinct_lower_case_words() {
        for (i, p) in PRESETS.iter().enumerate() {
            assert!(
                !p.slug.is_empty()
                    && !p.slug.starts_with('-')
                    && !p.slug.ends_with('-')
                    && p.slug
                        .chars()
                        .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '-'),
                "{:?}",
                p.slug
            );
            assert!(!p.about.contains('\n'), "{}: one line", p.slug);
            assert!(PRESETS[i + 1..].iter().all(|q| q.slug != p.slug));
            assert_eq!(find(p.slug).unwrap().name, p.name);
        }
        assert!(find("Seed").is_none() && find("").is_none());
    }
}
