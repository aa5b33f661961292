//! What a Mesa driver decided for each render pass, read back from its own trace
//! (`MESA_GPU_TRACES=print` into `MESA_GPU_TRACEFILE`): on turnip, whether the pass ran on tile
//! (in GMEM, bin by bin) or straight to system memory, its bins, the bytes per pixel it
//! cleared, loaded and stored, and whether Adreno's low-resolution depth test (LRZ) ran, and if
//! not why. Drivers without the trace (lavapipe) write none: the report then says so.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result};

/// One render pass as the driver's trace describes it: the fields of its `start_render_pass`
/// and `end_render_pass` lines, by the driver's names (`tiledRender`, `numberOfBins`, `lrz`…).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TracedPass {
    pub fields: BTreeMap<String, String>,
}

impl TracedPass {
    pub fn get(&self, name: &str) -> &str {
        self.fields.get(name).map_or("?", String::as_str)
    }
}

/// The trace file this process asks the driver for, set in the environment before the device
/// starts (the driver reads it once, as it loads); `None` where the user set
/// `MESA_GPU_TRACES` already (their trace goes where they said).
pub fn request() -> Option<PathBuf> {
    if std::env::var_os("MESA_GPU_TRACES").is_some() {
        return None;
    }
    let path = std::env::temp_dir().join(format!("foveate-gpu-trace-{}.txt", std::process::id()));
    // Set before any Vulkan object exists, while this process runs one thread.
    std::env::set_var("MESA_GPU_TRACES", "print");
    std::env::set_var("MESA_GPU_TRACEFILE", &path);
    Some(path)
}

/// Every render pass in the trace at `path`, in the order the driver processed them.
pub fn read(path: &Path) -> Result<Vec<TracedPass>> {
    let text = std::fs::read_to_string(path)
        .with_context(|| format!("the driver's trace {}", path.display()))?;
    Ok(parse(&text))
}

/// Prints each mode's passes as the driver decided them (`recorded`: each mode's name and its
/// passes' names, in the order its `frames` frames recorded them), from the trace at `path`,
/// which it then removes.
pub fn report(path: &Path, recorded: &[(&str, Vec<&'static str>)], frames: u32) -> Result<()> {
    let traced = read(path);
    let _ = std::fs::remove_file(path);
    let passes = match traced {
        Ok(p) if !p.is_empty() => p,
        _ => {
            println!("\nthe driver wrote no trace of its render passes (MESA_GPU_TRACES: Mesa's turnip, RADV, ANV …)");
            return Ok(());
        }
    };
    let expected: usize = recorded.iter().map(|r| r.1.len() * frames as usize).sum();
    if passes.len() != expected {
        println!(
            "\nthe driver traced {} render passes where the frames recorded {expected}: not matched to the plan's passes",
            passes.len()
        );
        return Ok(());
    }
    println!("\nthe driver's decision for each pass (its trace, the last frame of each mode):");
    println!(
        "  {:<8} {:>4} {:>11} {:>5} {:>8} {:>13} {:>6} {:>4}  pass",
        "tiled", "spp", "size", "bins", "bin", "clear/load/st", "draws", "lrz"
    );
    let mut at = 0;
    for (mode, names) in recorded {
        at += names.len() * frames as usize;
        println!("  {mode}");
        for (pass, name) in passes[at - names.len()..at].iter().zip(names) {
            println!("{}", row(pass, name));
        }
    }
    Ok(())
}

fn row(p: &TracedPass, name: &str) -> String {
    let tiled = match p.get("tiledRender") {
        "true" => "GMEM",
        "false" => "sysmem",
        other => other,
    };
    let lrz = match (p.get("lrz"), p.get("lrzDisableReason")) {
        ("true", _) => "on".to_string(),
        (_, "") => "off".to_string(),
        (_, why) => format!("off ({why})"),
    };
    format!(
        "  {:<8} {:>4} {:>11} {:>5} {:>8} {:>13} {:>6} {:>4}  {name}",
        tiled,
        p.get("maxSamples"),
        format!("{}x{}", p.get("width"), p.get("height")),
        p.get("numberOfBins"),
        format!("{}x{}", p.get("binWidth"), p.get("binHeight")),
        format!(
            "{}/{}/{}",
            p.get("clearCPP"),
            p.get("loadCPP"),
            p.get("storeCPP")
        ),
        p.get("drawCount"),
        lrz
    )
}

/// The render passes of a `print` trace: a `start_render_pass:` line opens one, its
/// `end_render_pass:` line closes it; each line's `name=value, ` pairs are kept.
pub fn parse(text: &str) -> Vec<TracedPass> {
    let mut passes = Vec::new();
    let mut open: Option<TracedPass> = None;
    for line in text.lines() {
        if let Some(rest) = after(line, "start_render_pass:") {
            let mut pass = TracedPass::default();
            fields(rest, &mut pass.fields);
            open = Some(pass);
        } else if let Some(rest) = after(line, "end_render_pass:") {
            if let Some(mut pass) = open.take() {
                fields(rest, &mut pass.fields);
                passes.push(pass);
            }
        }
    }
    passes
}

fn after<'a>(line: &'a str, marker: &str) -> Option<&'a str> {
    line.find(marker).map(|i| &line[i + marker.len()..])
}

