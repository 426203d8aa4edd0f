//! The fuzz targets' bodies, one function each (fuzz_targets/NAME.rs calls NAME), and what they
//! check of what qjulia's parsers give back: an error is one line, and a scene that loads saves
//! to a file that loads to the same scene. tests/cli/fuzz_findings.rs includes this file to replay
//! the corpora and every finding (fuzz/regressions/) in the test suite, with no libFuzzer.

use qjulia::Scene;
use qjulia::mesh::MeshOptions;
use qjulia::scene::{
    SCENE_TEXT_LIMIT, SceneError, SceneLoader, SceneSource, scene_from_exr_bytes,
    scene_from_png_bytes,
};

/// A target's body: one input, checked (a panic is a finding).
pub type Target = fn(&[u8]);

/// Every target, by name, as fuzz/fuzz_targets/ and fuzz/corpus/ name them.
pub const TARGETS: [(&str, Target); 9] = [
    ("scene_toml", scene_toml),
    ("set", set),
    ("png_scene", png_scene),
    ("exr_scene", exr_scene),
    ("animation", animation),
    ("mesh_box", mesh_box),
    ("merge_part", merge_part),
    ("map_exr", map_exr),
    ("map_hdr", map_hdr),
];

/// Panics unless `message` is one non-empty line: what the CLI prints after "error: ".
pub fn one_line(message: impl std::fmt::Display) {
    let text = message.to_string();
    assert!(!text.is_empty(), "an empty error message");
    assert!(
        !text.contains('\n'),
        "an error of more than one line: {text:?}"
    );
}

/// Loads `text` as a scene file's TOML, as `--scene FILE` does (its length checked first).
pub fn load(text: &str) -> Result<SceneLoader, SceneError> {
    let source = SceneSource::File("fuzz.toml".into());
    qjulia::scene::check_scene_length(text, &source)?;
    let mut loader = SceneLoader::new();
    loader.toml_str(text, source)?;
    Ok(loader)
}

/// Panics unless the scene's own TOML loads back to the same scene (the saved file is the
/// scene).
pub fn round_trip(scene: &Scene) {
    let saved = scene.to_toml();
    let again = load(&saved)
        .and_then(|loader| loader.build())
        .unwrap_or_else(|e| panic!("a saved scene does not load: {e}\n{saved}"));
    assert_eq!(
        again.to_toml(),
        saved,
        "a saved scene loads to another scene"
    );
}

/// The scene TOML loader: any text ends in a scene or a one-line error, and a scene that loads
/// saves to a file that loads to the same scene.
pub fn scene_toml(data: &[u8]) {
    // A file that is not UTF-8 is refused before the loader sees it.
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    match load(text).and_then(|loader| loader.build()) {
        Ok(scene) => round_trip(&scene),
        Err(e) => one_line(e),
    }
}

/// `--set KEY=VALUE`: the input's NUL-separated pieces (NUL is the one byte no argument holds)
/// are `--set`s over the default scene, in order; the result is a scene (that saves and loads
/// back) or a one-line error.
pub fn set(data: &[u8]) {
    // Arguments reach clap as UTF-8 (an argument that is not is refused there).
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let mut loader = SceneLoader::new();
    for raw in text.split('\0') {
        if let Err(e) = loader.set(raw) {
            one_line(e);
            return;
        }
    }
    match loader.build() {
        Ok(scene) => round_trip(&scene),
        Err(e) => one_line(e),
    }
}

/// The PNG scene reader (`--scene FILE.png`, its `qjulia-scene` iTXt chunk): any bytes end in
/// the scene's text or a one-line error, and the text goes on to the loader.
pub fn png_scene(data: &[u8]) {
    let source = SceneSource::File("fuzz.png".into());
    match scene_from_png_bytes(data, &source) {
        Ok(text) => {
            assert!(
                text.len() <= SCENE_TEXT_LIMIT,
                "a chunk inflated past the limit"
            );
            match load(&text).and_then(|loader| loader.build()) {
                Ok(scene) => round_trip(&scene),
                Err(e) => one_line(e),
            }
        }
        Err(e) => one_line(e),
    }
}

