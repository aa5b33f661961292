//! `foveate results`: the results page (`docs/results.md`) and the README's verdict table,
//! generated from the committed run files `docs/results/index.csv` names — each section a
//! small table, the command that made it, its build and date — so no figure on them can drift
//! from its run. `--check` compares instead of writing (CI runs it through the tests).

mod runs;
mod sections;
mod sections_more;

use std::path::{Path, PathBuf};

use anyhow::{bail, Context, Result};
use clap::Args;

use runs::Runs;

/// Where the README's generated table begins and ends.
const README_BEGIN: &str = "<!-- results:readme begin (scripts/results.sh writes this) -->";
const README_END: &str = "<!-- results:readme end -->";

#[derive(Args)]
pub struct ResultsArgs {
    /// The repository's root (where README.md and docs/ are).
    #[arg(long, default_value = ".")]
    root: PathBuf,
    /// Compare the pages with what the run files give instead of writing them; an error names
    /// each page that differs.
    #[arg(long)]
    check: bool,
}

pub fn results(args: &ResultsArgs) -> Result<()> {
    let runs = Runs::read(&args.root)?;
    let page = sections::page(&runs)?;
    let readme_path = args.root.join("README.md");
    let readme = std::fs::read_to_string(&readme_path)
        .with_context(|| format!("reading {}", readme_path.display()))?;
    let readme_new = with_block(&readme, &sections::readme_table(&runs)?)?;
    let page_path = args.root.join("docs").join("results.md");
    let pages = [(page_path, page), (readme_path, readme_new)];
    if args.check {
        let stale: Vec<String> = (pages.iter())
            .filter(|(path, text)| std::fs::read_to_string(path).ok().as_deref() != Some(text))
            .map(|(path, _)| path.display().to_string())
            .collect();
        if !stale.is_empty() {
            bail!(
                "{} differ from what the run files give: run scripts/results.sh",
                stale.join(" and ")
            );
        }
        println!("docs/results.md and the README's table match their run files");
        return Ok(());
    }
    for (path, text) in &pages {
        foveate::write_atomic(path, text.as_bytes())?;
        println!("wrote {}", path.display());
    }
    Ok(())
}

/// `readme` with the text between its markers replaced by `table`.
fn with_block(readme: &str, table: &str) -> Result<String> {
    let (Some(begin), Some(end)) = (readme.find(README_BEGIN), readme.find(README_END)) else {
        bail!("README.md has no `{README_BEGIN}` … `{README_END}` block for the verdict table");
    };
    if end < begin {
        bail!("README.md's results block ends before it begins");
    }
    let head = &readme[..begin + README_BEGIN.len()];
    Ok(format!("{head}\n{table}{}", &readme[end..]))
}

/// A path under the root as the pages link it (from `docs/`, or from the root).
fn link_from(dir: &str, file: &Path) -> String {
    let file = file.to_string_lossy();
    match dir {
        "docs" => file
            .strip_prefix("docs/")
            .map_or(format!("../{file}"), str::to_string),
        _ => file.to_string(),
    }
}
