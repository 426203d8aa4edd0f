//! The `[animation]` table through the loader: its keys and defaults, keyframes written as
//! dotted keys or nested tables, `--set animation.*`, frames that follow the keyframes, and bad
//! input (one line naming the file or flag and the key; exit 2 and nothing written through the
//! binary).

use crate::common;

use qjulia::animation::{Animation, Keyframe};
use qjulia::scene::{Algebra, Scene, SceneError, SceneLoader, SceneSource, dot};

/// Builds a scene file's text (and `--set`s after it) into the scene and its animation.
fn load(toml: &str, sets: &[&str]) -> Result<(Scene, Animation), SceneError> {
    let mut l = SceneLoader::new();
    l.toml_str(toml, SceneSource::File("anim.toml".into()))?;
    for s in sets {
        l.set(s)?;
    }
    l.build_animated()
}

fn error(toml: &str, sets: &[&str]) -> String {
    load(toml, sets)
        .map(|_| ())
        .expect_err("the animation is bad")
        .to_string()
}

#[test]
fn no_animation_table_gives_the_defaults() {
    let (scene, animation) = load("", &[]).unwrap();
    assert_eq!(scene, Scene::default());
    assert_eq!(
        animation,
        Animation {
            frames: 120,
            fps: 30.0,
            path_radius: 0.08,
            keys: vec![],
        }
    );
    assert_eq!(load("[animation]\n", &[]).unwrap().1, Animation::default());
}

#[test]
fn the_table_and_its_keyframes_are_read() {
    let toml = r#"
[fractal]
epsilon = 0.002

[animation]
frames = 48
fps = 24
path_radius = 0.05

[[animation.keys]]
frame = 0
fractal.c = [-0.2, 0.6, 0.2, 0.2]
camera.eye = [0, 0, 3]

[[animation.keys]]
frame = 47
fractal.epsilon = 0.004
[animation.keys.camera]
eye = [1.0, 0.0, 2.5]
"#;
    let (scene, animation) = load(toml, &[]).unwrap();
    // The base scene has no animation in it.
    assert_eq!(scene.fractal.epsilon, 0.002);
    assert_eq!((animation.frames, animation.fps), (48, 24.0));
    assert_eq!(animation.path_radius, 0.05);
    let keys = &animation.keys;
    assert_eq!(keys.len(), 2);
    assert_eq!(keys[0].frame, 0);
    assert!(
        keys[0]
            .values
            .contains(&("fractal.c".into(), vec![-0.2, 0.6, 0.2, 0.2]))
    );
    assert!(
        keys[0]
            .values
            .contains(&("camera.eye".into(), vec![0.0, 0.0, 3.0]))
    );
    assert_eq!(
        keys[1],
        Keyframe {
            frame: 47,
            values: vec![
                ("camera.eye".into(), vec![1.0, 0.0, 2.5]),
                ("fractal.epsilon".into(), vec![0.004]),
            ],
        }
    );
    // The frames follow: keys exactly, epsilon held at the base's before its only key.
    let first = animation.scene_at(&scene, 0);
    assert_eq!(first.camera.eye, [0.0, 0.0, 3.0]);
    assert_eq!(first.fractal.epsilon, 0.004);
    let last = animation.scene_at(&scene, 47);
    assert_eq!(last.camera.eye, [1.0, 0.0, 2.5]);
    // fractal.c is keyed once: constant, no loop.
    for k in [0, 20, 47] {
        assert_eq!(animation.scene_at(&scene, k).fractal.c, scene.fractal.c);
    }
    // `render --scene anim.toml` sees the base scene only.
    let mut l = SceneLoader::new();
    l.toml_str(toml, SceneSource::File("anim.toml".into()))
        .unwrap();
    assert_eq!(l.build().unwrap(), scene);
}

#[test]
fn set_reaches_the_animation() {
    let (_, a) = load(
        "[animation]\nframes = 50\n",
        &[
            "animation.frames=10",
            "animation.fps=60",
            "animation.keys=[{frame = 9, camera.fov_y_degrees = 30}]",
        ],
    )
    .unwrap();
    assert_eq!((a.frames, a.fps), (10, 60.0));
    assert_eq!(
        a.keys,
        vec![Keyframe {
            frame: 9,
            values: vec![("camera.fov_y_degrees".into(), vec![30.0])],
        }]
    );
    // A key's frame is checked against the final frame count.
    let e = error(
        "[animation]\nframes = 50\n[[animation.keys]]\nframe = 20\n",
        &["animation.frames=10"],
    );
    assert_eq!(
        e,
        "anim.toml: animation.keys[0].frame = 20: must be in [0, 9] (animation.frames is 10)"
    );
    let e = error("", &["animation.frames=0"]);
    assert_eq!(
        e,
        "--set animation.frames=0: animation.frames must be in [1, 100000]"
    );
}

