//! The analytic pixel budget of a foveated frame (Di Donato 2017, Tables 2–4). `foveate pixels`
//! measures the same quantities on the GPU and compares them with these formulas.

/// Arm's tables were computed with π taken as 3.14; pass it to reproduce their printed cells.
#[allow(clippy::approx_constant)] // deliberately Arm's rounded π, not ours
pub const ARM_PI: f64 = 3.14;

/// Pixels shaded per frame, both eyes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PixelBudget {
    /// Pixels the fovea views shade.
    pub fovea: f64,
    /// Pixels the periphery views shade.
    pub periphery: f64,
}

impl PixelBudget {
    /// Both.
    pub fn total(&self) -> f64 {
        self.fovea + self.periphery
    }

    /// Reduction in percent against plain stereo at `screen`² per eye.
    pub fn reduction_percent(&self, screen: u32) -> f64 {
        100.0 * (1.0 - self.total() / (2.0 * screen as f64 * screen as f64))
    }

    /// Two periphery views of `periphery` pixels and two fovea views of `fovea` pixels. With
    /// stencil masks the fovea keeps its inset circle of `fovea_circle_px` and the periphery
    /// drops the hole of `periphery_hole_px` the fovea covers (both diameters in their own
    /// view's pixels).
    pub fn analytic(
        periphery: (u32, u32),
        fovea: (u32, u32),
        fovea_circle_px: f64,
        periphery_hole_px: f64,
        stencil: bool,
        pi: f64,
    ) -> PixelBudget {
        let area = |v: (u32, u32)| v.0 as f64 * v.1 as f64;
        if !stencil {
            return PixelBudget {
                fovea: 2.0 * area(fovea),
                periphery: 2.0 * area(periphery),
            };
        }
        PixelBudget {
            fovea: 2.0 * circle_in_view(fovea_circle_px, fovea, pi),
            periphery: 2.0 * (area(periphery) - pi * (periphery_hole_px / 2.0).powi(2)),
        }
    }

    /// The budget of a resolved foveation, with the true π.
    pub fn of(g: &super::FoveationGeometry) -> PixelBudget {
        PixelBudget::analytic(
            (g.periphery_view.width, g.periphery_view.height),
            (g.fovea_view.width, g.fovea_view.height),
            g.fovea_circle_px as f64,
            g.periphery_hole_px as f64,
            g.stencil,
            std::f64::consts::PI,
        )
    }
}

/// The area of a circle of `diameter` centred in a view of `view` pixels: π r² while it fits
/// (with `pi`, so Arm's rounded π reproduces their cells), else the part inside the view (the
/// fovea's circle reaches past its view by the filter's margin when the fovea fills it).
fn circle_in_view(diameter: f64, view: (u32, u32), pi: f64) -> f64 {
    let r = diameter / 2.0;
    let (a, b) = (view.0 as f64 / 2.0, view.1 as f64 / 2.0);
    if r <= a.min(b) {
        return pi * r * r;
    }
    // A quarter: ∫₀^min(a, r) min(b, √(r² − x²)) dx, with F the integral of √(r² − x²).
    let f = |x: f64| 0.5 * (x * (r * r - x * x).max(0.0).sqrt() + r * r * (x / r).asin());
    let (a, b) = (a.min(r), b);
    let quarter = if r <= b {
        f(a) - f(0.0)
    } else {
        let x0 = (r * r - b * b).sqrt();
        b * x0.min(a) + if a > x0 { f(a) - f(x0) } else { 0.0 }
    };
    4.0 * quarter
}

/// One printed row of Arm's Tables 2–4.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ArmRow {
    pub view: u32,
    pub ratio: f64,
    pub fovea: f64,
    pub periphery: f64,
    pub total: f64,
    pub reduction_percent: f64,
}

/// The fixed fovea of Arm's Table 4, in screen pixels.
pub const ARM_TABLE4_FOVEA: u32 = 256;

impl ArmRow {
    /// Arm's own formulas (π = 3.14) for this row of `table` at 1024² per eye.
    pub fn formula(&self, table: u32) -> PixelBudget {
        // Arm's definitions: the inset circle is the fixed fovea (table 4) or the view, the hole
        // that size times the ratio.
        let circle = if table == 4 {
            ARM_TABLE4_FOVEA as f64
        } else {
            self.view as f64
        };
        PixelBudget::analytic(
            (self.view, self.view),
            (self.view, self.view),
            circle,
            circle * self.ratio,
            table != 2,
            ARM_PI,
        )
    }

