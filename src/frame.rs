//! The one result both tracers produce: colour, depth and steps per pixel (its figures are in
//! [`crate::stats`]).

/// Path mode's word where the colour goes (the colour itself is the host's display transform
/// of the radiance, [`Frame::take_path_counters`]): the samples dropped as not
/// finite in its low `COUNTER_DROPPED_BITS` bits (at most `image.samples`, 4,096), the rays that
/// ran out of steps above them (at most 4,096 samples x 49 rays, 200,704, under 2^19).
pub const COUNTER_DROPPED_BITS: u32 = 13;
pub const COUNTER_DROPPED_MASK: u32 = 0x1fff;

/// A rendered image, row 0 at the top, pixel (i, j) at index `j * width + i`.
#[derive(Clone, Debug, PartialEq)]
pub struct Frame {
    pub width: u32,
    pub height: u32,
    /// Colour as RGBA8 0xFFBBGGRR per pixel, as the tracers pack it (alpha always 255).
    pub colour: Vec<u32>,
    /// The hit's ray parameter t (the distance from the eye along the unit ray); NaN on a miss.
    pub depth: Vec<f32>,
    /// The depth in f64, where the render ran in f64 (either tracer); empty otherwise.
    /// float32 cannot hold a deep zoom's depth: at a pixel footprint of 1e-10, its spacing near
    /// the hit is 10 pixels. `--depth` writes these, as float64, when they are there.
    pub depth_f64: Vec<f64>,
    /// Distance estimates along the primary ray.
    pub steps: Vec<u32>,
    /// Path mode: each pixel's mean linear radiance, of which `colour` is the display
    /// transform ([`crate::display::Display`]); empty in phong mode.
    pub radiance: Vec<[f32; 3]>,
    /// The AOVs `--hdr` writes, where they were asked for ([`crate::Readback::Hdr`]); each
    /// empty otherwise. Phong mode: each pixel's mean of its samples' unclamped colours (the
    /// PNG's colour is the mean of the clamped ones); empty in path mode, whose linear mean is
    /// `radiance` ([`Self::linear`] gives either).
    pub unclamped: Vec<[f32; 3]>,
    /// The AOVs: the base colour of the hit (shading.diffuse, or the orbit trap's palette
    /// colour), averaged over the samples whose primary ray hit; 0 where none did.
    pub albedo: Vec<[f32; 3]>,
    /// The AOVs: the shading normal at the hit (slice coordinates), averaged over the samples
    /// whose primary ray hit; 0 where none did. A mean of unit vectors: of length 1 where every
    /// sample hit the same face, shorter where they disagree.
    pub normal: Vec<[f32; 3]>,
    /// The AOVs: the sum of the squared deviations of the samples' luminances from their mean
    /// (Welford's M2), of which the denoiser makes each pixel's variance; empty where the AOVs
    /// were not asked for.
    pub luminance_m2: Vec<f32>,
    /// The AOVs: how many of the samples the pixel's mean holds hit (its hit fraction, times
    /// those samples: all it kept; with adaptive sampling, taken to the samples it took:
    /// accumulate.wgsl's `finish_aovs`); the denoiser's
    /// demodulation and guide. Empty where the AOVs were not asked for.
    pub hits: Vec<f32>,
    /// The AOVs: the depth of the hits (the primary ray's t, through the lens where it is
    /// open), averaged over the samples whose primary ray hit; 0 where none did. The denoiser's
    /// depth guide. Empty where the AOVs were not asked for.
    pub hit_depth: Vec<f32>,
    /// The AOVs, path mode: each pixel's mean of its samples' first-hit specular light, the
    /// part of their radiance the first hit's specular lobes reflected (shaders/path.wgsl's
    /// `PathResult.specular`), the denoiser's specular signal; empty in phong mode and where the
    /// AOVs were not asked for.
    pub specular: Vec<[f32; 3]>,
    /// The AOVs, path mode: the cosine of the view direction to the first hit's shading normal,
    /// averaged over the samples whose primary ray hit (0 where none did): the denoiser's
    /// specular reflectance is taken at it. Empty where [`Self::specular`] is.
    pub view_cosine: Vec<f32>,
    /// Where the frame was denoised (`image.denoise`): the linear mean before the denoiser
    /// (`--hdr`'s `noisy.R/G/B`); [`Self::linear`] is then the denoised image. Empty otherwise.
    pub noisy: Vec<[f32; 3]>,
    /// Path mode: each pixel's two halves, the mean colours of its two independently drawn
    /// streams (shaders/accumulate.wgsl's `Halves`), whose disagreement is its error estimate
    /// ([`crate::estimate::half_variance`]); NaN in a half that holds no sample. What the pixel
    /// shows (before a denoiser) is their mean, or the one half where the other is empty. Empty
    /// in phong mode and where the accumulator was not read back.
    pub halves: Vec<[[f32; 3]; 2]>,
    /// The samples each pixel took: `image.samples`, or fewer where adaptive sampling
    /// (`path.noise_target`) stopped it. The renderer fills it for every slice it renders
    /// ([`crate::Renderer::render_rows`]); empty elsewhere (the 2D view), and in a frame a
    /// kernel returns before the renderer has it, where no pixel stopped early.
    pub samples: Vec<u32>,
    /// Values that came out NaN or infinite on the way (colour, depth; the depth map's miss
    /// marker aside). Must be 0: the stability suite checks it.
    pub non_finite: u64,
    /// Distance estimates made for these pixels, every sample and every ray (the 2D view:
    /// iterations).
    pub estimates: u64,
    /// Quaternion iterations (z <- z^2 + c) made for these pixels, every sample and every ray:
    /// in the distance estimates, the normals and the orbit trap (the 2D view: its iterations).
    pub iterations: u64,
    /// Path mode: samples whose radiance was not finite, or negative, and which were dropped
    /// (left out of their pixel's n, mean, variance and adaptive state). Unlike
    /// [`Self::non_finite`], which counts values of the finished frame, these never reach it.
    pub nonfinite_samples: u64,
    /// Path mode: rays that ran out of `max_steps` without a hit or an escape (camera, shadow
    /// and bounce rays, every sample).
    pub exhausted_rays: u64,
}

