//! The performance page's tables (docs/performance.md) from `sward bench --json` reports: what
//! `scripts/gpu-measure.sh` writes after measuring on a machine with a GPU, so a session
//! that is lent one spends its minutes measuring. The reports are read as JSON values
//! (any mode: the three columns with their sweep, `--flight`, `--light`), so the tables
//! follow whatever the bench wrote.

use serde_json::Value;

fn num(v: &Value, path: &[&str]) -> Option<f64> {
    path.iter().try_fold(v, |v, k| v.get(k))?.as_f64()
}

fn cell(v: Option<f64>, digits: usize) -> String {
    v.map_or_else(|| "n/a".into(), |x| format!("{x:.digits$}"))
}

fn count(v: Option<f64>) -> String {
    v.map_or_else(
        || "n/a".into(),
        |x| super::table::thousands(x.max(0.0).round() as u64),
    )
}

/// A table's heading: `title`, then the report's adapter, size, frames and date.
fn heading(title: &str, r: &Value) -> String {
    format!(
        "#### {title}\n\n{}, {}x{}, {} frames after {} warm-up ({})\n\n",
        r["adapter"].as_str().unwrap_or("unknown adapter"),
        r["size"].get(0).and_then(Value::as_f64).unwrap_or(0.0),
        r["size"].get(1).and_then(Value::as_f64).unwrap_or(0.0),
        num(r, &["frames"]).unwrap_or(0.0),
        num(r, &["warmup"]).unwrap_or(0.0),
        r["date"].as_str().unwrap_or(""),
    )
}

/// One report's table (`label` names the run: scene, size, settings), in Markdown.
pub fn report_table(label: &str, r: &Value) -> String {
    let mut out = heading(label, r);
    if let Some(configs) = r["configurations"].as_array() {
        out += "| configuration | GPU ms | wall ms | FPS | blades drawn | vertex inv. | fragment inv. | compute inv. | lit fragments / grass pixel |\n|---|---:|---:|---:|---:|---:|---:|---:|---:|\n";
        for c in configs {
            let w = &c["work"];
            out += &format!(
                "| {} | {} | {} | {} | {} | {} | {} | {} | {} |\n",
                c["name"].as_str().unwrap_or("?"),
                cell(num(c, &["frame_ms"]), 2),
                cell(num(c, &["wall_ms"]), 2),
                cell(num(c, &["fps"]), 1),
                count(num(c, &["blades", "drawn"])),
                count(num(w, &["vertex_invocations"])),
                count(num(w, &["fragment_invocations"])),
                count(num(w, &["compute_invocations"])),
                cell(num(w, &["lit_fragments_per_pixel"]), 2),
            );
        }
    }
    if let Some(sweep) = r["sweep"].as_array().filter(|s| !s.is_empty()) {
        out += "\n| blades | drawn | GPU ms | wall ms | FPS | GPU MiB |\n|---:|---:|---:|---:|---:|---:|\n";
        for p in sweep {
            out += &format!(
                "| {} | {} | {} | {} | {} | {} |\n",
                count(num(p, &["blades"])),
                count(num(p, &["drawn"])),
                cell(num(p, &["frame_ms"]), 2),
                cell(num(p, &["wall_ms"]), 2),
                cell(num(p, &["fps"]), 1),
                cell(num(p, &["gpu_mib"]), 0),
            );
        }
    }
    if r.get("pop_ratio").is_some() {
        out += "| GPU p50 ms | GPU p95 ms | wall p50 ms | wall p95 ms | blades drawn (mean) | pop ratio |\n|---:|---:|---:|---:|---:|---:|\n";
        out += &format!(
            "| {} | {} | {} | {} | {} | {} |\n",
            cell(num(r, &["p50_ms"]), 2),
            cell(num(r, &["p95_ms"]), 2),
            cell(num(r, &["wall_p50_ms"]), 2),
            cell(num(r, &["wall_p95_ms"]), 2),
            count(num(r, &["blades_drawn_mean"])),
            cell(num(r, &["pop_ratio"]), 2),
        );
    }
    if let Some(configs) = r["configs"].as_array() {
        out += "| light | GPU ms | / no shadows | wall ms | / no shadows | shadows ms | fragment inv. | lit fragments / grass pixel |\n|---|---:|---:|---:|---:|---:|---:|---:|\n";
        for c in configs {
            let w = &c["work"];
            out += &format!(
                "| {} | {} | {} | {} | {} | {} | {} | {} |\n",
                c["config"].as_str().unwrap_or("?"),
                cell(num(c, &["frame_ms"]), 2),
                cell(num(c, &["frame_over_no_shadows"]), 3),
                cell(num(c, &["wall_ms"]), 2),
                cell(num(c, &["wall_over_no_shadows"]), 3),
                cell(num(c, &["shadows_ms"]), 2),
                count(num(w, &["fragment_invocations"])),
                cell(num(w, &["lit_fragments_per_pixel"]), 2),
            );
        }
    }
    out
}