#[test]
fn octonion_keyframes_have_the_algebras_length() {
    let toml = r#"
[fractal]
algebra = "octonion"
[[animation.keys]]
frame = 3
fractal.c = [0.1, 0.2, 0.3, 0.4, 0.5, 0.0, 0.0, 0.0]
"#;
    let (scene, a) = load(toml, &[]).unwrap();
    assert_eq!(scene.fractal.c.len(), 8);
    assert_eq!(a.scene_at(&scene, 0).fractal.c[4], 0.5);
    let e = error(&toml.replace(", 0.0, 0.0, 0.0]", "]"), &[]);
    assert!(
        e.starts_with("anim.toml: animation.keys[0].fractal.c = [")
            && e.contains("must be an array of 8 numbers (fractal.algebra is \"octonion\"), not 5"),
        "{e}"
    );
}

#[test]
fn a_slice_animation_in_every_algebra_stays_orthonormal() {
    for algebra in Algebra::ALL {
        let n = algebra.dim();
        let axis = |k: usize, c: f64, s: f64, other: usize| {
            let mut v = vec![0.0; n];
            v[k] = c;
            v[other] = s;
            format!("{v:?}")
        };
        let (c, s) = (0.6f64, 0.8f64);
        // Key 0: the standard slice; key 30: x turned towards the last axis.
        let toml = format!(
            "[fractal]\nalgebra = \"{}\"\n[animation]\nframes = 31\n\
             [[animation.keys]]\nframe = 0\nslice.x = {}\n\
             [[animation.keys]]\nframe = 30\nslice.x = {}\n",
            algebra.name(),
            axis(0, 1.0, 0.0, n - 1),
            axis(0, c, s, n - 1),
        );
        let (scene, a) = load(&toml, &[]).unwrap();
        for k in 0..31 {
            let f = a.scene_at(&scene, k);
            let axes = [&f.slice.x, &f.slice.y, &f.slice.z];
            for i in 0..3 {
                for j in 0..3 {
                    let expected = if i == j { 1.0 } else { 0.0 };
                    assert!((dot(axes[i], axes[j]) - expected).abs() < 1e-12);
                }
            }
        }
        let end = a.scene_at(&scene, 30).slice.x;
        assert!((end[0] - c).abs() < 1e-12 && (end[n - 1] - s).abs() < 1e-12);
    }
}

