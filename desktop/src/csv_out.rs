//! CSV tables the commands write: through the `csv` crate, so fields holding commas or quotes
//! are quoted and every row has as many fields as the header (a short or long row is an error,
//! not a shifted column).

use std::fmt::Display;
use std::path::Path;

use anyhow::{Context, Result};

pub struct CsvTable {
    writer: csv::Writer<Vec<u8>>,
}

impl CsvTable {
    pub fn new(header: &[&str]) -> Result<Self> {
        let mut writer = csv::Writer::from_writer(Vec::new());
        writer.write_record(header)?;
        Ok(CsvTable { writer })
    }

    /// One row; an empty string stands for a missing value.
    pub fn row(&mut self, fields: &[&dyn Display]) -> Result<()> {
        self.writer
            .write_record(fields.iter().map(|f| f.to_string()))
            .context("CSV row")
    }

    pub fn into_string(self) -> Result<String> {
        let bytes = self.writer.into_inner().context("CSV table")?;
        Ok(String::from_utf8(bytes)?)
    }

    /// Writes the table where `--csv` asked for it, and says so.
    pub fn save(self, path: Option<&Path>) -> Result<()> {
        if let Some(path) = path {
            foveate::write_atomic(path, self.into_string()?.as_bytes())?;
            println!("wrote {}", path.display());
        }
        Ok(())
    }
}

/// A float with `decimals` places, or an empty field for none.
pub fn opt(value: Option<f64>, decimals: usize) -> String {
    value.map_or(String::new(), |v| format!("{v:.decimals$}"))
}
