//! `--hdr FILE.exr`: the OpenEXR read back by a reader that is not ours (OpenImageIO's
//! `oiiotool`; where it is missing the test skips, except under CI, `QJULIA_CI=1`, where it
//! fails) and by the exr crate, against the tracers' own numbers: R, G, B path mode's radiance
//! and phong mode's unclamped colour, Z the depth, the albedo of a flat scene, unit normals,
//! the scene in the header (`--scene FILE.exr` gives the same scene and the same PNG);
//! `animate --hdr` and `--resume`; the GPU's AOVs against the CPU twin's; a bad path.

use crate::common;

use std::path::Path;
use std::process::Command;

use crate::common::{files_in, qjulia, stderr};
use qjulia::scene::SceneLoader;
use qjulia::{Frame, Picture, Precision, Readback, Scene, TraceParams};

/// A small scene's `--set`s: 32x24 pixels.
const SIZE: [&str; 4] = ["--width", "32", "--height", "24"];

/// The channels of an EXR by name, its size and its channels' sample types as the exr crate
/// reads them.
struct Exr {
    size: (usize, usize),
    channels: Vec<(String, Vec<f32>)>,
    all_f32: bool,
}

impl Exr {
    fn read(path: &Path) -> Exr {
        let image = exr::prelude::read_first_flat_layer_from_file(path)
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let layer = image.layer_data;
        let mut all_f32 = true;
        let channels = layer
            .channel_data
            .list
            .iter()
            .map(|c| {
                let values = match &c.sample_data {
                    exr::prelude::FlatSamples::F32(v) => v.clone(),
                    other => {
                        all_f32 = false;
                        other.values_as_f32().collect()
                    }
                };
                (c.name.to_string(), values)
            })
            .collect();
        Exr {
            size: (layer.size.0, layer.size.1),
            channels,
            all_f32,
        }
    }

    fn channel(&self, name: &str) -> &[f32] {
        &self
            .channels
            .iter()
            .find(|(n, _)| n == name)
            .unwrap_or_else(|| panic!("no channel {name}"))
            .1
    }

    /// Three channels as one value per pixel.
    fn triple(&self, names: [&str; 3]) -> Vec<[f32; 3]> {
        let [a, b, c] = names.map(|n| self.channel(n));
        (0..a.len()).map(|k| [a[k], b[k], c[k]]).collect()
    }

    fn names(&self) -> Vec<&str> {
        self.channels.iter().map(|(n, _)| n.as_str()).collect()
    }
}

/// Renders with the binary in `dir` on the CPU: `args` after `render`, the small size.
fn render(dir: &Path, args: &[&str]) {
    let all = [&["render", "--backend", "cpu"][..], &SIZE, args].concat();
    let out = qjulia(dir, &all);
    assert!(out.status.success(), "{}: {}", all.join(" "), stderr(&out));
}

/// The scene of `--set`s at the small size.
fn small_scene(sets: &[&str]) -> Scene {
    let mut all = vec!["image.width=32", "image.height=24"];
    all.extend_from_slice(sets);
    common::scene(&all)
}

/// The `--set` arguments of `sets`.
fn set_args<'a>(sets: &[&'a str]) -> Vec<&'a str> {
    sets.iter().flat_map(|s| ["--set", *s]).collect()
}

/// Bit-for-bit equality of float arrays, NaN equal to NaN: the first pixel that differs.
fn first_difference(a: &[f32], b: &[f32]) -> Option<(usize, f32, f32)> {
    assert_eq!(a.len(), b.len(), "lengths");
    a.iter()
        .zip(b)
        .enumerate()
        .find(|(_, (x, y))| x.to_bits() != y.to_bits() && !(x.is_nan() && y.is_nan()))
        .map(|(k, (x, y))| (k, *x, *y))
}

fn channel_of(values: &[[f32; 3]], c: usize) -> Vec<f32> {
    values.iter().map(|v| v[c]).collect()
}

