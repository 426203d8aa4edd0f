// The path tracer's material: Lambert diffuse plus a GGX (Trowbridge-Reitz) specular lobe with
// height-correlated Smith masking and Schlick's Fresnel, with Kulla and Conty's (2017)
// multiple-scattering lobe for the light single scattering loses, and its sampling (the GGX lobe
// by its visible normals, Heitz 2018; the diffuse and multiple-scattering lobes by the cosine
// hemisphere). Needs shaders/ggx_albedo.wgsl.
// Twin: src/cpu/bsdf.rs, same names, same order (tests/architecture/twins.rs). The book's chapter
// "Materials" (docs/book/materials.md) gives every formula.
//
// Everything here is f32, in both the f32 and the f64 kernels: a path's geometry may need f64
// (a deep zoom), its radiance never does, and lavapipe's f64 trigonometry is wrong. The CPU
// twin is generic (f32 and f64).
//
// Directions are in the local shading frame: the normal is +z, wo points away from the surface
// toward where the light goes (the eye), wi toward where it comes from; both unit length.
#import ggx_albedo

const PI: f32 = 3.14159265358979;
// alpha = roughness^2 breaks the visible-normal sampling at 0 (the distribution becomes a
// delta): roughness is held at least this, so alpha >= 4e-4, a mirror for every picture.
const ROUGHNESS_MIN: f32 = 0.02;

// The surface's material, as the scene gives it (keep in sync with `Material` in
// src/cpu/bsdf.rs).
struct Material {
    // The base colour: shading.diffuse or the orbit-trap palette's colour, linear.
    albedo: vec3<f32>,
    roughness: f32,
    metallic: f32,
    // The dielectric reflectance at normal incidence is 0.08 * specular.
    specular: f32,
    // Kulla and Conty's multiple-scattering lobe on (material.multiscatter): multiscatter_eval.
    multiscatter: bool,
}

// An orthonormal frame with n as its z axis (Duff et al. 2017, "Building an Orthonormal Basis,
// Revisited"): no branch, no singularity but at n.z = -0 exactly, where the sign picks -1.
struct Basis {
    t: vec3<f32>,
    b: vec3<f32>,
    n: vec3<f32>,
}

fn basis_from_normal(n: vec3<f32>) -> Basis {
    let s = select(-1.0, 1.0, n.z >= 0.0);
    let a = -1.0 / (s + n.z);
    let b = n.x * n.y * a;
    return Basis(
        vec3<f32>(1.0 + s * n.x * n.x * a, s * b, -s * n.x),
        vec3<f32>(b, s + n.y * n.y * a, -n.y),
        n,
    );
}

fn to_local(f: Basis, v: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(dot(v, f.t), dot(v, f.b), dot(v, f.n));
}

fn to_world(f: Basis, v: vec3<f32>) -> vec3<f32> {
    return f.t * v.x + f.b * v.y + f.n * v.z;
}

// Rec. 709 luminance of a linear colour.
fn luminance(c: vec3<f32>) -> f32 {
    return dot(c, vec3<f32>(0.2126, 0.7152, 0.0722));
}

// GGX's alpha: roughness squared, roughness held at ROUGHNESS_MIN at least.
fn ggx_alpha(roughness: f32) -> f32 {
    let r = max(roughness, ROUGHNESS_MIN);
    return r * r;
}

// The reflectance at normal incidence: 0.08 * specular for a dielectric, the albedo for a
// metal, linear between.
fn material_f0(m: Material) -> vec3<f32> {
    return mix(vec3<f32>(0.08 * m.specular), m.albedo, m.metallic);
}

// Whether the material has a specular lobe at all. With F0 = 0, Schlick's grazing term would
// still reflect: metallic = 0 with specular = 0 is pure Lambert.
fn has_specular_lobe(m: Material) -> bool {
    return m.metallic > 0.0 || m.specular > 0.0;
}

