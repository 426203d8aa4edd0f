//! The path tracer's material, Lambert plus GGX with visible-normal sampling and Kulla and
//! Conty's multiple-scattering lobe: the twin of shaders/bsdf.wgsl (same names, same order;
//! tests/architecture/twins.rs), generic over f32 and f64 where the shader is f32 throughout. The book's chapter "Materials" gives every formula.
//!
//! Directions are in the local shading frame: the normal is +z, `wo` points toward where the
//! light goes (the eye), `wi` toward where it comes from; both unit length.

use super::ggx_albedo::{ggx_albedo, ggx_average_albedo};
use crate::algebra::{Real, Vec2, Vec3};

/// The shader's `PI` (shaders/light.wgsl uses it too).
pub(crate) fn pi<F: Real>() -> F {
    F::lit(std::f64::consts::PI)
}

/// alpha = roughness^2 breaks the visible-normal sampling at 0 (the distribution becomes a
/// delta): roughness is held at least this, so alpha >= 4e-4, a mirror for every picture.
pub const ROUGHNESS_MIN: f64 = 0.02;

/// The surface's material, as the scene gives it (keep in sync with `Material` in
/// shaders/bsdf.wgsl).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Material<F> {
    /// The base colour: shading.diffuse or the orbit-trap palette's colour, linear.
    pub albedo: Vec3<F>,
    pub roughness: F,
    pub metallic: F,
    /// The dielectric reflectance at normal incidence is 0.08 * specular.
    pub specular: F,
    /// Kulla and Conty's multiple-scattering lobe on (`material.multiscatter`):
    /// [`multiscatter_eval`].
    pub multiscatter: bool,
}

/// An orthonormal frame with `n` as its z axis (Duff et al. 2017, "Building an Orthonormal
/// Basis, Revisited").
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Basis<F> {
    pub t: Vec3<F>,
    pub b: Vec3<F>,
    pub n: Vec3<F>,
}

pub fn basis_from_normal<F: Real>(n: Vec3<F>) -> Basis<F> {
    let s = if n.z >= F::zero() {
        F::one()
    } else {
        -F::one()
    };
    let a = -F::one() / (s + n.z);
    let b = n.x * n.y * a;
    Basis {
        t: Vec3::new(F::one() + s * n.x * n.x * a, s * b, -s * n.x),
        b: Vec3::new(b, s + n.y * n.y * a, -n.y),
        n,
    }
}

pub fn to_local<F: Real>(f: Basis<F>, v: Vec3<F>) -> Vec3<F> {
    Vec3::new(v.dot(f.t), v.dot(f.b), v.dot(f.n))
}

pub fn to_world<F: Real>(f: Basis<F>, v: Vec3<F>) -> Vec3<F> {
    f.t * v.x + f.b * v.y + f.n * v.z
}

/// Rec. 709 luminance of a linear colour.
pub fn luminance<F: Real>(c: Vec3<F>) -> F {
    c.dot(Vec3::new(F::lit(0.2126), F::lit(0.7152), F::lit(0.0722)))
}

/// GGX's alpha: roughness squared, roughness held at [`ROUGHNESS_MIN`] at least.
pub fn ggx_alpha<F: Real>(roughness: F) -> F {
    let r = roughness.max(F::lit(ROUGHNESS_MIN));
    r * r
}

/// The reflectance at normal incidence: 0.08 * specular for a dielectric, the albedo for a
/// metal, linear between (WGSL's `mix`).
pub fn material_f0<F: Real>(m: Material<F>) -> Vec3<F> {
    let dielectric = Vec3::splat(F::lit(0.08) * m.specular);
    dielectric * (F::one() - m.metallic) + m.albedo * m.metallic
}

/// Whether the material has a specular lobe at all. With F0 = 0, Schlick's grazing term would
/// still reflect: metallic = 0 with specular = 0 is pure Lambert.
pub fn has_specular_lobe<F: Real>(m: Material<F>) -> bool {
    m.metallic > F::zero() || m.specular > F::zero()
}

/// Schlick's Fresnel: F0 + (1 - F0) (1 - cos)^5.
pub fn fresnel_schlick<F: Real>(f0: Vec3<F>, cos_theta: F) -> Vec3<F> {
    let c = (F::one() - cos_theta).max(F::zero()).min(F::one());
    let c2 = c * c;
    f0 + (Vec3::splat(F::one()) - f0) * (c2 * c2 * c)
}

