//! The work views of `image.view` (README's "Views"): what the tracer's steps array shows, drawn
//! on the host from [`Frame::steps`], so both backends give them without a shader of their own.
//! `steps` is the sphere-tracing steps per primary ray; `divergence` is, for fixed 8x8 screen
//! blocks aligned to pixel (0, 0), the block's most steps minus the pixel's own (the work its SIMD
//! lane idles through, Crane's Figure 9). Both are heat maps in one perceptual colour map on a
//! logarithmic scale, with a legend strip added below the image in the PNG.

use crate::frame::Frame;
use crate::scene::View;
use crate::stats::{block_maxima, block_of, divergence};
/// Rows of the legend strip added below a heat map's PNG.
pub const LEGEND_HEIGHT: u32 = 52;
/// The legend strip's background (dark grey, apart from the black of pixels with no work).
pub const LEGEND_BACKGROUND: [u8; 3] = [32, 32, 32];

/// The colour map: viridis (dark blue-violet through teal and green to yellow), perceptually
/// even and readable in grey, as nine stops from 0 to 1, linearly interpolated.
pub const COLOUR_STOPS: [[u8; 3]; 9] = [
    [68, 1, 84],
    [71, 45, 123],
    [59, 82, 139],
    [44, 114, 142],
    [33, 145, 140],
    [40, 174, 128],
    [94, 201, 98],
    [173, 220, 48],
    [253, 231, 37],
];

/// The colour map at `t` in [0, 1] (clamped; NaN counts as 0).
pub fn colour_map(t: f64) -> [u8; 3] {
    let t = if t.is_nan() { 0.0 } else { t.clamp(0.0, 1.0) };
    let x = t * (COLOUR_STOPS.len() - 1) as f64;
    let k = (x.floor() as usize).min(COLOUR_STOPS.len() - 2);
    let f = x - k as f64;
    let (a, b) = (COLOUR_STOPS[k], COLOUR_STOPS[k + 1]);
    [0, 1, 2].map(|c| (a[c] as f64 + (b[c] as f64 - a[c] as f64) * f).round() as u8)
}

/// What the legend says: the values at the ends and the middle of the colour bar, and what
/// they count.
#[derive(Clone, Debug, PartialEq)]
pub struct Legend {
    pub min: u32,
    /// The value at the bar's middle (the scale is logarithmic), rounded.
    pub mid: u32,
    pub max: u32,
    pub title: &'static str,
}

/// Where a value lies on the colour bar from `min` to `max`: the logarithmic scale
/// ln(1 + v - min) / ln(1 + max - min), so that the many pixels with few steps are told apart
/// as well as the few with many; 0 when min = max.
pub fn scale(v: u32, min: u32, max: u32) -> f64 {
    if max <= min {
        return 0.0;
    }
    (v.saturating_sub(min) as f64).ln_1p() / ((max - min) as f64).ln_1p()
}

impl Legend {
    fn new(min: u32, max: u32, title: &'static str) -> Self {
        // scale(mid) = 1/2: 1 + mid - min = sqrt(1 + max - min).
        let mid = min + ((1.0 + (max - min) as f64).sqrt() - 1.0).round() as u32;
        Self {
            min,
            mid,
            max,
            title,
        }
    }
}

/// A heat map: RGB8 pixels row by row, row 0 at the top, and its legend.
#[derive(Clone, Debug, PartialEq)]
pub struct HeatMap {
    pub width: u32,
    pub height: u32,
    pub rgb: Vec<u8>,
    pub legend: Legend,
}

/// The `steps` view: steps per primary ray, from the fewest to the most taken in this image
/// (min and max in the legend), black where the ray misses the bounding ball (0 steps).
pub fn steps_view(steps: &[u32], width: u32, height: u32) -> HeatMap {
    heat_map(steps, width, height, "steps per ray (log scale)", |k| {
        steps[k] > 0
    })
}

/// The `divergence` view: wasted steps per pixel (see [`divergence`]), black where its whole
/// block misses the bounding ball (no work at all). A pixel that misses in a block that works
/// idles the whole block's work and is coloured by it.
pub fn divergence_view(steps: &[u32], width: u32, height: u32) -> HeatMap {
    let wasted = divergence(steps, width, height);
    let block_max = block_maxima(steps, width, height);
    let works = |k: usize| block_max[block_of(k, width)] > 0;
    heat_map(
        &wasted,
        width,
        height,
        "wasted steps per pixel, 8x8 tiles (log scale)",
        works,
    )
}

