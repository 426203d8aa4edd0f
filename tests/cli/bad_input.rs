//! Bad input everywhere it enters, fuzzed: random and mutated scenes through the loader (TOML
//! files and `--set` layers), a sample of them through the binary, and the explorer's open.
//! Never a panic; a one-line error naming the key; exit 2; nothing written; in the explorer the
//! previous scene kept.

use crate::common;

use proptest::prelude::*;
use qjulia::scene::{KEYS, Scene, SceneLoader, SceneSource};

/// A TOML value of any type, including the troublesome ones.
fn value() -> impl Strategy<Value = String> {
    let number = prop_oneof![
        Just("nan".to_string()),
        Just("inf".to_string()),
        Just("-inf".to_string()),
        Just("0".to_string()),
        Just("-1".to_string()),
        Just("1e300".to_string()),
        Just("99999999999".to_string()),
        any::<i32>().prop_map(|i| i.to_string()),
        (-1e6f64..1e6).prop_map(|f| format!("{f:?}")),
        (0.0f64..200.0).prop_map(|f| format!("{f:?}")),
    ];
    let array =
        prop::collection::vec(number.clone(), 0..6).prop_map(|v| format!("[{}]", v.join(", ")));
    prop_oneof![
        number,
        array,
        Just("true".to_string()),
        Just("\"text\"".to_string()),
        Just("[1, \"a\", 3]".to_string()),
        Just("{ x = 1 }".to_string()),
        Just("[[1, 2], [3]]".to_string()),
        "[a-z]{1,8}",
    ]
}

/// A key: mostly real ones, sometimes unknown or malformed.
fn key() -> impl Strategy<Value = String> {
    prop_oneof![
        8 => prop::sample::select(KEYS).prop_map(str::to_string),
        1 => "[a-z]{1,6}\\.[a-z_]{1,10}",
        1 => prop::sample::select(KEYS).prop_map(|k| format!("{k}.x")),
        1 => prop::sample::select(&["fractal", "camera", "image", ""][..]).prop_map(str::to_string),
    ]
}

/// Checks what a loader gave: a valid scene, or one clean line naming what is wrong.
fn check(result: Result<Scene, qjulia::scene::SceneError>) -> Result<(), TestCaseError> {
    match result {
        Ok(scene) => {
            // Whatever loads is valid: it survives a round trip and has a finite camera.
            let mut again = SceneLoader::new();
            again
                .toml_str(&scene.to_toml(), SceneSource::Default)
                .unwrap();
            prop_assert_eq!(again.build().unwrap(), scene.clone());
            let frame = scene.camera_frame();
            prop_assert!(
                frame
                    .forward
                    .iter()
                    .chain(&frame.right)
                    .chain(&frame.up)
                    .all(|v| v.is_finite())
            );
        }
        Err(e) => {
            let line = e.to_string();
            prop_assert!(!line.contains('\n'), "multi-line error: {line:?}");
            prop_assert!(!line.is_empty());
            if let Some(k) = &e.key {
                prop_assert!(line.contains(k.as_str()), "{line:?} does not name {k}");
            }
        }
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 600, ..ProptestConfig::default() })]

    #[test]
    fn random_set_layers_never_panic(sets in prop::collection::vec((key(), value()), 1..5)) {
        let mut loader = SceneLoader::new();
        let mut result = Ok(());
        for (k, v) in &sets {
            result = result.and_then(|()| loader.set(&format!("{k}={v}")));
        }
        check(result.and_then(|()| loader.build()))?;
    }

    #[test]
    fn random_scene_files_never_panic(entries in prop::collection::vec((key(), value()), 0..8)) {
        let text: String = entries.iter().map(|(k, v)| format!("{} = {v}\n", if k.is_empty() { "x" } else { k })).collect();
        let mut loader = SceneLoader::new();
        let result = loader.toml_str(&text, SceneSource::File("fuzz.toml".into())).and_then(|()| loader.build());
        check(result)?;
    }

    #[test]
    fn mutated_scene_files_never_panic(cuts in prop::collection::vec((any::<prop::sample::Index>(), any::<u8>()), 1..6)) {
        let mut bytes = Scene::default().to_toml().into_bytes();
        for (at, byte) in cuts {
            let i = at.index(bytes.len());
            bytes[i] = byte;
        }
        let text = String::from_utf8_lossy(&bytes);
        let mut loader = SceneLoader::new();
        let result = loader.toml_str(&text, SceneSource::File("mutated.toml".into())).and_then(|()| loader.build());
        check(result)?;
    }
}

