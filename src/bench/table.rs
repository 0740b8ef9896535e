//! `sward bench`'s report as text: the paper's table, one column per configuration, then
//! the ratios and the sweep.

use super::{BenchReport, BladeCounts, ConfigReport, GpuMs};

/// `1234567` as `1,234,567`, the way the paper prints blade counts.
pub fn thousands(n: u64) -> String {
    let digits = n.to_string();
    let mut out = String::with_capacity(digits.len() + digits.len() / 3);
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i).is_multiple_of(3) {
            out.push(',');
        }
        out.push(c);
    }
    out
}

/// The report as the paper's table, one column per configuration, then the ratios and
/// the sweep.
pub fn format_report(r: &BenchReport) -> String {
    use std::fmt::Write;
    let mut s = String::new();
    let _ = writeln!(s, "sward bench: {}", r.scene);
    let _ = writeln!(s, "adapter: {}", r.adapter);
    let _ = writeln!(s, "date: {}", r.date);
    let _ = writeln!(
        s,
        "{}x{}, {} measured frames after {} warm-up frames, dt = 1/30 s, fixed camera",
        r.size[0], r.size[1], r.frames, r.warmup
    );
    if !r.timestamps {
        let _ = writeln!(
            s,
            "the adapter has no timestamp queries: no GPU pass times, frame times are wall-clock"
        );
    }
    let _ = writeln!(s);
    let c = &r.configurations;
    let row = |s: &mut String, label: &str, values: Vec<String>| {
        let _ = write!(s, "{label:<46}");
        for v in values {
            let _ = write!(s, "{v:>16}");
        }
        let _ = writeln!(s);
    };
    let each = |f: &dyn Fn(&ConfigReport) -> String| c.iter().map(f).collect::<Vec<_>>();
    let ms = |v: Option<f64>| v.map_or_else(|| "n/a".to_string(), |v| format!("{v:.3}"));
    row(&mut s, "measurement", each(&|x| x.name.clone()));
    let time_label = if r.timestamps {
        "frame time, GPU passes (ms)"
    } else {
        "frame time, wall clock (ms)"
    };
    row(
        &mut s,
        "FPS (1000 / frame time)",
        each(&|x| format!("{:.1}", x.fps)),
    );
    row(&mut s, time_label, each(&|x| format!("{:.3}", x.frame_ms)));
    row(
        &mut s,
        "  wall clock per frame, submit to read-back (ms)",
        each(&|x| format!("{:.3}", x.wall_ms)),
    );
    let count = |f: fn(&BladeCounts) -> u64| each(&|x: &ConfigReport| thousands(f(&x.blades)));
    let _ = writeln!(s, "blades (last frame)");
    row(&mut s, "  total", count(|b| b.total));
    row(&mut s, "  drawn", count(|b| b.drawn));
    row(&mut s, "  culled", count(|b| b.culled));
    row(&mut s, "    by patch", count(|b| b.culled_patch));
    row(
        &mut s,
        "    by orientation",
        count(|b| b.culled_orientation),
    );
    row(&mut s, "    by view frustum", count(|b| b.culled_frustum));
    row(&mut s, "    by distance", count(|b| b.culled_distance));
    row(&mut s, "    by occlusion", count(|b| b.culled_occlusion));
    row(
        &mut s,
        "      of which with their patch",
        count(|b| b.culled_occlusion_patch),
    );
    row(
        &mut s,
        "      of which hidden by grass",
        count(|b| b.culled_occlusion_grass),
    );
    row(
        &mut s,
        "  drawn at LOD 0 (full mesh)",
        count(|b| b.drawn_per_level[0]),
    );
    row(&mut s, "  drawn at LOD 1", count(|b| b.drawn_per_level[1]));
    row(
        &mut s,
        "  drawn at LOD 2 (one segment)",
        count(|b| b.drawn_per_level[2]),
    );
    row(
        &mut s,
        "  drawn late (not seen last frame)",
        count(|b| b.drawn_late),
    );
    row(&mut s, "  stepped by the physics", count(|b| b.stepped));
    row(
        &mut s,
        "    of which throttled",
        count(|b| b.stepped_throttled),
    );
    row(&mut s, "patches visible", count(|b| b.visible_patches));
    work_rows(&mut s, c, &row);
    row(
        &mut s,
        "blades reset, non-finite state (since start)",
        each(&|x| thousands(x.blades_reset_nonfinite)),
    );
    let gpu = |f: fn(&GpuMs) -> f64| each(&|x: &ConfigReport| ms(x.gpu_ms.as_ref().map(f)));
    let _ = writeln!(s, "GPU time (ms, mean)");
    row(
        &mut s,
        "  physical model (update + wind)",
        gpu(|g| g.physics),
    );
    row(&mut s, "    blade update", gpu(|g| g.update));
    row(&mut s, "    wind solver", gpu(|g| g.wind));
    row(
        &mut s,
        "  visibility (occluders, pyramids, patches, culls)",
        gpu(|g| g.visibility),
    );
    row(&mut s, "  rendering (draw)", gpu(|g| g.rendering));
    row(&mut s, "  sun shadows (cascades)", gpu(|g| g.shadows));
    row(&mut s, "  tone mapping", gpu(|g| g.tone_map));
    row(&mut s, "  billboards (cull)", gpu(|g| g.billboards));
    row(&mut s, "  tiles (generation)", gpu(|g| g.tiles));
    row(&mut s, "  overlays and upscale", gpu(|g| g.overlays));
    row(
        &mut s,
        "  far levels' gains (measured)",
        gpu(|g| g.far_gain),
    );
    row(&mut s, "  skinning", gpu(|g| g.skinning));
    row(&mut s, "  GPU frame (every timed pass)", gpu(|g| g.frame()));
    row(
        &mut s,
        "collision spheres in the scene",
        each(&|x| thousands(x.colliders)),
    );
    row(
        &mut s,
        "collision spheres considered (broad phase)",
        each(&|x| thousands(x.colliders_considered)),
    );
    row(
        &mut s,
        "  sphere tests per stepped blade",
        each(&|x| format!("{:.2}", x.sphere_tests_per_blade)),
    );
    let _ = writeln!(s, "memory");
    row(
        &mut s,
        "  bytes per blade (layout)",
        each(&|x| x.memory.bytes_per_blade.to_string()),
    );
    row(
        &mut s,
        "  bytes per blade (blade buffers / blades)",
        each(&|x| format!("{:.2}", x.memory.measured_bytes_per_blade)),
    );
    row(
        &mut s,
        "  GPU memory of the scene (MiB)",
        each(&|x| format!("{:.1}", x.memory.gpu_mib)),
    );
    let _ = writeln!(s);
    let _ = writeln!(s, "ratios (this run)");
    // Small ratios (physics per blade against drawing per blade) keep three significant
    // digits instead of rounding to zero.
    let ratio = |v: Option<f64>, digits: usize| match v {
        None => "n/a".to_string(),
        Some(v) if v != 0.0 && v.abs() < 0.01 => format!("{v:.3e}"),
        Some(v) => format!("{v:.digits$}"),
    };
    let _ = writeln!(
        s,
        "  frame time, culling off / all features:                        {}",
        ratio(r.ratios.culling_off_over_all_frame_time, 3)
    );
    let _ = writeln!(
        s,
        "  blades culled one by one / blades in visible patches:         {}",
        ratio(r.ratios.culled_over_visible_patch_blades, 3)
    );
    let _ = writeln!(
        s,
        "  physics ms per stepped blade / rendering ms per drawn blade:  {}",
        ratio(r.ratios.physics_per_blade_over_rendering_per_drawn_blade, 4)
    );
    if let (Some(mean), Some(failing), Some(ok)) = (
        r.ratios.culled_vs_unculled_mean_difference,
        r.ratios.culled_vs_unculled_failing_pixels,
        r.ratios.culled_render_within_snapshot_tolerance,
    ) {
        let _ = writeln!(
            s,
            "  culled vs unculled frame: mean difference {mean:.3} (tolerance {}), failing pixels {:.3} % (tolerance {:.1} %): {}",
            sward::compare::MEAN_TOLERANCE,
            failing * 100.0,
            sward::compare::MAX_FAILING * 100.0,
            if ok { "within" } else { "OUTSIDE" }
        );
    }
    // A frame that takes far longer on the wall clock than its timed passes means the
    // timestamps missed work; say so rather than let the GPU rows pass for the whole truth.
    let missed: Vec<String> = c
        .iter()
        .filter(|x| x.gpu_ms.is_some() && x.wall_ms > 1.5 * x.frame_ms + 5.0)
        .map(|x| format!("{} (+{:.1} ms)", x.name, x.wall_ms - x.frame_ms))
        .collect();
    if !missed.is_empty() {
        let _ = writeln!(
            s,
            "note: the wall clock per frame exceeds the timed GPU passes in {}: the adapter's \
             timestamps do not cover all of the work (a software adapter may finish a pass \
             after its end timestamp); compare the wall-clock row between columns",
            missed.join(", ")
        );
    }
    if !r.sweep.is_empty() {
        let _ = writeln!(s);
        let _ = writeln!(s, "sweep (all features, density scaled)");
        let _ = writeln!(
            s,
            "{:>12}{:>12}{:>12}{:>14}{:>14}{:>10}{:>12}",
            "requested",
            "blades",
            "drawn",
            time_label_short(r.timestamps),
            "wall (ms)",
            "FPS",
            "GPU MiB"
        );
        for p in &r.sweep {
            let _ = writeln!(
                s,
                "{:>12}{:>12}{:>12}{:>14.3}{:>14.3}{:>10.1}{:>12.1}",
                thousands(p.requested),
                thousands(p.blades),
                thousands(p.drawn),
                p.frame_ms,
                p.wall_ms,
                p.fps,
                p.gpu_mib
            );
        }
    }
    s
}

