//! What became of each accumulated pixel's history, counted by a counting frame's output pass
//! (`shaders/history_outcomes.glsl`): used as it was, clipped towards the neighbourhood, taken
//! from what the fovea showed, or dropped, and why. Timed frames count nothing.

use crate::metrics::Region;
use crate::plan::{FramePlan, HISTORY_OUTCOME_SLOTS};

/// What one accumulated pixel did with its history, in the shader's slot order.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum HistoryOutcome {
    /// The history was used as it was.
    Kept,
    /// The history was used, clipped towards the periphery's neighbourhood (it had moved out
    /// of its box: ghosting held back, or the jitter's outliers).
    Clipped,
    /// The history was used, and it held what the fovea showed over the periphery's hole.
    FromFovea,
    /// The whole history was dropped (the first frame, a teleport).
    Reset,
    /// The frame before did not see this direction (behind the eye or beyond its view).
    OffScreen,
    /// The frame before saw another surface there (the disocclusion test).
    Disoccluded,
    /// The history there held nothing (the lens hid it, or nothing was kept over the hole).
    Empty,
    /// In the periphery's hole: nothing rendered to accumulate; the fovea is shown.
    Hole,
    /// Beyond the accumulation's reach ([`TemporalConfig::within_deg`](crate::foveation::TemporalConfig::within_deg)):
    /// the frame's periphery shown as it is, no history read or kept.
    Beyond,
}

impl HistoryOutcome {
    /// Every outcome, in slot order.
    pub const ALL: [HistoryOutcome; 9] = [
        HistoryOutcome::Kept,
        HistoryOutcome::Clipped,
        HistoryOutcome::FromFovea,
        HistoryOutcome::Reset,
        HistoryOutcome::OffScreen,
        HistoryOutcome::Disoccluded,
        HistoryOutcome::Empty,
        HistoryOutcome::Hole,
        HistoryOutcome::Beyond,
    ];

    /// Its name in tables.
    pub fn name(self) -> &'static str {
        match self {
            HistoryOutcome::Kept => "kept",
            HistoryOutcome::Clipped => "clipped",
            HistoryOutcome::FromFovea => "from fovea",
            HistoryOutcome::Reset => "reset",
            HistoryOutcome::OffScreen => "off-screen",
            HistoryOutcome::Disoccluded => "disoccluded",
            HistoryOutcome::Empty => "empty",
            HistoryOutcome::Hole => "hole",
            HistoryOutcome::Beyond => "beyond reach",
        }
    }

    /// Whether the pixel started again from this frame's periphery (its history dropped).
    pub fn rejected(self) -> bool {
        matches!(
            self,
            HistoryOutcome::Reset
                | HistoryOutcome::OffScreen
                | HistoryOutcome::Disoccluded
                | HistoryOutcome::Empty
        )
    }
}

// The plan sizes the counter by these: an outcome's slots, region by region.
const _: () =
    assert!(HistoryOutcome::ALL.len() * Region::ALL.len() == HISTORY_OUTCOME_SLOTS as usize);

/// One counting frame's history outcomes: pixels per outcome and region, both eyes together.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct HistoryOutcomes {
    /// Indexed by outcome ([`HistoryOutcome::ALL`]'s order), then region ([`Region::ALL`]'s).
    pub pixels: [[u64; 3]; 9],
}

impl HistoryOutcomes {
    /// Pixels with `outcome` in `region`.
    pub fn get(&self, outcome: HistoryOutcome, region: Region) -> u64 {
        self.pixels[outcome as usize][region as usize]
    }

    /// Pixels with `outcome`, over every region.
    pub fn total(&self, outcome: HistoryOutcome) -> u64 {
        self.pixels[outcome as usize].iter().sum()
    }

    /// Pixels the accumulation covered (every outcome but the hole: those beyond its reach
    /// too) in `region`.
    pub fn accumulated(&self, region: Region) -> u64 {
        HistoryOutcome::ALL
            .iter()
            .filter(|&&o| o != HistoryOutcome::Hole)
            .map(|&o| self.get(o, region))
            .sum()
    }

    /// The share of `region`'s accumulated pixels with `outcome` (0 where none accumulated).
    pub fn share(&self, outcome: HistoryOutcome, region: Region) -> f64 {
        match self.accumulated(region) {
            0 => 0.0,
            n => self.get(outcome, region) as f64 / n as f64,
        }
    }

    /// Element-wise sum, for totals over frames.
    pub fn add(&mut self, other: &HistoryOutcomes) {
        for (mine, theirs) in self.pixels.iter_mut().zip(&other.pixels) {
            for (a, b) in mine.iter_mut().zip(theirs) {
                *a += b;
            }
        }
    }

    /// The outcomes from a counting frame's counter values (every slot the plan made), when
    /// the plan counts them.
    pub(super) fn from_counters(plan: &FramePlan, counters: &[u32]) -> Option<Self> {
        let base = plan.history_outcome_base()? as usize;
        let slots = &counters[base..base + HISTORY_OUTCOME_SLOTS as usize];
        let mut outcomes = HistoryOutcomes::default();
        for (row, counts) in outcomes.pixels.iter_mut().zip(slots.chunks_exact(3)) {
            for (pixels, &n) in row.iter_mut().zip(counts) {
                *pixels = u64::from(n);
            }
        }
        Some(outcomes)
    }
}
