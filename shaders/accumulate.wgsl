// The accumulation: a sample's outcome (Pixel), the sample positions in the pixel and on the lens,
// adaptive sampling's two streams, the packed colour, the AOVs with their M2, the noise rule, the
// halves, and (WGSL only) their loads and stores in the accumulator.
//
// Part of the tracer that shaders/trace.wgsl composes. Twin: src/cpu/trace/accumulate.rs, function
// by function, with the same names in the same order (checked by tests/architecture/twins.rs, which
// lists the functions only one side has); a change to one is a change to both.
#import real
#import params
#import colour

// With several samples: the mean of the samples' clamped colours so far (rgb).
@group(0) @binding(5) var<storage, read_write> accumulated: array<vec4<f32>>;
// With AOVS: three vec4s a pixel, from index 3 * index on, the Aovs so far (store_aovs).
@group(0) @binding(6) var<storage, read_write> out_aovs: array<vec4<f32>>;

// One sample's outcome: its colour (unclamped), depth and steps, whether it hit, and where
// it was shaded, the hit point and its shading normal (0 where it was not: a miss, or no
// shading).
struct Pixel {
    colour: vec3<Real>,
    depth: Real,
    steps: u32,
    hit: bool,
    point: vec3<Real>,
    normal: vec3<Real>,
}

// Where sample k lies in its pixel, (x, y) in [0, 1)^2 from the pixel's top left corner:
// (0.5, 0.5), the centre, for sample 0; else the Halton point of index k in bases 2 and 3
// (k < 4096: its 12 binary and 8 ternary digits, so both coordinates are exact in f32).
fn sample_position(k: u32) -> vec2<Real> {
    if k == 0u {
        return vec2<Real>(0.5, 0.5);
    }
    let base2 = reverseBits(k) >> 20u;
    var base3 = 0u;
    var rest = k;
    for (var digit = 0u; digit < 8u; digit++) {
        base3 = base3 * 3u + rest % 3u;
        rest /= 3u;
    }
    return vec2<Real>(Real(base2) * (1.0 / 4096.0), Real(base3) * (1.0 / 6561.0));
}

// Where sample k (>= 1) lies on the lens before the aperture's map, (u, v) in [0, 1)^2: the
// Halton point of index k in bases 5 and 7 (the sub-pixel positions take 2 and 3), from k's
// first 6 quinary and 5 septenary digits as integers over 15625 and 16807 (k < 4096 has no more).
fn lens_position(k: u32) -> vec2<f32> {
    var base5 = 0u;
    var rest = k;
    for (var digit = 0u; digit < 6u; digit++) {
        base5 = base5 * 5u + rest % 5u;
        rest /= 5u;
    }
    var base7 = 0u;
    rest = k;
    for (var digit = 0u; digit < 5u; digit++) {
        base7 = base7 * 7u + rest % 7u;
        rest /= 7u;
    }
    return vec2<f32>(f32(base5) * (1.0 / 15625.0), f32(base7) * (1.0 / 16807.0));
}

// Adaptive sampling's two streams (docs/book/adaptive.md): sample k of an adaptive pixel is
// sample k / 2 of stream k % 2, as (stream, index). Each stream's stop is decided by its own
// samples and applied to the other's mean (add_to_streams), so that no half of what the pixel
// shows depends on its own stop. Without adaptive sampling every sample is stream 0's: (0, k)
// (phong mode; path mode has both streams anyway: path_uniform.wgsl's path_stream).
fn sample_stream(k: u32) -> vec2<u32> {
    if adaptive() {
        return vec2<u32>(k & 1u, k >> 1u);
    }
    return vec2<u32>(0u, k);
}

// Stream 1's points in phong mode are stream 0's turned by this Cranley-Patterson shift (modulo
// 1, in the pixel and on the lens alike): R2's (0.7549, 0.5698) rounded to 11 bits, exact in
// f32. The streams' points are then apart, each stream as well spread as the Halton points.
const STREAM_SHIFT: vec2<f32> = vec2<f32>(1545.0 / 2048.0, 1167.0 / 2048.0);

