//! The sampler of the path tracer (issue 19), the CPU twin of shaders/sobol.wgsl: the same
//! functions with the same names in the same order (tests/architecture/twins.rs), in u32 arithmetic only, so
//! that the CPU and every GPU backend draw the same bits for a (pixel, sample, dimension). Two
//! samplers: `sobol`, Owen-scrambled Sobol' points in Burley's hash form ("Practical Hash-based
//! Owen Scrambling", JCGT 2020), and `random`, an integer hash of the three numbers kept for
//! comparison. The exact definition is in docs/book/sampler.md. Nothing renders with it yet.

/// The sampler `sobol` ([`sample_bits`]'s `sampler`).
pub const SAMPLER_SOBOL: u32 = 0;
/// The sampler `random`.
pub const SAMPLER_RANDOM: u32 = 1;

// The dimensions of a path, in the order they are drawn: the image plane first (2: x, y),
// then the lens (2), then each bounce b its own DIMS_PER_BOUNCE dimensions from
// DIM_BOUNCE_BASE + b * DIMS_PER_BOUNCE on, three padding groups (SOBOL_DIMS dimensions each):
// the sun's 2D point, the sphere light's 2D point, then the BSDF's 2D direction, its lobe's
// choice and Russian roulette. Each 2D point takes its group's first two dimensions, the
// best-stratified pair (a (0, 2)-sequence), as the image plane's does; a light and its lobe
// choice share no group with another light. Dimensions 2 and 3 of the sun's group are the
// environment map's 2D point; the sphere light's group's third is the fog's free flight.

/// The image plane's 2D point: dimensions 0 and 1.
pub const DIM_PIXEL: u32 = 0;
/// The lens' 2D point: dimensions 2 and 3.
pub const DIM_LENS: u32 = 2;
/// Bounce 0's first dimension.
pub const DIM_BOUNCE_BASE: u32 = 4;
/// Dimensions each bounce takes: three padding groups.
pub const DIMS_PER_BOUNCE: u32 = 12;
/// Within a bounce: the point on the sun (2D), its first group's first two dimensions.
pub const DIM_SUN: u32 = 0;
/// Within a bounce: the point on the environment map (2D), the sun's group's third and fourth.
pub const DIM_ENVIRONMENT: u32 = 2;
/// Within a bounce: the point on the sphere light (2D), its second group's first two.
pub const DIM_SPHERE_LIGHT: u32 = 4;
/// Within a bounce: the fog's free-flight distance (1D), the sphere light's group's third (the
/// ray leaving the bounce's vertex takes it; a scattering event in the fog is the next vertex).
pub const DIM_FOG: u32 = 6;
/// Within a bounce: the BSDF's direction (2D), its third group's first two.
pub const DIM_BSDF: u32 = 8;
/// Within a bounce: which BSDF lobe (1D), in the direction's group.
pub const DIM_BSDF_CHOICE: u32 = 10;
/// Within a bounce: Russian roulette (1D).
pub const DIM_ROULETTE: u32 = 11;

/// Dimensions of the Sobol' sequence tabulated; dimension d is Sobol' dimension d % SOBOL_DIMS
/// of the padding group d / SOBOL_DIMS (Burley's padding).
pub const SOBOL_DIMS: u32 = 4;
/// What the index shuffle's seed is salted with.
pub const SEED_SHUFFLE: u32 = 0x5348_5546;
/// What the scramble's seed is salted with.
pub const SEED_SCRAMBLE: u32 = 0x5343_524d;