/// One of the paper's measured scenes (Jahrmann & Wimmer 2017, Tables 1 and 3: a GTX 780M
/// at 1024x768 with 8x MSAA), per configuration (all features, collisions off, culling
/// off): frame time, blades drawn, and the physical model's, the visibility's and the
/// rendering's times (ms).
struct PaperScene {
    frame_ms: [f64; 3],
    drawn: [f64; 3],
    physics_ms: [f64; 3],
    visibility_ms: [f64; 3],
    rendering_ms: [f64; 3],
}

/// Table 1 of the paper.
const PAPER_NATURE: PaperScene = PaperScene {
    frame_ms: [8.130, 7.742, 12.821],
    drawn: [43_128.0, 43_128.0, 168_333.0],
    physics_ms: [0.547, 0.041, 0.519],
    visibility_ms: [1.401, 1.392, 2.375],
    rendering_ms: [2.057, 2.082, 3.872],
};

/// Table 3 of the paper.
const PAPER_HELICOPTER: PaperScene = PaperScene {
    frame_ms: [17.860, 17.692, 28.624],
    drawn: [165_135.0, 165_135.0, 503_382.0],
    physics_ms: [1.421, 1.372, 1.570],
    visibility_ms: [6.817, 6.792, 8.142],
    rendering_ms: [5.471, 5.398, 9.149],
};

