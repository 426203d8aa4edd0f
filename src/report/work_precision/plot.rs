//! `work_precision.png`: colour error against render time, one panel per scene.

use std::path::Path;

use super::Row;

/// Colour RMSE against seconds, log-log, one series per method, one panel per scene.
pub fn plot(path: &Path, rows: &[Row]) -> Result<(), String> {
    use plotters::prelude::*;
    crate::heatmap::register_plot_font();
    let mut scenes: Vec<&str> = rows.iter().map(|r| r.setting.scene_name).collect();
    scenes.dedup();
    let (w, panel_h) = (1100u32, 620u32);
    let h = panel_h * scenes.len().max(1) as u32;
    let mut buffer = vec![255u8; (w * h * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut buffer, (w, h)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| e.to_string())?;
        let panels = root.split_evenly((scenes.len().max(1), 1));
        for (panel, scene) in panels.iter().zip(&scenes) {
            let mine: Vec<&Row> = rows
                .iter()
                .filter(|r| r.setting.scene_name == *scene)
                .collect();
            // Log-log, drawn as log10 values on linear axes labelled with the values themselves.
            let point = |r: &Row| {
                (
                    r.seconds.max(1e-5).log10(),
                    r.metrics.colour_rmse.max(0.01).log10(),
                )
            };
            let (x0, x1) = mine
                .iter()
                .map(|r| point(r).0)
                .fold((f64::MAX, f64::MIN), |(a, b), x| (a.min(x), b.max(x)));
            let (y0, y1) = mine
                .iter()
                .map(|r| point(r).1)
                .fold((f64::MAX, f64::MIN), |(a, b), y| (a.min(y), b.max(y)));
            let mut chart = ChartBuilder::on(panel)
                .caption(
                    format!("{scene}: colour error against render time"),
                    ("sans-serif", 26),
                )
                .margin(16)
                .x_label_area_size(48)
                .y_label_area_size(70)
                .build_cartesian_2d(x0 - 0.1..x1 + 0.1, y0 - 0.1..y1 + 0.1)
                .map_err(|e| e.to_string())?;
            chart
                .configure_mesh()
                .x_labels(10)
                .y_labels(10)
                .x_label_formatter(&|x| format!("{:.3}", 10f64.powf(*x)))
                .y_label_formatter(&|y| format!("{:.1}", 10f64.powf(*y)))
                .x_desc("seconds per image (log)")
                .y_desc("colour RMSE vs truth, 8-bit steps (log)")
                .label_style(("sans-serif", 16))
                .axis_desc_style(("sans-serif", 18))
                .draw()
                .map_err(|e| e.to_string())?;
            let mut methods: Vec<&str> = mine.iter().map(|r| r.setting.method).collect();
            methods.dedup();
            methods.sort();
            methods.dedup();
            for (k, method) in methods.iter().enumerate() {
                let mut points: Vec<(f64, f64)> = mine
                    .iter()
                    .filter(|r| r.setting.method == *method)
                    .map(|r| point(r))
                    .collect();
                points.sort_by(|a, b| a.0.total_cmp(&b.0));
                crate::report::plot::draw_series(&mut chart, &points, k, method, 4)?;
            }
            crate::report::plot::draw_legend(&mut chart, 16)?;
        }
        root.present().map_err(|e| e.to_string())?;
    }
    image::save_buffer(path, &buffer, w, h, image::ExtendedColorType::Rgb8)
        .map_err(|e| e.to_string())
}