/// The GGX distribution of normals D(h), `h` in the local frame (h.z > 0).
pub fn ggx_d<F: Real>(h: Vec3<F>, alpha: F) -> F {
    let a2 = alpha * alpha;
    let k = h.x * h.x + h.y * h.y + a2 * h.z * h.z;
    a2 / (pi::<F>() * k * k)
}

/// Smith's Lambda for GGX: (-1 + sqrt(1 + alpha^2 tan^2 theta)) / 2, written without the
/// tangent.
pub fn smith_lambda<F: Real>(w: Vec3<F>, alpha: F) -> F {
    let c2 = w.z * w.z;
    let s2 = (w.x * w.x + w.y * w.y).max(F::zero());
    F::lit(0.5) * ((F::one() + alpha * alpha * s2 / c2).sqrt() - F::one())
}

/// The masking of one direction, G1 = 1 / (1 + Lambda).
pub fn smith_g1<F: Real>(w: Vec3<F>, alpha: F) -> F {
    F::one() / (F::one() + smith_lambda(w, alpha))
}

/// Height-correlated masking-shadowing, G2 = 1 / (1 + Lambda(wo) + Lambda(wi)).
pub fn smith_g2<F: Real>(wo: Vec3<F>, wi: Vec3<F>, alpha: F) -> F {
    F::one() / (F::one() + smith_lambda(wo, alpha) + smith_lambda(wi, alpha))
}

/// A visible normal of the GGX lobe seen from `wo` (wo.z > 0), from `u` in [0, 1)^2 (Heitz
/// 2018, "Sampling the GGX Distribution of Visible Normals"): stretch wo to the hemisphere
/// configuration, sample the projected disc with its far half squeezed, lift to the hemisphere,
/// unstretch.
pub fn sample_ggx_vndf<F: Real>(wo: Vec3<F>, alpha: F, u: Vec2<F>) -> Vec3<F> {
    let vh = Vec3::new(alpha * wo.x, alpha * wo.y, wo.z).normalize();
    let len2 = vh.x * vh.x + vh.y * vh.y;
    let mut t1 = Vec3::new(F::one(), F::zero(), F::zero());
    if len2 > F::zero() {
        t1 = Vec3::new(-vh.y, vh.x, F::zero()) / len2.sqrt();
    }
    let t2 = vh.cross(t1);
    let r = u.x.sqrt();
    let phi = F::lit(2.0) * pi::<F>() * u.y;
    let p1 = r * phi.cos();
    let s = F::lit(0.5) * (F::one() + vh.z);
    let p2 = (F::one() - s) * (F::one() - p1 * p1).max(F::zero()).sqrt() + s * (r * phi.sin());
    let nh = t1 * p1 + t2 * p2 + vh * (F::one() - p1 * p1 - p2 * p2).max(F::zero()).sqrt();
    Vec3::new(alpha * nh.x, alpha * nh.y, nh.z.max(F::zero())).normalize()
}

/// The density of [`sample_ggx_vndf`]'s reflected direction wi = reflect(-wo, h), per solid
/// angle: D_wo(h) / (4 wo.h) with D_wo(h) = G1(wo) max(0, wo.h) D(h) / wo.z; 0 for a normal
/// below the surface (h.z <= 0), which the distribution has none of.
pub fn ggx_reflection_pdf<F: Real>(wo: Vec3<F>, h: Vec3<F>, alpha: F) -> F {
    let wo_h = wo.dot(h);
    if wo_h <= F::zero() || wo.z <= F::zero() || h.z <= F::zero() {
        return F::zero();
    }
    smith_g1(wo, alpha) * ggx_d(h, alpha) / (F::lit(4.0) * wo.z)
}

/// A cosine-distributed direction about +z from `u` in [0, 1)^2 (polar: r = sqrt(u.x)).
pub fn sample_cosine_hemisphere<F: Real>(u: Vec2<F>) -> Vec3<F> {
    let r = u.x.sqrt();
    let phi = F::lit(2.0) * pi::<F>() * u.y;
    Vec3::new(
        r * phi.cos(),
        r * phi.sin(),
        (F::one() - u.x).max(F::zero()).sqrt(),
    )
}