/// The paper's table for `scene` ("nature" or "helicopter") beside sward's bench report of
/// the same scene (best measured in the paper's setup: `--size 1024x768 --set
/// render.msaa=8`), in Markdown; `None` for another scene name.
pub fn paper_table(scene: &str, r: &Value) -> Option<String> {
    let paper = match scene {
        "nature" => &PAPER_NATURE,
        "helicopter" => &PAPER_HELICOPTER,
        _ => return None,
    };
    let configs = r["configurations"].as_array();
    let config = |i: usize| configs.and_then(|c| c.get(i));
    let mut out = heading(
        &format!("{scene}: the paper (GTX 780M, 1024x768, 8x MSAA) beside sward"),
        r,
    );
    out += "| measurement | all features: paper | sward | collisions off: paper | sward | culling off: paper | sward |\n|---|---:|---:|---:|---:|---:|---:|\n";
    type Row<'a> = (
        &'a str,
        &'a [f64; 3],
        &'a dyn Fn(&Value) -> Option<f64>,
        bool,
    );
    let rows: [Row; 6] = [
        (
            "frame time, GPU (ms)",
            &paper.frame_ms,
            &|c| num(c, &["frame_ms"]),
            false,
        ),
        (
            "wall clock (ms)",
            &paper.frame_ms,
            &|c| num(c, &["wall_ms"]),
            false,
        ),
        (
            "blades drawn",
            &paper.drawn,
            &|c| num(c, &["blades", "drawn"]),
            true,
        ),
        (
            "physical model (ms)",
            &paper.physics_ms,
            &|c| num(c, &["gpu_ms", "physics"]),
            false,
        ),
        (
            "visibility (ms)",
            &paper.visibility_ms,
            &|c| num(c, &["gpu_ms", "visibility"]),
            false,
        ),
        (
            "rendering (ms)",
            &paper.rendering_ms,
            &|c| num(c, &["gpu_ms", "rendering"]),
            false,
        ),
    ];
    for (name, theirs, ours, counted) in rows {
        out += &format!("| {name} |");
        for (i, t) in theirs.iter().enumerate() {
            let show = |v: Option<f64>| if counted { count(v) } else { cell(v, 3) };
            // The paper timed the frame once: its wall clock row repeats the frame time.
            let paper = if name.starts_with("wall") {
                "–".into()
            } else {
                show(Some(*t))
            };
            out += &format!(" {paper} | {} |", show(config(i).and_then(ours)));
        }
        out.push('\n');
    }
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_three_column_report_becomes_one_row_per_configuration_and_sweep_point() {
        let r = serde_json::json!({
            "adapter": "Some GPU", "date": "2026-11-25 12:00 UTC", "size": [1920, 1080],
            "frames": 10, "warmup": 5,
            "configurations": [
                {"name": "all features", "frame_ms": 8.126, "wall_ms": 9.5, "fps": 123.1,
                 "blades": {"drawn": 43439}, "work": {"vertex_invocations": 1000,
                 "fragment_invocations": 2000, "compute_invocations": 3000,
                 "lit_fragments_per_pixel": 1.2}},
                {"name": "culling off", "frame_ms": 20.0, "wall_ms": 21.0, "fps": 50.0,
                 "blades": {"drawn": 100000}, "work": null}
            ],
            "sweep": [{"blades": 10000000, "drawn": 500000, "frame_ms": 30.0, "wall_ms": 31.0,
                       "fps": 33.3, "gpu_mib": 1000.0}]
        });
        let t = report_table("nature", &r);
        assert!(
            t.contains("Some GPU, 1920x1080, 10 frames after 5 warm-up"),
            "{t}"
        );
        assert!(
            t.contains(
                "| all features | 8.13 | 9.50 | 123.1 | 43,439 | 1,000 | 2,000 | 3,000 | 1.20 |"
            ),
            "{t}"
        );
        assert!(
            t.contains("| culling off | 20.00 | 21.00 | 50.0 | 100,000 | n/a | n/a | n/a | n/a |"),
            "{t}"
        );
        assert!(
            t.contains("| 10,000,000 | 500,000 | 30.00 | 31.00 | 33.3 | 1000 |"),
            "{t}"
        );
    }

    #[test]
    fn the_papers_tables_stand_beside_the_report_column_by_column() {
        let r = serde_json::json!({
            "adapter": "Some GPU", "date": "d", "size": [1024, 768], "frames": 60, "warmup": 10,
            "configurations": [
                {"name": "all features", "frame_ms": 6.93, "wall_ms": 8.88,
                 "blades": {"drawn": 45246},
                 "gpu_ms": {"physics": 0.369, "visibility": 1.553, "rendering": 4.537}},
                {"name": "collisions off", "frame_ms": 6.24, "wall_ms": 7.95,
                 "blades": {"drawn": 45207}, "gpu_ms": {}},
            ]
        });
        let t = paper_table("nature", &r).unwrap();
        assert!(
            t.contains("| frame time, GPU (ms) | 8.130 | 6.930 | 7.742 | 6.240 | 12.821 | n/a |"),
            "{t}"
        );
        assert!(
            t.contains("| blades drawn | 43,128 | 45,246 | 43,128 | 45,207 | 168,333 | n/a |"),
            "{t}"
        );
        assert!(t.contains("| wall clock (ms) | – | 8.880 |"), "{t}");
        assert!(
            t.contains("| physical model (ms) | 0.547 | 0.369 | 0.041 | n/a |"),
            "{t}"
        );
        assert!(paper_table("helicopter", &r)
            .unwrap()
            .contains("| rendering (ms) | 5.471 | 4.537 |"));
        assert!(paper_table("prairie", &r).is_none());
    }
}