// Where sample k lies in its pixel in phong mode: its stream's index's sample_position, shifted
// by STREAM_SHIFT in stream 1.
fn stream_position(k: u32) -> vec2<Real> {
    let s = sample_stream(k);
    let p = sample_position(s.y);
    if s.x == 0u {
        return p;
    }
    return fract(p + vec2<Real>(STREAM_SHIFT));
}

// Where sample k lies on the lens before the aperture's map in phong mode: lens_position of its
// stream's index + 1, shifted by STREAM_SHIFT in stream 1.
fn stream_lens_position(k: u32) -> vec2<f32> {
    let s = sample_stream(k);
    let p = lens_position(s.y + 1u);
    if s.x == 0u {
        return p;
    }
    return fract(p + STREAM_SHIFT);
}

// Colour clamped to [0, 1], times 255, rounded half up, packed as RGBA8 0xFFBBGGRR (opaque).
// (In f32 whatever the precision: a colour needs no more.)
fn pack_colour(colour: vec3<Real>) -> u32 {
    let c = vec3<f32>(colour);
    let v = vec3<u32>(floor(clamp(c, vec3<f32>(0.0), vec3<f32>(1.0)) * 255.0 + 0.5));
    return v.x | (v.y << 8u) | (v.z << 16u) | 0xff000000u;
}

// The AOVs of a pixel's samples so far (`--hdr`, the denoiser): the mean of their unclamped
// colours and the sum of the squared deviations of their luminances from the running mean
// (Welford's M2: the denoiser's variance), and over the samples whose primary ray hit, how many
// did and the means of their hits' base colours, shading normals and depths (0 while none has);
// in path mode also the mean of their first hits' specular light (path.wgsl's
// PathResult.specular; 0 in phong mode), and over the hits the mean cosine of the view
// direction to the shading normal (the denoiser's specular reflectance). In f32 in both
// precisions, as the accumulator is.
struct Aovs {
    colour: vec3<f32>,
    hits: f32,
    albedo: vec3<f32>,
    normal: vec3<f32>,
    m2: f32,
    depth: f32,
    specular: vec3<f32>,
    cosine: f32,
}

// Rec. 709 luminance of a linear colour, as shaders/bsdf.wgsl's `luminance` (the phong module
// has no bsdf.wgsl).
fn sample_luminance(c: vec3<f32>) -> f32 {
    return dot(c, vec3<f32>(0.2126, 0.7152, 0.0722));
}

// Welford's rule: the sum of squared deviations from the mean m2 of luminances, with one more
// luminance l, given the mean's luminance before it (before) and after (after),
// M2_k = M2_(k-1) + (l_k - L(m_(k-1))) (l_k - L(m_k)).
fn add_m2(m2: f32, l: f32, before: f32, after: f32) -> f32 {
    return m2 + (l - before) * (l - after);
}

// Adds sample k (0-based) to the AOVs: its colour and its specular light to the running means
// over the samples, m_k = m_(k-1) + (c_k - m_(k-1)) / (k + 1), and its luminance l_k to M2
// (add_m2); where it hit, its albedo, normal, depth and view cosine to the running means over
// the hits, by the same rule with the hits counted so far.
fn add_aovs(a: Aovs, k: u32, colour: vec3<f32>, hit: bool, albedo: vec3<f32>, normal: vec3<f32>, depth: f32, specular: vec3<f32>, cosine: f32) -> Aovs {
    var out = a;
    out.colour = a.colour + (colour - a.colour) / f32(k + 1u);
    out.specular = a.specular + (specular - a.specular) / f32(k + 1u);
    let l = sample_luminance(colour);
    out.m2 = add_m2(a.m2, l, sample_luminance(a.colour), sample_luminance(out.colour));
    if hit {
        out.hits = a.hits + 1.0;
        out.albedo = a.albedo + (albedo - a.albedo) / out.hits;
        out.normal = a.normal + (normal - a.normal) / out.hits;
        out.depth = a.depth + (depth - a.depth) / out.hits;
        out.cosine = a.cosine + (cosine - a.cosine) / out.hits;
    }
    return out;
}