/// The Fresnel of light that scatters between microfacets before it leaves (Kulla and Conty
/// 2017): the cosine-weighted average of Schlick's, F_avg = F0 + (1 - F0) / 21, through every
/// further bounce, F_avg^2 E_avg / (1 - F_avg (1 - E_avg)); 1 for F0 = 1.
pub fn multiscatter_fresnel<F: Real>(m: Material<F>, e_avg: F) -> Vec3<F> {
    let one = Vec3::splat(F::one());
    let f0 = material_f0(m);
    let f_avg = f0 + (one - f0) / F::lit(21.0);
    let through = one - f_avg * (F::one() - e_avg);
    let top = f_avg.mul_elem(f_avg) * e_avg;
    Vec3::new(top.x / through.x, top.y / through.y, top.z / through.z)
}

/// The E_avg of the material's multiple-scattering lobe, looked up once for each use; 1 where
/// it has none (multiscatter off, or no specular lobe). The lobe is there where this is below
/// 1: where the GGX lobe is rough enough to lose light.
pub fn multiscatter_average<F: Real>(m: Material<F>) -> F {
    if !(m.multiscatter && has_specular_lobe(m)) {
        return F::one();
    }
    ggx_average_albedo(m.roughness)
}

/// The multiple-scattering lobe's share of the light toward `wo`: lum(F_ms) (1 - E(wo.z)), the
/// light single scattering loses there; 0 without the lobe. The cosine lobe draws it.
pub fn multiscatter_weight<F: Real>(m: Material<F>, wo: Vec3<F>) -> F {
    let e_avg = multiscatter_average(m);
    if e_avg >= F::one() {
        return F::zero();
    }
    let f_ms = multiscatter_fresnel(m, e_avg);
    luminance(f_ms) * (F::one() - ggx_albedo(wo.z, m.roughness))
}

/// Kulla and Conty's lobe, f_ms(wo, wi) = F_ms (1 - E(wo.z)) (1 - E(wi.z)) / (pi (1 - E_avg)),
/// without the cosine: the light single scattering loses, given back, spread as its loss is
/// (src/cpu/ggx_albedo.rs's tables). With F0 = 1 it makes the directional albedo 1 at every
/// roughness; it is symmetric in wo and wi. 0 without the lobe.
pub fn multiscatter_eval<F: Real>(m: Material<F>, wo: Vec3<F>, wi: Vec3<F>) -> Vec3<F> {
    let e_avg = multiscatter_average(m);
    if e_avg >= F::one() {
        return Vec3::zero();
    }
    let e_o = ggx_albedo(wo.z, m.roughness);
    let e_i = ggx_albedo(wi.z, m.roughness);
    let f_ms = multiscatter_fresnel(m, e_avg);
    f_ms * ((F::one() - e_o) * (F::one() - e_i) / (pi::<F>() * (F::one() - e_avg)))
}

/// The probability of drawing the specular lobe for `wo`: its Fresnel-weighted share,
/// s = lum(F(wo.z)) against the cosine lobe's d = (1 - metallic) lum(albedo) (1 - lum(F(wo.z)))
/// + [`multiscatter_weight`]; 0 without a specular lobe, 1 without a cosine one.
pub fn specular_probability<F: Real>(m: Material<F>, wo: Vec3<F>) -> F {
    if !has_specular_lobe(m) {
        return F::zero();
    }
    let f = luminance(fresnel_schlick(material_f0(m), wo.z));
    let d =
        (F::one() - m.metallic) * luminance(m.albedo) * (F::one() - f) + multiscatter_weight(m, wo);
    if d <= F::zero() {
        return F::one();
    }
    f / (f + d)
}