// Schlick's Fresnel: F0 + (1 - F0) (1 - cos)^5.
fn fresnel_schlick(f0: vec3<f32>, cos_theta: f32) -> vec3<f32> {
    let c = clamp(1.0 - cos_theta, 0.0, 1.0);
    let c2 = c * c;
    return f0 + (vec3<f32>(1.0) - f0) * (c2 * c2 * c);
}

// The GGX distribution of normals D(h), h in the local frame (h.z > 0).
fn ggx_d(h: vec3<f32>, alpha: f32) -> f32 {
    let a2 = alpha * alpha;
    let k = h.x * h.x + h.y * h.y + a2 * h.z * h.z;
    return a2 / (PI * k * k);
}

// Smith's Lambda for GGX: (-1 + sqrt(1 + alpha^2 tan^2 theta)) / 2, written without the tangent.
fn smith_lambda(w: vec3<f32>, alpha: f32) -> f32 {
    let c2 = w.z * w.z;
    let s2 = max(w.x * w.x + w.y * w.y, 0.0);
    return 0.5 * (sqrt(1.0 + alpha * alpha * s2 / c2) - 1.0);
}

// The masking of one direction, G1 = 1 / (1 + Lambda).
fn smith_g1(w: vec3<f32>, alpha: f32) -> f32 {
    return 1.0 / (1.0 + smith_lambda(w, alpha));
}

// Height-correlated masking-shadowing, G2 = 1 / (1 + Lambda(wo) + Lambda(wi)).
fn smith_g2(wo: vec3<f32>, wi: vec3<f32>, alpha: f32) -> f32 {
    return 1.0 / (1.0 + smith_lambda(wo, alpha) + smith_lambda(wi, alpha));
}

// A visible normal of the GGX lobe seen from wo (wo.z > 0), from u in [0, 1)^2 (Heitz 2018,
// "Sampling the GGX Distribution of Visible Normals"): stretch wo to the hemisphere
// configuration, sample the projected disc with its far half squeezed, lift to the hemisphere,
// unstretch.
fn sample_ggx_vndf(wo: vec3<f32>, alpha: f32, u: vec2<f32>) -> vec3<f32> {
    let vh = normalize(vec3<f32>(alpha * wo.x, alpha * wo.y, wo.z));
    let len2 = vh.x * vh.x + vh.y * vh.y;
    var t1 = vec3<f32>(1.0, 0.0, 0.0);
    if len2 > 0.0 {
        t1 = vec3<f32>(-vh.y, vh.x, 0.0) / sqrt(len2);
    }
    let t2 = cross(vh, t1);
    let r = sqrt(u.x);
    let phi = 2.0 * PI * u.y;
    let p1 = r * cos(phi);
    let s = 0.5 * (1.0 + vh.z);
    let p2 = (1.0 - s) * sqrt(max(1.0 - p1 * p1, 0.0)) + s * (r * sin(phi));
    let nh = t1 * p1 + t2 * p2 + vh * sqrt(max(1.0 - p1 * p1 - p2 * p2, 0.0));
    return normalize(vec3<f32>(alpha * nh.x, alpha * nh.y, max(nh.z, 0.0)));
}

// The density of sample_ggx_vndf's reflected direction wi = reflect(-wo, h), per solid angle:
// D_wo(h) / (4 wo.h) with D_wo(h) = G1(wo) max(0, wo.h) D(h) / wo.z; 0 for a normal below the
// surface (h.z <= 0), which the distribution has none of.
fn ggx_reflection_pdf(wo: vec3<f32>, h: vec3<f32>, alpha: f32) -> f32 {
    let wo_h = dot(wo, h);
    if wo_h <= 0.0 || wo.z <= 0.0 || h.z <= 0.0 {
        return 0.0;
    }
    return smith_g1(wo, alpha) * ggx_d(h, alpha) / (4.0 * wo.z);
}

// A cosine-distributed direction about +z from u in [0, 1)^2 (polar: r = sqrt(u.x)).
fn sample_cosine_hemisphere(u: vec2<f32>) -> vec3<f32> {
    let r = sqrt(u.x);
    let phi = 2.0 * PI * u.y;
    return vec3<f32>(r * cos(phi), r * sin(phi), sqrt(max(1.0 - u.x, 0.0)));
}

