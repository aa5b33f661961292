//! The run files the results are generated from: `docs/results/index.csv` names each (an id the
//! sections ask for, its file, the command that wrote it, the build, the date, the device), and
//! each file is a CSV a command wrote.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use anyhow::{anyhow, Context, Result};

/// One run: where its file is and how it was made.
pub(super) struct Run {
    /// Relative to the repository's root.
    pub file: PathBuf,
    pub command: String,
    pub build: String,
    pub date: String,
    pub device: String,
    /// The CSV's rows, by column name.
    pub rows: Vec<HashMap<String, String>>,
}

impl Run {
    /// The first row whose `column` is `value`.
    pub fn row(&self, column: &str, value: &str) -> Result<&HashMap<String, String>> {
        self.rows
            .iter()
            .find(|r| r.get(column).map(String::as_str) == Some(value))
            .ok_or_else(|| anyhow!("{}: no row with {column} = {value}", self.file.display()))
    }

    /// The rows whose `column` is `value`.
    pub fn rows_where<'a>(
        &'a self,
        column: &'a str,
        value: &'a str,
    ) -> impl Iterator<Item = &'a HashMap<String, String>> + 'a {
        (self.rows.iter()).filter(move |r| r.get(column).map(String::as_str) == Some(value))
    }

    /// How the pages cite it: the command, the build, the date, the device and the file.
    pub fn provenance(&self, from_dir: &str) -> String {
        format!(
            "`{}` — build `{}`, {}, {}; [run file]({})",
            self.command,
            self.build,
            self.date,
            self.device,
            super::link_from(from_dir, &self.file)
        )
    }
}

/// Every run the index names.
pub(super) struct Runs {
    runs: HashMap<String, Run>,
}

impl Runs {
    /// The index and every file it names, under `root`.
    pub fn read(root: &Path) -> Result<Runs> {
        let index = root.join("docs").join("results").join("index.csv");
        let mut reader = csv::Reader::from_path(&index)
            .with_context(|| format!("reading the run index {}", index.display()))?;
        let mut runs = HashMap::new();
        for record in reader.deserialize::<HashMap<String, String>>() {
            let record = record.with_context(|| format!("{}", index.display()))?;
            let field = |name: &str| {
                record
                    .get(name)
                    .cloned()
                    .ok_or_else(|| anyhow!("{}: a row without `{name}`", index.display()))
            };
            let file = PathBuf::from(field("file")?);
            let rows = read_rows(&root.join(&file))?;
            let run = Run {
                file,
                command: field("command")?,
                build: field("build")?,
                date: field("date")?,
                device: field("device")?,
                rows,
            };
            runs.insert(field("id")?, run);
        }
        Ok(Runs { runs })
    }

    /// The run `id`, or an error naming it.
    pub fn get(&self, id: &str) -> Result<&Run> {
        self.runs
            .get(id)
            .ok_or_else(|| anyhow!("docs/results/index.csv names no run `{id}`"))
    }
}

fn read_rows(path: &Path) -> Result<Vec<HashMap<String, String>>> {
    let mut reader =
        csv::Reader::from_path(path).with_context(|| format!("reading {}", path.display()))?;
    reader
        .deserialize()
        .collect::<Result<Vec<_>, _>>()
        .with_context(|| format!("{}", path.display()))
}

/// A number from a row's `column`.
pub(super) fn num(row: &HashMap<String, String>, column: &str) -> Result<f64> {
    let text = row
        .get(column)
        .ok_or_else(|| anyhow!("no column `{column}`"))?;
    text.trim()
        .parse()
        .with_context(|| format!("`{column}` = `{text}` is not a number"))
}