// Adds sample k's pixel to the AOVs: its colour, and where it hit, the base colour of its hit
// (hit_albedo), its shading normal and its depth. (The host sets AOVS only with SHADE: every hit
// is shaded.)
fn add_pixel_aovs(a: Aovs, k: u32, pixel: Pixel) -> Aovs {
    var albedo = vec3<f32>(0.0);
    if pixel.hit {
        albedo = vec3<f32>(hit_albedo(pixel.point));
    }
    return add_aovs(a, k, vec3<f32>(pixel.colour), pixel.hit, albedo, vec3<f32>(pixel.normal), f32(pixel.depth), vec3<f32>(0.0), 0.0);
}

// The AOVs pixel `index` holds in out_aovs: colour and hits, albedo and M2, normal and depth,
// specular light and view cosine.
fn load_aovs(index: u32) -> Aovs {
    let a = out_aovs[4u * index];
    let b = out_aovs[4u * index + 1u];
    let c = out_aovs[4u * index + 2u];
    let d = out_aovs[4u * index + 3u];
    return Aovs(a.xyz, a.w, b.xyz, c.xyz, b.w, c.w, d.xyz, d.w);
}

fn store_aovs(index: u32, a: Aovs) {
    out_aovs[4u * index] = vec4<f32>(a.colour, a.hits);
    out_aovs[4u * index + 1u] = vec4<f32>(a.albedo, a.m2);
    out_aovs[4u * index + 2u] = vec4<f32>(a.normal, a.depth);
    out_aovs[4u * index + 3u] = vec4<f32>(a.specular, a.cosine);
}

// Adaptive sampling (params.noise_target > 0; the book's chapter "Adaptive sampling"), by
// cross-fitting. Each pixel decides alone, after each of its samples, so any split of the image
// into bands, tiles or dispatches gives the same pixels. Its samples alternate between two
// streams (sample_stream), A (stream 0) and B (stream 1). Each stream's own rule (stream_fires)
// sees that stream's samples alone and stops it after its draw tau_A, tau_B. The pixel shows
// half the mean of B's first tau_A samples plus half the mean of A's first tau_B (streams_mean),
// so that neither half depends on its own stream's stop, and it samples both streams until both
// rules have fired and each stream has the draws the other's stop asks of it (sampling_done).

// A pixel's noise is taken relative to its mean luminance or to this, whichever is larger (the
// floor for dark pixels, in linear luminance: 1 is phong mode's white).
const NOISE_LUMINANCE_FLOOR: f32 = 0.01;

#if ADAPTIVE
// Whether this pipeline samples adaptively. Without ADAPTIVE (shaders/kernels.json) false: the
// streams' functions are still in the text, and the specialisation (src/gpu/kernel/specialise.rs)
// cuts every branch this decides.
fn adaptive() -> bool {
    return params.noise_target > 0.0 && params.samples > 1u;
}
#else
fn adaptive() -> bool {
    return false;
}
#endif

// A pixel's noise after n >= 2 samples whose luminances' M2 is m2: the standard error of its
// mean luminance, sqrt(m2 / (n (n - 1))), relative to that mean (at least the floor).
fn pixel_noise(m2: f32, n: u32, mean_luminance: f32) -> f32 {
    let k = f32(n);
    let variance = max(m2 / (k * (k - 1.0)), 0.0);
    return sqrt(variance) / max(abs(mean_luminance), NOISE_LUMINANCE_FLOOR);
}

// A pixel's adaptive state, the accumulator's four planes (load_streams):
//   a      = (A's mean colour, tau_A: 0 until A's rule fires),
//   b      = (B's mean colour, the samples in it),
//   rule_a = (A's mean luminance, its M2 (add_m2), its samples kept, the samples in A's colour),
//   rule_b = (B's mean luminance, its M2, its samples kept, tau_B: 0 until B's rule fires).
// A's mean colour takes A's draws while B's rule has not fired, which are A's first tau_B; B's
// takes B's first tau_A. Each stream's luminances are counted until its own rule fires. The
// counts are exact in f32. A sample that is not valid (path mode's sample_valid) is a draw of its
// stream but joins nothing. Once the pixel is done the first plane holds what it shows
// (streams_mean) and minus the samples it took, and the next two its halves (store_streams).
struct Streams {
    a: vec4<f32>,
    b: vec4<f32>,
    rule_a: vec4<f32>,
    rule_b: vec4<f32>,
}