fn time_label_short(timestamps: bool) -> &'static str {
    if timestamps {
        "GPU (ms)"
    } else {
        "frame (ms)"
    }
}

/// The work rows of the table: one counted frame's invocations per stage (the frame's
/// hardware-independent cost) and the lit grass's fragments per covered pixel.
fn work_rows(s: &mut String, c: &[ConfigReport], row: &dyn Fn(&mut String, &str, Vec<String>)) {
    use std::fmt::Write;
    use sward::render::work::WorkSummary;
    if c.iter().all(|x| x.work.is_none()) {
        return;
    }
    let each = |f: fn(&WorkSummary) -> String| {
        c.iter()
            .map(|x| {
                x.work
                    .as_ref()
                    .map_or_else(|| "n/a".to_string(), |w| f(&w.summary))
            })
            .collect::<Vec<_>>()
    };
    let _ = writeln!(s, "work (one counted frame, invocations)");
    row(
        s,
        "  vertex shader",
        each(|w| thousands(w.vertex_invocations)),
    );
    row(
        s,
        "  primitives rasterised",
        each(|w| thousands(w.primitives)),
    );
    row(
        s,
        "  fragment shader",
        each(|w| thousands(w.fragment_invocations)),
    );
    row(
        s,
        "  compute shader",
        each(|w| thousands(w.compute_invocations)),
    );
    row(
        s,
        "  pixels covered by grass",
        each(|w| thousands(w.grass_pixels)),
    );
    row(
        s,
        "  lit grass fragments per covered pixel",
        each(|w| {
            w.lit_fragments_per_pixel
                .map_or_else(|| "n/a".into(), |r| format!("{r:.2}"))
        }),
    );
}
