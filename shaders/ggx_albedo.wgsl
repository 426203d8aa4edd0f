// GGX's directional and average albedo, the tables of multiple-scattering compensation (Kulla
// and Conty 2017, "Revisiting Physically Based Shading at Imageworks"): shaders/bsdf.wgsl's
// `multiscatter_eval` reads them. f32, imports nothing.
// Twin: src/cpu/ggx_albedo.rs, same names, same order (tests/architecture/twins.rs); it reads its numbers
// from this file. src/cpu/ggx_quadrature.rs makes them: `QJULIA_BLESS=1 cargo test --test
// multiscatter` writes the tables below again, and the test fails where they are not what its
// integrals give.
//
// E(mu, roughness) is the light a white (F = 1) single-scattering GGX lobe reflects from the
// direction of cosine mu, over the hemisphere; E_avg(roughness) = 2 int_0^1 E(mu) mu dmu.

// The table's cosines: mu_i = (i / (ALBEDO_MU - 1))^2, closer together toward grazing, where a
// smooth lobe's albedo falls steeply.
const ALBEDO_MU: u32 = 32u;
// The table's roughnesses: r_j = j / (ALBEDO_ROUGHNESS - 1) (the lobe's: held at the
// roughness floor, as ggx_alpha holds it).
const ALBEDO_ROUGHNESS: u32 = 32u;

// Where x in [0, 1] falls among n samples at i / (n - 1): the cell's first sample and the
// weight of its last.
struct TableCell {
    index: u32,
    weight: f32,
}

fn table_cell(x: f32, n: u32) -> TableCell {
    let s = clamp(x, 0.0, 1.0) * f32(n - 1u);
    let i = min(u32(floor(s)), n - 2u);
    return TableCell(i, s - f32(i));
}

// Entry k of the E table (row by row, a row a roughness): GGX_ALBEDO holds two entries a word,
// each a 16-bit unorm (entry 2i in the low half of word i), exact to 7.6e-6. Packed, the
// private array is half as long, which shortens the pipeline's build on lavapipe by 0.2 s of
// each process (docs/PERFORMANCE.md); the tests hold the packed numbers to the integrals.
fn albedo_entry(k: u32) -> f32 {
    let pair = unpack2x16unorm(GGX_ALBEDO[k >> 1u]);
    return select(pair.x, pair.y, (k & 1u) == 1u);
}

// The directional albedo E(mu, roughness) of a white single-scattering GGX lobe: albedo_entry,
// bilinearly between its entries in sqrt(mu) and roughness (both clamped to [0, 1]).
fn ggx_albedo(mu: f32, roughness: f32) -> f32 {
    let c = table_cell(sqrt(max(mu, 0.0)), ALBEDO_MU);
    let r = table_cell(roughness, ALBEDO_ROUGHNESS);
    let k = r.index * ALBEDO_MU + c.index;
    let e00 = albedo_entry(k);
    let e10 = albedo_entry(k + 1u);
    let e01 = albedo_entry(k + ALBEDO_MU);
    let e11 = albedo_entry(k + ALBEDO_MU + 1u);
    let low = e00 + (e10 - e00) * c.weight;
    let high = e01 + (e11 - e01) * c.weight;
    return low + (high - low) * r.weight;
}

// The average albedo E_avg(roughness) = 2 int_0^1 E(mu) mu dmu: GGX_AVERAGE_ALBEDO, linearly
// between its entries.
fn ggx_average_albedo(roughness: f32) -> f32 {
    let r = table_cell(roughness, ALBEDO_ROUGHNESS);
    let low = GGX_AVERAGE_ALBEDO[r.index];
    let high = GGX_AVERAGE_ALBEDO[r.index + 1u];
    return low + (high - low) * r.weight;
}

