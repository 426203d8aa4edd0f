//! OpenEXR output (`--hdr FILE.exr`): one part of float32 channels, gathered band by band and
//! written at the end. `R`, `G`, `B` the linear mean ([`Frame::linear`]: path mode's radiance,
//! phong mode's unclamped colour mean; with a denoiser the denoised one, and the mean before
//! it in `noisy.R/G/B`, [`NOISY_CHANNELS`]), `albedo.R/G/B` and `N.X/Y/Z` the AOVs
//! ([`Frame::albedo`], [`Frame::normal`]), `Z` the depth (NaN where the ray hits nothing, as
//! `--depth` writes it); in path mode where the material has a specular lobe,
//! `specular.R/G/B` the first hits' specular light ([`Frame::specular`], before any denoiser)
//! and `reflectance.R/G/B` the specular reflectance the denoiser divides it by
//! ([`crate::denoise::specular_reflectance`] at [`Frame::view_cosine`], 0 where no sample
//! hit); and the scene's TOML in the `qjulia-scene` string attribute of the header ([`crate::scene::scene_from_exr`] reads it back). ZIP compression (lossless, 16 rows
//! a block), scan lines top to bottom.

use std::io::{Seek, Write};

use exr::prelude::{
    AnyChannel, AnyChannels, Encoding, FlatSamples, Image, ImageAttributes, Layer, LayerAttributes,
    SmallVec, Text, WritableImage,
};

use crate::frame::Frame;
use crate::scene::{SCENE_EXR_ATTRIBUTE, Scene};

/// The channels, in the order [`HdrImage`] holds them (the file stores them sorted by name).
pub const CHANNELS: [&str; 10] = [
    "R", "G", "B", "albedo.R", "albedo.G", "albedo.B", "N.X", "N.Y", "N.Z", "Z",
];

/// The layer a denoised image's mean before the denoiser goes in ([`Frame::noisy`]).
pub const NOISY_CHANNELS: [&str; 3] = ["noisy.R", "noisy.G", "noisy.B"];

/// Path mode's specular layers: the first hits' specular light, then the reflectance.
pub const SPECULAR_CHANNELS: [&str; 6] = [
    "specular.R",
    "specular.G",
    "specular.B",
    "reflectance.R",
    "reflectance.G",
    "reflectance.B",
];

/// The channels of a whole image, filled band by band, top to bottom (40 bytes a pixel in
/// host memory until it is written, 52 with the noisy layer, 68 with the specular ones).
pub struct HdrImage {
    width: u32,
    height: u32,
    channels: [Vec<f32>; 10],
    /// `noisy.R/G/B`, where the bands were denoised.
    noisy: [Vec<f32>; 3],
    /// `specular.R/G/B` and each pixel's view cosine, in path mode.
    specular: [Vec<f32>; 3],
    view_cosine: Vec<f32>,
}

impl HdrImage {
    /// An image of `width` x `height` with no rows yet.
    pub fn new(width: u32, height: u32) -> Self {
        let pixels = width as usize * height as usize;
        Self {
            width,
            height,
            channels: std::array::from_fn(|_| Vec::with_capacity(pixels)),
            noisy: Default::default(),
            specular: Default::default(),
            view_cosine: Vec::new(),
        }
    }

    /// The whole of `frame` (rendered with its AOVs).
    pub fn of(frame: &Frame) -> Self {
        let mut image = Self::new(frame.width, frame.height);
        image.add_band(frame);
        image
    }

    /// Appends a band of whole rows; it must hold the AOVs ([`crate::Readback::Hdr`]).
    pub fn add_band(&mut self, band: &Frame) {
        let pixels = band.pixel_count();
        let linear = band.linear();
        assert!(
            linear.len() == pixels && band.albedo.len() == pixels && band.normal.len() == pixels,
            "a band for the EXR carries its AOVs (Readback::Hdr)"
        );
        assert_eq!(band.width, self.width, "a band of the image's width");
        for (k, values) in [linear, &band.albedo, &band.normal].into_iter().enumerate() {
            for c in 0..3 {
                self.channels[3 * k + c].extend(values.iter().map(|v| v[c]));
            }
        }
        self.channels[9].extend_from_slice(&band.depth);
        if !band.noisy.is_empty() {
            for c in 0..3 {
                self.noisy[c].extend(band.noisy.iter().map(|v| v[c]));
            }
        }
        if band.specular.len() == pixels && band.view_cosine.len() == pixels {
            for c in 0..3 {
                self.specular[c].extend(band.specular.iter().map(|v| v[c]));
            }
            self.view_cosine.extend_from_slice(&band.view_cosine);
        }
    }