/// The `samples` view: the samples each pixel took ([`Frame::samples`]), from the fewest to the
/// most in this image: where adaptive sampling (`path.noise_target`) spent its samples. Every
/// pixel is shown.
pub fn samples_view(samples: &[u32], width: u32, height: u32) -> HeatMap {
    heat_map(
        samples,
        width,
        height,
        "samples per pixel (log scale)",
        |_| true,
    )
}

/// Values mapped from their smallest to their largest (over the pixels `shown`) onto the colour
/// map by [`scale`]; black where not shown.
fn heat_map(
    values: &[u32],
    width: u32,
    height: u32,
    title: &'static str,
    shown: impl Fn(usize) -> bool,
) -> HeatMap {
    let (mut min, mut max) = (u32::MAX, 0u32);
    for (k, &v) in values.iter().enumerate() {
        if shown(k) {
            min = min.min(v);
            max = max.max(v);
        }
    }
    if min > max {
        (min, max) = (0, 0);
    }
    let rgb = values
        .iter()
        .enumerate()
        .flat_map(|(k, &v)| {
            if shown(k) {
                colour_map(scale(v, min, max))
            } else {
                [0, 0, 0]
            }
        })
        .collect();
    HeatMap {
        width,
        height,
        rgb,
        legend: Legend::new(min, max, title),
    }
}

/// The heat map of a work view (None for the shaded view, and for the samples view without
/// the samples, `samples` empty), of a frame's steps or samples ([`Frame::steps`],
/// [`Frame::samples`]).
pub fn heat_map_of(
    view: View,
    steps: &[u32],
    samples: &[u32],
    width: u32,
    height: u32,
) -> Option<HeatMap> {
    match view {
        View::Shaded => None,
        View::Steps => Some(steps_view(steps, width, height)),
        View::Divergence => Some(divergence_view(steps, width, height)),
        View::Samples if samples.is_empty() => None,
        View::Samples => Some(samples_view(samples, width, height)),
    }
}

/// The picture a view shows of a frame, without legend: the shaded colour, or a heat map.
pub fn view_rgb(frame: &Frame, view: View) -> (Vec<u8>, Option<Legend>) {
    let (steps, samples) = (&frame.steps, &frame.samples);
    match heat_map_of(view, steps, samples, frame.width, frame.height) {
        None => (frame.rgb8(), None),
        Some(map) => (map.rgb, Some(map.legend)),
    }
}

/// The PNG's pixels for a view of a frame: the shaded picture as it is, or a heat map with a
/// legend strip of [`LEGEND_HEIGHT`] rows added below it. Returns (width, height, RGB8).
pub fn view_image(frame: &Frame, view: View) -> (u32, u32, Vec<u8>) {
    let (mut rgb, legend) = view_rgb(frame, view);
    match legend {
        None => (frame.width, frame.height, rgb),
        Some(legend) => {
            rgb.extend(legend_strip(&legend, frame.width));
            (frame.width, frame.height + LEGEND_HEIGHT, rgb)
        }
    }
}

/// Which side of a legend label its anchor is on: the left end of the text, its middle or its
/// right end (the top of the text is at the anchor's height).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TextAnchor {
    Left,
    Centre,
    Right,
}

/// The colour bar of a legend strip, in pixels from the strip's top left corner.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LegendBar {
    /// Columns `left..right` and rows `top..bottom` (the ends exclusive); min at the left.
    pub left: i32,
    pub right: i32,
    pub top: i32,
    pub bottom: i32,
    /// The one-pixel columns of the ticks under the bar's first, middle and last columns, each
    /// from the bar's bottom to `tick_bottom` (exclusive).
    pub ticks: [i32; 3],
    pub tick_bottom: i32,
}

/// Where the parts of a legend strip go, in pixels from its top left corner (x right, y down):
/// the one layout of the PNG's strip ([`legend_strip`]) and of the explorer's legend over its
/// view.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LegendLayout {
    /// The space kept clear at the strip's left and right.
    pub margin: i32,
    /// The colour bar, where the strip is wide enough for one.
    pub bar: Option<LegendBar>,
    /// The min, mid and max values: the x of each label's anchor, and its side of the text.
    pub labels: [(i32, TextAnchor); 3],
    /// The top of the value labels.
    pub label_top: i32,
    /// The title's anchor, the middle of its top, [x, y].
    pub title: [i32; 2],
}

impl LegendLayout {
    /// Whether a title `text_width` pixels wide fits between the margins.
    pub fn title_fits(&self, text_width: i32, width: i32) -> bool {
        text_width + 2 * self.margin < width
    }
}