// The tables (private variables, not consts: they are indexed by runtime values): E row by row,
// a row a roughness, two 16-bit unorm entries a word (albedo_entry), then E_avg in f32. Written
// by src/cpu/ggx_quadrature.rs's `wgsl_tables`.
var<private> GGX_ALBEDO: array<u32, 512> = array<u32, 512>(
    0xeefbf3dcu, 0xffbffea0u, 0xfff7ffebu, 0xfffdfffbu, 0xfffefffeu, 0xfffffffeu, 0xffffffffu, 0xffffffffu,
    0xffffffffu, 0xffffffffu, 0xffffffffu, 0xffffffffu, 0xffffffffu, 0xffffffffu, 0xffffffffu, 0xffffffffu,
    0xe45efafbu, 0xfe23f6ecu, 0xffc7ff71u, 0xfff1ffe4u, 0xfffafff7u, 0xfffdfffcu, 0xfffefffdu, 0xfffefffeu,
    0xfffefffeu, 0xffffffffu, 0xffffffffu, 0xffffffffu, 0xffffffffu, 0xffffffffu, 0xffffffffu, 0xffffffffu,
    0xf3dbfeb5u, 0xec15e45du, 0xfc10f6ebu, 0xff06fe23u, 0xffa8ff71u, 0xffd9ffc6u, 0xffebffe4u, 0xfff4fff0u,
    0xfff8fff6u, 0xfffafff9u, 0xfffcfffbu, 0xfffdfffcu, 0xfffdfffdu, 0xfffdfffdu, 0xfffefffeu, 0xfffefffeu,
    0xfa39ff6bu, 0xe459eccfu, 0xf048e7eau, 0xfad2f6e8u, 0xfe20fcf5u, 0xff2ffecau, 0xff96ff6eu, 0xffc4ffb1u,
    0xffdaffd1u, 0xffe7ffe1u, 0xffeeffebu, 0xfff2fff0u, 0xfff5fff4u, 0xfff7fff6u, 0xfff8fff7u, 0xfff9fff9u,
    0xfcadffabu, 0xe9a1f3d2u, 0xe624e44eu, 0xf22bec06u, 0xfa03f6deu, 0xfd48fc04u, 0xfea0fe18u, 0xff3afefbu,
    0xff86ff66u, 0xffafff9eu, 0xffc7ffbdu, 0xffd5ffcfu, 0xffdeffdau, 0xffe4ffe2u, 0xffe8ffe7u, 0xffebffeau,
    0xfdd6ffc9u, 0xef7bf7ccu, 0xe437e7edu, 0xe95fe536u, 0xf328ee81u, 0xf96bf6cau, 0xfc88fb42u, 0xfe09fd6au,
    0xfecdfe7bu, 0xff37ff09u, 0xff73ff59u, 0xff98ff88u, 0xffb0ffa5u, 0xffbfffb8u, 0xffcaffc5u, 0xffd2ffceu,
    0xfe77ffd8u, 0xf3a9fa1cu, 0xe6d4ec92u, 0xe499e40eu, 0xebc4e79bu, 0xf3b0effeu, 0xf8e8f6a6u, 0xfbd4fa97u,
    0xfd6bfcbeu, 0xfe4efdedu, 0xfed2fe99u, 0xff23feffu, 0xff56ff3fu, 0xff77ff68u, 0xff8eff84u, 0xff9fff97u,
    0xfed6ffe1u, 0xf677fb87u, 0xea7bf067u, 0xe3cae5fau, 0xe64ae410u, 0xed58e9a4u, 0xf3e9f0dcu, 0xf866f66au,
    0xfb24f9f2u, 0xfcc4fc0fu, 0xfdbefd50u, 0xfe58fe14u, 0xfebbfe8fu, 0xfefcfedeu, 0xff28ff14u, 0xff47ff39u,
    0xff11ffe7u, 0xf859fc6fu, 0xedcaf33fu, 0xe52fe8d4u, 0xe37ce362u, 0xe7e1e52au, 0xee4ceb12u, 0xf3e0f147u,
    0xf7d5f60eu, 0xfa69f944u, 0xfc0bfb52u, 0xfd16fc9fu, 0xfdc3fd76u, 0xfe37fe03u, 0xfe85fe62u, 0xfebdfea3u,
    0xff37ffeau, 0xf9a0fd06u, 0xf06af548u, 0xe75ceb92u, 0xe2cbe455u, 0xe410e2c8u, 0xe902e646u, 0xeebeebebu,
    0xf399f154u, 0xf727f588u, 0xf996f87du, 0xfb38fa7cu, 0xfc4ffbd1u, 0xfd0dfcb7u, 0xfd8ffd54u, 0xfdecfdc1u,
    0xff4effecu, 0xfa7cfd6au, 0xf262f6b8u, 0xe98bedd9u, 0xe355e5ebu, 0xe1e0e1fbu, 0xe4ace2dcu, 0xe99ce703u,
    0xeebdec3cu, 0xf30cf106u, 0xf64cf4cdu, 0xf89ef78fu, 0xfa3ef981u, 0xfb5ffadbu, 0xfc2bfbceu, 0xfcbdfc7au,
    0xff5dffedu, 0xfb0ffdaau, 0xf3cdf7b4u, 0xeb67ef99u, 0xe460e78eu, 0xe0e4e21du, 0xe176e0b6u, 0xe4f4e2f3u,
    0xe9ace742u, 0xee4eec0eu, 0xf233f05du, 0xf537f3d0u, 0xf771f66au, 0xf90ff851u, 0xfa3bf9b1u, 0xfb14fab0u,
    0xff64ffeeu, 0xfb6bfdd0u, 0xf4c5f85bu, 0xecd4f0dau, 0xe579e8f3u, 0xe09be2a3u, 0xdf3adf79u, 0xe101dfc8u,
    0xe4c1e2b7u, 0xe932e6f4u, 0xed6ceb5fu, 0xf101ef4eu, 0xf3d6f283u, 0xf600f4ffu, 0xf79ef6deu, 0xf8d3f844u,
    0xff67ffeeu, 0xfb9ffde2u, 0xf562f8beu, 0xedd2f1afu, 0xe65fe9fbu, 0xe09ce331u, 0xddaadebfu, 0xddbedd5au,
    0xe032debcu, 0xe3fbe1fdu, 0xe826e611u, 0xec0eea29u, 0xef66edceu, 0xf21af0d4u, 0xf438f33au, 0xf5d9f516u,
    0xff65ffedu, 0xfbb3fde6u, 0xf5b4f8edu, 0xee68f226u, 0xe6f3ea9eu, 0xe09de391u, 0xdc79de38u, 0xdb07db69u,
    0xdc0fdb45u, 0xdedbdd4au, 0xe294e0a7u, 0xe67fe48cu, 0xea28e861u, 0xed51ebceu, 0xefedeeb1u, 0xf205f109u,
    0xff60ffecu, 0xfbadfdddu, 0xf5c9f8f2u, 0xeea2f24fu, 0xe72ceae0u, 0xe070e3a6u, 0xdb65dda8u, 0xd8a6d9b7u,
    0xd849d82fu, 0xd9e9d8e3u, 0xdcdddb44u, 0xe079dea0u, 0xe42fe257u, 0xe7a5e5f6u, 0xeaaee939u, 0xed3bec04u,
    0xff58ffebu, 0xfb92fdcau, 0xf5abf8d3u, 0xee8bf235u, 0xe707eac8u, 0xdffce365u, 0xda3ddce7u, 0xd66ad80fu,
    0xd4c3d551u, 0xd524d4b8u, 0xd71dd5f7u, 0xda1dd885u, 0xdd98dbd2u, 0xe121df60u, 0xe472e2d4u, 0xe763e5f8u,
    0xff4effe9u, 0xfb65fdafu, 0xf561f896u, 0xee2cf1e1u, 0xe689ea5du, 0xdf34e2c9u, 0xd8e2dbe0u, 0xd427d64au,
    0xd159d280u, 0xd080d0b1u, 0xd15ed0beu, 0xd386d250u, 0xd67fd4f0u, 0xd9d9d826u, 0xdd3edb8fu, 0xe072dee1u,
    0xff42ffe8u, 0xfb29fd8du, 0xf4f2f840u, 0xed90f15au, 0xe5b9e9a8u, 0xde16e1d7u, 0xd741da88u, 0xd1bed44eu,
    0xcdebcf9bu, 0xcbe8ccafu, 0xcb9ecb8fu, 0xccc6cc09u, 0xcf01cdc8u, 0xd1e8d065u, 0xd522d380u, 0xd868d6c7u,
    0xff35ffe6u, 0xfadffd64u, 0xf463f7d4u, 0xecbcf0a8u, 0xe49ee8b1u, 0xdca2e092u, 0xd54fd8dbu, 0xcf1bd20bu,
    0xca5dcc89u, 0xc745c89bu, 0xc5d6c65au, 0xc5e7c5b2u, 0xc734c66bu, 0xc96cc838u, 0xcc39cac5u, 0xcf53cdc1u,
    0xff25ffe4u, 0xfa89fd35u, 0xf3b7f753u, 0xebb7efd0u, 0xe33ee780u, 0xdadcdf02u, 0xd30bd6dau, 0xcc30cf79u,
    0xc69ec93au, 0xc286c460u, 0xbffac10eu, 0xbeebbf45u, 0xbf2dbee5u, 0xc082bfb9u, 0xc2a4c17eu, 0xc550c3edu,
    0xff14ffe1u, 0xfa29fd01u, 0xf2f1f6c2u, 0xea86eed5u, 0xe1a0e619u, 0xd8cbdd2cu, 0xd075d48au, 0xc8facc97u,
    0xc2a0c5a5u, 0xbd9abff0u, 0xba01bb9fu, 0xb7d3b8bdu, 0xb6f8b73du, 0xb747b6feu, 0xb88ab7cdu, 0xba87b975u,
    0xff02ffdfu, 0xf9bffcc8u, 0xf215f621u, 0xe92fedbcu, 0xdfcce483u, 0xd674db17u, 0xcd92d1efu, 0xc576c967u,
    0xbe5fc1c7u, 0xb87abb44u, 0xb3e2b604u, 0xb09eb216u, 0xaea3af79u, 0xadd6ae19u, 0xae12add6u, 0xaf2aae86u,
    0xfeeeffdcu, 0xf94dfc8bu, 0xf124f571u, 0xe7b5ec87u, 0xddc6e2c4u, 0xd3e0d8cau, 0xca68cf11u, 0xc1a9c5edu,
    0xb9dabda1u, 0xb323b65au, 0xad9cb038u, 0xa94fab4eu, 0xa638a79du, 0xa448a51cu, 0xa366a3b7u, 0xa371a350u,
    0xfed9ffdau, 0xf8d2fc4au, 0xf021f4b5u, 0xe61ceb3au, 0xdb94e0dfu, 0xd113d64bu, 0xc6fdcbf6u, 0xbd98c231u,
    0xb515b938u, 0xad95b133u, 0xa72daa3du, 0xa1e6a465u, 0x9dc19fb0u, 0x9ab29c18u, 0x98ab998fu, 0x97939803u,
    0xfec3ffd7u, 0xf850fc05u, 0xef0df3edu, 0xe468e9d7u, 0xd93bded8u, 0xce16d3a0u, 0xc35ac8a6u, 0xb94bbe3au,
    0xb016b493u, 0xa7d5abd5u, 0xa09aa416u, 0x9a6b9d61u, 0x954897b9u, 0x912a9319u, 0x8e048f79u, 0x8bc78ccau,
    0xfeacffd4u, 0xf7c7fbbdu, 0xedeaf31au, 0xe29be860u, 0xd6c0dcb4u, 0xcaedd0ceu, 0xbf86c527u, 0xb4caba0fu,
    0xaae4afbbu, 0xa1eaa649u, 0x99ea9dcau, 0x92e59648u, 0x8cdb8fc1u, 0x87c28a31u, 0x8391858eu, 0x803a81cbu,
    0xfe94ffd0u, 0xf738fb71u, 0xecb9f23du, 0xe0b8e6d7u, 0xd427da76u, 0xc7a0cddbu, 0xbb87c181u, 0xb01eb5bau,
    0xa589aab7u, 0x9bdea096u, 0x93259763u, 0x8b5e8f24u, 0x848387d4u, 0x7e8c816cu, 0x796c7be2u, 0x75167728u,
    0xfe7bffcdu, 0xf6a3fb23u, 0xeb7cf158u, 0xdec2e53fu, 0xd174d821u, 0xc433cacau, 0xb766bdb9u, 0xab4eb141u,
    0xa00fa592u, 0x95bb9ac7u, 0x8c5790ebu, 0x83e187ffu, 0x7c4f7ffcu, 0x759678d8u, 0x6fa97287u, 0x6a7a6cfau,
    0xfe61ffcau, 0xf609fad1u, 0xea34f06au, 0xdcbae398u, 0xceaad5b9u, 0xc0acc7a1u, 0xb329b9d6u, 0xa664acacu,
    0x9a7fa054u, 0x8f8b94e6u, 0x858a8a6cu, 0x7c7880e4u, 0x74497845u, 0x6cef7082u, 0x665a698du, 0x607c6355u,
    0xfe46ffc6u, 0xf56afa7du, 0xe8e2ef75u, 0xdaa4e1e4u, 0xcbcdd33fu, 0xbd0fc463u, 0xaed7b5ddu, 0xa167a803u,
    0x94e29b05u, 0x89588efdu, 0x7eca83f1u, 0x753079dfu, 0x6c7d70bau, 0x64a16875u, 0x5d8c60ffu, 0x572b5a46u,
    0xfe2bffc3u, 0xf4c7fa27u, 0xe786ee78u, 0xd880e025u, 0xc8e1d0b6u, 0xb962c115u, 0xaa75b1d4u, 0x9c5ea34cu,
    0x8f4195afu, 0x832c8915u, 0x781f7d85u, 0x6e1272f9u, 0x64f56966u, 0x5cb760bbu, 0x554658e6u, 0x4e8e51d3u,
);

var<private> GGX_AVERAGE_ALBEDO: array<f32, 32> = array<f32, 32>(
    0.999999, 0.9999924, 0.9998982, 0.9995603, 0.9987489, 0.99717176, 0.9946656, 0.99100727,
    0.9858218, 0.97890455, 0.97014135, 0.95932835, 0.94628304, 0.9309305, 0.91324306, 0.8932084,
    0.87087286, 0.8463441, 0.81977254, 0.79135895, 0.76134354, 0.730001, 0.6976304, 0.66454667,
    0.6310687, 0.59750956, 0.5641662, 0.5313125, 0.49919215, 0.4680142, 0.43795118, 0.4091385,
);