#[test]
fn bad_animations_are_one_line_naming_the_key() {
    let cases = [
        (
            "[animation]\nframes = 0\n",
            "anim.toml: animation.frames = 0: must be in [1, 100000]",
        ),
        (
            "[animation]\nframes = 100001\n",
            "anim.toml: animation.frames = 100001: must be in [1, 100000]",
        ),
        (
            "[animation]\nframes = 2.5\n",
            "anim.toml: animation.frames = 2.5: must be an integer",
        ),
        (
            "[animation]\nfps = 0\n",
            "anim.toml: animation.fps = 0: must be > 0",
        ),
        (
            "[animation]\nfps = nan\n",
            "anim.toml: animation.fps = nan: must be finite",
        ),
        (
            "[animation]\npath_radius = -0.1\n",
            "anim.toml: animation.path_radius = -0.1: must be >= 0",
        ),
        (
            "[animation]\nspeed = 2\n",
            "anim.toml: unknown key animation.speed; the [animation] keys are frames, fps, \
             path_radius and keys",
        ),
        ("animation = 3\n", "anim.toml: animation must be a table"),
        (
            "[animation.keys]\nframe = 0\n",
            "anim.toml: animation.keys must be an array of tables ([[animation.keys]])",
        ),
        (
            "[animation]\nframes = 10\n[[animation.keys]]\nframe = 4\n[[animation.keys]]\nframe = 4\n",
            "anim.toml: animation.keys[1].frame = 4: repeats animation.keys[0]'s frame",
        ),
        (
            "[animation]\nframes = 10\n[[animation.keys]]\nframe = 10\n",
            "anim.toml: animation.keys[0].frame = 10: must be in [0, 9] (animation.frames is 10)",
        ),
        (
            "[[animation.keys]]\nframe = -1\n",
            "anim.toml: animation.keys[0].frame = -1: must be in [0, 119] (animation.frames is 120)",
        ),
        (
            "[[animation.keys]]\nfractal.c = [0, 0, 0, 0]\n",
            "anim.toml: animation.keys[0].frame is missing",
        ),
        (
            "[[animation.keys]]\nframe = 1.0\n",
            "anim.toml: animation.keys[0].frame = 1.0: must be an integer",
        ),
        (
            "[[animation.keys]]\nframe = 0\n[[animation.keys]]\nframe = 1\nshading.shadows = false\n",
            "anim.toml: animation.keys[1].shading.shadows cannot be animated: it is true or \
             false; keyframes set floats and float vectors (fractal.c, fractal.epsilon, \
             camera.eye, slice.x, ...)",
        ),
        (
            "[[animation.keys]]\nframe = 0\nfractal.max_iterations = 20\n",
            "animation.keys[0].fractal.max_iterations cannot be animated: it is an integer",
        ),
        (
            "[[animation.keys]]\nframe = 0\nfractal.algebra = \"octonion\"\n",
            "animation.keys[0].fractal.algebra cannot be animated: it is a choice of names",
        ),
        (
            "[[animation.keys]]\nframe = 0\nfractal.colour = 1.0\n",
            "animation.keys[0].fractal.colour cannot be animated: it is not a scene key",
        ),
        (
            "[[animation.keys]]\nframe = 0\nfractal.c = [1, 2]\n",
            "anim.toml: animation.keys[0].fractal.c = [1, 2]: must be an array of 4 numbers, not 2",
        ),
        (
            "[[animation.keys]]\nframe = 0\nfractal.epsilon = \"small\"\n",
            "anim.toml: animation.keys[0].fractal.epsilon = \"small\": must be a number",
        ),
        (
            "[[animation.keys]]\nframe = 0\nfractal.epsilon = -1\n",
            "anim.toml: animation.keys[0].fractal.epsilon = -1: must be > 0",
        ),
        (
            "[[animation.keys]]\nframe = 0\ncamera.eye = [0, 0, 0]\n",
            "anim.toml: animation.keys[0].camera.eye = [0, 0, 0]: must differ from the other \
             of camera.eye, camera.target",
        ),
        (
            "[[animation.keys]]\nframe = 0\nslice.x = [0, 1, 0, 0]\n",
            "anim.toml: animation.keys[0].slice.x = [0, 1, 0, 0]: makes the slice basis (x, \
             y, z) not orthonormal",
        ),
        (
            "[[animation.keys]]\nframe = 0\nshading.diffuse = [1, 2, 0]\n",
            "anim.toml: animation.keys[0].shading.diffuse = [1, 2, 0]: must have every \
             component in [0, 1]",
        ),
        // Valid keys whose track leaves the range between them: epsilon dips below 0. On
        // [1, 99] the track is 0.001 + 98 m_1 h10(s) with m_1 = (0.001 - 0.1) / 99 = -0.001 and
        // s = (k - 1) / 98: frame 2 (h10 = 0.0100) stays above 0, frame 3 (h10 = 0.0196) not.
        (
            "[animation]\nframes = 100\n\
             [[animation.keys]]\nframe = 0\nfractal.epsilon = 0.1\n\
             [[animation.keys]]\nframe = 1\nfractal.epsilon = 0.001\n\
             [[animation.keys]]\nframe = 99\nfractal.epsilon = 0.001\n",
            "anim.toml: animation.keys give frame 3 fractal.epsilon = -0.000919",
        ),
    ];
    for (toml, expected) in cases {
        let e = error(toml, &[]);
        assert!(e.contains(expected), "{toml}\n{e}\nexpected {expected}");
        assert_eq!(e.lines().count(), 1, "{e}");
    }
}

/// Through the binary: exit 2, one line naming the file and the key, nothing written.
#[test]
fn render_rejects_a_bad_animation_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    for (toml, key) in [
        ("[animation]\nfps = 0\n", "animation.fps"),
        (
            "[animation]\nframes = 5\n[[animation.keys]]\nframe = 5\n",
            "animation.keys[0].frame",
        ),
        (
            "[[animation.keys]]\nframe = 0\nimage.width = 64\n",
            "animation.keys[0].image.width cannot be animated",
        ),
    ] {
        std::fs::write(dir.path().join("bad.toml"), toml).unwrap();
        let args = [
            "render",
            "--backend",
            "cpu",
            "--scene",
            "bad.toml",
            "-o",
            "x.png",
        ];
        common::assert_refused(dir.path(), &args, "error: bad.toml: ", key);
    }
}