/// The direction numbers, 32 per dimension, bit k of the index XORing in entry 32 * d + k.
/// Dimension 0 is the van der Corput sequence (1 << (31 - k): the index's bits reversed);
/// dimensions 1 to 3 follow from Joe and Kuo's primitive polynomials and initial numbers
/// (new-joe-kuo-6.21201, their dimensions 2 to 4: s = 1, a = 0, m = 1; s = 2, a = 1, m = 1 3;
/// s = 3, a = 1, m = 1 3 1) by Bratley and Fox's recurrence (tests/render/sobol.rs derives them again).
pub const SOBOL_DIRECTIONS: [u32; 128] = [
    0x80000000, 0x40000000, 0x20000000, 0x10000000, 0x08000000, 0x04000000, 0x02000000, 0x01000000,
    0x00800000, 0x00400000, 0x00200000, 0x00100000, 0x00080000, 0x00040000, 0x00020000, 0x00010000,
    0x00008000, 0x00004000, 0x00002000, 0x00001000, 0x00000800, 0x00000400, 0x00000200, 0x00000100,
    0x00000080, 0x00000040, 0x00000020, 0x00000010, 0x00000008, 0x00000004, 0x00000002, 0x00000001,
    0x80000000, 0xc0000000, 0xa0000000, 0xf0000000, 0x88000000, 0xcc000000, 0xaa000000, 0xff000000,
    0x80800000, 0xc0c00000, 0xa0a00000, 0xf0f00000, 0x88880000, 0xcccc0000, 0xaaaa0000, 0xffff0000,
    0x80008000, 0xc000c000, 0xa000a000, 0xf000f000, 0x88008800, 0xcc00cc00, 0xaa00aa00, 0xff00ff00,
    0x80808080, 0xc0c0c0c0, 0xa0a0a0a0, 0xf0f0f0f0, 0x88888888, 0xcccccccc, 0xaaaaaaaa, 0xffffffff,
    0x80000000, 0xc0000000, 0x60000000, 0x90000000, 0xe8000000, 0x5c000000, 0x8e000000, 0xc5000000,
    0x68800000, 0x9cc00000, 0xee600000, 0x55900000, 0x80680000, 0xc09c0000, 0x60ee0000, 0x90550000,
    0xe8808000, 0x5cc0c000, 0x8e606000, 0xc5909000, 0x6868e800, 0x9c9c5c00, 0xeeee8e00, 0x5555c500,
    0x8000e880, 0xc0005cc0, 0x60008e60, 0x9000c590, 0xe8006868, 0x5c009c9c, 0x8e00eeee, 0xc5005555,
    0x80000000, 0xc0000000, 0x20000000, 0x50000000, 0xf8000000, 0x74000000, 0xa2000000, 0x93000000,
    0xd8800000, 0x25400000, 0x59e00000, 0xe6d00000, 0x78080000, 0xb40c0000, 0x82020000, 0xc3050000,
    0x208f8000, 0x51474000, 0xfbea2000, 0x75d93000, 0xa0858800, 0x914e5400, 0xdbe79e00, 0x25db6d00,
    0x58800080, 0xe54000c0, 0x79e00020, 0xb6d00050, 0x800800f8, 0xc00c0074, 0x200200a2, 0x50050093,
];

/// A 32-bit integer hash: the PCG hash (Jarzynski and Olano, "Hash Functions for GPU
/// Rendering", JCGT 2020), one LCG step then PCG's output permutation.
pub fn sampler_hash(x: u32) -> u32 {
    let state = x.wrapping_mul(747796405).wrapping_add(2891336453);
    let word = ((state >> ((state >> 28) + 4)) ^ state).wrapping_mul(277803737);
    (word >> 22) ^ word
}

/// Three numbers hashed into one: each folded into the hash of those before it.
pub fn hash3(a: u32, b: u32, c: u32) -> u32 {
    sampler_hash(sampler_hash(sampler_hash(a) ^ b) ^ c)
}

/// A Laine-Karras style permutation of x: each output bit is the input bit flipped by a function
/// of the bits below it and the seed (multiplications by even numbers and the addition carry
/// upwards only). The steps and constants are Burley's.
pub fn laine_karras(x: u32, seed: u32) -> u32 {
    let mut v = x;
    v ^= v.wrapping_mul(0x3d20adea);
    v = v.wrapping_add(seed);
    v = v.wrapping_mul((seed >> 16) | 1);
    v ^= v.wrapping_mul(0x05526c56);
    v ^= v.wrapping_mul(0x53a22864);
    v
}

/// Nested uniform (Owen) scrambling of a 0.32 fixed-point number: [`laine_karras`] on the bits
/// reversed, so that each bit is flipped by a function of the bits above it.
pub fn nested_uniform_scramble(x: u32, seed: u32) -> u32 {
    laine_karras(x.reverse_bits(), seed).reverse_bits()
}