// A stream's luminance statistics (rule: mean, M2, samples kept) with one more luminance l, by
// Welford's rule (add_m2, at least 0); the fourth float is kept.
fn add_luminance(rule: vec4<f32>, l: f32) -> vec4<f32> {
    var out = rule;
    out.z = rule.z + 1.0;
    out.x = rule.x + (l - rule.x) / out.z;
    out.y = max(add_m2(rule.y, l, rule.x, out.x), 0.0);
    return out;
}

// Whether a stream's rule fires after its draw `draws` (from 1), its luminances' statistics being
// `rule` (add_luminance): at its cap of samples / 2 draws, or from half the floor
// max(min(min_samples, samples), 4) (rounded up) on, with at least 2 samples kept and a noise
// (pixel_noise) at most the target.
fn stream_fires(rule: vec4<f32>, draws: u32) -> bool {
    if draws >= params.samples / 2u {
        return true;
    }
    let floor = (max(min(params.min_samples, params.samples), 4u) + 1u) / 2u;
    if draws < floor || rule.z < 2.0 {
        return false;
    }
    return pixel_noise(rule.y, u32(rule.z), rule.x) <= f32(params.noise_target);
}

// A pixel's streams with its sample k taken (draw k / 2 + 1 of stream k % 2), of colour `colour`
// where it is valid.
fn add_to_streams(s: Streams, k: u32, valid: bool, colour: vec3<f32>) -> Streams {
    var out = s;
    let draws = k / 2u + 1u;
    let l = sample_luminance(colour);
    if k % 2u == 0u {
        // A's draw joins A's colour while B's rule has not fired.
        if valid && s.rule_b.w == 0.0 {
            out.rule_a.w = s.rule_a.w + 1.0;
            out.a = vec4<f32>(s.a.xyz + (colour - s.a.xyz) / out.rule_a.w, s.a.w);
        }
        if s.a.w == 0.0 {
            if valid {
                out.rule_a = vec4<f32>(add_luminance(s.rule_a, l).xyz, out.rule_a.w);
            }
            if stream_fires(out.rule_a, draws) {
                out.a.w = f32(draws);
            }
        }
    } else {
        // B's draw joins B's colour while A's rule has not fired, or up to A's stop.
        if valid && (s.a.w == 0.0 || f32(draws) <= s.a.w) {
            out.b.w = s.b.w + 1.0;
            out.b = vec4<f32>(s.b.xyz + (colour - s.b.xyz) / out.b.w, out.b.w);
        }
        if s.rule_b.w == 0.0 {
            if valid {
                out.rule_b = vec4<f32>(add_luminance(s.rule_b, l).xyz, 0.0);
            }
            if stream_fires(out.rule_b, draws) {
                out.rule_b.w = f32(draws);
            }
        }
    }
    return out;
}

// Whether a pixel whose streams are s is done once it has taken `taken` samples: both rules have
// fired and B has its first tau_A draws (A has its first tau_B whenever B's rule has fired), or
// it has taken every sample.
fn sampling_done(s: Streams, taken: u32) -> bool {
    if taken >= params.samples {
        return true;
    }
    return s.a.w > 0.0 && s.rule_b.w > 0.0 && f32(taken / 2u) >= s.a.w;
}

// A pixel's two halves (path mode, and an adaptive pixel once it is done): each stream's mean
// colour and the samples in it, a = (A's mean colour, n_A), b = (B's mean colour, n_B). The
// streams are drawn independently, so the halves' disagreement estimates the error of what the
// pixel shows (docs/CONTRACT.md's `estimated_rmse`): E[(a - b)^2] / 4 = Var((a + b) / 2).
struct Halves {
    a: vec4<f32>,
    b: vec4<f32>,
}