/// Named bad inputs through the binary: exit 2, one line naming the key, nothing written.
#[test]
fn the_binary_refuses_bad_scenes_cleanly() {
    let cases: &[(&str, &str)] = &[
        ("camera.eye=[0, 0, 0]", "camera.eye"),
        ("camera.up=[0, 0, 5]", "camera.up"),
        ("slice.x=[0, 1, 0, 0]", "slice.x"),
        ("slice.z=[0, 0, 0, 0]", "slice.z"),
        ("camera.fov_y_degrees=0", "camera.fov_y_degrees"),
        ("camera.fov_y_degrees=180", "camera.fov_y_degrees"),
        ("fractal.epsilon=-0.1", "fractal.epsilon"),
        ("fractal.max_iterations=0", "fractal.max_iterations"),
        ("fractal.max_steps=2000000", "fractal.max_steps"),
        ("image.width=70000", "image.width"),
        ("image.height=0", "image.height"),
        ("fractal.c=[1, 2, 3, 4, 5]", "fractal.c"),
        ("light.position=inf", "light.position"),
        ("light.position=[1, nan, 2]", "light.position"),
        ("shading.shadows=3", "shading.shadows"),
        ("shading.background=[2, 0, 0]", "shading.background"),
        ("fractal=1", "fractal"),
        ("camera.eye.x=1", "camera.eye"),
        ("image.samples=0", "image.samples"),
        ("image.samples=4097", "image.samples"),
        ("cut.normal=[0, 0, 0]", "cut.normal"),
        ("cut.offset=nan", "cut.offset"),
        ("light.radius=-1", "light.radius"),
        ("shading.occlusion=2", "shading.occlusion"),
        ("shading.ambient=-0.5", "shading.ambient"),
        ("shading.colouring=\"plaid\"", "shading.colouring"),
        ("shading.trap_scale=0", "shading.trap_scale"),
        ("path.noise_target=-0.1", "path.noise_target"),
        ("path.noise_target=nan", "path.noise_target"),
        ("path.min_samples=0", "path.min_samples"),
        ("path.min_samples=5000", "path.min_samples"),
    ];
    let dir = tempfile::tempdir().unwrap();
    for (set, key) in cases {
        let args = [
            "render",
            "--backend",
            "cpu",
            "--set",
            set,
            "-o",
            "x.png",
            "--depth",
            "d.npy",
        ];
        common::assert_refused(dir.path(), &args, "error: --set ", key);
    }
}

/// The explorer's open: the error is shown on one line and the previous scene stays.
#[test]
fn the_explorer_keeps_its_scene_when_a_file_is_bad() {
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("bad.toml");
    std::fs::write(&bad, "[camera]\nfov_y_degrees = 190\n").unwrap();
    let scene = qjulia::scene::presets::PRESETS[4].scene();
    let mut app = qjulia::explore::ExplorerApp::with_scene(scene.clone());
    app.open(&bad);
    assert_eq!(app.scene, scene);
    let (message, is_error) = app.message().expect("an error is shown");
    assert!(
        is_error && !message.contains('\n') && message.contains("camera.fov_y_degrees"),
        "{message}"
    );
    let good = dir.path().join("good.toml");
    std::fs::write(&good, "[fractal]\nc = [0.1, 0.2, 0.3, 0.4]\n").unwrap();
    app.open(&good);
    assert_eq!(app.scene.fractal.c, [0.1, 0.2, 0.3, 0.4]);
}
