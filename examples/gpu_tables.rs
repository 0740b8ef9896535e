//! Writes the README's performance tables (Markdown) from `sward bench --json` reports:
//! `cargo run --release --example gpu_tables -- LABEL=report.json ...` prints one table
//! per report, headed by its label; a label `paper:nature` or `paper:helicopter` prints the
//! paper's table for that scene beside the report instead. `scripts/gpu-measure.sh` runs it
//! after measuring.

use std::process::ExitCode;

fn main() -> ExitCode {
    let mut out = String::new();
    for arg in std::env::args().skip(1) {
        let Some((label, path)) = arg.split_once('=') else {
            eprintln!("gpu_tables: {arg}: expected LABEL=report.json");
            return ExitCode::FAILURE;
        };
        let report = match std::fs::read(path)
            .map_err(|e| e.to_string())
            .and_then(|b| serde_json::from_slice(&b).map_err(|e| e.to_string()))
        {
            Ok(r) => r,
            Err(e) => {
                eprintln!("gpu_tables: {path}: {e}");
                return ExitCode::FAILURE;
            }
        };
        let table = match label.strip_prefix("paper:") {
            Some(scene) => match sward_app::bench::gpu_tables::paper_table(scene, &report) {
                Some(t) => t,
                None => {
                    eprintln!("gpu_tables: {label}: the paper measured nature and helicopter");
                    return ExitCode::FAILURE;
                }
            },
            None => sward_app::bench::gpu_tables::report_table(label, &report),
        };
        out += &table;
        out.push('\n');
    }
    print!("{out}");
    ExitCode::SUCCESS
}
