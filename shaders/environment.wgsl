// The environment map (`[environment]`, docs/book/atmosphere.md): an equirectangular HDR image
// about `sky.up`, turned by `rotation_degrees`, looked up texel by texel (piecewise constant):
// path mode's sky and phong mode's background, and with shading.environment_light phong mode's
// ambient light, its irradiance from nine spherical harmonics prefiltered on the host; and its
// importance sampling for the path tracer's next-event estimation. f32 throughout; reads
// `params` (env_up, env_front, env_rotation, env_intensity, env_map). Without the feature
// ENVIRONMENT (shaders/kernels.json) the kernel has none of it: environment_on() is false and the
// functions the others call are stubs that nothing reaches.
//
// Twin: src/cpu/environment.rs, same names, same order (tests/architecture/twins.rs).
#import params

// A direction drawn toward the map (sample_environment), the radiance along it and the density
// per solid angle it was drawn with (0: no sample).
struct EnvSample {
    wi: vec3<f32>,
    radiance: vec3<f32>,
    pdf: f32,
}

#if ENVIRONMENT
// The map's buffer (src/envmap.rs packs it, src/cpu/environment.rs states it): the width and
// height (floats, exact), the irradiance's nine coefficients (RGB, a vec4 slot each), then per
// texel its RGB and its density over the map's [0, 1)^2, then the marginal CDF over rows
// (height + 1 entries), then each row's CDF (width + 1 entries each).
const ENV_WIDTH: u32 = 0u;
const ENV_HEIGHT: u32 = 1u;
const ENV_IRRADIANCE: u32 = 4u;
const ENV_TEXELS: u32 = 40u;
// The largest f32 below 1: where u or v would round up to 1.
const ENV_ONE_BELOW: f32 = 0.99999994;
const ENV_PI: f32 = 3.14159265358979;

// Where no map is bound a placeholder of a few words: environment_on is false, nothing reads it.
@group(0) @binding(8) var<storage, read> environment: array<f32>;

// The map's frame: up (sky.up), front (u = 0 at rotation 0) and right = front x up (u = 1/4),
// the turn in radians, and the radiance's factor.
struct EnvFrame {
    up: vec3<f32>,
    front: vec3<f32>,
    right: vec3<f32>,
    rotation: f32,
    intensity: f32,
}

// Whether the scene has a map (environment.file).
fn environment_on() -> bool {
    return params.env_map != 0u;
}

fn env_frame() -> EnvFrame {
    let up = vec3<f32>(params.env_up);
    let front = vec3<f32>(params.env_front);
    return EnvFrame(up, front, cross(front, up), f32(params.env_rotation), f32(params.env_intensity));
}

// The map's width and height in texels.
fn env_size() -> vec2<u32> {
    return vec2<u32>(u32(environment[ENV_WIDTH]), u32(environment[ENV_HEIGHT]));
}

// The map's (u, v) of the unit direction d: v = theta / pi from up, u = phi / (2 pi) about up
// from front toward right, less the rotation, in [0, 1).
fn env_direction_uv(f: EnvFrame, d: vec3<f32>) -> vec2<f32> {
    let cos_theta = clamp(dot(d, f.up), -1.0, 1.0);
    let turns = (atan2(dot(d, f.right), dot(d, f.front)) - f.rotation) / (2.0 * ENV_PI);
    let u = turns - floor(turns);
    let v = acos(cos_theta) / ENV_PI;
    return vec2<f32>(min(u, ENV_ONE_BELOW), min(v, ENV_ONE_BELOW));
}

// The unit direction of the map's (u, v): env_direction_uv's inverse.
fn env_uv_direction(f: EnvFrame, uv: vec2<f32>) -> vec3<f32> {
    let theta = ENV_PI * uv.y;
    let phi = 2.0 * ENV_PI * uv.x + f.rotation;
    let s = sin(theta);
    return f.front * (s * cos(phi)) + f.right * (s * sin(phi)) + f.up * cos(theta);
}

// The texel (u, v) falls in, as its index j * width + i.
fn env_texel(uv: vec2<f32>) -> u32 {
    let size = env_size();
    let i = min(u32(uv.x * f32(size.x)), size.x - 1u);
    let j = min(u32(uv.y * f32(size.y)), size.y - 1u);
    return j * size.x + i;
}

// The radiance along the unit direction d: the texel it falls in, times the intensity.
fn env_radiance(d: vec3<f32>) -> vec3<f32> {
    let f = env_frame();
    let k = ENV_TEXELS + 4u * env_texel(env_direction_uv(f, d));
    return vec3<f32>(environment[k], environment[k + 1u], environment[k + 2u]) * f.intensity;
}