// A pixel's halves with its valid sample k (of stream k % 2) of colour `colour` joined to its
// stream's running mean, m_n = m_(n-1) + (c - m_(n-1)) / n.
fn add_to_halves(h: Halves, k: u32, colour: vec3<f32>) -> Halves {
    var out = h;
    if k % 2u == 0u {
        let n = h.a.w + 1.0;
        out.a = vec4<f32>(h.a.xyz + (colour - h.a.xyz) / n, n);
    } else {
        let n = h.b.w + 1.0;
        out.b = vec4<f32>(h.b.xyz + (colour - h.b.xyz) / n, n);
    }
    return out;
}

// What a pixel whose halves are h shows: half A's mean colour plus half B's, or the one half's
// where the other has no sample in it (black where neither has).
fn halves_mean(h: Halves) -> vec3<f32> {
    if h.a.w == 0.0 {
        return h.b.xyz;
    }
    if h.b.w == 0.0 {
        return h.a.xyz;
    }
    return 0.5 * (h.a.xyz + h.b.xyz);
}

// An adaptive pixel's halves: A's mean of its first tau_B draws, B's of its first tau_A.
fn streams_halves(s: Streams) -> Halves {
    return Halves(vec4<f32>(s.a.xyz, s.rule_a.w), s.b);
}

// What a pixel whose streams are s shows: its halves' mean (halves_mean).
fn streams_mean(s: Streams) -> vec3<f32> {
    return halves_mean(streams_halves(s));
}

// A done pixel's AOVs with their hits and M2 taken to the `taken` samples it took, which the host
// divides by (denoise::mean_variance, denoise::hit_fraction): hits / taken is then the fraction of the n = n_A + n_B
// samples in its colours that hit, and M2 / (taken (taken - 1)) the variance of what it shows,
// M2 / (n - 1) (1 / n_A + 1 / n_B) / 4 (1 / n with one stream empty).
fn finish_aovs(a: Aovs, s: Streams, taken: u32) -> Aovs {
    var out = a;
    let n = s.rule_a.w + s.b.w;
    let t = f32(taken);
    if n == 0.0 {
        return out;
    }
    out.hits = a.hits * t / n;
    var spread = 1.0 / n;
    if s.rule_a.w > 0.0 && s.b.w > 0.0 {
        spread = 0.25 * (1.0 / s.rule_a.w + 1.0 / s.b.w);
    }
    out.m2 = 0.0;
    if n >= 2.0 && t >= 2.0 {
        out.m2 = a.m2 / (n - 1.0) * spread * (t * (t - 1.0));
    }
    return out;
}

// A pixel's streams (Streams), from the accumulator's four planes: plane p of pixel `index` is
// element p arrayLength / 4 + index (the host allocates accumulated four times the pixels).
fn load_streams(index: u32) -> Streams {
    let plane = arrayLength(&accumulated) / 4u;
    return Streams(
        accumulated[index],
        accumulated[plane + index],
        accumulated[2u * plane + index],
        accumulated[3u * plane + index],
    );
}

// Keeps a pixel's streams after a dispatch: once it is done (after `taken` samples; 0 while it
// samples), what it shows and minus its samples in the first plane and its halves in the next
// two (store_halves); else all four planes (load_streams).
fn store_streams(index: u32, s: Streams, taken: u32) {
    if taken > 0u {
        accumulated[index] = vec4<f32>(streams_mean(s), -f32(taken));
        store_halves(index, streams_halves(s));
        return;
    }
    let plane = arrayLength(&accumulated) / 4u;
    accumulated[index] = s.a;
    accumulated[plane + index] = s.b;
    accumulated[2u * plane + index] = s.rule_a;
    accumulated[3u * plane + index] = s.rule_b;
}

// A pixel's halves (Halves) from the accumulator's second and third planes, where path mode
// keeps them (and an adaptive pixel once done: store_streams).
fn load_halves(index: u32) -> Halves {
    let plane = arrayLength(&accumulated) / 4u;
    return Halves(accumulated[plane + index], accumulated[2u * plane + index]);
}

fn store_halves(index: u32, h: Halves) {
    let plane = arrayLength(&accumulated) / 4u;
    accumulated[plane + index] = h.a;
    accumulated[2u * plane + index] = h.b;
}
