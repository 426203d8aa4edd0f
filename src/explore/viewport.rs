//! The central panel: the view, on whole physical pixels, showing the tracer's texture (or a
//! step view's heat map, or in 2D mode the 2D Julia set), with the mouse on it (`input`).

use super::app::{ExplorerApp, Mode};
use super::heat_texture::HeatTexture;
use crate::scene::View;

/// The whole texture.
const FULL_UV: egui::Rect = egui::Rect::from_min_max(egui::pos2(0.0, 0.0), egui::pos2(1.0, 1.0));

impl ExplorerApp {
    /// The view, filling the panel, with mouse control of the camera (of the 2D view in 2D
    /// mode).
    pub(super) fn view_panel(&mut self, ui: &mut egui::Ui) {
        // Whole physical pixels, so that each texel lands on one screen pixel.
        let ppp_screen = ui.ctx().pixels_per_point();
        let snap = |p: egui::Pos2| {
            egui::pos2((p.x * ppp_screen).round(), (p.y * ppp_screen).round()) / ppp_screen
        };
        let available = ui.available_rect_before_wrap();
        let rect = egui::Rect::from_min_max(snap(available.min), snap(available.max));
        self.view_rect = rect;
        let response = ui.allocate_rect(rect, egui::Sense::click_and_drag());
        let ppp = ui.ctx().pixels_per_point() * self.resolution_scale;
        self.view_pixels = [
            (rect.width() * ppp).round().max(1.0) as u32,
            (rect.height() * ppp).round().max(1.0) as u32,
        ];
        match self.mode {
            Mode::Slice3d => {
                self.mouse_3d(ui, rect, &response);
                self.view_3d(ui, rect, &response);
            }
            Mode::Julia2d => {
                self.mouse_2d(ui, rect, &response);
                self.view_2d(ui, rect);
            }
        }
    }

    /// The 3D view: the shaded picture, or a step view's heat map with its legend.
    fn view_3d(&mut self, ui: &mut egui::Ui, rect: egui::Rect, response: &egui::Response) {
        let interacting = response.dragged()
            || self.animation.playing
            || self.timeline.playing
            || ui.input(|i| i.pointer.any_down());
        let view_scene = self.view_scene();
        let Some(view) = &mut self.slice_texture else {
            self.no_gpu(ui, rect);
            return;
        };
        view.update(&view_scene, self.view_pixels, interacting);
        let shown = self.scene.image.view;
        if shown == View::Shaded {
            if let Some((texture, _)) = view.texture() {
                ui.painter()
                    .image(texture, rect, FULL_UV, egui::Color32::WHITE);
            }
        } else {
            // Step views: a heat map of the steps read back from the image shown.
            let stats = view.stats();
            if let Some((steps, size)) = &stats.steps {
                let generation = stats.steps_generation;
                HeatTexture::refresh(&mut self.heat, ui.ctx(), shown, steps, *size, generation);
            }
            if let Some(heat) = self.heat.as_ref().filter(|h| h.shows(shown)) {
                heat.paint(ui.painter(), rect);
            }
        }
        if view.busy() {
            ui.ctx().request_repaint();
        }
    }

    /// The 2D mode: the 2D Julia set of c.
    fn view_2d(&mut self, ui: &mut egui::Ui, rect: egui::Rect) {
        let scene = self.view_scene();
        let Some(view2d) = &mut self.julia2d_texture else {
            self.no_gpu(ui, rect);
            return;
        };
        view2d.update(&scene);
        if let Some((texture, _)) = view2d.texture() {
            ui.painter()
                .image(texture, rect, FULL_UV, egui::Color32::WHITE);
        }
        if view2d.busy() || !view2d.is_refined(&scene) {
            ui.ctx().request_repaint();
        }
    }

    /// In place of the view when there is no GPU renderer: why, and what to install.
    fn no_gpu(&self, ui: &mut egui::Ui, rect: egui::Rect) {
        let text = format!(
            "No GPU renderer: {}\n{}",
            self.gpu_error.as_deref().unwrap_or("unknown error"),
            crate::error::INSTALL_ADAPTER_HINT
        );
        ui.put(rect, egui::Label::new(text));
    }
}