// The Fresnel of light that scatters between microfacets before it leaves (Kulla and Conty
// 2017): the cosine-weighted average of Schlick's, F_avg = F0 + (1 - F0) / 21, through every
// further bounce, F_avg^2 E_avg / (1 - F_avg (1 - E_avg)); 1 for F0 = 1.
fn multiscatter_fresnel(m: Material, e_avg: f32) -> vec3<f32> {
    let f0 = material_f0(m);
    let f_avg = f0 + (vec3<f32>(1.0) - f0) / 21.0;
    return f_avg * f_avg * e_avg / (vec3<f32>(1.0) - f_avg * (1.0 - e_avg));
}

// The E_avg of the material's multiple-scattering lobe, looked up once for each use; 1 where
// it has none (multiscatter off, or no specular lobe). The lobe is there where this is below 1:
// where the GGX lobe is rough enough to lose light.
fn multiscatter_average(m: Material) -> f32 {
    if !(m.multiscatter && has_specular_lobe(m)) {
        return 1.0;
    }
    return ggx_average_albedo(m.roughness);
}

// The multiple-scattering lobe's share of the light toward wo: lum(F_ms) (1 - E(wo.z)), the
// light single scattering loses there; 0 without the lobe. The cosine lobe draws it.
fn multiscatter_weight(m: Material, wo: vec3<f32>) -> f32 {
    let e_avg = multiscatter_average(m);
    if e_avg >= 1.0 {
        return 0.0;
    }
    let f_ms = multiscatter_fresnel(m, e_avg);
    return luminance(f_ms) * (1.0 - ggx_albedo(wo.z, m.roughness));
}

// Kulla and Conty's lobe, f_ms(wo, wi) = F_ms (1 - E(wo.z)) (1 - E(wi.z)) / (pi (1 - E_avg)),
// without the cosine: the light single scattering loses, given back, spread as its loss is
// (shaders/ggx_albedo.wgsl's tables). With F0 = 1 it makes the directional albedo 1 at every
// roughness; it is symmetric in wo and wi. 0 without the lobe.
fn multiscatter_eval(m: Material, wo: vec3<f32>, wi: vec3<f32>) -> vec3<f32> {
    let e_avg = multiscatter_average(m);
    if e_avg >= 1.0 {
        return vec3<f32>(0.0);
    }
    let e_o = ggx_albedo(wo.z, m.roughness);
    let e_i = ggx_albedo(wi.z, m.roughness);
    let f_ms = multiscatter_fresnel(m, e_avg);
    return f_ms * ((1.0 - e_o) * (1.0 - e_i) / (PI * (1.0 - e_avg)));
}

// The probability of drawing the specular lobe for wo: its Fresnel-weighted share,
// s = lum(F(wo.z)) against the cosine lobe's d = (1 - metallic) lum(albedo) (1 - lum(F(wo.z)))
// + multiscatter_weight; 0 without a specular lobe, 1 without a cosine one.
fn specular_probability(m: Material, wo: vec3<f32>) -> f32 {
    if !has_specular_lobe(m) {
        return 0.0;
    }
    let f = luminance(fresnel_schlick(material_f0(m), wo.z));
    let d = (1.0 - m.metallic) * luminance(m.albedo) * (1.0 - f) + multiscatter_weight(m, wo);
    if d <= 0.0 {
        return 1.0;
    }
    return f / (f + d);
}

