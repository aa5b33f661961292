//! The plan's attachments as `foveate plan` prints them: each one's format, size and bytes,
//! and its share of the frame's external traffic on a tile GPU (loaded, stored, sampled, read
//! back: the plan's formula), so the frame's total reads line by line.

use std::fmt;

use super::model::FramePlan;
use super::print::mib;

impl FramePlan {
    pub(super) fn write_attachments(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "attachments (traffic per frame on a tile GPU, by the plan's formula):"
        )?;
        let name = (self.attachments.iter().map(|a| a.name.len()))
            .chain(["name".len()])
            .max()
            .unwrap_or(4);
        writeln!(
            f,
            "  {:<2} {:<name$} {:<8} {:<10} {:>7} {:>11} {:>6} {:>9} {:>11} {:>11} {:>11} {:>11} {:>11}",
            "#", "name", "role", "format", "samples", "extent", "layers", "transient", "bytes",
            "loaded", "stored", "sampled", "read back"
        )?;
        let traffic = self.attachment_traffic();
        for (i, (a, t)) in self.attachments.iter().zip(&traffic).enumerate() {
            writeln!(
                f,
                "  {:<2} {:<name$} {:<8} {:<10} {:>7} {:>11} {:>6} {:>9} {:>11} {:>11} {:>11} {:>11} {:>11}",
                i,
                a.name,
                format!("{:?}", a.role).to_lowercase(),
                format!("{:?}", a.format),
                a.samples,
                format!("{}x{}", a.width, a.height),
                a.layers,
                if a.transient { "yes" } else { "no" },
                mib(a.bytes()),
                mib(t.loaded),
                mib(t.stored),
                mib(t.sampled),
                mib(t.read_back),
            )?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::super::tests::{config, planned};
    use super::super::*;
    use crate::foveation::FoveationConfig;

    /// The default foveation (periphery accumulated) at 4×.
    fn accumulated() -> FramePlan {
        planned(&RenderConfig {
            foveation: Some(FoveationConfig::default()),
            ..config(StereoMode::Multiview, 4)
        })
    }

    /// Each attachment's traffic is what its uses say: the history read this frame is sampled
    /// whole and the one written stored whole, the output stored and read back, a transient
    /// attachment moves nothing, and the rows add up to the frame's total. Mutations: the
    /// sampled bytes counted against the pass's colour attachment, or a transient attachment's
    /// stores counted, fail it.
    #[test]
    fn each_attachment_moves_what_its_uses_say() {
        let plan = accumulated();
        let traffic = plan.attachment_traffic();
        let named = |prefix: &str| {
            let i = (plan.attachments.iter())
                .position(|a| a.name.starts_with(prefix))
                .unwrap_or_else(|| panic!("no {prefix} in {plan}"));
            (plan.attachments[i].bytes(), traffic[i])
        };
        let (bytes, read) = named("periphery history (even frames read)");
        assert_eq!((read.sampled, read.stored, read.loaded), (bytes, 0, 0));
        let (bytes, written) = named("periphery history (even frames write)");
        assert_eq!((written.stored, written.sampled), (bytes, 0));
        let output = plan.outputs()[0];
        let out = traffic[output];
        let out_bytes = plan.attachments[output].bytes();
        assert_eq!((out.stored, out.read_back), (out_bytes, out_bytes));
        for (a, t) in plan.attachments.iter().zip(&traffic) {
            if a.transient {
                assert_eq!(t.total(), 0, "{} is transient", a.name);
            }
        }
        let sum: u64 = traffic.iter().map(|t| t.total()).sum();
        assert_eq!(sum, plan.external_traffic_bytes());
    }

    /// The printed table's traffic columns add up to the printed total, to the printout's
    /// rounding. Mutation: a column left out of the row fails it.
    #[test]
    fn the_printed_rows_add_up_to_the_printed_total() {
        let text = accumulated().to_string();
        let mib = |s: &str| s.trim_end_matches(" MiB").trim().parse::<f64>().unwrap();
        let rows: Vec<f64> = (text.lines())
            .skip_while(|l| !l.starts_with("attachments"))
            .skip(2)
            .take_while(|l| !l.starts_with("passes"))
            .map(|l| {
                let fields: Vec<&str> = l.split(" MiB").collect();
                // bytes, loaded, stored, sampled, read back: the last four are traffic.
                (fields[fields.len() - 5..fields.len() - 1].iter())
                    .map(|f| mib(f.rsplit(' ').next().unwrap()))
                    .sum()
            })
            .collect();
        assert!(rows.len() >= 5, "{text}");
        let total_line = (text.lines())
            .find(|l| l.starts_with("estimated external traffic"))
            .unwrap();
        let total = mib(total_line
            .split(": ")
            .nth(1)
            .unwrap()
            .split(" (")
            .next()
            .unwrap());
        let sum: f64 = rows.iter().sum();
        let rounding = 0.005 * 4.0 * rows.len() as f64;
        assert!(
            (sum - total).abs() <= rounding,
            "{sum} against {total}\n{text}"
        );
    }
}