    /// Where Arm's printed cells disagree with Arm's own formulas beyond their rounding, or
    /// with each other: one sentence per cell, empty where the row is consistent.
    pub fn discrepancies(&self, table: u32) -> Vec<String> {
        let b = self.formula(table);
        // Within a pixel or 0.02 %: Arm rounded Table 4's hole to whole pixels (179 for
        // 256 · 0.7 = 179.2) but not Table 3's (501.2), 113 pixels apart at 716².
        let close = |ours: f64, printed: f64| (ours - printed).abs() <= 1.5f64.max(2e-4 * printed);
        let mut found = Vec::new();
        for (cell, printed, formula) in [
            ("fovea", self.fovea, b.fovea),
            ("periphery", self.periphery, b.periphery),
            ("total", self.total, b.total()),
        ] {
            if !close(formula, printed) {
                found.push(format!(
                    "{cell} printed {printed:.0}, Arm's formula gives {formula:.0} ({:+.0})",
                    printed - formula
                ));
            }
        }
        let sum = self.fovea + self.periphery;
        if (sum - self.total).abs() > 1.5 {
            found.push(format!(
                "total printed {:.0}, its fovea + periphery cells sum to {sum:.0}",
                self.total
            ));
        }
        // Arm truncates its percentages to one decimal (74.45 → 74.4, 60.28 → 60.2).
        let truncated = (b.reduction_percent(1024) * 10.0 + 1e-6).floor() / 10.0;
        if (truncated - self.reduction_percent).abs() > 1e-9 {
            found.push(format!(
                "reduction printed {} %, Arm's formula gives {truncated} %",
                self.reduction_percent
            ));
        }
        found
    }
}

/// Arm's printed rows: table 2 (no stencil), 3 (stencil), 4 (stencil, fixed 256² fovea).
pub fn arm_table(table: u32) -> &'static [ArmRow] {
    const fn row(
        view: u32,
        ratio: f64,
        fovea: f64,
        periphery: f64,
        total: f64,
        reduction_percent: f64,
    ) -> ArmRow {
        ArmRow {
            view,
            ratio,
            fovea,
            periphery,
            total,
            reduction_percent,
        }
    }
    const T2: [ArmRow; 3] = [
        row(716, 0.7, 1_025_312.0, 1_025_312.0, 2_050_624.0, 2.2),
        row(512, 0.5, 524_288.0, 524_288.0, 1_048_576.0, 50.0),
        row(366, 0.35, 267_912.0, 267_912.0, 535_824.0, 74.4),
    ];
    const T3: [ArmRow; 3] = [
        row(716, 0.7, 804_870.0, 630_926.0, 1_435_796.0, 31.5),
        row(512, 0.5, 411_566.0, 421_396.0, 832_963.0, 60.2),
        row(366, 0.35, 210_311.0, 242_149.0, 452_460.0, 78.4),
    ];
    // The 366 row as Arm printed it, though its own cells disagree (see
    // `ArmRow::discrepancies`).
    const T4: [ArmRow; 3] = [
        row(716, 0.7, 102_892.0, 975_008.0, 1_077_899.0, 48.6),
        row(512, 0.5, 102_892.0, 498_565.0, 601_457.0, 71.3),
        row(366, 0.35, 102_892.0, 254_768.0, 357_659.0, 82.9),
    ];
    match table {
        2 => &T2,
        3 => &T3,
        4 => &T4,
        _ => &[],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The formulas with π = 3.14 give Arm's printed cells (to their rounding; their Table 3
    /// total 832,963 is one more than its own fovea + periphery cells), except Table 4's 366
    /// row, whose periphery cell is hundreds of pixels off the formula. Mutation: a wrong π, a
    /// hole without the ratio or a mistyped cell flags a consistent row.
    #[test]
    fn formulas_reproduce_arms_tables_but_one_row() {
        for table in [2, 3, 4] {
            for r in arm_table(table) {
                let found = r.discrepancies(table);
                if table == 4 && r.view == 366 {
                    assert!(
                        found.iter().any(|f| f.starts_with("periphery")),
                        "{found:?}"
                    );
                } else {
                    assert!(found.is_empty(), "table {table} {}: {found:?}", r.view);
                }
            }
        }
    }
}