/// The layout of a legend strip `width` pixels wide and [`LEGEND_HEIGHT`] high: a colour bar
/// rows 5 to 15 between margins of 6, ticks 3 pixels long under its ends and middle, the values
/// 5 pixels under the bar, and the title one line (16 pixels) under them.
pub fn legend_layout(width: u32) -> LegendLayout {
    let margin = 6;
    let (bar_top, bar_bottom) = (5, 15);
    let width = width as i32;
    let bar = (width > 2 * margin + 1).then(|| {
        let (left, last) = (margin, width - margin - 1);
        LegendBar {
            left,
            right: last + 1,
            top: bar_top,
            bottom: bar_bottom,
            ticks: [left, (left + last) / 2, last],
            tick_bottom: bar_bottom + 3,
        }
    });
    let label_top = bar_bottom + 5;
    LegendLayout {
        margin,
        bar,
        labels: [
            (margin, TextAnchor::Left),
            (width / 2, TextAnchor::Centre),
            (width - margin, TextAnchor::Right),
        ],
        label_top,
        title: [width / 2, label_top + 16],
    }
}

/// The legend strip, `width` by [`LEGEND_HEIGHT`] pixels, laid out by [`legend_layout`]: the
/// colour bar from min (left) to max (right) with ticks at its ends and middle, their values
/// under them, and the title below (where it fits).
pub fn legend_strip(legend: &Legend, width: u32) -> Vec<u8> {
    use plotters::prelude::*;
    use plotters::style::text_anchor::{HPos, Pos, VPos};
    let h = LEGEND_HEIGHT;
    let layout = legend_layout(width);
    let mut buffer: Vec<u8> = std::iter::repeat_n(LEGEND_BACKGROUND, (width * h) as usize)
        .flatten()
        .collect();
    let white = [235u8; 3];
    let mut put = |x: i32, y: i32, colour: [u8; 3]| {
        let k = ((y as u32 * width + x as u32) * 3) as usize;
        buffer[k..k + 3].copy_from_slice(&colour);
    };
    if let Some(bar) = layout.bar {
        let span = (bar.right - 1 - bar.left) as f64;
        for x in bar.left..bar.right {
            for y in bar.top..bar.bottom {
                put(x, y, colour_map((x - bar.left) as f64 / span));
            }
        }
        for x in bar.ticks {
            for y in bar.bottom..bar.tick_bottom {
                put(x, y, white);
            }
        }
    }
    register_plot_font();
    {
        let root = BitMapBackend::with_buffer(&mut buffer, (width, h)).into_drawing_area();
        let font = ("sans-serif", 13)
            .into_font()
            .color(&RGBColor(235, 235, 235));
        let at = |anchor| {
            let h = match anchor {
                TextAnchor::Left => HPos::Left,
                TextAnchor::Centre => HPos::Center,
                TextAnchor::Right => HPos::Right,
            };
            font.pos(Pos::new(h, VPos::Top))
        };
        let values = [legend.min, legend.mid, legend.max];
        // Drawing errors only mean text that does not fit: the bar is what matters.
        for (value, (x, anchor)) in values.into_iter().zip(layout.labels) {
            let _ = root.draw_text(&value.to_string(), &at(anchor), (x, layout.label_top));
        }
        let fits = root
            .estimate_text_size(legend.title, &font)
            .is_ok_and(|(w, _)| layout.title_fits(w as i32, width as i32));
        if fits {
            let [x, y] = layout.title;
            let _ = root.draw_text(legend.title, &at(TextAnchor::Centre), (x, y));
        }
        let _ = root.present();
    }
    buffer
}