impl Frame {
    /// No rows yet, `width` pixels wide: [`Self::append`] bands to it.
    pub fn empty(width: u32) -> Self {
        Self {
            width,
            height: 0,
            colour: Vec::new(),
            depth: Vec::new(),
            depth_f64: Vec::new(),
            steps: Vec::new(),
            radiance: Vec::new(),
            unclamped: Vec::new(),
            albedo: Vec::new(),
            normal: Vec::new(),
            luminance_m2: Vec::new(),
            hits: Vec::new(),
            hit_depth: Vec::new(),
            specular: Vec::new(),
            view_cosine: Vec::new(),
            noisy: Vec::new(),
            halves: Vec::new(),
            samples: Vec::new(),
            non_finite: 0,
            estimates: 0,
            iterations: 0,
            nonfinite_samples: 0,
            exhausted_rays: 0,
        }
    }

    pub fn pixel_count(&self) -> usize {
        self.width as usize * self.height as usize
    }

    /// Appends the rows of `band` (of the same width) below this frame's.
    pub fn append(&mut self, band: &Frame) {
        debug_assert_eq!(self.width, band.width);
        self.height += band.height;
        self.colour.extend_from_slice(&band.colour);
        self.depth.extend_from_slice(&band.depth);
        self.depth_f64.extend_from_slice(&band.depth_f64);
        self.steps.extend_from_slice(&band.steps);
        self.radiance.extend_from_slice(&band.radiance);
        self.unclamped.extend_from_slice(&band.unclamped);
        self.albedo.extend_from_slice(&band.albedo);
        self.normal.extend_from_slice(&band.normal);
        self.luminance_m2.extend_from_slice(&band.luminance_m2);
        self.hits.extend_from_slice(&band.hits);
        self.hit_depth.extend_from_slice(&band.hit_depth);
        self.specular.extend_from_slice(&band.specular);
        self.view_cosine.extend_from_slice(&band.view_cosine);
        self.noisy.extend_from_slice(&band.noisy);
        self.halves.extend_from_slice(&band.halves);
        self.samples.extend_from_slice(&band.samples);
        self.non_finite += band.non_finite;
        self.estimates += band.estimates;
        self.iterations += band.iterations;
        self.nonfinite_samples += band.nonfinite_samples;
        self.exhausted_rays += band.exhausted_rays;
    }