/// OpenImageIO's oiiotool reads the file: its size, its ten float channels by name, and the
/// scene attribute. Skips where oiiotool is missing (`apt-get install openimageio-tools`),
/// fails so under CI.
#[test]
fn oiiotool_reads_the_channels_and_the_scene() {
    let found = Command::new("oiiotool")
        .arg("--help")
        .output()
        .is_ok_and(|o| o.status.success());
    if !found {
        common::skip_outside_ci(
            "oiiotool_reads_the_channels_and_the_scene",
            "the reading by oiiotool",
            "oiiotool not on PATH: apt-get install openimageio-tools (.ci/run installs it)",
        );
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    render(dir.path(), &["--hdr", "a.exr", "--set", "image.samples=2"]);
    let out = Command::new("oiiotool")
        .args(["--info", "-v", "a.exr"])
        .current_dir(dir.path())
        .output()
        .expect("run oiiotool");
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{text}{}", stderr(&out));
    let first = text
        .lines()
        .find(|l| l.starts_with("a.exr"))
        .unwrap_or_else(|| panic!("no summary line:\n{text}"));
    // "a.exr : 32 x 24, 10 channel, float openexr"
    let words: Vec<&str> = first.split([' ', ',']).filter(|w| !w.is_empty()).collect();
    assert_eq!(
        words[2..],
        ["32", "x", "24", "10", "channel", "float", "openexr"],
        "{first}"
    );
    let list = text
        .lines()
        .find_map(|l| l.trim().strip_prefix("channel list:"))
        .unwrap_or_else(|| panic!("no channel list:\n{text}"));
    let mut channels: Vec<&str> = list.split(',').map(str::trim).collect();
    channels.sort();
    let mut expected = qjulia::hdr::CHANNELS.to_vec();
    expected.sort();
    assert_eq!(channels, expected, "{list}");
    // The attribute, with the scene's text in it.
    assert!(
        text.lines()
            .any(|l| l.trim().starts_with("qjulia-scene: \"[fractal]")),
        "no qjulia-scene attribute:\n{text}"
    );
    assert!(text.contains("samples = 2"), "the scene's keys:\n{text}");
}

/// Path mode: R, G, B are the CPU's Frame::radiance bit for bit, Z its depth (NaN exactly on
/// the misses), all channels float32 of the image's size.
#[test]
fn path_mode_writes_the_radiance_and_the_depth() {
    let sets = [
        "shading.model=\"path\"",
        "image.samples=3",
        "sun.intensity=2",
    ];
    let dir = tempfile::tempdir().unwrap();
    render(
        dir.path(),
        &[&set_args(&sets)[..], &["--hdr", "p.exr"]].concat(),
    );
    let exr = Exr::read(&dir.path().join("p.exr"));
    assert_eq!(exr.size, (32, 24));
    assert!(exr.all_f32, "float32 channels");
    let mut names = exr.names();
    names.sort();
    // Path mode with a specular lobe (the default material's) adds the specular layers.
    let mut expected = qjulia::hdr::CHANNELS.to_vec();
    expected.extend(qjulia::hdr::SPECULAR_CHANNELS);
    expected.sort();
    assert_eq!(names, expected);
    // The reflectance is the lobes' share of the light, in (0, 1) where a sample hit, 0 where
    // none did; the specular light is part of the radiance.
    for k in 0..32 * 24 {
        let r = exr.channel("reflectance.G")[k];
        // The albedo is 0 where no sample hit (the default diffuse colour has green).
        match exr.channel("albedo.G")[k] == 0.0 {
            true => assert_eq!(r, 0.0, "pixel {k}: a miss reflects nothing"),
            false => assert!(r > 0.0 && r < 1.0, "pixel {k}: reflectance {r}"),
        }
        assert!(exr.channel("specular.G")[k] <= exr.channel("G")[k] * 1.0001 + 1e-6);
    }
    // The frame as the renderer makes it without the AOVs.
    let scene = small_scene(&sets);
    let (frame, _) = common::cpu_renderer(&scene, Precision::F32)
        .render_frame(&scene, Picture::SHADED)
        .unwrap();
    assert_eq!(frame.radiance.len(), 32 * 24);
    for (c, name) in ["R", "G", "B"].into_iter().enumerate() {
        let diff = first_difference(exr.channel(name), &channel_of(&frame.radiance, c));
        assert_eq!(diff, None, "{name} against the radiance");
    }
    assert_eq!(first_difference(exr.channel("Z"), &frame.depth), None, "Z");
    let misses = frame.depth.iter().filter(|d| d.is_nan()).count();
    assert!(
        misses > 0 && misses < 32 * 24,
        "{misses} misses: both kinds"
    );
    // Not the display image: path mode's radiance goes past 1 under this sun.
    assert!(exr.channel("R").iter().any(|&r| r > 1.0));
}

/// Phong mode at one sample: R, G, B are the CPU twin's unclamped colour of each pixel (past 1
/// in the highlights, which the PNG clamps), the normals its shading normal (unit length on a
/// hit, 0 on a miss), Z the depth as `--depth` writes it.
#[test]
fn phong_mode_writes_the_unclamped_colour_and_the_normal() {
    let sets = ["shading.specular=1.5"];
    let dir = tempfile::tempdir().unwrap();
    render(
        dir.path(),
        &[
            &set_args(&sets)[..],
            &["--hdr", "a.exr", "--depth", "d.npy"],
        ]
        .concat(),
    );
    let exr = Exr::read(&dir.path().join("a.exr"));
    assert_eq!(exr.size, (32, 24));
    let scene = small_scene(&sets);
    let p = TraceParams::<f32>::new(&scene);
    let (mut over_one, mut hits) = (0, 0);
    let (rgb, normal) = (
        exr.triple(["R", "G", "B"]),
        exr.triple(["N.X", "N.Y", "N.Z"]),
    );
    for j in 0..24 {
        for i in 0..32 {
            let k = (j * 32 + i) as usize;
            let pixel = p.trace_pixel(i, j, 0, 0.0, true);
            let c = pixel.colour;
            assert_eq!(rgb[k], [c.x, c.y, c.z], "pixel ({i}, {j}) colour");
            over_one += (c.x.max(c.y).max(c.z) > 1.0 && pixel.hit) as u32;
            let n = pixel.normal;
            assert_eq!(normal[k], [n.x, n.y, n.z], "pixel ({i}, {j}) normal");
            let length = normal[k].iter().map(|v| v * v).sum::<f32>().sqrt();
            match pixel.hit {
                true => assert!((length - 1.0).abs() < 1e-5, "({i}, {j}): |N| = {length}"),
                false => assert_eq!(length, 0.0, "({i}, {j}): a miss has no normal"),
            }
            hits += pixel.hit as u32;
        }
    }
    assert!(over_one > 0, "the highlights go past 1 unclamped");
    assert!(hits > 0 && hits < 32 * 24);
    // Z is the depth map, NaN where it is.
    let npy = std::fs::read(dir.path().join("d.npy")).unwrap();
    let depth: Vec<f32> = bytemuck::pod_collect_to_vec(&npy[npy.len() - 4 * 32 * 24..]);
    assert_eq!(
        first_difference(exr.channel("Z"), &depth),
        None,
        "Z against --depth"
    );
}

/// A flat-coloured scene: the albedo is shading.diffuse wherever sample 0 hit, diffuse or 0
/// elsewhere (0 where no sample hit), at 4 samples; the mean normals are at most of unit length
/// and close to it inside the set's silhouette.
#[test]
fn the_albedo_of_a_flat_scene_is_its_diffuse_colour() {
    let sets = ["shading.diffuse=[0.3, 0.5, 0.7]", "image.samples=4"];
    let dir = tempfile::tempdir().unwrap();
    render(
        dir.path(),
        &[&set_args(&sets)[..], &["--hdr", "a.exr"]].concat(),
    );
    let exr = Exr::read(&dir.path().join("a.exr"));
    let diffuse = [0.3f32, 0.5, 0.7];
    let albedo = exr.triple(["albedo.R", "albedo.G", "albedo.B"]);
    let normal = exr.triple(["N.X", "N.Y", "N.Z"]);
    let depth = exr.channel("Z");
    let length = |n: [f32; 3]| n.iter().map(|v| v * v).sum::<f32>().sqrt();
    let mut none = 0;
    for k in 0..albedo.len() {
        if !depth[k].is_nan() {
            assert_eq!(albedo[k], diffuse, "pixel {k} hit");
        } else {
            assert!(albedo[k] == diffuse || albedo[k] == [0.0; 3], "pixel {k}");
            none += (albedo[k] == [0.0; 3]) as u32;
        }
        assert!(
            length(normal[k]) <= 1.0 + 1e-5,
            "pixel {k}: |N| {}",
            length(normal[k])
        );
    }
    assert!(none > 0, "some pixels no sample hit");
    // Inside the silhouette (a hit with every neighbour a hit) the samples' normals agree.
    let hit = |i: i32, j: i32| {
        (0..32).contains(&i) && (0..24).contains(&j) && !depth[(j * 32 + i) as usize].is_nan()
    };
    let mut inside = 0;
    for j in 0..24 {
        for i in 0..32 {
            if (-1..=1).all(|dj| (-1..=1).all(|di| hit(i + di, j + dj))) {
                let n = length(normal[(j * 32 + i) as usize]);
                assert!(n > 0.5, "({i}, {j}): |N| {n}");
                inside += 1;
            }
        }
    }
    assert!(inside > 10, "{inside} pixels inside");
}

/// `--scene FILE.exr` reads back the scene the EXR carries: the same Scene as the PNG's and the
/// scene rendered, and the same PNG bytes rendered again. An EXR without the attribute is one
/// line naming the file, exit 2.
#[test]
fn the_scene_reads_back_from_the_exr() {
    let sets = ["shading.colouring=\"orbit_trap\"", "image.samples=2"];
    let dir = tempfile::tempdir().unwrap();
    render(
        dir.path(),
        &[&set_args(&sets)[..], &["-o", "a.png", "--hdr", "a.exr"]].concat(),
    );
    let load = |name: &str| {
        let mut loader = SceneLoader::new();
        loader.file(&dir.path().join(name)).unwrap();
        loader.build().unwrap()
    };
    assert_eq!(load("a.exr"), small_scene(&sets));
    assert_eq!(load("a.exr"), load("a.png"));
    render(dir.path(), &["--scene", "a.exr", "-o", "again.png"]);
    let bytes = |name: &str| std::fs::read(dir.path().join(name)).unwrap();
    assert!(bytes("a.png") == bytes("again.png"), "the same PNG");
    // An EXR of another writer, without the scene.
    let plain = dir.path().join("plain.exr");
    exr::prelude::write_rgb_file(&plain, 4, 4, |_, _| (0.5f32, 0.5f32, 0.5f32)).unwrap();
    common::assert_refused(
        dir.path(),
        &["render", "--backend", "cpu", "--scene", "plain.exr"],
        "error: plain.exr",
        "holds no qjulia scene",
    );
}

/// `animate --hdr` writes frame-NNNNN.exr beside each PNG, each the EXR `render --hdr` writes
/// of that frame; `--resume` renders again a frame whose EXR is missing, and without `--hdr`
/// counts the PNGs alone.
#[test]
fn animate_writes_an_exr_per_frame_and_resume_wants_both() {
    let dir = tempfile::tempdir().unwrap();
    let scene = "[image]\nwidth = 32\nheight = 24\n\n[animation]\nframes = 3\n";
    std::fs::write(dir.path().join("anim.toml"), scene).unwrap();
    let animate = |extra: &[&str]| {
        let args = [
            &["animate", "--scene", "anim.toml", "--backend", "cpu"][..],
            &["--out", "f", "--hdr"],
            extra,
        ]
        .concat();
        let out = qjulia(dir.path(), &args);
        assert!(out.status.success(), "{}", stderr(&out));
        stderr(&out)
    };
    animate(&[]);
    let frames = dir.path().join("f");
    let names: Vec<String> = (0..3)
        .flat_map(|k| [format!("frame-{k:05}.exr"), format!("frame-{k:05}.png")])
        .collect();
    assert_eq!(files_in(&frames), names);
    for k in 0..3 {
        let png = qjulia::scene::scene_from_png(&frames.join(&names[2 * k + 1])).unwrap();
        let exr = qjulia::scene::scene_from_exr(&frames.join(&names[2 * k])).unwrap();
        assert_eq!(exr, png, "frame {k} carries its own scene");
    }
    // Frame 1's EXR is render --hdr's of its scene, byte for byte.
    render(
        dir.path(),
        &["--scene", "f/frame-00001.png", "--hdr", "one.exr"],
    );
    let bytes = |p: &Path| std::fs::read(p).unwrap();
    assert!(bytes(&frames.join("frame-00001.exr")) == bytes(&dir.path().join("one.exr")));
    std::fs::remove_file(frames.join("frame-00001.exr")).unwrap();
    std::fs::write(frames.join("frame-00001.png"), b"stale").unwrap();
    let told = animate(&["--resume"]);
    assert!(
        told.contains("2 frames already complete, 1 to render"),
        "{told}"
    );
    assert_eq!(files_in(&frames), names);
    assert!(bytes(&frames.join("frame-00001.exr")) == bytes(&dir.path().join("one.exr")));
    assert!(
        bytes(&frames.join("frame-00001.png")) != b"stale",
        "the PNG again too"
    );
    // Without --hdr a frame is its PNG, as before.
    std::fs::remove_file(frames.join("frame-00002.exr")).unwrap();
    let args = ["animate", "--scene", "anim.toml", "--backend", "cpu"];
    let out = qjulia(
        dir.path(),
        &[&args[..], &["--out", "f", "--resume"]].concat(),
    );
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("3 frames already complete, 0 to render"),
        "{}",
        stderr(&out)
    );
    // With --hdr it is missing, and rendered.
    let told = animate(&["--resume"]);
    assert!(
        told.contains("2 frames already complete, 1 to render"),
        "{told}"
    );
}

