//! Printing workload counts: what a counting frame measured (fragments per step and view, scene
//! and total), and bytes in MiB.

use foveate::plan::CountedStep;
use foveate::render::FrameStats;

/// Bytes in MiB, as the workload columns print them.
pub fn mib(bytes: u64) -> f64 {
    bytes as f64 / (1024.0 * 1024.0)
}

const VIEW_NAMES: [&str; 7] = [
    "left eye",
    "right eye",
    "left fovea",
    "right fovea",
    "left ring",
    "right ring",
    "far view",
];

/// The counting frame's fragments: the scene's and the whole frame's, then every counted step
/// per view (`view_pixels`, the pixels of one view of the scene pass, scales the scene draws to
/// fragments per pixel); then each pass's primitives (`pass_names` in plan order).
pub fn print_fragments(counts: &FrameStats, view_pixels: u64, pass_names: &[&str]) {
    println!(
        "  fragments (a separate counting frame): scene {}, total {} (every pass: masks, composites, probes included)",
        counts.scene_fragments(),
        counts.total_fragments()
    );
    for step in &counts.steps {
        let views: Vec<String> = step
            .views
            .iter()
            .enumerate()
            .filter(|&(_, &n)| n > 0)
            .map(|(v, &n)| {
                if step.step == CountedStep::Scene {
                    format!(
                        "{} {n} ({:.3}/px)",
                        VIEW_NAMES[v],
                        n as f64 / view_pixels as f64
                    )
                } else {
                    format!("{} {n}", VIEW_NAMES[v])
                }
            })
            .collect();
        println!(
            "    {} / {}: {}",
            step.pass,
            step.step.name(),
            if views.is_empty() {
                "0".to_string()
            } else {
                views.join(", ")
            }
        );
    }
    if !counts.pass_statistics.is_empty() {
        println!(
            "  per pass (pipeline statistics, summed over views; lavapipe counts each view of a multiview pass):"
        );
        for (name, p) in pass_names.iter().zip(&counts.pass_statistics) {
            println!(
                "    {name}: {} primitives assembled, {} clipped in, {} rasterised; {} fragment shader invocations",
                p.assembled, p.clipped_in, p.rasterised, p.fragment_invocations
            );
        }
    }
}
