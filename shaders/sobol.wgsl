// The sampler of the path tracer (issue 19): Owen-scrambled Sobol' points in Burley's hash form
// ("Practical Hash-based Owen Scrambling", JCGT 2020), and a plain integer hash kept for
// comparison, in u32 arithmetic only so that every backend and the CPU draw the same bits for a
// (pixel, sample, dimension). Stands alone: it imports nothing. The exact definition is in
// docs/book/sampler.md.
//
// Twin: src/cpu/sobol.rs, function by function, with the same names in the same order
// (tests/architecture/twins.rs).

// The sampler `sobol` (sample_bits's `sampler`).
const SAMPLER_SOBOL: u32 = 0u;
// The sampler `random`.
const SAMPLER_RANDOM: u32 = 1u;

// The dimensions of a path, in the order they are drawn: the image plane first (2: x, y),
// then the lens (2), then each bounce b its own DIMS_PER_BOUNCE dimensions from
// DIM_BOUNCE_BASE + b * DIMS_PER_BOUNCE on, three padding groups (SOBOL_DIMS dimensions each):
// the sun's 2D point, the sphere light's 2D point, then the BSDF's 2D direction, its lobe's
// choice and Russian roulette. Each 2D point takes its group's first two dimensions, the
// best-stratified pair (a (0, 2)-sequence), as the image plane's does; a light and its lobe
// choice share no group with another light. Dimensions 2 and 3 of the sun's group are the
// environment map's 2D point; the sphere light's group's third is the fog's free flight.

// The image plane's 2D point: dimensions 0 and 1.
const DIM_PIXEL: u32 = 0u;
// The lens' 2D point: dimensions 2 and 3.
const DIM_LENS: u32 = 2u;
// Bounce 0's first dimension.
const DIM_BOUNCE_BASE: u32 = 4u;
// Dimensions each bounce takes: three padding groups.
const DIMS_PER_BOUNCE: u32 = 12u;
// Within a bounce: the point on the sun (2D), its first group's first two dimensions.
const DIM_SUN: u32 = 0u;
// Within a bounce: the point on the environment map (2D), the sun's group's third and fourth.
const DIM_ENVIRONMENT: u32 = 2u;
// Within a bounce: the point on the sphere light (2D), its second group's first two.
const DIM_SPHERE_LIGHT: u32 = 4u;
// Within a bounce: the fog's free-flight distance (1D), the sphere light's group's third (the
// ray leaving the bounce's vertex takes it; a scattering event in the fog is the next vertex).
const DIM_FOG: u32 = 6u;
// Within a bounce: the BSDF's direction (2D), its third group's first two.
const DIM_BSDF: u32 = 8u;
// Within a bounce: which BSDF lobe (1D), in the direction's group.
const DIM_BSDF_CHOICE: u32 = 10u;
// Within a bounce: Russian roulette (1D).
const DIM_ROULETTE: u32 = 11u;

// Dimensions of the Sobol' sequence drawn; dimension d is Sobol' dimension d % SOBOL_DIMS
// of the padding group d / SOBOL_DIMS (Burley's padding).
const SOBOL_DIMS: u32 = 4u;
// What the index shuffle's seed is salted with.
const SEED_SHUFFLE: u32 = 0x53485546u;
// What the scramble's seed is salted with.
const SEED_SCRAMBLE: u32 = 0x5343524du;

