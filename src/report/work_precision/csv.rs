//! `work_precision.csv`: one row per measured setting.

use std::fmt::Write as _;

use super::Row;

/// One row per setting, the columns the issue asks for and a few more.
pub fn csv(rows: &[Row]) -> String {
    let mut out = String::from(
        "scene,backend,precision,method,setting,epsilon,pixel_epsilon,max_iterations,escape_radius_squared,\
         step_scale,normal,normal_delta,seconds,steps_mean,mask_disagreement,depth_error_p50,depth_error_p95,\
         depth_error_max,normal_error_deg_p50,normal_error_deg_p95,psnr_db,colour_rmse,overstep_rate,non_finite,\
         samples,light_radius,occlusion\n",
    );
    for r in rows {
        let (s, m) = (&r.setting, &r.metrics);
        let f = &s.scene.fractal;
        let (backend, precision) = r
            .setting
            .runner
            .name()
            .split_once(' ')
            .unwrap_or(("?", "?"));
        let _ = writeln!(
            out,
            "{},{backend},{precision},{},\"{}\",{},{},{},{},{},{},{},{:.6},{:.2},{:.6},{:.4},{:.4},{:.4},{:.4},{:.4},{:.3},{:.4},{:.6},{},{},{},{}",
            s.scene_name,
            s.method,
            s.label,
            f.epsilon,
            f.pixel_epsilon,
            f.max_iterations,
            f.escape_radius_squared,
            f.step_scale,
            s.scene.shading.normal.name(),
            s.scene.shading.normal_delta,
            r.seconds,
            r.steps_mean,
            m.mask_disagreement,
            m.depth_error_p50,
            m.depth_error_p95,
            m.depth_error_max,
            m.normal_error_deg_p50,
            m.normal_error_deg_p95,
            m.psnr_db,
            m.colour_rmse,
            m.overstep_rate,
            m.non_finite,
            s.scene.image.samples,
            s.scene.light.radius,
            s.scene.shading.occlusion
        );
    }
    out
}