/// Point `index` of the unscrambled Sobol' sequence in dimension `dim` (< SOBOL_DIMS), as a
/// 0.32 fixed-point number: the XOR of the direction numbers of the index's set bits. Dimension
/// 0's numbers are the bits 1 << (31 - k), whose XOR is the index's bits reversed; dimension 1's
/// are Pascal's triangle mod 2 ([`pascal_xor`]); dimensions 2 and 3 are [`sobol_dim2`] and
/// [`sobol_dim3`], which the kernel writes out number by number.
pub fn sobol(index: u32, dim: u32) -> u32 {
    match dim {
        0 => index.reverse_bits(),
        1 => pascal_xor(index).reverse_bits(),
        2 => sobol_dim2(index),
        _ => sobol_dim3(index),
    }
}

/// Sobol' dimension 1 before its bits are reversed: bit j of the result is the XOR of the
/// index's bits k with C(k, j) odd, which by Lucas' theorem are the k whose set bits include
/// j's; five shifted XORs sum each bit's supersets, one bit of j at a time.
pub fn pascal_xor(index: u32) -> u32 {
    let mut y = index;
    y ^= (y >> 1) & 0x5555_5555;
    y ^= (y >> 2) & 0x3333_3333;
    y ^= (y >> 4) & 0x0f0f_0f0f;
    y ^= (y >> 8) & 0x00ff_00ff;
    y ^= (y >> 16) & 0x0000_ffff;
    y
}

/// Direction number `direction` where bit k of the index is set, else 0: a mask, no branch.
pub fn direction_if(index: u32, k: u32, direction: u32) -> u32 {
    direction & 0u32.wrapping_sub((index >> k) & 1)
}

/// Sobol' dimension 2 (Joe and Kuo's 3): the XOR of its direction numbers
/// (`SOBOL_DIRECTIONS[64..96]`) over the index's set bits. The kernel writes the 32 masks out as
/// straight-line code; here they are folded over the table, the same bits.
pub fn sobol_dim2(index: u32) -> u32 {
    (0..32).fold(0, |x, k| {
        x ^ direction_if(index, k, SOBOL_DIRECTIONS[64 + k as usize])
    })
}

/// Sobol' dimension 3 (Joe and Kuo's 4) as [`sobol_dim2`]: `SOBOL_DIRECTIONS[96..128]`.
pub fn sobol_dim3(index: u32) -> u32 {
    (0..32).fold(0, |x, k| {
        x ^ direction_if(index, k, SOBOL_DIRECTIONS[96 + k as usize])
    })
}

/// The `sobol` sampler's bits for (pixel, sample, dimension): the sample's index shuffled by a
/// nested uniform scramble seeded per (pixel, padding group), the point of the group's Sobol'
/// dimension there, scrambled with a seed per (pixel, dimension).
pub fn sobol_sample(pixel: u32, sample: u32, dim: u32) -> u32 {
    let group = dim / SOBOL_DIMS;
    let index = nested_uniform_scramble(sample, hash3(pixel, group, SEED_SHUFFLE));
    let x = sobol(index, dim % SOBOL_DIMS);
    nested_uniform_scramble(x, hash3(pixel, dim, SEED_SCRAMBLE))
}

/// The `random` sampler's bits for (pixel, sample, dimension): the three hashed, then hashed
/// once more (so that no draw is a seed of the `sobol` sampler).
pub fn random_sample(pixel: u32, sample: u32, dim: u32) -> u32 {
    sampler_hash(hash3(pixel, sample, dim))
}

/// The bits of `sampler` (SAMPLER_SOBOL or SAMPLER_RANDOM) for (pixel, sample, dimension).
pub fn sample_bits(sampler: u32, pixel: u32, sample: u32, dim: u32) -> u32 {
    if sampler == SAMPLER_RANDOM {
        return random_sample(pixel, sample, dim);
    }
    sobol_sample(pixel, sample, dim)
}

/// The bits as a number in [0, 1): the top 24 bits times 2^-24, exact in f32.
pub fn to_unit(bits: u32) -> f32 {
    (bits >> 8) as f32 * (1.0 / 16_777_216.0)
}