/// The AOVs of the GPU (f32) agree with the CPU twin's: phong with orbit-trap colours and 4
/// samples (two dispatches' worth with the AOVs carried between them), and path mode.
#[test]
fn gpu_and_cpu_aovs_agree() {
    let Some(tracer) = common::gpu("gpu_and_cpu_aovs_agree") else {
        return;
    };
    // Phong, on the tests' tracer, against cpu::render_rows.
    let scene = small_scene(&["shading.colouring=\"orbit_trap\"", "image.samples=4"]);
    let p = TraceParams::<f32>::new(&scene);
    let mut gpu = Frame::empty(p.width);
    tracer
        .render_bands(&p, true, Readback::Hdr, &mut |band| {
            gpu.append(&band);
            Ok(())
        })
        .unwrap();
    let cpu = qjulia::cpu::render_rows(&p, true, true, 0..p.height);
    assert_aovs_agree("phong", &gpu, &cpu, true);
    // The AOVs changed nothing else.
    let plain = tracer.render(&p).unwrap().frame;
    assert_eq!(
        plain.colour, gpu.colour,
        "the colour with and without the AOVs"
    );
    assert_eq!(plain.steps, gpu.steps);
    // Path mode, on a GPU renderer of the same device.
    let scene = small_scene(&[
        "shading.model=\"path\"",
        "image.samples=2",
        "sun.intensity=2",
    ]);
    let kernels = std::sync::Arc::new(qjulia::gpu::GpuKernels::new(tracer.context().clone()));
    let renderer =
        qjulia::Planner::on_device(kernels, qjulia::Backend::Gpu, qjulia::PrecisionChoice::F32)
            .plan(&scene, Picture::SHADED.into(), &mut |_| {})
            .unwrap()
            .renderer;
    let render = |renderer: &qjulia::Renderer| {
        let mut frame = Frame::empty(32);
        renderer
            .render_with(&scene, Picture::SHADED, Readback::Hdr, &mut |band| {
                frame.append(band);
                Ok(())
            })
            .unwrap();
        frame
    };
    let gpu = render(&renderer);
    let cpu = render(&common::cpu_renderer(&scene, Precision::F32));
    assert!(
        gpu.unclamped.is_empty() && cpu.unclamped.is_empty(),
        "path mode: the radiance"
    );
    assert_aovs_agree("path", &gpu, &cpu, false);
}

