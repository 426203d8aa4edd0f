//! The side panel's sliders of scene keys (range and scale from the scene schema) and its
//! colour picker, which every group uses.

use crate::explore::input::slider;

/// A colour picker for an `[f64; 3]` in [0, 1].
pub(super) fn colour_edit(ui: &mut egui::Ui, colour: &mut [f64; 3]) {
    let mut rgb = colour.map(|c| c as f32);
    if ui.color_edit_button_rgb(&mut rgb).changed() {
        *colour = rgb.map(|c| (c as f64).clamp(0.0, 1.0));
    }
}

/// The slider of a float scene key: range and scale from the scene schema.
pub(super) fn key_slider<'a>(value: &'a mut f64, path: &str) -> egui::Slider<'a> {
    let s = slider(path);
    egui::Slider::new(value, s.range())
        .logarithmic(s.logarithmic)
        .clamping(egui::SliderClamping::Edits)
}

/// The slider of an integer scene key: range and scale from the scene schema.
pub(super) fn key_slider_u32<'a>(value: &'a mut u32, path: &str) -> egui::Slider<'a> {
    let s = slider(path);
    egui::Slider::new(value, s.range_u32())
        .logarithmic(s.logarithmic)
        .clamping(egui::SliderClamping::Edits)
}