/// f(wo, wi), without the cosine: (1 - metallic) (1 - F(wo.z)) (1 - F(wi.z)) albedo / pi for
/// the diffuse lobe (the light the surface lets in and out again, so that the two lobes
/// together do not reflect more than arrives), F(wo.h) D(h) G2 / (4 wo.z wi.z) for the
/// specular one, h the half vector, and with multiscatter the multiple-scattering lobe
/// ([`multiscatter_eval`]). All are symmetric in wo and wi (wo.h = wi.h). Zero unless both lie
/// above the surface; without a specular lobe, (1 - metallic) albedo / pi.
pub fn bsdf_eval<F: Real>(m: Material<F>, wo: Vec3<F>, wi: Vec3<F>) -> Vec3<F> {
    if wo.z <= F::zero() || wi.z <= F::zero() {
        return Vec3::zero();
    }
    let diffuse = m.albedo * (F::one() - m.metallic) / pi::<F>();
    if !has_specular_lobe(m) {
        return diffuse;
    }
    let f0 = material_f0(m);
    let one = Vec3::splat(F::one());
    let transmitted = (one - fresnel_schlick(f0, wo.z)).mul_elem(one - fresnel_schlick(f0, wi.z));
    transmitted.mul_elem(diffuse) + ggx_reflection(m, wo, wi) + multiscatter_eval(m, wo, wi)
}

/// The GGX lobe's single scattering, F(wo.h) D(h) G2 / (4 wo.z wi.z), h the half vector (both
/// directions above the surface).
pub fn ggx_reflection<F: Real>(m: Material<F>, wo: Vec3<F>, wi: Vec3<F>) -> Vec3<F> {
    let h = (wo + wi).normalize();
    let alpha = ggx_alpha(m.roughness);
    let f = fresnel_schlick(material_f0(m), wo.dot(h));
    f * (ggx_d(h, alpha) * smith_g2(wo, wi, alpha) / (F::lit(4.0) * wo.z * wi.z))
}

/// The specular part of [`bsdf_eval`]: the GGX lobe and the multiple-scattering lobe, the
/// light the surface reflects without letting it in (the denoiser's specular signal,
/// [`crate::cpu::path::Light`]); 0 without a specular lobe or unless both directions lie above
/// the surface.
pub fn bsdf_specular<F: Real>(m: Material<F>, wo: Vec3<F>, wi: Vec3<F>) -> Vec3<F> {
    if wo.z <= F::zero() || wi.z <= F::zero() || !has_specular_lobe(m) {
        return Vec3::zero();
    }
    ggx_reflection(m, wo, wi) + multiscatter_eval(m, wo, wi)
}

/// The density, per solid angle, with which [`bsdf_sample`] draws `wi`: the mixture of the two
/// lobes' densities (the cosine lobe's draws the diffuse and the multiple-scattering light),
/// weighted by the probability of choosing each.
pub fn bsdf_pdf<F: Real>(m: Material<F>, wo: Vec3<F>, wi: Vec3<F>) -> F {
    if wo.z <= F::zero() || wi.z <= F::zero() {
        return F::zero();
    }
    let p_spec = specular_probability(m, wo);
    let mut pdf = (F::one() - p_spec) * wi.z / pi::<F>();
    if p_spec > F::zero() {
        let h = (wo + wi).normalize();
        pdf = pdf + p_spec * ggx_reflection_pdf(wo, h, ggx_alpha(m.roughness));
    }
    pdf
}

/// A direction drawn from the BSDF for `wo`, with f(wo, wi) and the density it was drawn with.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BsdfSample<F> {
    pub wi: Vec3<F>,
    pub f: Vec3<F>,
    /// 0: no direction (below the surface); the path ends.
    pub pdf: F,
}

/// Draws `wi`: the specular lobe when `u_lobe` < [`specular_probability`], else the diffuse
/// lobe; then f and the mixture density ([`bsdf_pdf`]) of wi, which is the density it was
/// drawn from.
pub fn bsdf_sample<F: Real>(m: Material<F>, wo: Vec3<F>, u_lobe: F, u: Vec2<F>) -> BsdfSample<F> {
    let none = BsdfSample {
        wi: Vec3::new(F::zero(), F::zero(), F::one()),
        f: Vec3::zero(),
        pdf: F::zero(),
    };
    if wo.z <= F::zero() {
        return none;
    }
    let wi = if u_lobe < specular_probability(m, wo) {
        let h = sample_ggx_vndf(wo, ggx_alpha(m.roughness), u);
        // WGSL's reflect(-wo, h) = -wo - 2 dot(h, -wo) h.
        h * (F::lit(2.0) * wo.dot(h)) - wo
    } else {
        sample_cosine_hemisphere(u)
    };
    if wi.z <= F::zero() {
        return none;
    }
    BsdfSample {
        wi,
        f: bsdf_eval(m, wo, wi),
        pdf: bsdf_pdf(m, wo, wi),
    }
}