/// The tracer's AOV output is allocated whole only for a run that reads it back: a plain
/// render's is a placeholder of one pixel (64 bytes), the other outputs whole either way.
#[test]
fn the_aov_buffer_is_allocated_only_when_read() {
    let Some(tracer) = common::gpu("the_aov_buffer_is_allocated_only_when_read") else {
        return;
    };
    let kernel = tracer.kernel();
    let names: Vec<&str> = kernel.spec().outputs.iter().map(|o| o.name).collect();
    assert_eq!(names.last(), Some(&"aovs"));
    let sizes = |read: &[bool]| -> Vec<u64> {
        let buffers = kernel.output_buffers(1000, "test", read);
        buffers.iter().map(|b| b.size()).collect()
    };
    // The work counts are 16 bytes a pixel (two 64-bit counts), the accumulator four planes of
    // 16 bytes a pixel (the running mean or stream A's, then the rest of adaptive sampling's
    // streams: accumulate.wgsl's `Streams`).
    assert_eq!(sizes(&[]), [4000, 4000, 4000, 16000, 64000, 64]);
    let mut read = vec![false; names.len()];
    *read.last_mut().unwrap() = true;
    assert_eq!(sizes(&read), [4000, 4000, 4000, 16000, 64000, 64000]);
}

/// Where both tracers hit with sample 0, the albedo within 1e-3 and the normal within 1e-2 on
/// 98% of those pixels; the unclamped colour (phong) within 2/255 on 98% of all pixels.
fn assert_aovs_agree(name: &str, gpu: &Frame, cpu: &Frame, phong: bool) {
    let n = cpu.pixel_count();
    for (what, v) in [("albedo", &gpu.albedo), ("normal", &gpu.normal)] {
        assert_eq!(v.len(), n, "{name}: the GPU's {what}");
    }
    let close = |a: [f32; 3], b: [f32; 3], tol: f32| (0..3).all(|c| (a[c] - b[c]).abs() <= tol);
    let both: Vec<usize> = (0..n)
        .filter(|&k| !gpu.depth[k].is_nan() && !cpu.depth[k].is_nan())
        .collect();
    assert!(both.len() > n / 10, "{name}: {} pixels hit", both.len());
    let share = |ok: usize, of: usize| ok as f64 / of as f64;
    let albedo = both
        .iter()
        .filter(|&&k| close(gpu.albedo[k], cpu.albedo[k], 1e-3))
        .count();
    let normal = both
        .iter()
        .filter(|&&k| close(gpu.normal[k], cpu.normal[k], 1e-2))
        .count();
    eprintln!(
        "{name}: albedo agrees on {albedo}/{}, normal on {normal}/{}",
        both.len(),
        both.len()
    );
    assert!(share(albedo, both.len()) >= 0.98, "{name}: albedo");
    assert!(share(normal, both.len()) >= 0.98, "{name}: normal");
    // Not all zero: a hit has a base colour and a normal.
    assert!(
        both.iter()
            .all(|&k| cpu.albedo[k] != [0.0; 3] && cpu.normal[k] != [0.0; 3])
    );
    if phong {
        assert_eq!(gpu.unclamped.len(), n, "{name}: the GPU's colour");
        let colour = (0..n)
            .filter(|&k| close(gpu.unclamped[k], cpu.unclamped[k], 2.0 / 255.0))
            .count();
        eprintln!("{name}: colour agrees on {colour}/{n}");
        assert!(share(colour, n) >= 0.98, "{name}: colour");
        assert!(
            gpu.specular.is_empty() && cpu.specular.is_empty(),
            "{name}: no specular"
        );
        return;
    }
    // Path mode's specular signal: the first hits' specular direct light, within the pixel's
    // radiance, and the view cosine of the hits.
    assert_eq!(gpu.specular.len(), n, "{name}: the GPU's specular light");
    assert_eq!(gpu.view_cosine.len(), n, "{name}: the GPU's view cosine");
    let specular = (0..n)
        .filter(|&k| close(gpu.specular[k], cpu.specular[k], 2e-3))
        .count();
    let cosine = both
        .iter()
        .filter(|&&k| (gpu.view_cosine[k] - cpu.view_cosine[k]).abs() <= 1e-2)
        .count();
    eprintln!("{name}: specular agrees on {specular}/{n}, view cosine on {cosine}");
    assert!(share(specular, n) >= 0.95, "{name}: specular light");
    assert!(share(cosine, both.len()) >= 0.98, "{name}: view cosine");
    for f in [gpu, cpu] {
        assert!(
            (0..n).all(|k| (0..3).all(|c| f.specular[k][c] <= f.radiance[k][c] * 1.0001 + 1e-6)),
            "{name}: the specular light is part of the radiance"
        );
        assert!(
            both.iter().any(|&k| f.specular[k] != [0.0; 3]),
            "{name}: some hit reflects light specularly"
        );
    }
}

/// `--hdr` into a folder that does not exist: one line naming the file, exit 1 as any output
/// error, and nothing written (not the PNG either).
#[test]
fn an_exr_into_a_missing_folder_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let args = [
        &["render", "--backend", "cpu"][..],
        &SIZE,
        &["-o", "a.png", "--hdr", "missing/a.exr"],
    ]
    .concat();
    let out = qjulia(dir.path(), &args);
    let text = stderr(&out);
    assert_eq!(out.status.code(), Some(1), "{text}");
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), 1, "{text}");
    assert!(lines[0].starts_with("error: missing/a.exr"), "{text}");
    assert_eq!(
        files_in(dir.path()),
        Vec::<String>::new(),
        "nothing written"
    );
}