    /// Path mode: moves the path kernel's counter words, which it leaves where the colour goes
    /// (the colour is the display transform's, made after), into [`Self::nonfinite_samples`]
    /// and [`Self::exhausted_rays`], and clears the colour.
    pub fn take_path_counters(&mut self) {
        use rayon::prelude::*;
        let (dropped, exhausted) = self
            .colour
            .par_iter()
            .map(|&w| {
                let dropped = (w & COUNTER_DROPPED_MASK) as u64;
                (dropped, (w >> COUNTER_DROPPED_BITS) as u64)
            })
            .reduce(|| (0, 0), |a, b| (a.0 + b.0, a.1 + b.1));
        self.nonfinite_samples += dropped;
        self.exhausted_rays += exhausted;
        self.colour.fill(0);
    }

    /// Colour as 8-bit RGB bytes, row by row (in parallel: a 4K frame is 8.3 Mpixel).
    pub fn rgb8(&self) -> Vec<u8> {
        use rayon::prelude::*;
        let mut rgb = vec![0; self.colour.len() * 3];
        rgb.par_chunks_mut(3 * 4096)
            .zip(self.colour.par_chunks(4096))
            .for_each(|(out, colour)| {
                for (o, &c) in out.chunks_exact_mut(3).zip(colour) {
                    o.copy_from_slice(&unpack_rgb(c));
                }
            });
        rgb
    }

    /// The linear mean colour `--hdr` writes as R, G, B: path mode's radiance, or phong mode's
    /// unclamped colour mean (empty where the AOVs were not asked for in phong mode).
    pub fn linear(&self) -> &[[f32; 3]] {
        match self.radiance.is_empty() {
            true => &self.unclamped,
            false => &self.radiance,
        }
    }

    /// Puts a denoised linear image and its packed colours in place of the mean's, keeping
    /// the mean in [`Self::noisy`].
    pub fn set_denoised(&mut self, linear: Vec<[f32; 3]>, colour: Vec<u32>) {
        assert_eq!(
            linear.len(),
            self.pixel_count(),
            "a denoised image of the frame's size"
        );
        self.noisy = std::mem::replace(self.linear_mut(), linear);
        self.colour = colour;
    }

    /// [`Self::linear`], to change.
    fn linear_mut(&mut self) -> &mut Vec<[f32; 3]> {
        match self.radiance.is_empty() {
            true => &mut self.unclamped,
            false => &mut self.radiance,
        }
    }

    /// The samples pixel `k` took: [`Self::samples`]' where the frame has them, else
    /// `uniform` (every pixel's).
    pub fn samples_of(&self, k: usize, uniform: u32) -> u32 {
        self.samples.get(k).copied().unwrap_or(uniform)
    }

    /// Fills [`Self::samples`] with `uniform` where it is empty (no pixel stopped early).
    pub fn fill_samples(&mut self, uniform: u32) {
        if self.samples.is_empty() {
            self.samples = vec![uniform; self.pixel_count()];
        }
    }

    /// Whether each pixel's primary ray hit the set.
    pub fn hit_mask(&self) -> Vec<bool> {
        self.depth.iter().map(|d| !d.is_nan()).collect()
    }
}

/// `[r, g, b]` of a packed 0xAABBGGRR colour.
pub fn unpack_rgb(c: u32) -> [u8; 3] {
    [c as u8, (c >> 8) as u8, (c >> 16) as u8]
}