    /// Rows added so far.
    pub fn rows(&self) -> u32 {
        (self.channels[9].len() / self.width.max(1) as usize) as u32
    }

    /// Writes the image as OpenEXR with `scene` in its header; every row must be there.
    pub fn write(mut self, scene: &Scene, to: impl Write + Seek) -> std::io::Result<()> {
        assert_eq!(self.rows(), self.height, "every row of the EXR is there");
        let size = (self.width as usize, self.height as usize);
        let pixels = self.channels[9].len();
        assert!(
            self.noisy.iter().all(|c| c.is_empty() || c.len() == pixels),
            "every band or none was denoised"
        );
        let specular = self.specular_layers(scene);
        let channels: SmallVec<[AnyChannel<FlatSamples>; 4]> = CHANNELS
            .iter()
            .zip(self.channels)
            .chain(NOISY_CHANNELS.iter().zip(self.noisy))
            .chain(SPECULAR_CHANNELS.iter().zip(specular))
            .filter(|(_, values)| values.len() == pixels)
            .map(|(name, values)| AnyChannel::new(*name, FlatSamples::F32(values)))
            .collect();
        let layer = LayerAttributes {
            software_name: Some(Text::from(concat!("qjulia ", env!("CARGO_PKG_VERSION")))),
            ..Default::default()
        };
        let mut attributes = ImageAttributes::with_size(size);
        // The scene as its UTF-8 bytes: OpenEXR's strings are bytes, and a scene is ASCII but
        // for what its TOML strings may hold.
        attributes.other.insert(
            Text::from(SCENE_EXR_ATTRIBUTE),
            exr::meta::attribute::AttributeValue::Text(Text::from_slice_unchecked(
                scene.to_toml().as_bytes(),
            )),
        );
        write_exr(attributes, size, layer, channels, to)
    }

    /// [`SPECULAR_CHANNELS`]' values where every band had them and `scene`'s material has a
    /// specular lobe; empty otherwise.
    fn specular_layers(&mut self, scene: &Scene) -> [Vec<f32>; 6] {
        let pixels = self.channels[9].len();
        let material = crate::denoise::scene_material(scene);
        if self.view_cosine.len() != pixels || !crate::cpu::bsdf::has_specular_lobe(material) {
            return Default::default();
        }
        let [r, g, b] = std::mem::take(&mut self.specular);
        let albedo = &self.channels[3..6];
        let reflectance: Vec<[f32; 3]> = (0..pixels)
            .map(|k| match self.view_cosine[k] > 0.0 {
                true => {
                    let albedo =
                        crate::algebra::Vec3::new(albedo[0][k], albedo[1][k], albedo[2][k]);
                    let m = crate::cpu::bsdf::Material { albedo, ..material };
                    crate::denoise::specular_reflectance(m, self.view_cosine[k])
                }
                false => [0.0; 3],
            })
            .collect();
        let channel = |c: usize| reflectance.iter().map(|v| v[c]).collect();
        [r, g, b, channel(0), channel(1), channel(2)]
    }
}

/// Writes one part of float32 and uint32 `channels` (sorted by name, as OpenEXR stores them) of
/// `size`, ZIP-compressed (lossless, 16 rows a block), with `attributes` and `layer`: the one
/// EXR writer of `--hdr` and of `render --tile`'s partials ([`crate::tile`]).
pub fn write_exr(
    attributes: ImageAttributes,
    size: (usize, usize),
    layer: LayerAttributes,
    channels: SmallVec<[AnyChannel<FlatSamples>; 4]>,
    to: impl Write + Seek,
) -> std::io::Result<()> {
    let image = Image::new(
        attributes,
        Layer::new(
            size,
            layer,
            Encoding::SMALL_LOSSLESS,
            AnyChannels::sort(channels),
        ),
    );
    image.write().to_buffered(to).map_err(|e| match e {
        exr::error::Error::Io(e) => e,
        e => std::io::Error::other(e),
    })
}