/// The OpenEXR scene reader (`--scene FILE.exr`, its `qjulia-scene` header attribute): any bytes
/// end in the scene's text or a one-line error, and the text goes on to the loader.
pub fn exr_scene(data: &[u8]) {
    let source = SceneSource::File("fuzz.exr".into());
    match scene_from_exr_bytes(data, &source) {
        Ok(text) => match load(&text).and_then(|loader| loader.build()) {
            Ok(scene) => round_trip(&scene),
            Err(e) => one_line(e),
        },
        Err(e) => one_line(e),
    }
}

/// The `[animation]` table and its keys: a scene file with one ends in a scene and an animation
/// or a one-line error; every frame's scene is valid data, and the animation's file loads back
/// to the same animation.
pub fn animation(data: &[u8]) {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let (base, animation) = match load(text).and_then(|l| l.build_animated()) {
        Ok(built) => built,
        Err(e) => return one_line(e),
    };
    // The first, a middle and the last frame.
    let last = animation.frames.saturating_sub(1);
    for frame in [0, last / 2, last] {
        let scene = animation.scene_at(&base, frame);
        assert!(
            scene.fractal.c.iter().all(|x| x.is_finite()),
            "frame {frame}'s c is not finite"
        );
    }
    let saved = qjulia::scene::animation::scene_file(&base, &animation);
    let (base2, animation2) = load(&saved)
        .and_then(|l| l.build_animated())
        .unwrap_or_else(|e| panic!("a saved animation does not load: {e}\n{saved}"));
    assert_eq!(
        qjulia::scene::animation::scene_file(&base2, &animation2),
        saved,
        "a saved animation loads to another"
    );
}

/// `mesh --box X0,Y0,Z0,X1,Y1,Z1`: any text ends in a box of finite corners, each below the
/// other, or a one-line error.
pub fn mesh_box(data: &[u8]) {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    match MeshOptions::parse_box(text) {
        Ok([low, high]) => {
            for k in 0..3 {
                assert!(
                    low[k].is_finite() && high[k].is_finite(),
                    "{low:?} {high:?}"
                );
                assert!(low[k] < high[k], "an empty box {low:?} {high:?}");
            }
        }
        Err(e) => one_line(e),
    }
}

/// The memory a part's pixels may take here (64 MiB): a header claiming more is refused, as the
/// host's own memory bounds a real merge. libFuzzer's -malloc_limit_mb (256) holds the reader
/// to it.
const MEMORY: u64 = 64 << 20;

/// `merge`'s part reader (a partial EXR of `render --tile`): any bytes end in a whole part or a
/// one-line error, and never allocates for more pixels than its budget.
pub fn merge_part(data: &[u8]) {
    if let Err(e) = qjulia::tile::check_part_bytes(data, std::path::Path::new("fuzz.exr"), MEMORY) {
        one_line(e);
    }
}

/// The memory a fuzzed environment map may take: a header that asks for more is refused before
/// its pixels are read.
const MAP_BUDGET: u64 = 64 << 20;

/// The environment map's OpenEXR reader (`environment.file`): any bytes end in a map exactly
/// twice as wide as high, of finite texels >= 0, or a one-line reason.
pub fn map_exr(data: &[u8]) {
    map(data, qjulia::envmap::MapFormat::OpenExr);
}

/// The environment map's Radiance `.hdr` reader, as [`map_exr`].
pub fn map_hdr(data: &[u8]) {
    map(data, qjulia::envmap::MapFormat::Radiance);
}

fn map(data: &[u8], format: qjulia::envmap::MapFormat) {
    match qjulia::envmap::from_bytes(data, format, Some(MAP_BUDGET)) {
        Ok(m) => {
            assert_eq!(m.width, 2 * m.height);
            assert_eq!(m.texels.len(), m.width * m.height);
            assert!(
                m.texels
                    .iter()
                    .flatten()
                    .all(|c| c.is_finite() && *c >= 0.0)
            );
        }
        Err(e) => one_line(e),
    }
}