/// Registers the embedded font (egui's Ubuntu Light) as plotters' "sans-serif", once: plots and
/// legends look the same everywhere and need no system fonts.
pub(crate) fn register_plot_font() {
    static FONT: std::sync::Once = std::sync::Once::new();
    FONT.call_once(|| {
        let _ = plotters::style::register_font(
            "sans-serif",
            plotters::style::FontStyle::Normal,
            epaint_default_fonts::UBUNTU_LIGHT,
        );
    });
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn steps_view_is_black_on_misses_and_spans_the_colour_map() {
        let steps = [0, 3, 5, 11];
        let map = steps_view(&steps, 2, 2);
        assert_eq!(
            map.legend,
            Legend {
                min: 3,
                mid: 5,
                max: 11,
                title: "steps per ray (log scale)"
            }
        );
        assert_eq!(&map.rgb[0..3], &[0, 0, 0]);
        assert_eq!(&map.rgb[3..6], &COLOUR_STOPS[0]);
        // 5 is 2 above the minimum of 3, on a scale of 8: ln 3 / ln 9 = 1/2.
        assert_eq!(&map.rgb[6..9], &COLOUR_STOPS[4]);
        assert_eq!(&map.rgb[9..12], &COLOUR_STOPS[8]);
        // Nothing hit: all black, legend 0 to 0.
        let none = steps_view(&[0, 0], 2, 1);
        assert!(none.rgb.iter().all(|&c| c == 0));
        assert_eq!((none.legend.min, none.legend.max), (0, 0));
    }

    #[test]
    fn divergence_view_is_black_only_where_a_whole_block_is_idle() {
        // 16x8: the left tile works (one pixel 4 steps), the right one does nothing.
        let mut steps = vec![0u32; 128];
        steps[0] = 4;
        let map = divergence_view(&steps, 16, 8);
        assert_eq!((map.legend.min, map.legend.mid, map.legend.max), (0, 1, 4));
        let px = |i: usize, j: usize| &map.rgb[(j * 16 + i) * 3..(j * 16 + i) * 3 + 3];
        assert_eq!(px(0, 0), &COLOUR_STOPS[0]);
        assert_eq!(px(1, 0), &COLOUR_STOPS[8]);
        assert_eq!(px(12, 3), &[0, 0, 0]);
    }

    #[test]
    fn the_scale_is_logarithmic_from_min_to_max() {
        assert_eq!(scale(3, 3, 11), 0.0);
        assert_eq!(scale(11, 3, 11), 1.0);
        assert!((scale(5, 3, 11) - 0.5).abs() < 1e-15);
        assert_eq!(scale(7, 7, 7), 0.0);
        assert_eq!(Legend::new(4, 171, "").mid, 4 + 12);
    }

    #[test]
    fn colour_map_ends_and_middle() {
        assert_eq!(colour_map(0.0), COLOUR_STOPS[0]);
        assert_eq!(colour_map(1.0), COLOUR_STOPS[8]);
        assert_eq!(colour_map(0.5), COLOUR_STOPS[4]);
        assert_eq!(colour_map(-3.0), COLOUR_STOPS[0]);
        assert_eq!(colour_map(f64::NAN), COLOUR_STOPS[0]);
        // Perceptual: brightness rises along the map.
        let luma = |c: [u8; 3]| 0.2126 * c[0] as f64 + 0.7152 * c[1] as f64 + 0.0722 * c[2] as f64;
        for k in 1..COLOUR_STOPS.len() {
            assert!(luma(COLOUR_STOPS[k]) > luma(COLOUR_STOPS[k - 1]));
        }
    }

    #[test]
    fn the_legend_layout_keeps_its_margins() {
        let layout = legend_layout(200);
        let bar = layout.bar.unwrap();
        assert_eq!((bar.left, bar.right, bar.top, bar.bottom), (6, 194, 5, 15));
        assert_eq!((bar.ticks, bar.tick_bottom), ([6, 99, 193], 18));
        assert_eq!(layout.labels.map(|(x, _)| x), [6, 100, 194]);
        assert_eq!((layout.label_top, layout.title), (20, [100, 36]));
        assert!(legend_layout(13).bar.is_none());
    }

    #[test]
    fn the_png_of_a_heat_map_has_the_legend_below() {
        let frame = Frame {
            width: 200,
            height: 20,
            colour: vec![0xff00_0000; 4000],
            depth: vec![f32::NAN; 4000],
            depth_f64: Vec::new(),
            steps: (0..4000).map(|k| k % 50).collect(),
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
        };
        let (w, h, rgb) = view_image(&frame, View::Steps);
        assert_eq!((w, h), (200, 20 + LEGEND_HEIGHT));
        assert_eq!(rgb.len(), (w * h * 3) as usize);
        // The bar's ends are the map's ends; the strip has light text on it.
        let px = |i: u32, j: u32| {
            let k = ((j * w + i) * 3) as usize;
            [rgb[k], rgb[k + 1], rgb[k + 2]]
        };
        assert_eq!(px(6, 20 + 8), COLOUR_STOPS[0]);
        assert_eq!(px(193, 20 + 8), COLOUR_STOPS[8]);
        assert_eq!(px(99, 20 + 8), colour_map((99 - 6) as f64 / 187.0));
        let text = (20 + 20..h)
            .flat_map(|j| (0..w).map(move |i| (i, j)))
            .filter(|&(i, j)| px(i, j)[0] > 150)
            .count();
        assert!(text > 20, "no legend text drawn");
        // The shaded view is the frame's colour, as it is.
        let (w, h, rgb) = view_image(&frame, View::Shaded);
        assert_eq!((w, h, rgb), (200, 20, frame.rgb8()));
    }
}
