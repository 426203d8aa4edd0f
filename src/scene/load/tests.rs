//! The loader's unit tests: layers, `--set`, errors naming their source and key, validation.

use super::*;

fn build(layers: &[&str]) -> Result<Scene, SceneError> {
    let mut l = SceneLoader::new();
    for s in layers {
        l.set(s)?;
    }
    l.build()
}

#[test]
fn defaults_round_trip_through_toml() {
    let s = Scene::default();
    let mut l = SceneLoader::new();
    l.toml_str(&s.to_toml(), SceneSource::File("x.toml".into()))
        .unwrap();
    assert_eq!(l.build().unwrap(), s);
}

#[test]
fn set_overrides_and_bare_words() {
    let s = build(&[
        "fractal.c=[0,0,0,0]",
        "image.width=64",
        "shading.shadows=false",
    ])
    .unwrap();
    assert_eq!(s.fractal.c, [0.0; 4]);
    assert_eq!(s.image.width, 64);
    assert!(!s.shading.shadows);
    let e = build(&["image.width=wide"]).unwrap_err();
    assert_eq!(
        e.to_string(),
        "--set image.width=wide: image.width must be an integer"
    );
}

#[test]
fn errors_name_source_and_key() {
    let e = build(&["fractal.epsilon=nan"]).unwrap_err();
    assert_eq!(
        e.to_string(),
        "--set fractal.epsilon=nan: fractal.epsilon must be finite"
    );
    let mut l = SceneLoader::new();
    l.toml_str(
        "[camera]\nfov_y_degrees = 190\n",
        SceneSource::File("scene.toml".into()),
    )
    .unwrap();
    assert_eq!(
        l.build().unwrap_err().to_string(),
        "scene.toml: camera.fov_y_degrees = 190: must be in (0, 180)"
    );
    let e = build(&["fractal.colour=1"]).unwrap_err();
    assert_eq!(e.key.as_deref(), Some("fractal.colour"));
    assert!(e.to_string().contains("unknown key fractal.colour"), "{e}");
    let e = build(&["fractal.c=[1,2,3]"]).unwrap_err();
    assert!(
        e.to_string()
            .contains("must be an array of 4 numbers, not 3"),
        "{e}"
    );
    let e = build(&["camera.eye=[0,0,0]"]).unwrap_err();
    assert_eq!(e.key.as_deref(), Some("camera.eye"));
    let e = build(&["camera.up=[0,0,2]"]).unwrap_err();
    assert_eq!(e.key.as_deref(), Some("camera.up"));
    let e = build(&["image.height=0"]).unwrap_err();
    assert!(e.to_string().contains("must be in [1, 65536]"), "{e}");
}

#[test]
fn view2d_and_image_view_are_read_and_checked() {
    let s = build(&[
        "view2d.center=[-0.5, 0.25]",
        "view2d.extent=0.5",
        "view2d.max_iterations=1000",
        "image.view=divergence",
    ])
    .unwrap();
    assert_eq!(s.view2d.center, [-0.5, 0.25]);
    assert_eq!(s.view2d.extent, 0.5);
    assert_eq!(s.view2d.max_iterations, 1000);
    assert_eq!(s.image.view, super::super::View::Divergence);
    for (set, message) in [
        (
            "view2d.extent=0",
            "--set view2d.extent=0: view2d.extent must be > 0",
        ),
        ("view2d.extent=-2", "view2d.extent must be > 0"),
        ("view2d.extent=inf", "view2d.extent must be finite"),
        (
            "view2d.max_iterations=0",
            "view2d.max_iterations must be in [1, 100000]",
        ),
        (
            "view2d.max_iterations=100001",
            "view2d.max_iterations must be in [1, 100000]",
        ),
        (
            "view2d.center=[1]",
            "view2d.center must be an array of 2 numbers, not 1",
        ),
        ("view2d.center=[0, nan]", "view2d.center must be finite"),
        (
            "image.view=normals",
            "image.view must be one of \"shaded\", \"steps\", \"divergence\"",
        ),
    ] {
        let e = build(&[set]).unwrap_err();
        assert!(e.to_string().contains(message), "{set}: {e}");
        assert_eq!(e.key.as_deref(), set.split('=').next(), "{set}");
    }
}

#[test]
fn slice_basis_is_reorthonormalised_within_tolerance_only() {
    let s = build(&["slice.x=[1.0004,0,0,0]"]).unwrap();
    assert_eq!(s.slice.x, [1.0, 0.0, 0.0, 0.0]);
    let e = build(&["slice.y=[0.1,1,0,0]"]).unwrap_err();
    assert_eq!(e.key.as_deref(), Some("slice.y"));
}

#[test]
fn later_layers_win() {
    let mut l = SceneLoader::new();
    l.toml_str(
        "[image]\nwidth = 10\nheight = 20\n",
        SceneSource::File("a.toml".into()),
    )
    .unwrap();
    l.flag("image.width", Value::Integer(30), "--width 30");
    l.set("image.width=40").unwrap();
    let s = l.build().unwrap();
    assert_eq!((s.image.width, s.image.height), (40, 20));
}