// A 32-bit integer hash: the PCG hash (Jarzynski and Olano, "Hash Functions for GPU
// Rendering", JCGT 2020), one LCG step then PCG's output permutation.
fn sampler_hash(x: u32) -> u32 {
    let state = x * 747796405u + 2891336453u;
    let word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

// Three numbers hashed into one: each folded into the hash of those before it.
fn hash3(a: u32, b: u32, c: u32) -> u32 {
    return sampler_hash(sampler_hash(sampler_hash(a) ^ b) ^ c);
}

// A Laine-Karras style permutation of x: each output bit is the input bit flipped by a function
// of the bits below it and the seed (multiplications by even numbers and the addition carry
// upwards only). The steps and constants are Burley's.
fn laine_karras(x: u32, seed: u32) -> u32 {
    var v = x;
    v ^= v * 0x3d20adeau;
    v = v + seed;
    v = v * ((seed >> 16u) | 1u);
    v ^= v * 0x05526c56u;
    v ^= v * 0x53a22864u;
    return v;
}

// Nested uniform (Owen) scrambling of a 0.32 fixed-point number: laine_karras on the bits
// reversed, so that each bit is flipped by a function of the bits above it.
fn nested_uniform_scramble(x: u32, seed: u32) -> u32 {
    return reverseBits(laine_karras(reverseBits(x), seed));
}

// Point `index` of the unscrambled Sobol' sequence in dimension `dim` (< SOBOL_DIMS), as a
// 0.32 fixed-point number: the XOR of the direction numbers of the index's set bits. Dimension
// 0's numbers are the bits 1 << (31 - k), whose XOR is the index's bits reversed; dimension 1's
// are Pascal's triangle mod 2 (pascal_xor); dimensions 2 and 3 are their numbers written out
// (sobol_dim2, sobol_dim3). None loops over the index's bits or reads a table: the same bits.
fn sobol(index: u32, dim: u32) -> u32 {
    if dim == 0u {
        return reverseBits(index);
    }
    if dim == 1u {
        return reverseBits(pascal_xor(index));
    }
    if dim == 2u {
        return sobol_dim2(index);
    }
    return sobol_dim3(index);
}

// Sobol' dimension 1 before its bits are reversed: bit j of the result is the XOR of the
// index's bits k with C(k, j) odd, which by Lucas' theorem are the k whose set bits include
// j's; five shifted XORs sum each bit's supersets, one bit of j at a time.
fn pascal_xor(index: u32) -> u32 {
    var y = index;
    y ^= (y >> 1u) & 0x55555555u;
    y ^= (y >> 2u) & 0x33333333u;
    y ^= (y >> 4u) & 0x0f0f0f0fu;
    y ^= (y >> 8u) & 0x00ff00ffu;
    y ^= (y >> 16u) & 0x0000ffffu;
    return y;
}

// Direction number `direction` where bit k of the index is set, else 0: a mask, no branch.
fn direction_if(index: u32, k: u32, direction: u32) -> u32 {
    return direction & (0u - ((index >> k) & 1u));
}

// Sobol' dimension 2 (Joe and Kuo's 3): the XOR of its direction numbers (src/cpu/sobol.rs's
// SOBOL_DIRECTIONS[64..96]) over the index's set bits, as 32 masks written out, so that a
// draw is straight-line code: no loop over the bits, no lookup in a table.
fn sobol_dim2(index: u32) -> u32 {
    return direction_if(index, 0u, 0x80000000u) ^ direction_if(index, 1u, 0xc0000000u)
        ^ direction_if(index, 2u, 0x60000000u) ^ direction_if(index, 3u, 0x90000000u)
        ^ direction_if(index, 4u, 0xe8000000u) ^ direction_if(index, 5u, 0x5c000000u)
        ^ direction_if(index, 6u, 0x8e000000u) ^ direction_if(index, 7u, 0xc5000000u)
        ^ direction_if(index, 8u, 0x68800000u) ^ direction_if(index, 9u, 0x9cc00000u)
        ^ direction_if(index, 10u, 0xee600000u) ^ direction_if(index, 11u, 0x55900000u)
        ^ direction_if(index, 12u, 0x80680000u) ^ direction_if(index, 13u, 0xc09c0000u)
        ^ direction_if(index, 14u, 0x60ee0000u) ^ direction_if(index, 15u, 0x90550000u)
        ^ direction_if(index, 16u, 0xe8808000u) ^ direction_if(index, 17u, 0x5cc0c000u)
        ^ direction_if(index, 18u, 0x8e606000u) ^ direction_if(index, 19u, 0xc5909000u)
        ^ direction_if(index, 20u, 0x6868e800u) ^ direction_if(index, 21u, 0x9c9c5c00u)
        ^ direction_if(index, 22u, 0xeeee8e00u) ^ direction_if(index, 23u, 0x5555c500u)
        ^ direction_if(index, 24u, 0x8000e880u) ^ direction_if(index, 25u, 0xc0005cc0u)
        ^ direction_if(index, 26u, 0x60008e60u) ^ direction_if(index, 27u, 0x9000c590u)
        ^ direction_if(index, 28u, 0xe8006868u) ^ direction_if(index, 29u, 0x5c009c9cu)
        ^ direction_if(index, 30u, 0x8e00eeeeu) ^ direction_if(index, 31u, 0xc5005555u);
}

// Sobol' dimension 3 (Joe and Kuo's 4) as sobol_dim2: SOBOL_DIRECTIONS[96..128] written out.
fn sobol_dim3(index: u32) -> u32 {
    return direction_if(index, 0u, 0x80000000u) ^ direction_if(index, 1u, 0xc0000000u)
        ^ direction_if(index, 2u, 0x20000000u) ^ direction_if(index, 3u, 0x50000000u)
        ^ direction_if(index, 4u, 0xf8000000u) ^ direction_if(index, 5u, 0x74000000u)
        ^ direction_if(index, 6u, 0xa2000000u) ^ direction_if(index, 7u, 0x93000000u)
        ^ direction_if(index, 8u, 0xd8800000u) ^ direction_if(index, 9u, 0x25400000u)
        ^ direction_if(index, 10u, 0x59e00000u) ^ direction_if(index, 11u, 0xe6d00000u)
        ^ direction_if(index, 12u, 0x78080000u) ^ direction_if(index, 13u, 0xb40c0000u)
        ^ direction_if(index, 14u, 0x82020000u) ^ direction_if(index, 15u, 0xc3050000u)
        ^ direction_if(index, 16u, 0x208f8000u) ^ direction_if(index, 17u, 0x51474000u)
        ^ direction_if(index, 18u, 0xfbea2000u) ^ direction_if(index, 19u, 0x75d93000u)
        ^ direction_if(index, 20u, 0xa0858800u) ^ direction_if(index, 21u, 0x914e5400u)
        ^ direction_if(index, 22u, 0xdbe79e00u) ^ direction_if(index, 23u, 0x25db6d00u)
        ^ direction_if(index, 24u, 0x58800080u) ^ direction_if(index, 25u, 0xe54000c0u)
        ^ direction_if(index, 26u, 0x79e00020u) ^ direction_if(index, 27u, 0xb6d00050u)
        ^ direction_if(index, 28u, 0x800800f8u) ^ direction_if(index, 29u, 0xc00c0074u)
        ^ direction_if(index, 30u, 0x200200a2u) ^ direction_if(index, 31u, 0x50050093u);
}

// The `sobol` sampler's bits for (pixel, sample, dimension): the sample's index shuffled by a
// nested uniform scramble seeded per (pixel, padding group), the point of the group's Sobol'
// dimension there, scrambled with a seed per (pixel, dimension).
fn sobol_sample(pixel: u32, sample: u32, dim: u32) -> u32 {
    let group = dim / SOBOL_DIMS;
    let index = nested_uniform_scramble(sample, hash3(pixel, group, SEED_SHUFFLE));
    let x = sobol(index, dim % SOBOL_DIMS);
    return nested_uniform_scramble(x, hash3(pixel, dim, SEED_SCRAMBLE));
}

// The `random` sampler's bits for (pixel, sample, dimension): the three hashed, then hashed
// once more (so that no draw is a seed of the `sobol` sampler).
fn random_sample(pixel: u32, sample: u32, dim: u32) -> u32 {
    return sampler_hash(hash3(pixel, sample, dim));
}

// The bits of `sampler` (SAMPLER_SOBOL or SAMPLER_RANDOM) for (pixel, sample, dimension).
fn sample_bits(sampler: u32, pixel: u32, sample: u32, dim: u32) -> u32 {
    if sampler == SAMPLER_RANDOM {
        return random_sample(pixel, sample, dim);
    }
    return sobol_sample(pixel, sample, dim);
}

// The bits as a number in [0, 1): the top 24 bits times 2^-24, exact in f32.
fn to_unit(bits: u32) -> f32 {
    return f32(bits >> 8u) * 0x1p-24f;
}