// f(wo, wi), without the cosine: (1 - metallic) (1 - F(wo.z)) (1 - F(wi.z)) albedo / pi for the
// diffuse lobe (the light the surface lets in and out again, so that the two lobes together do
// not reflect more than arrives), F(wo.h) D(h) G2 / (4 wo.z wi.z) for the specular one, h the
// half vector, and with multiscatter the multiple-scattering lobe (multiscatter_eval). All are
// symmetric in wo and wi (wo.h = wi.h). Zero unless both lie above the surface; without a
// specular lobe, (1 - metallic) albedo / pi.
fn bsdf_eval(m: Material, wo: vec3<f32>, wi: vec3<f32>) -> vec3<f32> {
    if wo.z <= 0.0 || wi.z <= 0.0 {
        return vec3<f32>(0.0);
    }
    let diffuse = (1.0 - m.metallic) * m.albedo / PI;
    if !has_specular_lobe(m) {
        return diffuse;
    }
    let f0 = material_f0(m);
    let one = vec3<f32>(1.0);
    let transmitted = (one - fresnel_schlick(f0, wo.z)) * (one - fresnel_schlick(f0, wi.z));
    return transmitted * diffuse + ggx_reflection(m, wo, wi) + multiscatter_eval(m, wo, wi);
}

// The GGX lobe's single scattering, F(wo.h) D(h) G2 / (4 wo.z wi.z), h the half vector (both
// directions above the surface).
fn ggx_reflection(m: Material, wo: vec3<f32>, wi: vec3<f32>) -> vec3<f32> {
    let h = normalize(wo + wi);
    let alpha = ggx_alpha(m.roughness);
    let f = fresnel_schlick(material_f0(m), dot(wo, h));
    return f * (ggx_d(h, alpha) * smith_g2(wo, wi, alpha) / (4.0 * wo.z * wi.z));
}

// The specular part of bsdf_eval: the GGX lobe and the multiple-scattering lobe, the light the
// surface reflects without letting it in (the denoiser's specular signal, path_vertex.wgsl's
// `Light`); 0 without a specular lobe or unless both directions lie above the surface.
fn bsdf_specular(m: Material, wo: vec3<f32>, wi: vec3<f32>) -> vec3<f32> {
    if wo.z <= 0.0 || wi.z <= 0.0 || !has_specular_lobe(m) {
        return vec3<f32>(0.0);
    }
    return ggx_reflection(m, wo, wi) + multiscatter_eval(m, wo, wi);
}

// The density, per solid angle, with which bsdf_sample draws wi: the mixture of the two lobes'
// densities (the cosine lobe's draws the diffuse and the multiple-scattering light), weighted
// by the probability of choosing each.
fn bsdf_pdf(m: Material, wo: vec3<f32>, wi: vec3<f32>) -> f32 {
    if wo.z <= 0.0 || wi.z <= 0.0 {
        return 0.0;
    }
    let p_spec = specular_probability(m, wo);
    var pdf = (1.0 - p_spec) * wi.z / PI;
    if p_spec > 0.0 {
        let h = normalize(wo + wi);
        pdf += p_spec * ggx_reflection_pdf(wo, h, ggx_alpha(m.roughness));
    }
    return pdf;
}

// A direction drawn from the BSDF for wo, with f(wo, wi) and the density it was drawn with.
struct BsdfSample {
    wi: vec3<f32>,
    f: vec3<f32>,
    // 0: no direction (below the surface); the path ends.
    pdf: f32,
}

// Draws wi: the specular lobe when u_lobe < specular_probability, else the diffuse lobe; then
// f and the mixture density (bsdf_pdf) of wi, which is the density it was drawn from.
fn bsdf_sample(m: Material, wo: vec3<f32>, u_lobe: f32, u: vec2<f32>) -> BsdfSample {
    let none = BsdfSample(vec3<f32>(0.0, 0.0, 1.0), vec3<f32>(0.0), 0.0);
    if wo.z <= 0.0 {
        return none;
    }
    var wi: vec3<f32>;
    if u_lobe < specular_probability(m, wo) {
        let h = sample_ggx_vndf(wo, ggx_alpha(m.roughness), u);
        wi = reflect(-wo, h);
    } else {
        wi = sample_cosine_hemisphere(u);
    }
    if wi.z <= 0.0 {
        return none;
    }
    return BsdfSample(wi, bsdf_eval(m, wo, wi), bsdf_pdf(m, wo, wi));
}
