//! The step views in the explorer (and the samples view, of the counts): the heat map of the
//! steps the view read back, uploaded as an
//! egui texture and remade only when new steps arrive, and its legend painted over the bottom
//! of the view, laid out as the PNG's legend strip ([`crate::heatmap::legend_layout`]).

use crate::heatmap::{HeatMap, LEGEND_BACKGROUND, LEGEND_HEIGHT, Legend, TextAnchor};
use crate::scene::View;

/// The heat map of a step view, uploaded for egui.
pub(super) struct HeatTexture {
    handle: egui::TextureHandle,
    /// The view's steps generation and the view it was made for.
    generation: u64,
    view: View,
    legend: Legend,
}

impl HeatTexture {
    /// Whether this is the heat map of `view` for the steps of `generation`.
    pub fn is_for(&self, view: View, generation: u64) -> bool {
        self.generation == generation && self.view == view
    }

    /// Whether this is a heat map of `view` (of any generation).
    pub fn shows(&self, view: View) -> bool {
        self.view == view
    }

    pub fn legend(&self) -> &Legend {
        &self.legend
    }

    /// Makes `slot` the heat map of `view` for `values` (the steps, or for the samples view
    /// the samples each pixel took; `size` pixels, of `generation`), unless it already is; the
    /// texture is reused.
    pub fn refresh(
        slot: &mut Option<Self>,
        ctx: &egui::Context,
        view: View,
        values: &[u32],
        size: [u32; 2],
        generation: u64,
    ) {
        if slot.as_ref().is_some_and(|h| h.is_for(view, generation)) {
            return;
        }
        let (steps, samples) = match view {
            View::Samples => (&[][..], values),
            _ => (values, &[][..]),
        };
        let Some(map) = crate::heatmap::heat_map_of(view, steps, samples, size[0], size[1]) else {
            return;
        };
        let HeatMap { rgb, legend, .. } = map;
        let image = egui::ColorImage::from_rgb([size[0] as usize, size[1] as usize], &rgb);
        let options = egui::TextureOptions::NEAREST;
        let handle = match slot.take() {
            Some(mut h) => {
                h.handle.set(image, options);
                h.handle
            }
            None => ctx.load_texture("qjulia-heat-map", image, options),
        };
        *slot = Some(Self {
            handle,
            generation,
            view,
            legend,
        });
    }

    /// Paints the heat map over `rect`, and its legend over the bottom of it.
    pub fn paint(&self, painter: &egui::Painter, rect: egui::Rect) {
        let uv = egui::Rect::from_min_max(egui::pos2(0.0, 0.0), egui::pos2(1.0, 1.0));
        painter.image(self.handle.id(), rect, uv, egui::Color32::WHITE);
        paint_legend(painter, rect, &self.legend);
    }
}

/// A step view's legend over the bottom of the view: the colour bar from min to max, the values
/// at its ends and middle and what it counts, where the PNG's legend strip has them.
fn paint_legend(painter: &egui::Painter, rect: egui::Rect, legend: &Legend) {
    let height = LEGEND_HEIGHT as f32;
    let strip = egui::Rect::from_min_max(egui::pos2(rect.min.x, rect.max.y - height), rect.max);
    let [r, g, b] = LEGEND_BACKGROUND;
    painter.rect_filled(strip, 0.0, egui::Color32::from_rgb(r, g, b));
    let layout = crate::heatmap::legend_layout(strip.width().round() as u32);
    let at = |x: f32, y: i32| egui::pos2(strip.min.x + x, strip.min.y + y as f32);
    let colour = egui::Color32::from_gray(235);
    if let Some(bar) = layout.bar {
        let (left, right) = (bar.left as f32, bar.right as f32);
        let segments = 96;
        for k in 0..segments {
            let x0 = left + (right - left) * k as f32 / segments as f32;
            let x1 = left + (right - left) * (k + 1) as f32 / segments as f32;
            let [r, g, b] = crate::heatmap::colour_map(k as f64 / (segments - 1) as f64);
            painter.rect_filled(
                egui::Rect::from_min_max(at(x0, bar.top), at(x1 + 0.5, bar.bottom)),
                0.0,
                egui::Color32::from_rgb(r, g, b),
            );
        }
        // A tick through the middle of its pixel column.
        for x in bar.ticks {
            let x = x as f32 + 0.5;
            painter.line_segment(
                [at(x, bar.bottom), at(x, bar.tick_bottom)],
                egui::Stroke::new(1.0, colour),
            );
        }
    }
    let font = egui::FontId::proportional(12.0);
    let values = [legend.min, legend.mid, legend.max];
    for (value, (x, anchor)) in values.into_iter().zip(layout.labels) {
        let align = match anchor {
            TextAnchor::Left => egui::Align2::LEFT_TOP,
            TextAnchor::Centre => egui::Align2::CENTER_TOP,
            TextAnchor::Right => egui::Align2::RIGHT_TOP,
        };
        painter.text(
            at(x as f32, layout.label_top),
            align,
            value.to_string(),
            font.clone(),
            colour,
        );
    }
    let [x, y] = layout.title;
    painter.text(
        at(x as f32, y),
        egui::Align2::CENTER_TOP,
        legend.title,
        font,
        colour,
    );
}