// The map's irradiance at the unit normal n divided by pi (the mean radiance over the hemisphere
// about n, cosine-weighted), times the intensity: the nine coefficients' polynomial in n's
// coordinates in the map's own frame (x toward u = 0, y toward u = 1/4, z up), at least 0.
fn env_irradiance(n: vec3<f32>) -> vec3<f32> {
    let f = env_frame();
    let a = dot(n, f.front);
    let b = dot(n, f.right);
    let c = cos(f.rotation);
    let s = sin(f.rotation);
    let x = a * c + b * s;
    let y = b * c - a * s;
    let z = dot(n, f.up);
    let basis = array<f32, 9>(1.0, y, z, x, x * y, y * z, 3.0 * z * z - 1.0, x * z, x * x - y * y);
    var e = vec3<f32>(0.0);
    for (var k = 0u; k < 9u; k++) {
        let at = ENV_IRRADIANCE + 4u * k;
        e += vec3<f32>(environment[at], environment[at + 1u], environment[at + 2u]) * basis[k];
    }
    return max(e, vec3<f32>(0.0)) * f.intensity;
}

// The map as a light: importance sampling by the 2D piecewise-constant distribution packed with it, the marginal
// over rows then the row's conditional over texels, each CDF searched by bisection; a direction's
// density per solid angle is its texel's density over [0, 1)^2 divided by 2 pi^2 sin(theta).

// The piece of the CDF of n pieces at environment[start..start + n] that u falls in: the last k
// with cdf[k] <= u.
fn env_bisect(start: u32, n: u32, u: f32) -> u32 {
    var lo = 0u;
    var hi = n;
    while hi - lo > 1u {
        let mid = (lo + hi) / 2u;
        if environment[start + mid] <= u {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    return lo;
}

// Where u falls within piece k of the CDF at start, of n pieces: (k + du) / n, du the CDF
// inverted within the piece (its middle for a piece of no mass), below 1.
fn env_piece_point(start: u32, k: u32, n: u32, u: f32) -> f32 {
    let c0 = environment[start + k];
    let width = environment[start + k + 1u] - c0;
    var du = 0.5;
    if width > 0.0 {
        du = clamp((u - c0) / width, 0.0, 1.0);
    }
    return min((f32(k) + du) / f32(n), ENV_ONE_BELOW);
}

// A direction toward the map drawn from u in [0, 1)^2 with the radiance of its texel (times the
// intensity) and its density per solid angle (pdf 0, no sample, at a pole).
fn sample_environment(u: vec2<f32>) -> EnvSample {
    let size = env_size();
    let marginal = ENV_TEXELS + 4u * size.x * size.y;
    let j = env_bisect(marginal, size.y, u.y);
    let v = env_piece_point(marginal, j, size.y, u.y);
    let row = marginal + size.y + 1u + j * (size.x + 1u);
    let i = env_bisect(row, size.x, u.x);
    let x = env_piece_point(row, i, size.x, u.x);
    let k = ENV_TEXELS + 4u * (j * size.x + i);
    let f = env_frame();
    let wi = env_uv_direction(f, vec2<f32>(x, v));
    let s = sin(ENV_PI * v);
    let pdf_uv = environment[k + 3u];
    if s <= 0.0 || pdf_uv <= 0.0 {
        return EnvSample(wi, vec3<f32>(0.0), 0.0);
    }
    let radiance = vec3<f32>(environment[k], environment[k + 1u], environment[k + 2u]) * f.intensity;
    return EnvSample(wi, radiance, pdf_uv / (2.0 * ENV_PI * ENV_PI * s));
}

// The density per solid angle with which sample_environment draws the unit direction d.
fn environment_pdf(d: vec3<f32>) -> f32 {
    let uv = env_direction_uv(env_frame(), d);
    let s = sin(ENV_PI * uv.y);
    if s <= 0.0 {
        return 0.0;
    }
    return environment[ENV_TEXELS + 4u * env_texel(uv) + 3u] / (2.0 * ENV_PI * ENV_PI * s);
}
#else
fn environment_on() -> bool {
    return false;
}

// Never called: environment_on() is false.
fn env_radiance(d: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(0.0);
}

// Never called: environment_on() is false.
fn env_irradiance(n: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(0.0);
}

// Never called: environment_on() is false.
fn sample_environment(u: vec2<f32>) -> EnvSample {
    return EnvSample(vec3<f32>(0.0, 0.0, 1.0), vec3<f32>(0.0), 0.0);
}

// Never called: environment_on() is false.
fn environment_pdf(d: vec3<f32>) -> f32 {
    return 0.0;
}
#endif