fn fields(text: &str, into: &mut BTreeMap<String, String>) {
    for pair in text.split(", ") {
        if let Some((name, value)) = pair.trim().trim_end_matches(',').split_once('=') {
            into.insert(name.to_string(), value.to_string());
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two passes from a real trace of turnip (Adreno 650, the default foveation's periphery
    /// and output passes), timestamps and the steps between them left as the driver wrote them.
    /// Mutation: matching the end line to the wrong pass, or splitting on `,` alone (the reason
    /// `lrzDisableReason=` is empty), fails it.
    #[test]
    fn a_print_trace_gives_each_pass_its_fields() {
        let text = "\
0000000000000000        +0: start_cmd_buffer: appName=foveate, engineName=foveate, level=VK_COMMAND_BUFFER_LEVEL_PRIMARY, render_pass_continue=0, 
1932102308140680780 +1201603044: start_render_pass: maxSamples=1, clearCPP=8, loadCPP=0, storeCPP=8, hasDepth=true, ubwc=y|y, width=1080, height=1152, attachment_count=2, numberOfBins=24, binWidth=192, binHeight=320, 
204913846309160040 -1201603044: start_binning_ib
43910766391984128 +10223616: end_render_pass: tiledRender=true, drawCount=7, avgPerSampleBandwidth=7, lrz=true, lrzDisableReason=, lrzDisabledAtDraw=0, lrzStatus=INVALID, 
1829587348619316        +0: start_render_pass: maxSamples=1, clearCPP=0, loadCPP=0, storeCPP=8, hasDepth=false, ubwc=yy, width=1800, height=1920, attachment_count=2, numberOfBins=50, binWidth=192, binHeight=384, 
1829587348619316        +0: end_render_pass: tiledRender=false, drawCount=1, avgPerSampleBandwidth=10, lrz=false, lrzDisableReason=, lrzDisabledAtDraw=0, lrzStatus=INVALID, 
END OF FRAME 0
";
        let passes = parse(text);
        assert_eq!(passes.len(), 2);
        assert_eq!(passes[0].get("tiledRender"), "true");
        assert_eq!(passes[0].get("numberOfBins"), "24");
        assert_eq!(passes[0].get("storeCPP"), "8");
        assert_eq!(passes[0].get("lrzDisableReason"), "");
        assert_eq!(passes[1].get("tiledRender"), "false");
        assert_eq!(passes[1].get("width"), "1800");
        assert_eq!(passes[1].get("drawCount"), "1");
        assert_eq!(passes[1].get("nothing"), "?");
    }
}
